"""Draw docs/figures/motion_generation.png: four poses with their centre- and circle-point
curves and a four-bar chosen on them, and five poses with their Burmester points and the
best-ranked four-bar (run from the repository root)."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mechsynth as ms  # noqa: E402
from mechsynth.plotting import layout_problems, style  # noqa: E402


def poses():
    cr = ms.FourBar(crank=1.2, coupler=3.5, rocker=3.0, ground=4.0)
    m = cr.motion(ms.deg([10, 55, 110, 170, 230]), coupler_points={"P": (1.1, 0.9)})
    return np.column_stack([m.points["P"].x, m.points["P"].y, m.links["coupler"].angle + 0.4])


def main(path=Path(__file__).parent / "figures" / "motion_generation.png"):
    p = poses()
    with style():
        fig, axes = plt.subplots(1, 2, figsize=(13.0, 6.0), layout="constrained")
        four = ms.motion_generation(p[:4], centres=[(0.0, 0.0), (4.0, 0.0)])
        four.plot(0, ax=axes[0], title="4 poses: centre- and circle-point curves\n"
                  "a four-bar on pivots chosen on the centre-point curve")  # fmt: skip
        five = ms.motion_generation(p)
        five.plot(0, ax=axes[1], title="5 poses: the Burmester points\n"
                  "the best-ranked four-bar (min transmission angle "
                  f"{ms.to_deg(five.best.min_transmission):.1f} deg)")  # fmt: skip
        problems = layout_problems(fig)
        if problems:
            raise SystemExit("\n".join(problems))
        fig.savefig(path, dpi=110)
    print(path)


if __name__ == "__main__":
    main()
