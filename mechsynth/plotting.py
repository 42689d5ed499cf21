"""The house style of every figure mechsynth draws, and the checks that keep it.

* :data:`PALETTE` — Okabe and Ito's colour-blind-safe colours, the default colour cycle inside
  :func:`style`; :data:`LINESTYLES` to tell curves apart without colour.
* :func:`style` — a context manager with the house rc settings (font sizes, grid, readable
  ticks, constrained layout).
* :func:`force_unit`, :func:`torque_unit` — N or kN (N m or kN m) by the size of the values
  when the display force unit is the newton, else the display unit.
* :func:`crank_axis` — a crank-angle axis over one turn with ticks every 45 or 60 deg.
* :func:`title` — "what, design, speed" titles.
* :func:`layout_problems` — overlapping text, text outside the figure and markers clipped by
  their axes: what the figure-regression test asserts away.
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
      unit wants an engineering prefix (k, M) or a scale.
    """
    import re

    from matplotlib.legend import Legend

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    problems = []
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
    for ax in fig.axes:
        leg = ax.get_legend()
        if leg is not None and leg.get_visible():
            lb = leg.get_window_extent(renderer)
            # data curves only (reference lines such as axhline span the axes)
            for line in (ln for ln in ax.get_lines() if ln.get_transform() == ax.transData):
                hidden = [
                    p
                    for p in _line_points(line)
                    if lb.x0 < p[0] < lb.x1 and lb.y0 < p[1] < lb.y1 and ax.bbox.contains(*p)
                ]
                if hidden:
                    problems.append(
                        f"legend of {ax.get_title()!r} hides {len(hidden)} point(s) of "
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
