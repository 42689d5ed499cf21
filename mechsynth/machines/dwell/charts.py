"""Design charts (nomograms) of the coupler-curve dwell linkage over (r, k) for several bends gamma.

For each design of a grid the coupler curve of C is sampled at ``n_angles`` crank angles and
reduced to:

* ``dwell_deg`` — alpha_Sigma, the longest crank window whose minimax straight-line fit has a
  half-width <= the tolerance E (``mechsynth.machines.dwell.metrics``), with its ``phi_L_deg`` and
  ``xi_deg``;
* ``S_max`` — relative stroke of link 5 with its slot along that line;
* ``width_2E`` — the smallest band width 2E over all windows of a fixed length ``window_deg``.

Lengths are relative to the rod (rod = 1).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .linkage import DwellSliderCrank
from .metrics import best_window_width, dwell_metrics

__all__ = ["DwellChart", "dwell_chart_data", "plot_dwell_chart", "write_csv"]

FIELDS = ("gamma_deg", "r", "k", "dwell_deg", "phi_L_deg", "xi_deg", "E", "S_max", "width_2E")


@dataclass(frozen=True)
class DwellChart:
    """Grids of dwell metrics, arrays of shape (len(gamma_deg), len(k), len(r))."""

    r: np.ndarray
    k: np.ndarray
    gamma_deg: np.ndarray
    tolerance: float
    window_deg: float
    n_angles: int
    dwell_deg: np.ndarray
    phi_L_deg: np.ndarray
    xi_deg: np.ndarray
    E: np.ndarray
    S_max: np.ndarray
    width_2E: np.ndarray

    def rows(self):
        """Table rows (dicts with the keys of ``FIELDS``)."""
        g, kk, rr = np.meshgrid(self.gamma_deg, self.k, self.r, indexing="ij")
        cols = [g, rr, kk, self.dwell_deg, self.phi_L_deg, self.xi_deg, self.E, self.S_max]
        cols.append(self.width_2E)
        flat = [np.ravel(c) for c in cols]
        return [dict(zip(FIELDS, (float(v[i]) for v in flat))) for i in range(flat[0].size)]

    def plot(self, path=None):
        return plot_dwell_chart(self, path)


def dwell_chart_data(r, k, gamma_deg, tolerance=0.002, window_deg=90.0, n_angles=360):
    """Evaluate the dwell metrics on the grid ``r`` x ``k`` for each bend in ``gamma_deg``."""
    r = np.asarray(r, dtype=float)
    k = np.asarray(k, dtype=float)
    gamma_deg = np.atleast_1d(np.asarray(gamma_deg, dtype=float))
    if n_angles < 36:
        raise ValueError(f"n_angles must be >= 36, got {n_angles}")
    phi = np.arange(n_angles) * 2.0 * np.pi / n_angles
    g = np.deg2rad(gamma_deg)[:, None, None, None]
    mech = DwellSliderCrank(r=r[None, None, :, None], k=k[None, :, None, None], gamma=g)
    x, y = mech.coupler_curve(phi)
    x, y = np.broadcast_arrays(x, y)
    win = dwell_metrics(phi, x, y, tolerance)
    width, _ = best_window_width(phi, x, y, np.deg2rad(window_deg))
    return DwellChart(
        r=r,
        k=k,
        gamma_deg=gamma_deg,
        tolerance=float(tolerance),
        window_deg=float(window_deg),
        n_angles=int(n_angles),
        dwell_deg=np.rad2deg(win["dwell"]),
        phi_L_deg=np.rad2deg(win["phi_L"]),
        xi_deg=np.rad2deg(win["xi"]),
        E=win["deviation"],
        S_max=win["S_max"],
        width_2E=width,
    )


def write_csv(chart: DwellChart, path) -> Path:
    path = Path(path)
    with path.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=FIELDS)
        w.writeheader()
        for row in chart.rows():
            w.writerow({key: f"{val:.8g}" for key, val in row.items()})
    return path


def plot_dwell_chart(chart: DwellChart, path=None):
    """Nomogram sheet: one row per gamma; columns alpha_Sigma, 2E (fixed window), S_max."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ng = chart.gamma_deg.size
    fig, axes = plt.subplots(ng, 3, figsize=(13, 3.8 * ng), squeeze=False, constrained_layout=True)
    panels = [
        ("dwell_deg", f"dwell duration α_Σ, deg (E ≤ {chart.tolerance:g} l)", "viridis"),
        ("width_2E", f"band width 2E over a {chart.window_deg:g}° window, × l", "magma_r"),
        ("S_max", "relative stroke S_max of link 5, × l", "cividis"),
    ]
    rr, kk = np.meshgrid(chart.r, chart.k)
    for gi, gamma in enumerate(chart.gamma_deg):
        for ci, (field, title, cmap) in enumerate(panels):
            ax = axes[gi, ci]
            z = getattr(chart, field)[gi]
            if field == "width_2E":
                z = np.log10(np.maximum(z, 1e-9))
            cf = ax.contourf(rr, kk, z, levels=14, cmap=cmap, alpha=0.55)
            cs = ax.contour(rr, kk, z, levels=cf.levels[::2], colors="k", linewidths=0.7)
            fmt = (lambda v: f"{10**v:.2g}") if field == "width_2E" else "%.3g"
            ax.clabel(cs, fmt=fmt, fontsize=7)
            ax.grid(True, alpha=0.4, linestyle=":")
            ax.set_xlabel("r = l_OA / l")
            ax.set_ylabel("k = l_AC / l")
            ax.set_title(f"γ = {gamma:g}°: {title}", fontsize=9)
            cb = fig.colorbar(cf, ax=ax)
            if field == "width_2E":
                cb.set_label("log10(2E / l)")
    fig.suptitle(
        f"Dwell linkage on a central slider-crank: design chart ({chart.n_angles} crank angles)"
    )
    if path is not None:
        fig.savefig(path, dpi=120)
    return fig


