"""Draw docs/figures/spatial_pump_*.png by running the study spatial-pump (default settings) and
keeping three of its figures: the pitman forces as built, the tolerance chart and the design
chart. Run from the repository root: python docs/make_spatial_figures.py"""

import shutil
import tempfile
from pathlib import Path

from mechsynth.studies import run_study

FIGURES = Path(__file__).resolve().parent / "figures"
KEEP = ("pitman_forces", "tolerance_chart", "design_chart")


def main():
    with tempfile.TemporaryDirectory() as tmp:
        result = run_study("spatial-pump", out=tmp)
        for name in KEEP:
            figure = f"spatial_pump_{name}.png"
            shutil.copy(Path(tmp) / figure, FIGURES / figure)
    print(result.summary)


if __name__ == "__main__":
    main()
