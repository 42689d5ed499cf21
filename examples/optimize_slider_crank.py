"""Offset slider-crank with the smallest peak slider acceleration (the Python version of
optimize_slider_crank.toml), cross-checked by differential evolution.

Run: python examples/optimize_slider_crank.py [OUT_DIR]
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import mechsynth as ms  # noqa: E402
from mechsynth import objectives as ob  # noqa: E402


def main(out="results/optimize_slider_crank"):
    prob = ms.Problem(
        ms.SliderCrank,
        variables={"crank": (0.01, 0.2), "rod": (0.05, 0.2), "offset": (-0.1, 0.1)},
        speed=ms.rpm(600),
    )
    prob.minimize(ob.peak_acceleration("slider"))
    prob.subject_to(ob.stroke("slider") == 0.10, ob.max_pressure_angle() <= ms.deg(30))

    res = prob.solve(starts=6, seed=1)  # certified multi-start IPOPT
    print(res.report())
    check = prob.solve(method="de", seed=1)  # global search, then certified polish
    print(f"\ndifferential evolution + polish: {check.value:.10g} ({check.status})")

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    res.plot().savefig(out / "slider_crank_optimum.png", dpi=120)
    return res, check


if __name__ == "__main__":
    main(*sys.argv[1:])
