"""Paper 003 (second part): dwell linkage on a central slider-crank, synthesized for the longest
dwell.

Problem: find (r, k, gamma) maximizing the dwell duration alpha_Sigma subject to a dwell accuracy
(half-width E <= tolerance, lengths relative to the rod) and a relative stroke S_max >= a required
stroke of link 5. The dwell metrics are not smooth (the window length is an integer number of
samples), so the search is: a coarse chart grid (seed) -> a compass pattern search from the seed
at the full angular resolution (refinement) -> a dense (r, k) grid at the best gamma (certificate).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..kinematics.dwell import DwellSliderCrank
from ..objectives.dwell import dwell_window, relative_stroke
from ..synthesis.dwell_charts import dwell_chart_data
from . import StudyResult

R_BOUNDS = (0.05, 0.5)
K_BOUNDS = (0.3, 2.5)
G_BOUNDS = (-60.0, 60.0)


def evaluate(r, k, gamma_deg, tolerance, n_angles=720):
    """Dwell metrics of one design: dict with dwell_deg, phi_L_deg, deviation, xi_deg, S_max."""
    phi = np.arange(n_angles) * 2 * np.pi / n_angles
    m = DwellSliderCrank(r, k, np.deg2rad(gamma_deg))
    x, y = m.coupler_curve(phi)
    w = dwell_window(phi, x, y, tolerance)
    return {
        "r": float(r),
        "k": float(k),
        "gamma_deg": float(gamma_deg),
        "phi_L_deg": float(np.rad2deg(w.phi_L)),
        "dwell_deg": float(np.rad2deg(w.dwell)),
        "deviation": float(w.deviation),
        "xi_deg": float(np.rad2deg(w.xi)),
        "S_max": float(relative_stroke(x, y, w.xi)),
    }


def _score(d, stroke):
    """Dwell (deg) when the stroke constraint holds, else a penalty below every feasible value."""
    short = stroke - d["S_max"]
    return d["dwell_deg"] if short <= 0 else -1000.0 * short


def _inside(p):
    return (
        R_BOUNDS[0] <= p[0] <= R_BOUNDS[1]
        and K_BOUNDS[0] <= p[1] <= K_BOUNDS[1]
        and (G_BOUNDS[0] <= p[2] <= G_BOUNDS[1])
    )


def pattern_search(seed, tolerance, stroke, steps=(0.02, 0.05, 4.0), min_step=0.02, n_angles=720):
    """Compass search (r, k, gamma_deg) maximizing the dwell with the stroke constraint; returns
    (best design dict, number of evaluations)."""
    p = np.array(seed, dtype=float)
    best = evaluate(*p, tolerance, n_angles)
    f = _score(best, stroke)
    h = np.array(steps, dtype=float)
    scale = 1.0
    nfev = 1
    while scale >= min_step:
        improved = False
        for i in range(3):
            for sgn in (1.0, -1.0):
                q = p.copy()
                q[i] += sgn * h[i] * scale
                if not _inside(q):
                    continue
                d = evaluate(*q, tolerance, n_angles)
                nfev += 1
                fq = _score(d, stroke)
                if fq > f:
                    p, f, best, improved = q, fq, d, True
        if not improved:
            scale *= 0.5
    return best, nfev


def _draw(best, tolerance, out: Path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = 720
    phi = np.arange(n) * 2 * np.pi / n
    xi = np.deg2rad(best["xi_deg"])
    m = DwellSliderCrank(best["r"], best["k"], np.deg2rad(best["gamma_deg"]), xi=xi)
    w = dwell_window(phi, *m.coupler_curve(phi), tolerance)
    idx = (w.start + np.arange(w.count)) % n
    mo = m.motion(phi)
    c = mo.points["C"]
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(13, 5.2), constrained_layout=True)
    a1.plot(c.x, c.y, color="0.4", lw=1, label="coupler curve of C")
    a1.plot(np.asarray(c.x)[idx], np.asarray(c.y)[idx], color="C3", lw=2.5, label="dwell section")
    i0 = w.start
    pts = {name: (float(mo.points[name].x[i0]), float(mo.points[name].y[i0])) for name in "OABC"}
    for p, q in (("O", "A"), ("A", "B"), ("A", "C"), ("B", "C")):
        a1.plot(*zip(pts[p], pts[q]), "k-", lw=2)
    for name, (px, py) in pts.items():
        a1.plot(px, py, "ko", ms=5)
        a1.annotate(name, (px, py), textcoords="offset points", xytext=(4, 4))
    a1.axhline(0.0, color="0.6", ls="--", lw=0.8, label="slider guide")
    t = np.linspace(-0.6, 0.6, 2)
    cx, cy = pts["C"]
    a1.plot(
        cx + t * np.cos(xi), cy + t * np.sin(xi), "C0-", lw=4, alpha=0.4, label="slot of link 5"
    )
    a1.set_aspect("equal")
    a1.grid(True, alpha=0.4)
    a1.set_xlabel("x / l")
    a1.set_ylabel("y / l")
    a1.legend(fontsize=8)
    a1.set_title(
        f"r = {best['r']:.4f}, k = {best['k']:.4f}, γ = {best['gamma_deg']:.2f}°, "
        f"at φ_L = {best['phi_L_deg']:.1f}°"
    )
    s5 = np.asarray(mo.sliders["5"].position)
    deg = np.rad2deg(phi)
    a2.plot(deg, s5, "k-", lw=1.2, label="s5(φ)")
    a2.plot(deg[idx], s5[idx], "C3.", ms=2, label=f"dwell α_Σ = {best['dwell_deg']:.1f}°")
    a2.grid(True, alpha=0.4)
    a2.set_xlabel("crank angle φ, deg")
    a2.set_ylabel("displacement s5 of link 5, × l")
    a2.set_title(f"S_max = {best['S_max']:.4f} l, 2E = {2 * best['deviation']:.4g} l")
    a2.legend(fontsize=8)
    path = out / "dwell_best.png"
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def run(out=None, tolerance=0.002, stroke=0.3, n=10, dense=20):
    """Synthesize the longest-dwell linkage for half-width ``tolerance`` and stroke ``stroke``."""
    tolerance, stroke = float(tolerance), float(stroke)
    if tolerance <= 0 or stroke <= 0:
        raise ValueError(f"tolerance ({tolerance}) and stroke ({stroke}) must be positive")
    n, dense = int(n), int(dense)
    gammas = np.linspace(G_BOUNDS[0], G_BOUNDS[1], 7)
    chart = dwell_chart_data(
        np.linspace(*R_BOUNDS, n), np.linspace(*K_BOUNDS, n), gammas, tolerance, 90.0, 360
    )
    score = np.where(chart.S_max >= stroke, chart.dwell_deg, -np.inf)
    if not np.isfinite(score.max()):
        summary = f"no design on the seed grid reaches the stroke {stroke:g} l"
        return StudyResult("dwell", summary, {"tolerance": tolerance, "success": False})
    gi, ki, ri = np.unravel_index(int(np.argmax(score)), score.shape)
    seed = (chart.r[ri], chart.k[ki], chart.gamma_deg[gi])
    seed_design = evaluate(*seed, tolerance)
    best, nfev = pattern_search(seed, tolerance, stroke)
    # certificate: dense (r, k) grid at the best bend, full angular resolution
    cert = dwell_chart_data(
        np.linspace(*R_BOUNDS, dense),
        np.linspace(*K_BOUNDS, dense),
        [best["gamma_deg"]],
        tolerance,
        90.0,
        720,
    )
    cscore = np.where(cert.S_max >= stroke, cert.dwell_deg, -np.inf)
    cbest = float(cscore.max())
    success = best["S_max"] >= stroke and best["deviation"] <= tolerance
    certified = best["dwell_deg"] >= cbest - 1e-9
    data = {
        "tolerance": tolerance,
        "stroke": stroke,
        "best": best,
        "seed": seed_design,
        "evaluations": nfev,
        "certificate": {"dense_grid": dense, "best_dwell_deg": cbest, "passed": bool(certified)},
        "success": bool(success),
    }
    files = []
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        files.append(_draw(best, tolerance, out))
    summary = "\n".join(
        [
            f"Dwell synthesis: E <= {tolerance:g} l, S_max >= {stroke:g} l",
            f"seed (grid {n}x{n}x{gammas.size}): dwell {seed_design['dwell_deg']:.1f} deg",
            f"best: r={best['r']:.4f} k={best['k']:.4f} gamma={best['gamma_deg']:.2f} deg, "
            f"dwell {best['dwell_deg']:.1f} deg from phi_L={best['phi_L_deg']:.1f} deg, "
            f"E={best['deviation']:.4g} l, xi={best['xi_deg']:.2f} deg, S_max={best['S_max']:.4f}",
            f"certificate: best of a {dense}x{dense} grid at this gamma {cbest:.1f} deg "
            f"({'passed' if certified else 'NOT passed'})",
        ]
    )
    return StudyResult("dwell", summary, data, files)
