"""Figures of path generation: targets, traced curve, the linkage at the targets."""

from __future__ import annotations

import numpy as np

__all__ = ["path_figure", "pareto_figure"]


def path_figure(result, n: int = 360, show: int | None = None):
    """The best design of a :class:`~mechsynth.synthesis.path_generation.PathResult`: the
    targets (numbered), the coupler curve over a turn, the linkage drawn at the targets (at
    most ``show`` of them, default up to 4, spread over the targets) and the ground pivots."""
    import matplotlib.pyplot as plt

    from .. import display
    from ..plotting import PALETTE, style

    best = result._best()
    du = display.current()
    f = du.factor("m")
    unit = du.unit("m")
    t = result.targets / f
    phi = np.linspace(0.0, 2.0 * np.pi, n + 1)
    curve = best.trace(phi) / f
    pos = {k: v / f for k, v in best.positions().items()}
    m = len(t)
    show = min(m, 4) if show is None else max(0, min(int(show), m))
    pick = np.unique(np.round(np.linspace(0, m - 1, show)).astype(int)) if show else []
    with style():
        fig, ax = plt.subplots(figsize=(8.0, 5.2))
        for j, i in enumerate(pick):
            xs = [pos[k][i, 0] for k in ("O1", "A", "B", "O2")]
            ys = [pos[k][i, 1] for k in ("O1", "A", "B", "O2")]
            alpha = 1.0 if j == 0 else 0.35
            ax.plot(xs, ys, "-", color=PALETTE[4], lw=1.2, alpha=alpha,
                    label="linkage at the targets" if j == 0 else None)  # fmt: skip
            tri = np.array([pos["A"][i], pos["B"][i], pos["P"][i], pos["A"][i]])
            ax.fill(tri[:, 0], tri[:, 1], color=PALETTE[4], alpha=0.12 * alpha)
            ax.plot(tri[:, 0], tri[:, 1], "-", color=PALETTE[4], lw=0.8, alpha=alpha)
        ax.plot(curve[:, 0], curve[:, 1], "-", color=PALETTE[1], label="coupler curve")
        ax.plot(pos["P"][:, 0], pos["P"][:, 1], "o", ms=3.5, color=PALETTE[1],
                label="coupler point at the targets")  # fmt: skip
        ax.plot(t[:, 0], t[:, 1], "x", ms=6, mew=1.5, color=PALETTE[6], label="targets")
        for k in ("O1", "O2"):
            ax.plot(*pos[k][0], "^", ms=8, color=PALETTE[0])
            ax.annotate(k, pos[k][0], textcoords="offset points", xytext=(5, -11), fontsize=8)
        for i, (x, y) in enumerate(t):
            if m <= 24 or i % max(1, m // 12) == 0:
                ax.annotate(str(i + 1), (x, y), textcoords="offset points", xytext=(4, 4),
                            fontsize=7, color=PALETTE[6])  # fmt: skip
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel(f"x, {unit}")
        ax.set_ylabel(f"y, {unit}")
        mu0, mu1 = np.rad2deg(best.transmission)
        ax.set_title(
            f"path generation, {result.timing} timing: error {best.error:.4g} {unit}²"
            f" ({'sum of squares' if result.objective == 'squares' else 'largest square'}),\n"
            f"transmission angle {mu0:.1f}-{mu1:.1f} deg, {best.branch} branch"
        )
        ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0))
    return fig


def pareto_figure(front, published=None, title="error versus smallest transmission angle"):
    """The error-versus-transmission-angle front: ``front`` is a list of ``(mu_min rad,
    error)``; ``published`` an optional ``(mu_min rad, error, label)`` to mark."""
    import matplotlib.pyplot as plt

    from ..plotting import PALETTE, style

    mu = np.rad2deg([p[0] for p in front])
    err = np.array([p[1] for p in front])
    with style():
        fig, ax = plt.subplots(figsize=(6.0, 4.0))
        allerr = err if published is None else np.append(err, published[1])
        if np.nanmax(allerr) > 5 * np.nanmin(allerr):
            ax.set_yscale("log")
        ax.plot(mu, err, "o-", color=PALETTE[1], ms=4, label="this library (front)")
        if published is not None:
            ax.plot([np.rad2deg(published[0])], [published[1]], "s", color=PALETTE[6],
                        ms=7, label=published[2])  # fmt: skip
        ax.set_xlabel("smallest transmission angle over the turn, deg")
        ax.set_ylabel("error (sum of squared distances)")
        ax.set_title(title)
        ax.legend(loc="center right")
    return fig
