"""Draw docs/figures/dwell_construction.png: the dwell linkage, its coupler curve, the minimax band
of the dwell section and the hull edge that sets the band (run from the repository root)."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from mechsynth.machines.dwell.linkage import DwellSliderCrank  # noqa: E402
from mechsynth.machines.dwell.metrics import dwell_window  # noqa: E402


def main(path=Path(__file__).parent / "figures" / "dwell_construction.png"):
    n = 720
    phi = np.arange(n) * 2 * np.pi / n
    m = DwellSliderCrank(r=0.3, k=1.2, gamma=np.deg2rad(20))
    x, y = m.coupler_curve(phi)
    w = dwell_window(phi, x, y, 0.01)
    idx = (w.start + np.arange(w.count)) % n
    mo = m.motion(phi)
    i0 = w.start
    pts = {p: (float(mo.points[p].x[i0]), float(mo.points[p].y[i0])) for p in "OABC"}
    fig, ax = plt.subplots(figsize=(9, 5.5), constrained_layout=True)
    ax.plot(x, y, color="0.5", lw=1, label="coupler curve of C")
    ax.plot(x[idx], y[idx], "C3", lw=2.5, label=f"dwell section, α_Σ = {np.rad2deg(w.dwell):.1f}°")
    c, s = np.cos(w.xi), np.sin(w.xi)
    nx, ny = -s, c
    t = np.linspace(x[idx].min() - 0.1, x[idx].max() + 0.1, 2)
    for off, style in ((0.0, "-"), (w.deviation, "--"), (-w.deviation, "--")):
        # line n . p = c + off, parametrized along x
        ax.plot(t, (w.fit.c + off - nx * t) / ny, "C0" + style, lw=1)
    for p, q in (("O", "A"), ("A", "B"), ("A", "C"), ("B", "C")):
        ax.plot(*zip(pts[p], pts[q]), "k-", lw=2)
    for name, (px, py) in pts.items():
        ax.plot(px, py, "ko", ms=5)
        ax.annotate(name, (px, py), textcoords="offset points", xytext=(4, 4))
    ax.annotate("γ", pts["A"], textcoords="offset points", xytext=(14, -4), color="C2")
    ax.axhline(0, color="0.6", ls=":", lw=0.8)
    ax.set_aspect("equal")
    ax.grid(True, alpha=0.4)
    ax.set_xlabel("x / l")
    ax.set_ylabel("y / l")
    ax.set_title(
        f"r = 0.3, k = 1.2, γ = 20°: band of half-width E = {w.deviation:.4f} l around the "
        f"Chebyshev line (ξ = {np.rad2deg(w.xi):.2f}°), start φ_L = {np.rad2deg(w.phi_L):.1f}°",
        fontsize=9,
    )
    ax.legend(fontsize=8, loc="upper left")
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
