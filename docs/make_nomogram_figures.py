"""Draw the nomograms shown in docs/nomograms.md into docs/figures/nomogram_*.png (A4 sheets
at 1:1, written at 110 dpi; run from the repository root)."""

from pathlib import Path

import mechsynth as ms
from mechsynth.nomograms import library

FIGURES = {
    "nomogram_slider_crank.png": ("slider-crank", {}),
    "nomogram_pump_displacement.png": ("pump-displacement", {}),
    "nomogram_pump_torque.png": ("pump-torque", {}),
    "nomogram_extreme_velocity.png": ("extreme-velocity", {}),
    "nomogram_four_bar.png": ("four-bar", {}),
    "nomogram_acceleration.png": ("slider-crank-acceleration", {}),
}


def main(folder=Path(__file__).parent / "figures"):
    for file, (name, options) in FIGURES.items():
        with ms.display_units(library.preferred_units(name)):
            library.build(name, **options).save(folder / file, dpi=110)
        print(folder / file)


if __name__ == "__main__":
    main()
