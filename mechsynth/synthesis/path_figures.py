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
    at = best.trace(best.angles) / f
    m = len(t)
    show = min(m, 4) if show is None else max(0, min(int(show), m))
    pick = np.unique(np.round(np.linspace(0, m - 1, show)).astype(int)) if show else []
    sk = best.linkage.sketch(best.angles)
    pts = {k: (np.broadcast_to(x, (m,)) / f, np.broadcast_to(y, (m,)) / f)
           for k, (x, y) in sk.points.items()}  # fmt: skip
    with style():
        fig, ax = plt.subplots(figsize=(8.0, 5.2))
        for j, i in enumerate(pick):
            alpha = 1.0 if j == 0 else 0.35
            for k, bar in enumerate(sk.bars):
                xy = np.array([[pts[p][0][i], pts[p][1][i]] for p in bar.points])
                if bar.closed and len(xy) > 2:
                    ax.fill(xy[:, 0], xy[:, 1], color=PALETTE[4], alpha=0.12 * alpha)
                    xy = np.vstack([xy, xy[:1]])
                ax.plot(xy[:, 0], xy[:, 1], "-", marker="o", ms=3.0, color=PALETTE[4], lw=1.2,
                        alpha=alpha, label="linkage at the targets" if j == 0 and k == 0
                        else None)  # fmt: skip
        ax.plot(curve[:, 0], curve[:, 1], "-", color=PALETTE[1], label="coupler curve")
        ax.plot(at[:, 0], at[:, 1], "o", ms=3.5, color=PALETTE[1],
                label="coupler point at the targets")  # fmt: skip
        ax.plot(t[:, 0], t[:, 1], "x", ms=6, mew=1.5, color=PALETTE[6], label="targets")
        for k in sk.ground:
            g = (pts[k][0][0], pts[k][1][0])
            ax.plot(*g, "^", ms=8, color=PALETTE[0])
            ax.annotate(k, g, textcoords="offset points", xytext=(5, -11), fontsize=8)
        ax.set_aspect("equal", adjustable="datalim")
        fig.canvas.draw()  # the final limits, to keep the labels of crowded targets apart
        xy = ax.transData.transform(t)
        kept: list[np.ndarray] = []
        for i, (x, y) in enumerate(t):
            if all(np.hypot(*(xy[i] - q)) > 28.0 for q in kept):  # display pixels
                kept.append(xy[i])
                ax.annotate(str(i + 1), (x, y), textcoords="offset points", xytext=(4, 4),
                            fontsize=7, color=PALETTE[6])  # fmt: skip
        ax.set_xlabel(f"x, {unit}")
        ax.set_ylabel(f"y, {unit}")
        mu0, mu1 = np.rad2deg(best.transmission)
        kind = f"{best.branch} branch" if best.branch else best.linkage.name
        if result.timing == "shape":
            what = f"shape error {best.error:.3g}, points {best.sum_squares / f**2:.4g} {unit}²"
        else:
            kind_ = "sum of squares" if result.objective == "squares" else "largest square"
            what = f"error {best.error / f**2:.4g} {unit}² ({kind_})"
        ax.set_title(
            f"path generation, {result.timing} timing: {what},\n"
            f"transmission angle {mu0:.1f}-{mu1:.1f} deg, {kind}"
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


def bound_figure(bounds, titles):
    """One panel per :class:`~mechsynth.synthesis.path_bound.PathBound` of ``bounds``: its
    proved lower bound and the best error against the boxes evaluated, the gap between them
    shaded, the end's numbers in the title."""
    import matplotlib.pyplot as plt

    from ..plotting import PALETTE, style

    with style():
        fig, axes = plt.subplots(1, len(bounds), figsize=(5.2 * len(bounds), 4.0),
                                 squeeze=False)  # fmt: skip
        for ax, b, title in zip(axes[0], bounds, titles):
            h = np.array(b.history, dtype=float)
            boxes, low = h[:, 0], h[:, 1]
            best = np.where(np.isfinite(h[:, 2]), np.minimum(h[:, 2], b.best), np.nan)
            ax.fill_between(boxes, low, best, step="post", color=PALETTE[1], alpha=0.15,
                            lw=0, label="gap")  # fmt: skip
            ax.step(boxes, best, where="post", color=PALETTE[6], lw=1.4, ls="--",
                    label="best design")  # fmt: skip
            ax.step(boxes, low, where="post", color=PALETTE[1], lw=1.8,
                    label="proved lower bound")  # fmt: skip
            ax.set_xscale("log")
            top = np.nanmax(np.append(best, b.best)) if np.isfinite(b.best) else np.nanmax(low)
            ax.set_ylim(0.0, 1.15 * float(top))
            ax.set_xlabel("boxes evaluated")
            ax.set_ylabel("error (sum of squared distances), m²")
            state = "closed" if b.closed else (f"gap {100 * b.relative_gap:.3g} %")
            ax.set_title(f"{title}\n{b.lower:.5g} ≤ optimum ≤ {b.best:.5g} m² ({state}, "
                         f"{b.seconds:.1f} s)", fontsize=9)  # fmt: skip
            ax.legend(loc="center left", fontsize=8)
    return fig
