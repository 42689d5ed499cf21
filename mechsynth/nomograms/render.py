"""Drawing a nomogram on a sheet of paper at 1:1 (matplotlib, no TeX).

The figure is the paper: its size in inches is the sheet's, one axes covers it with millimetres
as data units, so a millimetre of the chart is a millimetre of the print at 100 %. Scales are
drawn with ticks and labels from :mod:`mechsynth.nomograms.ticks` on the side away from the other
scales, the scale's name and unit beyond its upper end, turning axes as plain lines, an example
isopleth dashed, and in the margin below: the relation, how to read the chart, the example, the
measured reading accuracy, the paper and the scale. A last pass removes any tick label that would
touch another text (finest steps first), so the sheet passes the house's ``layout_problems``.
"""

from __future__ import annotations

import textwrap
from pathlib import Path

import numpy as np

from ..errors import MechanismError
from ..plotting import PALETTE
from .scales import shown_unit
from .ticks import number_text, ticks

__all__ = ["draw", "save"]

TICK_LABEL = "mechsynth-nomogram-tick"
SCALE_TITLE = "mechsynth-nomogram-scale-title"
MM = 1.0 / 25.4  # inch per mm
FORMATS = (".png", ".pdf", ".svg")


def _side(nm, name, pts):
    """+1 or -1: the side of the scale (its tangent turned left, or right) for the ticks and
    labels -- the one where fewer points of the other scales lie within a label's reach
    (14 mm), away from the other scales on a tie."""
    others = [ps.position(ps.scale.sample(81)) for k, ps in nm.scales.items() if k != name]
    others += [_grid_points(g) for g in nm.grids.values()]
    if not others:
        return 1.0
    P = np.concatenate(others)
    q = pts[::5]
    t = np.gradient(pts, axis=0)[::5]
    t /= np.maximum(np.hypot(*t.T), 1e-12)[:, None]
    n = np.stack([-t[:, 1], t[:, 0]], axis=1)
    rel = P[None, :, :] - q[:, None, :]
    across = (rel * n[:, None, :]).sum(-1)
    along = np.abs((rel * t[:, None, :]).sum(-1))
    near = along < 3.0
    left = int(((across > 0) & (across < 14.0) & near).sum())
    right = int(((across < 0) & (across > -14.0) & near).sum())
    if left != right:
        return 1.0 if left < right else -1.0
    mid = pts[len(pts) // 2]
    away = mid - P.mean(axis=0)
    return 1.0 if float(n[len(n) // 2] @ away) >= 0 else -1.0


def _normals(points_before, points_after, sign):
    t = points_after - points_before
    t /= np.maximum(np.hypot(*t.T), 1e-12)[:, None]
    return sign * np.stack([-t[:, 1], t[:, 0]], axis=1)


def _anchor(n):
    """Text alignment for a label placed in the direction ``n`` from its tick."""
    ha = "left" if n[0] > 0.38 else ("right" if n[0] < -0.38 else "center")
    va = "bottom" if n[1] > 0.38 else ("top" if n[1] < -0.38 else "center")
    return ha, va


def _draw_scale(ax, nm, name, ink):
    ps = nm.scales[name]
    s = ps.scale
    curve = ps.position(s.sample(401))
    if s.turning:
        ax.plot(*curve.T, color="0.45", lw=0.7, solid_capstyle="butt")
        return
    ax.plot(*curve.T, color=ink, lw=0.9, solid_capstyle="butt")
    factor, _ = shown_unit(s)
    lo, hi = s.domain
    tk = ticks(ps.position, lo, hi, factor)
    sign = _side(nm, name, curve)
    span = hi - lo

    def marks(values, length, width):
        if len(values) == 0:
            return None, None
        v = np.clip(np.asarray(values) * factor, lo, hi)
        d = 1e-4 * span
        p = ps.position(v)
        n = _normals(ps.position(np.clip(v - d, lo, hi)), ps.position(np.clip(v + d, lo, hi)),
                     sign)
        seg = np.stack([p, p + length * n], axis=1)
        from matplotlib.collections import LineCollection

        ax.add_collection(LineCollection(seg, colors=ink, linewidths=width))
        return p, n

    marks(tk.minor, 1.2, 0.4)
    marks(tk.major, 2.2, 0.5)
    p, n = marks(tk.labelled, 2.8, 0.6)
    if p is not None:
        for (x, y), nn, text in zip(p, n, tk.texts, strict=True):
            ha, va = _anchor(nn)
            t = ax.text(x + 3.6 * nn[0], y + 3.6 * nn[1], text, fontsize=7, ha=ha, va=va,
                        color=ink)
            t.set_gid(TICK_LABEL)
    # the scale's name and unit beyond its upper (or right) end
    ends = ps.position(np.array([lo, hi]))
    top = 1 if (ends[1, 1], ends[1, 0]) > (ends[0, 1], ends[0, 0]) else 0
    near = ps.position(np.array([lo + 0.02 * span, hi - 0.02 * span]))[top]
    direction = ends[top] - near
    direction /= max(np.hypot(*direction), 1e-12)
    at = ends[top] + 5.0 * direction
    ha, va = _anchor(direction)
    t = ax.text(*at, s.label(), fontsize=8.5, fontweight="bold", ha=ha, va=va, color=ink)
    t.set_gid(SCALE_TITLE)


def _stagger_titles(fig, ax):
    """Keep every scale title on the sheet, and lift one that overlaps another (scales whose
    ends are close) above it."""
    from matplotlib.text import Text

    r = fig.canvas.get_renderer()  # text extents need the renderer, not a drawing
    titles = [t for t in fig.findobj(Text) if t.get_gid() == SCALE_TITLE]
    placed = []
    px = fig.dpi / 25.4  # pixels per mm (the axes is the sheet at 1:1)
    fb = fig.bbox
    for t in titles:
        bb = t.get_window_extent(r)
        shift = max(0.0, fb.x0 + 3 * px - bb.x0) - max(0.0, bb.x1 - (fb.x1 - 3 * px))
        if shift:  # keep the title on the sheet
            x, y = t.get_position()
            t.set_position((x + shift / px, y))
        for _ in range(6):
            bb = t.get_window_extent(r).padded(2.0)
            if not any(bb.overlaps(o) for o in placed):
                break
            x, y = t.get_position()
            t.set_position((x, y + 4.5))
        placed.append(t.get_window_extent(r))


def _grid_points(g, n=21):
    a, b = (ax.sample(n) for ax in g.grid.axes)
    return g.position(a[:, None], b[None, :]).reshape(-1, 2)


def _draw_grid(ax, nm, g, ink):
    """A grid scale: for each of its variables, the curves on which it is constant at the
    ticks chosen along the grid's edge, labelled at their upper ends, its title beyond."""
    for i, axis in enumerate(g.grid.axes):
        other = g.grid.axes[1 - i]
        olo, ohi = other.domain

        def at(v, o, i=i):
            return g.position(v, o) if i == 0 else g.position(o, v)

        factor, _ = shown_unit(axis)
        lo, hi = axis.domain
        tk = ticks(lambda v, olo=olo, at=at: at(v, olo), lo, hi, factor)
        span = other.sample(101)
        lines = list(tk.labelled) + list(tk.major)
        labelled = set(tk.labelled.tolist())
        for v in lines:  # labelled values in ink, the others light
            curve = at(np.full(101, v * factor), span)
            main = v in labelled
            ax.plot(*curve.T, color=ink if main else "0.72", lw=0.55 if main else 0.3,
                    solid_capstyle="butt")
        ends = []
        for v, text in zip(tk.labelled, tk.texts, strict=True):
            end, near = at(v * factor, ohi), at(v * factor, ohi - 0.02 * (ohi - olo))
            d = (end - near) / max(np.hypot(*(end - near)), 1e-12)
            ha, va = _anchor(d)
            t = ax.text(*(end + 1.5 * d), text, fontsize=7, ha=ha, va=va, color=ink)
            t.set_gid(TICK_LABEL)
            ends.append((end, d))
        if ends:
            end, d = max(ends, key=lambda e: (e[0][1], e[0][0]))
            if abs(d[0]) > abs(d[1]):  # labels beside the curves' ends: the title above them
                at, ha, va = end + np.array([0.0, 4.5]), "right" if d[0] > 0 else "left", "bottom"
            else:  # labels above (below) the ends: the title beyond them
                at, (ha, va) = end + 9.0 * d, _anchor(d)
            t = ax.text(*at, axis.label(), fontsize=8.5, fontweight="bold", ha=ha, va=va,
                        color=ink)
            t.set_gid(SCALE_TITLE)


def _prune_tick_labels(fig, pad=0.3):
    """Remove tick labels that touch another text or leave the sheet (finest first)."""
    from matplotlib.text import Text

    r = fig.canvas.get_renderer()
    texts = [t for t in fig.findobj(Text) if t.get_visible() and t.get_text().strip()]
    fixed = [t.get_window_extent(r) for t in texts if t.get_gid() != TICK_LABEL]
    labels = [t for t in texts if t.get_gid() == TICK_LABEL]
    fb = fig.bbox
    kept, removed = [], 0
    for t in labels:  # drawn coarse steps first: the list order of ticks() keeps values sorted
        bb = t.get_window_extent(r).expanded(1.0, 1.0)
        bb = bb.padded(pad)
        inside = fb.x0 <= bb.x0 and bb.x1 <= fb.x1 and fb.y0 <= bb.y0 and bb.y1 <= fb.y1
        if inside and not any(bb.overlaps(o) for o in fixed + kept):
            kept.append(bb)
        else:
            t.remove()
            removed += 1
    return removed


def _margin_text(nm, example_values, accuracy):
    lines = []
    if nm.relation:
        lines.append(f"Relation: {nm.relation}.")
    compound = any(ps.scale.turning for ps in nm.scales.values())
    how = (
        "How to read: lay a straightedge across the known values; read the unknown where it "
        "crosses its scale."
    )
    if compound:
        how += (" Compound chart: mark where the first line crosses the unlabelled turning axis "
                "and pivot the straightedge there for the next block.")
    lines.append(how)
    if example_values is not None:
        known = ", ".join(
            f"{nm.variable(k).title} = {_fmt(nm, k, example_values[k])}" for k in nm.inputs
        )
        out = nm.output
        text = f"Example (dashed): {known} -> {nm.variable(out).title} = " \
               f"{_fmt(nm, out, example_values[out])}"
        if nm.model is not None:
            truth = float(nm.model(**{k: example_values[k] for k in nm.inputs}))
            text += f" (model: {_fmt(nm, out, truth)})"
        for k, m in nm.models.items():
            if k != out:
                truth = float(m(**{i: example_values[i] for i in nm.inputs}))
                text += (f", {nm.variable(k).title} = {_fmt(nm, k, example_values[k])} "
                         f"(model: {_fmt(nm, k, truth)})")
        lines.append(text + ".")
    for a in accuracy or ():
        a = a.text()
        lines.append(a[0].upper() + a[1:] + ".")
    lines += list(nm.notes)
    lines.append(
        f"Paper {nm.paper.size_text}, scale 1:1: print at 100 % (no 'fit to page'); "
        "millimetres on the chart are millimetres on paper. Drawn by mechsynth."
    )
    return "\n".join(textwrap.fill(line, 118) for line in lines)


def _fmt(nm, name, value):
    factor, unit = shown_unit(nm.variable(name))
    return number_text(value / factor) + (f" {unit}" if unit else "")


def draw(nm, example=None, accuracy: bool = True):
    """The nomogram ``nm`` as a Figure of its paper's size at 1:1 (millimetre data units)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from ..plotting import style

    W, H = nm.paper.width, nm.paper.height
    with style():
        fig = Figure(figsize=(W * MM, H * MM), layout="none")
        FigureCanvasAgg(fig)
        ax = fig.add_axes((0, 0, 1, 1))
        ax.set_xlim(0, W)
        ax.set_ylim(0, H)
        ax.set_axis_off()
        ink = PALETTE[0]
        for name in nm.scales:
            _draw_scale(ax, nm, name, ink)
        for g in nm.grids.values():
            _draw_grid(ax, nm, g, ink)
        values = None
        example = dict(nm.example if example is None else example)
        if example:
            values = {k: float(v) for k, v in nm.isopleth(**example).items()}
            if any(not np.isfinite(v) for v in values.values()):
                raise MechanismError(
                    f"the example isopleth {example} misses a scale: {values}"
                )
            for b in nm.blocks:
                pts = np.array([nm.point(k, values) for k in b])
                order = np.argsort(pts[:, 0] + 1e-6 * pts[:, 1])
                pts = pts[order]
                ax.plot(*pts[[0, -1]].T, ls=(0, (5, 2.5)), color=PALETTE[5], lw=0.9)
                ax.plot(*pts.T, "o", ms=3.2, mfc="white", mec=PALETTE[5], mew=0.9,
                        clip_on=False)
        ax.text(W / 2, H - 11, nm.title, fontsize=12, fontweight="bold", ha="center",
                va="center")
        acc = list(nm.accuracies.values()) if accuracy else None
        ax.text(14, 8, _margin_text(nm, values, acc), fontsize=6.8, ha="left", va="bottom",
                linespacing=1.35, wrap=False)
        _stagger_titles(fig, ax)
        _prune_tick_labels(fig)
    return fig


def save(nm, path, example=None, dpi: int = 200) -> Path:
    """Write ``nm`` to ``path``: PDF, SVG or PNG by its suffix, atomically."""
    from ..fileio import save_figure

    path = Path(path)
    if path.suffix.lower() not in FORMATS:
        raise MechanismError(
            f"nomogram file must end in {', '.join(FORMATS)}, got {path.name!r}"
        )
    fig = draw(nm, example=example)
    save_figure(fig, path, dpi=dpi)
    return path
