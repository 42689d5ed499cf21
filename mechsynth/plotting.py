"""The house style of every figure mechsynth draws, and the checks that keep it.

* :data:`PALETTE` — Okabe and Ito's colour-blind-safe colours, the default colour cycle inside
  :func:`style`; :data:`LINESTYLES` to tell curves apart without colour.
* :func:`style` — a context manager with the house rc settings (font sizes, grid, readable
  ticks, constrained layout).
* :func:`force_unit`, :func:`torque_unit` — N or kN (N m or kN m) by the size of the values
  when the display force unit is the newton, else the display unit.
* :func:`crank_axis` — a crank-angle axis over one turn with ticks every 45 or 60 deg.
* :func:`title` — "what, design, speed" titles.
* :func:`equal_axes` — equal x and y scales on axes where directions matter (mechanism
  drawings, hodographs, force polygons), marked so that :func:`layout_problems` checks them.
* :func:`layout_problems` — overlapping text, text outside the figure, markers clipped by their
  axes, curves hidden under others, reference lines on the frame, series told apart by colour
  only, unequal scales on directional axes: what the figure-regression test asserts away.
* :func:`save` — write a figure (PNG) and close it.
"""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path

import numpy as np

from . import display
from .fileio import save_figure

__all__ = [
    "PALETTE",
    "LINESTYLES",
    "style",
    "force_unit",
    "torque_unit",
    "crank_axis",
    "title",
    "speed_text",
    "layout_problems",
    "equal_axes",
    "save",
    "label_contours",
    "prune_labels",
    "readable",
]

#: Okabe & Ito (2008): black, orange, sky blue, bluish green, blue, vermillion, reddish purple,
#: yellow -- distinguishable with every common colour-vision deficiency.
PALETTE = (
    "#000000",
    "#E69F00",
    "#56B4E9",
    "#009E73",
    "#0072B2",
    "#D55E00",
    "#CC79A7",
    "#F0E442",
)
LINESTYLES = ("-", "--", "-.", ":", (0, (5, 1, 1, 1)), (0, (3, 1, 1, 1, 1, 1)))

_RC = {
    "axes.prop_cycle": None,  # set in style()
    "axes.grid": True,
    "grid.alpha": 0.35,
    "grid.linestyle": ":",
    "axes.titlesize": 10,
    "axes.labelsize": 9,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "legend.fontsize": 8,
    "legend.framealpha": 0.9,
    "figure.titlesize": 11,
    "lines.linewidth": 1.5,
    "figure.constrained_layout.use": True,
    "savefig.dpi": 120,
}


@contextmanager
def style():
    """The house rc settings (colour-blind-safe cycle, sizes, grid, constrained layout)."""
    import matplotlib as mpl
    from cycler import cycler

    rc = dict(_RC)
    rc["axes.prop_cycle"] = cycler(color=PALETTE[1:7] + PALETTE[:1])
    with mpl.rc_context(rc):
        yield


def _thousands(values, si_unit: str) -> tuple[float, str]:
    """(divisor, unit) of the display unit of ``si_unit``, or of a thousand of it when the
    largest displayed magnitude reaches 10,000 (tick labels keep at most four digits): kN,
    kN m, klb; torques in in-lb as "1000 in-lb", the oilfield way."""
    du = display.current()
    factor, unit = du.factor(si_unit), du.unit(si_unit)
    with np.errstate(invalid="ignore"):
        peak = np.nanmax(np.abs(np.asarray(values, dtype=float))) / factor
    if not peak >= 1e4:
        return factor, unit
    return factor * 1e3, ("1000 " + unit if "-" in unit else "k" + unit)


def force_unit(values) -> tuple[float, str]:
    """(divisor, unit) for forces in newtons: the display unit, or a thousand of it (kN, klb)
    when the largest magnitude reaches 10,000 of it."""
    return _thousands(values, "N")


def torque_unit(values) -> tuple[float, str]:
    """(divisor, unit) for torques in N m: the display unit, or a thousand of it (kN m,
    1000 in-lb) when the largest magnitude reaches 10,000 of it."""
    return _thousands(values, "N m")