def chart_dwell(out, options):
    """``mechsynth chart dwell``: options gamma_deg=0,20,40 tolerance=0.002 n=40 window_deg=90
    n_angles=360 r=0.05:0.5 k=0.3:2.5."""
    from ...report import StudyResult
    from ...synthesis.charts import pop_span

    opts = dict(options)

    def span(key, default):
        return pop_span(opts, key, default)

    gammas = [float(v) for v in opts.pop("gamma_deg", "0,20,40").split(",")]
    tol = float(opts.pop("tolerance", "0.002"))
    n = int(opts.pop("n", "40"))
    window = float(opts.pop("window_deg", "90"))
    n_angles = int(opts.pop("n_angles", "360"))
    r_lo, r_hi = span("r", "0.05:0.5")
    k_lo, k_hi = span("k", "0.3:2.5")
    if opts:
        raise ValueError(f"unknown chart option(s): {', '.join(sorted(opts))}")
    if n < 3:
        raise ValueError(f"n (grid points per axis) must be >= 3, got {n}")
    chart = dwell_chart_data(
        np.linspace(r_lo, r_hi, n), np.linspace(k_lo, k_hi, n), gammas, tol, window, n_angles
    )
    files = []
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        files.append(write_csv(chart, out / "dwell_chart.csv"))
        fig = chart.plot(out / "dwell_chart.png")
        fig.savefig(out / "dwell_chart.svg")
        files.append(out / "dwell_chart.png")
        files.append(out / "dwell_chart.svg")
    i = np.unravel_index(int(np.argmax(chart.dwell_deg)), chart.dwell_deg.shape)
    best = {
        "gamma_deg": float(chart.gamma_deg[i[0]]),
        "k": float(chart.k[i[1]]),
        "r": float(chart.r[i[2]]),
        "dwell_deg": float(chart.dwell_deg[i]),
        "S_max": float(chart.S_max[i]),
    }
    summary = (
        f"dwell chart: {n} x {n} grid, gamma = {gammas} deg, E <= {tol:g} l, "
        f"{n_angles} crank angles; longest dwell {best['dwell_deg']:.1f} deg at {best}"
    )
    data = {"tolerance": tol, "grid": n, "gamma_deg": gammas, "best_on_grid": best}
    return StudyResult("dwell-chart", summary, data, [Path(f) for f in files])
