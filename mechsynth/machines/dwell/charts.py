"""Design charts (nomograms) of the coupler-curve dwell linkage over (r, k) for several bends gamma.

For each design of a grid the coupler curve of C is sampled at ``n_angles`` crank angles and
reduced to:

* ``dwell_deg`` — alpha_Sigma, the longest crank window whose minimax straight-line fit has a
  half-width <= the tolerance E (``mechsynth.machines.dwell.metrics``), with its ``phi_L_deg`` and
  ``xi_deg``;
* ``S_max`` — relative stroke of link 5 with its slot along that line;
* ``width_2E`` — the smallest band width 2E over all windows of a fixed length ``window_deg``.

A dwell only matters when link 5 also moves: designs whose stroke ``S_max`` is below the chart's
minimum stroke (``stroke``) are set apart (hatched in the dwell panels, never "best"); without
that filter the longest "dwell" is 360 deg of an output that hardly moves.

Lengths are relative to the rod (rod = 1).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import MechanismError
from ...fileio import output_dir, save_figure
from ...options import Option, chart_options
from .linkage import DwellSliderCrank
from .metrics import best_window_width, dwell_metrics

__all__ = ["DwellChart", "dwell_chart_data", "plot_dwell_chart", "write_csv"]

FIELDS = ("gamma_deg", "r", "k", "dwell_deg", "phi_L_deg", "xi_deg", "E", "S_max", "width_2E")


@dataclass(frozen=True)
class DwellChart:
    """Grids of dwell metrics, arrays of shape (len(gamma_deg), len(k), len(r)); ``stroke`` is
    the smallest relative stroke S_max of a design that counts (0: all count)."""

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
    stroke: float = 0.0

    @property
    def moves(self) -> np.ndarray:
        """Designs whose link 5 moves at least ``stroke`` (S_max >= stroke)."""
        return self.S_max >= self.stroke

    def best(self, gamma_index=None) -> dict | None:
        """The longest dwell among the designs that move at least ``stroke`` (over all bends,
        or the bend ``gamma_index``): ``{"gamma_deg", "r", "k", "dwell_deg", "S_max", "E",
        "xi_deg", "phi_L_deg", "on_edge"}`` or None when no design qualifies. ``on_edge`` names
        the axes (``"r"``, ``"k"``) on whose end the best design sits."""
        ok = self.moves.copy()
        if gamma_index is not None:
            sel = np.zeros_like(ok)
            sel[gamma_index] = True
            ok &= sel
        if not ok.any():
            return None
        i = np.unravel_index(int(np.argmax(np.where(ok, self.dwell_deg, -np.inf))), ok.shape)
        edge = [
            name
            for name, axis, j in (("k", self.k, i[1]), ("r", self.r, i[2]))
            if axis.size > 1 and j in (0, axis.size - 1)
        ]
        return {
            "gamma_deg": float(self.gamma_deg[i[0]]),
            "r": float(self.r[i[2]]),
            "k": float(self.k[i[1]]),
            "dwell_deg": float(self.dwell_deg[i]),
            "S_max": float(self.S_max[i]),
            "E": float(self.E[i]),
            "xi_deg": float(self.xi_deg[i]),
            "phi_L_deg": float(self.phi_L_deg[i]),
            "on_edge": edge,
        }

    def rows(self):
        """Table rows (dicts with the keys of ``FIELDS``)."""
        g, kk, rr = np.meshgrid(self.gamma_deg, self.k, self.r, indexing="ij")
        cols = [g, rr, kk, self.dwell_deg, self.phi_L_deg, self.xi_deg, self.E, self.S_max]
        cols.append(self.width_2E)
        flat = [np.ravel(c) for c in cols]
        return [dict(zip(FIELDS, (float(v[i]) for v in flat))) for i in range(flat[0].size)]

    def _table(self):
        from ... import tables

        g, kk, rr = (
            np.ravel(a) for a in np.meshgrid(self.gamma_deg, self.k, self.r, indexing="ij")
        )

        def rad(a):
            return np.deg2rad(np.ravel(a))

        return tables.table(
            [
                ("gamma", "rad", np.deg2rad(g)),
                ("r = l_OA/l", "", rr),
                ("k = l_AC/l", "", kk),
                ("dwell", "rad", rad(self.dwell_deg)),
                ("dwell start phi_L", "rad", rad(self.phi_L_deg)),
                ("slot angle xi", "rad", rad(self.xi_deg)),
                ("half-width E [l]", "", np.ravel(self.E)),
                ("stroke S_max [l]", "", np.ravel(self.S_max)),
                (f"band width 2E over {self.window_deg:g} deg [l]", "", np.ravel(self.width_2E)),
                (f"moves (S_max >= {self.stroke:g} l)", "", np.ravel(self.moves).astype(int)),
            ]
        )

    def to_dict(self) -> dict[str, list]:
        """One column per quantity, one entry per design (angles in the display angle unit,
        lengths relative to the rod)."""
        from ... import tables

        return tables.as_lists(self._table())

    def to_csv(self, path=None):
        """The columns of :meth:`to_dict` as CSV, written to ``path`` (returns it) or returned
        as text."""
        from ... import tables

        return tables.write_csv(self._table(), path)

    def plot(self, path=None):
        return plot_dwell_chart(self, path)


def dwell_chart_data(
    r, k, gamma_deg, tolerance=0.002, window_deg=90.0, n_angles=360, stroke=0.0, progress=None
):
    """Evaluate the dwell metrics on the grid ``r`` x ``k`` for each bend in ``gamma_deg``
    (one batch per bend, with a progress bar on a terminal); ``stroke`` is the chart's minimum
    relative stroke (see :class:`DwellChart`)."""
    from ...progress import bar

    r = np.asarray(r, dtype=float)
    k = np.asarray(k, dtype=float)
    gamma_deg = np.atleast_1d(np.asarray(gamma_deg, dtype=float))
    if n_angles < 36:
        raise MechanismError(f"n_angles must be >= 36, got {n_angles}")
    if not np.isfinite(stroke) or stroke < 0:
        raise MechanismError(
            f"stroke (minimum S_max, relative to the rod) must be >= 0, got {stroke}"
        )
    phi = np.arange(n_angles) * 2.0 * np.pi / n_angles
    parts = []
    for g in bar(gamma_deg, desc="dwell chart", enabled=progress, unit="bend"):
        mech = DwellSliderCrank(r=r[None, :, None], k=k[:, None, None], gamma=np.deg2rad(g))
        x, y = np.broadcast_arrays(*mech.coupler_curve(phi))
        win = dwell_metrics(phi, x, y, tolerance)
        width, _ = best_window_width(phi, x, y, np.deg2rad(window_deg))
        parts.append((win, width))

    def stack(key):
        return np.stack([w[key] for w, _ in parts])

    return DwellChart(
        r=r,
        k=k,
        gamma_deg=gamma_deg,
        tolerance=float(tolerance),
        window_deg=float(window_deg),
        n_angles=int(n_angles),
        dwell_deg=np.rad2deg(stack("dwell")),
        phi_L_deg=np.rad2deg(stack("phi_L")),
        xi_deg=np.rad2deg(stack("xi")),
        E=stack("deviation"),
        S_max=stack("S_max"),
        width_2E=np.stack([w for _, w in parts]),
        stroke=float(stroke),
    )


def write_csv(chart: DwellChart, path) -> Path:
    """Write ``chart.to_csv(path)``; returns the path."""
    return chart.to_csv(path)


def plot_dwell_chart(chart: DwellChart, path=None):
    """Nomogram sheet: one row per bend gamma; columns: dwell alpha_Sigma (designs below the
    minimum stroke hatched and left out of the colour scale), band width 2E over a fixed window
    (log scale), stroke S_max with the minimum-stroke line. One colour scale per column, shared
    by the rows; the longest dwell of each row starred."""
    import matplotlib.pyplot as plt
    from matplotlib.colors import LogNorm
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    from matplotlib.ticker import LogLocator, MaxNLocator

    from ...plotting import PALETTE, label_contours, prune_labels, style

    ng = chart.gamma_deg.size
    rr, kk = np.meshgrid(chart.r, chart.k)
    moves = chart.moves
    with style():
        fig, axes = plt.subplots(
            ng,
            3,
            figsize=(14, 1.0 + 3.9 * ng),
            squeeze=False,
            layout="constrained",
            sharex=True,
            sharey=True,
        )
        dwell = np.ma.MaskedArray(chart.dwell_deg, ~moves)
        top = float(dwell.max()) if dwell.count() else 360.0
        dwell_levels = MaxNLocator(12).tick_values(0.0, max(top, 10.0))
        width = np.maximum(chart.width_2E, 1e-9)
        lo, hi = float(np.percentile(width, 1)), float(width.max())
        width_levels = np.geomspace(lo, hi, 13)
        stroke_levels = MaxNLocator(10).tick_values(0.0, float(chart.S_max.max()))
        columns = []
        for gi, gamma in enumerate(chart.gamma_deg):
            row = axes[gi]
            cf0 = row[0].contourf(rr, kk, dwell[gi], levels=dwell_levels, cmap="viridis")
            cs = row[0].contour(
                rr, kk, dwell[gi], levels=dwell_levels[::2], colors="k", linewidths=0.6
            )
            label_contours(row[0], cs, fmt="%.0f")
            if (~moves[gi]).any():
                with plt.rc_context({"hatch.color": "0.45", "hatch.linewidth": 0.5}):
                    row[0].contourf(
                        rr,
                        kk,
                        (~moves[gi]).astype(float),
                        levels=[0.5, 1.5],
                        colors=["0.9"],
                        hatches=["//"],
                    )
            cf1 = row[1].contourf(
                rr,
                kk,
                width[gi],
                levels=width_levels,
                cmap="magma_r",
                norm=LogNorm(lo, hi),
                extend="min",
            )
            cs = row[1].contour(
                rr, kk, width[gi], levels=width_levels[::3], colors="k", linewidths=0.6
            )
            label_contours(row[1], cs, fmt=lambda v: f"{v:.2g}")
            cf2 = row[2].contourf(rr, kk, chart.S_max[gi], levels=stroke_levels, cmap="cividis")
            cs = row[2].contour(
                rr, kk, chart.S_max[gi], levels=stroke_levels[::2], colors="k", linewidths=0.6
            )
            label_contours(row[2], cs, fmt="%.2g")
            if chart.stroke > 0 and chart.S_max[gi].min() < chart.stroke < chart.S_max[gi].max():
                row[2].contour(
                    rr,
                    kk,
                    chart.S_max[gi],
                    levels=[chart.stroke],
                    colors=PALETTE[6],
                    linewidths=2.4,
                )
            best = chart.best(gi)
            if best is not None:
                for ax in row:
                    ax.plot(
                        best["r"],
                        best["k"],
                        "*",
                        ms=13,
                        color="gold",
                        mec="k",
                        clip_on=False,
                        zorder=6,
                    )
            for ax in row:
                ax.grid(True, alpha=0.3, ls=":")
            row[0].set_ylabel(f"γ = {gamma:g}°\nk = l_AC / l")
            columns = [cf0, cf1, cf2]
        for ax in axes[-1]:
            ax.set_xlabel("r = l_OA / l")
        heads = [
            f"dwell α_Σ (E ≤ {chart.tolerance:g} l, S_max ≥ {chart.stroke:g} l)",
            f"band width 2E over a {chart.window_deg:g}° window",
            "stroke S_max of link 5",
        ]
        units = ["deg", "× l (log scale)", "× l"]
        for ci, (cf, head, unit) in enumerate(zip(columns, heads, units)):
            axes[0, ci].set_title(f"{head}, {unit}", fontsize=9)
            cb = fig.colorbar(cf, ax=axes[:, ci], location="bottom", shrink=0.9, aspect=30)
            if ci == 1:
                cb.locator = LogLocator()
                cb.update_ticks()
            cb.set_label(f"{head.split(' (')[0]}, {unit}", fontsize=8)
        handles = [
            Line2D(
                [],
                [],
                marker="*",
                ms=11,
                color="gold",
                mec="k",
                ls="none",
                label="longest dwell of the bend (S_max ≥ minimum)",
            ),
            Patch(
                facecolor="0.9",
                hatch="//",
                edgecolor="0.45",
                label=f"link 5 moves less than S_max = {chart.stroke:g} l",
            ),
            Line2D([], [], color=PALETTE[6], lw=2.4, label=f"S_max = {chart.stroke:g} l"),
        ]
        fig.legend(handles=handles, loc="outside lower center", ncol=3, fontsize=8)
        fig.suptitle(
            "Dwell linkage on a central slider-crank: design chart "
            f"({chart.r.size} x {chart.k.size} designs per bend, {chart.n_angles} crank angles)"
        )
        prune_labels(fig)
        if path is not None:
            save_figure(fig, path, dpi=110)
    return fig


@chart_options(
    Option(
        "gamma_deg",
        (0.0, 20.0, 40.0),
        "bends gamma of the coupler, one panel column each",
        unit="deg",
        minimum=-180.0,
        maximum=180.0,
    ),
    Option(
        "tolerance",
        0.002,
        "half-width E of the dwell band, relative to the rod",
        minimum=0.0,
        exclusive=True,
    ),
    Option("stroke", 0.3, "minimum relative stroke S_max of a design that counts", minimum=0.0),
    Option("n", 40, "grid points per axis", minimum=3, maximum=1000),
    Option(
        "window_deg",
        90.0,
        "dwell window searched",
        unit="deg",
        minimum=0.0,
        exclusive=True,
        maximum=360.0,
    ),
    Option("n_angles", 360, "crank angles per turn", minimum=8, maximum=100_000),
    Option(
        "r",
        (0.05, 0.5),
        "range of the crank r (relative to the rod)",
        kind="span",
        minimum=0.0,
        exclusive=True,
    ),
    Option(
        "k",
        (0.3, 2.5),
        "range of the coupler point distance k (relative to the rod)",
        kind="span",
        minimum=0.0,
        exclusive=True,
    ),
    owner="chart 'dwell'",
)
def chart_dwell(out, options):
    """``mechsynth chart dwell``: dwell duration, band width and stroke S_max of the dwell
    linkage over (r, k) for a few bends; its options are ``chart_dwell.options``."""
    from ... import display
    from ...report import StudyResult

    gammas = list(options["gamma_deg"])
    tol, stroke, n = options["tolerance"], options["stroke"], options["n"]
    window, n_angles = options["window_deg"], options["n_angles"]
    r_lo, r_hi = options["r"]
    k_lo, k_hi = options["k"]
    chart = dwell_chart_data(
        np.linspace(r_lo, r_hi, n),
        np.linspace(k_lo, k_hi, n),
        gammas,
        tol,
        window,
        n_angles,
        stroke=stroke,
    )
    files = []
    if out is not None:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        out = output_dir(out)
        files.append(chart.to_csv(out / "dwell_chart.csv"))
        fig = chart.plot(out / "dwell_chart.png")
        save_figure(fig, out / "dwell_chart.svg")
        plt.close(fig)
        files.append(out / "dwell_chart.png")
        files.append(out / "dwell_chart.svg")
    best = chart.best()
    head = (
        f"dwell chart: {n} x {n} designs per bend (r {r_lo:g}..{r_hi:g}, k {k_lo:g}..{k_hi:g}), "
        f"bends gamma = {', '.join(f'{g:g}' for g in gammas)} deg, E <= {tol:g} l, "
        f"{n_angles} crank angles; {int(chart.moves.sum())} of {chart.moves.size} designs move "
        f"link 5 at least S_max = {stroke:g} l."
    )
    if best is None:
        summary = (
            head + f"\nNo design of the grid moves link 5 by {stroke:g} l: lower --set stroke."
        )
    else:
        deg = display.current().angle == "deg"

        def ang(v):
            return f"{v:.1f} deg" if deg else f"{np.deg2rad(v):.4f} rad"

        summary = (
            f"{head}\nLongest dwell: {ang(best['dwell_deg'])} at gamma = {ang(best['gamma_deg'])}, "
            f"r = {best['r']:.4g}, k = {best['k']:.4g} (stroke S_max = {best['S_max']:.4g} l, "
            f"half-width E = {best['E']:.3g} l, slot angle xi = {ang(best['xi_deg'])}, dwell "
            f"from phi = {ang(best['phi_L_deg'])})."
        )
        if best["on_edge"]:
            summary += (
                f"\nWARNING: it lies on the grid's edge in {' and '.join(best['on_edge'])}: the "
                "longest dwell may lie outside the chart; widen the range (--set r=LOW:HIGH, "
                "k=LOW:HIGH)."
            )
    data = {
        "tolerance": tol,
        "stroke": stroke,
        "grid": n,
        "gamma_deg": gammas,
        "moving_designs": int(chart.moves.sum()),
        "best_on_grid": best,
    }
    return StudyResult("dwell-chart", summary, data, [Path(f) for f in files])
