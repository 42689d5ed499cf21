"""Nail header of the AB4115 (paper 003): the punch-slider mass and crank counterweight that
minimize the largest crank-train joint reaction, by certified IPOPT on the CasADi kinetostatics,
cross-checked by a scan of the slider mass with the numeric kinetostatics.

Run: python examples/optimize_nail_header_slider.py [OUT_DIR]
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mechsynth as ms  # noqa: E402
from mechsynth.machines.nail_header import NailHeader  # noqa: E402
from mechsynth.objectives.forces import peak_reaction  # noqa: E402

JOINTS = ("R10", "R21", "R32")  # crank bearing, crank pin, wrist pin


def main(out="results/optimize_nail_header_slider"):
    # the machine turns clockwise at 600 rpm; 48 crank angles in the optimization
    prob = ms.Problem(
        NailHeader,
        variables={"m3": (1.0, 200.0), "counterweight": (0.0, 2.0)},
        speed=-ms.rpm(600),
        angles=48,
    )
    prob.minimize(peak_reaction(JOINTS))
    res = prob.solve(starts=3, seed=1)
    print(res.report())

    # cross-check: the paper's design and a scan of the slider mass (no counterweight) on a
    # finer angle grid
    phi = ms.cycle(720)

    def peak(header):
        f = header.forces(phi)
        return max(float(np.max(f.magnitude(j))) for j in JOINTS)

    masses = np.linspace(1.0, 200.0, 200)
    peaks = np.array([peak(NailHeader(m3=m)) for m in masses])
    best = int(np.argmin(peaks))
    paper = peak(NailHeader())
    optimum = peak(res.design)
    print(f"\npaper's design (m3 = 15 kg): largest crank-train reaction {paper:.0f} N")
    print(
        f"optimum m3 = {res.design.m3:.2f} kg, m_cw r_cw = {res.design.counterweight:.3f} kg m: "
        f"{optimum:.0f} N at 720 angles ({100 * (1 - optimum / paper):.1f} % lower)"
    )
    print(f"scan of m3 alone (1 kg steps): {masses[best]:.0f} kg, {peaks[best]:.0f} N")

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(7, 4.2), constrained_layout=True)
    ax.plot(masses, peaks / 1e3, label="scan of the slider mass (no counterweight)")
    ax.plot(res.design.m3, optimum / 1e3, "C3o", label="certified optimum (with counterweight)")
    ax.plot(15.0, paper / 1e3, "ks", label="paper's design, 15 kg")
    ax.set_xlabel("slider mass m3, kg")
    ax.set_ylabel("largest of R10, R21, R32, kN")
    ax.grid(True, alpha=0.4)
    ax.legend()
    fig.savefig(out / "nail_header_slider_mass.png", dpi=120)
    plt.close(fig)
    return res, peaks


if __name__ == "__main__":
    main(*sys.argv[1:])