def crank_axis(ax, label="crank angle", axis="x", start=0.0, span=360.0) -> None:
    """Label ``ax``'s axis as a crank angle in deg over ``[start, start + span]`` with ticks every
    45 deg (60 deg for spans over 360)."""
    step = 45.0 if span <= 360.0 else 60.0
    ticks = np.arange(start, start + span + 1e-9, step)
    if axis == "x":
        ax.set_xlim(start, start + span)
        ax.set_xticks(ticks)
        ax.set_xlabel(f"{label}, deg")
    else:
        ax.set_ylim(start, start + span)
        ax.set_yticks(ticks)
        ax.set_ylabel(f"{label}, deg")


def speed_text(speed) -> str:
    """A crank speed (rad/s) as ``"600 rpm"``; ``"analogs"`` for None."""
    if speed is None:
        return "analogs (per rad of crank angle)"
    return f"{abs(float(speed)) * 30.0 / np.pi:.4g} rpm"


def title(what: str, design: str = "", speed=None, show_speed: bool = True) -> str:
    """``"what — design, speed"`` on two lines when long."""
    parts = [p for p in (design, speed_text(speed) if show_speed else "") if p]
    tail = ", ".join(parts)
    if not tail:
        return what
    sep = "\n" if len(what) + len(tail) > 70 else " — "
    return f"{what}{sep}{tail}"


def save(fig, path, dpi: int = 120) -> Path:
    """Write ``fig`` to ``path`` and close it; returns the path."""
    import matplotlib.pyplot as plt

    path = Path(path)
    save_figure(fig, path, dpi=dpi)
    plt.close(fig)
    return path


