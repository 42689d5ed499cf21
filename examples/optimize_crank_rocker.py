"""Crank-rocker, 40 deg swing, unit time ratio, largest minimum transmission angle (the Python
version of optimize_crank_rocker.toml), compared with the Brodell & Soni closed form.

Run: python examples/optimize_crank_rocker.py [OUT_DIR]
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402

import mechsynth as ms  # noqa: E402
from mechsynth import objectives as ob  # noqa: E402


def main(out="results/optimize_crank_rocker"):
    psi = ms.deg(40)
    prob = ms.Problem(
        ms.FourBar,
        variables={"crank": (0.05, 0.5), "coupler": (0.3, 2.0), "rocker": (0.3, 1.5)},
        fixed={"ground": 1.0},
    )
    prob.maximize(ob.min_transmission_angle())
    prob.subject_to(ob.swing_angle("rocker") == psi, ob.time_ratio() == 1.0)
    res = prob.solve(starts=6)
    print(res.report())

    # unit time ratio: a = c sin(psi/2), a^2 + d^2 = b^2 + c^2, cos(mu_min) = a d / (b c)
    c, d = res.design.rocker, res.design.ground
    a = c * np.sin(psi / 2)
    b = np.sqrt(a**2 + d**2 - c**2)
    print(
        f"\nclosed form for rocker {c:.6g}: crank {a:.10g}, coupler {b:.10g}, "
        f"mu_min {np.rad2deg(np.arccos(a * d / (b * c))):.8f} deg; "
        f"optimizer: {ms.to_deg(res.value):.8f} deg"
    )

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    res.plot().savefig(out / "crank_rocker_optimum.png", dpi=120)
    return res


if __name__ == "__main__":
    main(*sys.argv[1:])