def readable(measure: str, output: str = "slider") -> str:
    """A measure's code name as words: ``"peak_acceleration(slider)"`` -> ``"peak acceleration
    of the slider"``; ``output`` names what the mechanism calls its slider (``"polished rod"``
    for a pumping unit)."""
    import re

    m = re.fullmatch(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*(?:\((.*)\))?\s*", measure)
    if not m:
        return measure
    words = m.group(1).replace("_", " ")
    args = [a.strip() for a in (m.group(2) or "").split(",") if a.strip()]
    if not args:
        return words
    target = args[0]
    who = f"the {output}" if target == "slider" else target
    rest = f" ({', '.join(args[1:])})" if len(args) > 1 else ""
    return f"{words} of {who}{rest}"


CONTOUR_LABEL = "mechsynth-contour-label"


def label_contours(ax, cs, fmt="%.3g", fontsize: float = 7.0, every: int = 1):
    """Label the contour set ``cs`` on a light box (the line shows no gap, so a label that
    :func:`prune_labels` removes leaves no hole); ``every`` labels every n-th level."""
    levels = cs.levels[::every] if every > 1 else cs.levels
    texts = ax.clabel(cs, levels, fmt=fmt, fontsize=fontsize, inline=False)
    for t in texts:
        t.set_bbox(dict(boxstyle="round,pad=0.12", fc="white", ec="none", alpha=0.8))
        t.set_gid(CONTOUR_LABEL)
    return texts


def prune_labels(fig, pad: float = 1.0) -> int:
    """Remove the contour labels (:func:`label_contours`) that overlap another text, another
    kept label, a legend, or stick out of their axes; returns how many were removed. Call it
    when the figure is complete (it lays the figure out)."""
    from matplotlib.legend import Legend

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    labels, others = [], []
    for t, bb in _texts(fig):
        (labels if t.get_gid() == CONTOUR_LABEL else others).append((t, bb))
    blocks = [bb for _, bb in others] + [
        leg.get_window_extent(renderer) for leg in fig.findobj(Legend)
    ]
    kept, removed = [], 0
    for t, bb in labels:
        box = t.get_bbox_patch().get_window_extent(renderer) if t.get_bbox_patch() else bb
        ab = t.axes.bbox if t.axes is not None else fig.bbox
        inside = (
            ab.x0 + pad <= box.x0
            and box.x1 <= ab.x1 - pad
            and ab.y0 + pad <= box.y0
            and (box.y1 <= ab.y1 - pad)
        )
        clash = any(box.overlaps(o) for o in blocks) or any(box.overlaps(k) for k in kept)
        if inside and not clash:
            kept.append(box)
        else:
            t.remove()
            removed += 1
    return removed


#: the attribute :func:`equal_axes` sets on axes whose directions matter
DIRECTIONAL = "mechsynth_directional"


def equal_axes(ax, adjustable: str = "box"):
    """Give ``ax`` equal x and y scales (one metre, newton or m/s is as long across as up) and
    mark it directional, so that :func:`layout_problems` reports the axes if a later call
    distorts them; for mechanism drawings, hodographs and force polygons. Returns ``ax``."""
    ax.set_aspect("equal", adjustable=adjustable)
    setattr(ax, DIRECTIONAL, True)
    return ax


# ------------------------------------------------------------------------------ checks
def _texts(fig):
    """Visible, non-empty text artists of the figure with their window extents."""
    from matplotlib.text import Text

    renderer = fig.canvas.get_renderer()
    # tick labels exist for ticks outside the view too; only the drawn ones count
    all_ticks, drawn = set(), set()
    for ax in fig.axes:
        for axis in ax._axis_map.values():
            for tick in axis.majorTicks + axis.minorTicks:
                all_ticks.update((id(tick.label1), id(tick.label2)))
            if not (ax.axison and axis.get_visible() and ax.get_visible()):
                continue
            for tick in axis._update_ticks():
                drawn.update((id(tick.label1), id(tick.label2)))
    out = []
    for t in fig.findobj(Text):
        if not t.get_visible() or not t.get_text().strip():
            continue
        if id(t) in all_ticks and id(t) not in drawn:
            continue
        if t.axes is not None and t.get_clip_on() and t.get_clip_box() is not None:
            # contour labels and annotations: skip those clipped away by their axes
            bb = t.get_window_extent(renderer)
            if not bb.overlaps(t.axes.bbox):
                continue
        out.append((t, t.get_window_extent(renderer)))
    return out


def _line_points(line) -> np.ndarray:
    """A visible line's finite points in display (pixel) coordinates."""
    xy = line.get_xydata()
    if not line.get_visible() or xy.size == 0:
        return np.zeros((0, 2))
    pts = line.get_transform().transform(xy)
    return pts[np.all(np.isfinite(pts), axis=1)]


def _draw_order(ax):
    """The visible lines of ``ax`` in the order they are drawn (by z-order, then as added)."""
    from matplotlib.lines import Line2D

    lines = [a for a in ax.get_children() if isinstance(a, Line2D) and a.get_visible()]
    return sorted(lines, key=lambda ln: ln.get_zorder())  # sorted() is stable


def _has_stroke(line) -> bool:
    return line.get_linestyle() not in ("None", " ", "") and line.get_linewidth() > 0


def _has_marker(line) -> bool:
    return line.get_marker() not in (None, "", "None", " ")


def _densify(pts: np.ndarray, step: float = 2.0, most: int = 4000) -> np.ndarray:
    """The polyline ``pts`` (pixels) with points at most ``step`` pixels apart (at most
    ``most`` points), so that a covered vertex list means a covered stroke."""
    if len(pts) < 2:
        return pts
    seg = np.hypot(*np.diff(pts, axis=0).T)
    total = seg.sum()
    if total == 0.0:
        return pts[:1]
    n = int(min(most, max(len(pts), np.ceil(total / step) + 1)))
    s = np.concatenate([[0.0], np.cumsum(seg)])
    t = np.linspace(0.0, total, n)
    return np.column_stack([np.interp(t, s, pts[:, 0]), np.interp(t, s, pts[:, 1])])


def _near(p: np.ndarray, q: np.ndarray, reach: float) -> np.ndarray:
    """Whether each point ``p`` (n, 2) lies within ``reach`` pixels of the polyline ``q``
    (m, 2). Points go in chunks of 128, each against only the segments whose box comes within
    ``reach`` of the chunk's box (a curve's neighbouring points meet few segments)."""
    out = np.zeros(len(p), dtype=bool)
    if len(q) == 1:
        return np.hypot(*(p - q[0]).T) <= reach
    a, d = q[:-1], np.diff(q, axis=0)
    lo, hi = np.minimum(a, q[1:]) - reach, np.maximum(a, q[1:]) + reach
    for start in range(0, len(p), 128):
        pc = p[start : start + 128]
        seg = np.flatnonzero(np.all((lo <= pc.max(axis=0)) & (hi >= pc.min(axis=0)), axis=1))
        if seg.size == 0:
            continue
        ds = d[seg]
        dd = np.einsum("ij,ij->i", ds, ds)
        rel = pc[:, None, :] - a[seg][None]
        t = np.clip(np.einsum("nmj,mj->nm", rel, ds) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
        r = rel - t[..., None] * ds[None]
        out[start : start + 128] = np.einsum("nmj,nmj->nm", r, r).min(axis=1) <= reach * reach
    return out


def _hidden_curves(ax, px: float, tol: float) -> list[str]:
    """Named lines (series) whose drawn stroke lies wholly under opaque solid lines drawn after
    them and at least as wide (a line with markers only when a later line has markers too)."""
    order = _draw_order(ax)
    problems = []
    for i, line in enumerate(order):
        if line.get_label().startswith("_"):
            continue  # series have names; unnamed lines are drawings' parts or guides
        later = [
            ln
            for ln in order[i + 1 :]
            if _has_stroke(ln) and ln.get_linestyle() == "-" and (ln.get_alpha() or 1.0) > 0.9
        ]
        if not later or not _has_stroke(line):
            continue
        if _has_marker(line) and not any(_has_marker(ln) for ln in later):
            continue  # the markers stay in sight
        pts = _line_points(line)
        b = ax.bbox
        shown = (b.x0 <= pts[:, 0]) & (pts[:, 0] <= b.x1) & (b.y0 <= pts[:, 1])
        shown &= pts[:, 1] <= b.y1
        if not shown.any():
            continue  # all out of view: nothing to hide
        pts = _densify(pts)
        own = line.get_linewidth() * px / 2.0
        covers = []  # (the other line's pixels, how near a point must be to lie under it)
        for other in later:
            reach = other.get_linewidth() * px / 2.0 - own + tol  # this stroke's whole width
            q = _line_points(other)  # inside the other's
            if reach >= 0.0 and len(q):  # (a thin line over a wide one leaves it in sight)
                covers.append((q, reach))
        # a sample first: hidden needs every point covered, and most curves part somewhere
        sample = pts[np.unique(np.linspace(0, len(pts) - 1, min(len(pts), 24)).astype(int))]
        hits = [_near(sample, q, reach) for q, reach in covers]
        if not np.logical_or.reduce(hits, axis=0).all():
            continue
        uncovered = np.ones(len(pts), dtype=bool)
        for k in np.argsort([-h.sum() for h in hits], kind="stable"):  # likeliest cover first
            q, reach = covers[k]
            todo = np.flatnonzero(uncovered)
            uncovered[todo] = ~_near(pts[todo], q, reach)
            if not uncovered.any():
                break
        if not uncovered.any():
            problems.append(
                f"{line.get_label()!r} in {ax.get_title()!r} is hidden under later curves"
            )
    return problems


def _reference_lines_on_frame(ax, tol: float) -> list[str]:
    """Horizontal or vertical lines (axhline, axvline, constant series) drawn on the axes'
    frame, where the frame hides them."""
    b = ax.bbox
    problems = []
    for line in _draw_order(ax):
        if not _has_stroke(line):
            continue
        pts = _line_points(line)
        if len(pts) < 2:
            continue
        half = line.get_linewidth() * ax.figure.dpi / 72.0 / 2.0
        # (name, the constant coordinate, the other one, the frame's edges, the view's span)
        for where, const, other, edges, span in (
            ("horizontal", pts[:, 1], pts[:, 0], (b.y0, b.y1), (b.x0, b.x1)),
            ("vertical", pts[:, 0], pts[:, 1], (b.x0, b.x1), (b.y0, b.y1)),
        ):
            shown = np.ptp(np.clip(other, *span))
            if np.ptp(const) > tol or shown < 0.1 * (span[1] - span[0]):
                continue
            pos = const[0]
            if not edges[0] - half - tol <= pos <= edges[1] + half + tol:
                continue  # out of view
            if min(abs(pos - edges[0]), abs(pos - edges[1])) <= half + tol + 1.0:
                label = line.get_label()
                name = label if not label.startswith("_") else "a reference line"
                problems.append(
                    f"{where} line {name!r} of {ax.get_title()!r} lies on the axes' frame"
                )
    return problems


def _look(line) -> tuple:
    """What tells a legend's line apart, colour and width aside: dash pattern, marker and
    whether the marker is hollow."""
    from matplotlib.colors import to_rgba

    dash = line._unscaled_dash_pattern if _has_stroke(line) else None
    dash = None if dash is None else (dash[0], tuple(dash[1]) if dash[1] else None)
    marker = line.get_marker() if _has_marker(line) else None
    hollow = marker is not None and to_rgba(line.get_markerfacecolor())[3] == 0.0
    return (dash, marker, hollow)


def _colour_only(leg, where: str, wider: float = 1.6) -> list[str]:
    """Entries of the legend ``leg`` whose lines differ from each other by colour alone: the
    same dash pattern and marker, and line widths less than ``wider`` times apart."""
    from matplotlib.colors import to_rgba
    from matplotlib.lines import Line2D

    handles = getattr(leg, "legend_handles", None) or leg.legendHandles
    entries = [
        (h, t.get_text())
        for h, t in zip(handles, leg.get_texts())
        if isinstance(h, Line2D) and (_has_stroke(h) or _has_marker(h))
    ]
    looks = [_look(h) for h, _ in entries]
    widths = [max(h.get_linewidth(), 1e-3) if _has_stroke(h) else 1.0 for h, _ in entries]
    group = list(range(len(entries)))  # alike entries joined into groups (union-find)

    def root(k):
        while group[k] != k:
            k = group[k]
        return k

    for a in range(len(entries)):
        for b in range(a + 1, len(entries)):
            ratio = max(widths[a], widths[b]) / min(widths[a], widths[b])
            if looks[a] == looks[b] and ratio < wider:
                group[root(b)] = root(a)
    members: dict[int, list] = {}
    for k, entry in enumerate(entries):
        members.setdefault(root(k), []).append(entry)
    problems = []
    for alike in members.values():
        if len(alike) < 2:
            continue
        colours = {to_rgba(h.get_color()) for h, _ in alike}
        names = ", ".join(repr(t) for _, t in alike)
        how = "colour only" if len(colours) == len(alike) else "nothing (same colour too)"
        problems.append(f"series {names} of {where} are told apart by {how}")
    return problems


def _unequal_scales(ax, rtol: float = 0.01) -> str | None:
    """A directional axes (:func:`equal_axes`) whose x and y scales differ, as drawn."""
    if not getattr(ax, DIRECTIONAL, False) or ax.name != "rectilinear":
        return None
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    b = ax.bbox
    if min(b.width, b.height) <= 0:
        return None
    sx, sy = abs(x1 - x0) / b.width, abs(y1 - y0) / b.height
    if abs(sx - sy) <= rtol * max(sx, sy):
        return None
    return (
        f"axes {ax.get_title()!r} shows directions but its x and y scales differ "
        f"({sx / sy:.3g}:1): use plotting.equal_axes"
    )


def layout_problems(fig, tol: float = 0.5) -> list[str]:
    """What a reader would see as defects of a drawn figure, one line each (empty if none):

    * two visible texts (titles, labels, tick labels, contour labels, legends' texts,
      annotations) that overlap by more than ``tol`` pixels in both directions, except the texts
      of one legend against each other;
    * text that sticks out of the figure;
    * a legend that covers plotted data points of its axes (lines, markers);
    * a marker drawn so close to its axes' edge that the axes clip part of it;
    * an axis labelled with a raw parameter name (``N_guide_angle, deg``) instead of words;
    * tick labels that need more than four digits before the decimal point (``200000``): the
      unit wants an engineering prefix (k, M) or a scale;
    * a named curve (a series with a label) hidden under others: every drawn pixel of its stroke
      lies under opaque solid lines drawn after it (within ``tol`` pixels, at least one, of
      their edges), e.g. two joints' equal forces; a wide pale line under a thin one shows;
    * a horizontal or vertical line (axhline, axvline, a constant series) on the axes' frame;
    * two or more series of one legend that differ by colour only (same dash pattern and
      marker, widths less than 1.6 times apart), unreadable in grey print and to a
      colour-blind reader;
    * axes marked directional by :func:`equal_axes` whose x and y scales differ as drawn.
    """
    import re

    from matplotlib.legend import Legend

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    problems = []
    px = fig.dpi / 72.0  # pixels per point
    fb = fig.bbox
    texts = _texts(fig)
    owners = {}
    for leg in fig.findobj(Legend):
        for t in leg.get_texts():
            owners[id(t)] = id(leg)
        owners[id(leg.get_title())] = id(leg)
    for t, bb in texts:
        if bb.x0 < fb.x0 - tol or bb.y0 < fb.y0 - tol or bb.x1 > fb.x1 + tol or bb.y1 > fb.y1 + tol:
            problems.append(f"text {t.get_text()!r} sticks out of the figure")
    for i, (a, ba) in enumerate(texts):
        for b, bbx in texts[i + 1 :]:
            if owners.get(id(a)) is not None and owners.get(id(a)) == owners.get(id(b)):
                continue
            w = min(ba.x1, bbx.x1) - max(ba.x0, bbx.x0)
            h = min(ba.y1, bbx.y1) - max(ba.y0, bbx.y0)
            if w > tol and h > tol:
                problems.append(f"texts {a.get_text()!r} and {b.get_text()!r} overlap")
    for leg in fig.legends:
        problems += _colour_only(leg, "the figure's legend")
    for ax in fig.axes:
        if ax.name == "rectilinear":  # projected (3-D, polar) axes draw lines their own way
            problems += _hidden_curves(ax, px, max(tol, 1.0))
            problems += _reference_lines_on_frame(ax, tol)
        unequal = _unequal_scales(ax)
        if unequal:
            problems.append(unequal)
        leg = ax.get_legend()
        if leg is not None and leg.get_visible():
            problems += _colour_only(leg, repr(ax.get_title()))
            lb = leg.get_window_extent(renderer)
            # data curves only (reference lines such as axhline span the axes)
            for line in (ln for ln in ax.get_lines() if ln.get_transform() == ax.transData):
                pts, b = _line_points(line), ax.bbox
                x, y = pts[:, 0], pts[:, 1]
                under = (lb.x0 < x) & (x < lb.x1) & (lb.y0 < y) & (y < lb.y1)
                under &= (b.x0 <= x) & (x <= b.x1) & (b.y0 <= y) & (y <= b.y1)
                if under.any():
                    problems.append(
                        f"legend of {ax.get_title()!r} hides {int(under.sum())} point(s) of "
                        f"{line.get_label()!r}"
                    )
        for line in ax.get_lines():
            if line.get_marker() in (None, "", "None", " ") or not line.get_clip_on():
                continue
            r = line.get_markersize() * fig.dpi / 72.0 / 2.0
            b = ax.bbox
            for p in _line_points(line):
                inside = b.x0 <= p[0] <= b.x1 and b.y0 <= p[1] <= b.y1
                near = (
                    p[0] - b.x0 < r - tol
                    or b.x1 - p[0] < r - tol
                    or p[1] - b.y0 < r - tol
                    or b.y1 - p[1] < r - tol
                )
                if inside and near:
                    problems.append(
                        f"marker of {line.get_label()!r} at the edge of {ax.get_title()!r} "
                        "is clipped"
                    )
                    break
        for axis in (ax.xaxis, ax.yaxis):
            label = axis.get_label()
            text = label.get_text() if label.get_visible() else ""
            if re.fullmatch(r"[A-Za-z][A-Za-z0-9]*_\w+", text.split(",")[0].strip()):
                problems.append(f"axis label {text!r} is a raw parameter name, not words")
            for tick in axis.get_ticklabels():
                digits = re.sub(r"[^0-9.]", "", tick.get_text().replace("\u2212", "-"))
                if tick.get_visible() and len(digits.split(".")[0]) > 4:
                    problems.append(
                        f"tick label {tick.get_text()!r} of {text or 'an axis'!r} needs more than "
                        "four digits: use an engineering prefix or a scale"
                    )
                    break
    return problems
