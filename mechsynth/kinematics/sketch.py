"""What a mechanism looks like: a small description that one generic renderer draws and animates.

A mechanism describes itself at a set of crank angles (the *frames*) with a :class:`Sketch`:
its joints' positions per frame, the links drawn between them, the frame pivots, the sliders
with their guides, and any extra outlines (a horsehead, a bridle). It says nothing about
matplotlib: :mod:`mechsynth.kinematics.drawing` turns any sketch into a figure or an animation.
So a new mechanism (or a general linkage) gets ``draw`` and ``animate`` by writing ``sketch``.

All coordinates are in SI (m); angles in rad from +x, counter-clockwise.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import MechanismError

__all__ = ["Bar", "Slider", "Outline", "Sketch"]


@dataclass(frozen=True)
class Bar:
    """A rigid link drawn through its joints: two points make a bar, three or more a plate
    (filled when ``closed``)."""

    name: str
    points: tuple[str, ...]
    closed: bool = False


@dataclass(frozen=True)
class Slider:
    """A block at the moving point ``point`` sliding along the direction ``angle`` (rad; a
    number, or one value per frame for a turning guide).

    ``through`` is None for a guide fixed to the frame (drawn as a hatched straight guide over
    the block's travel); otherwise it names a point of the link that carries the guide (a slot),
    and the slot is drawn through it over the block's travel relative to that point.
    """

    point: str
    angle: Any = 0.0
    through: str | None = None
    name: str = ""


@dataclass(frozen=True)
class Outline:
    """An extra polyline: ``x``, ``y`` of shape (frames, k) moving with the frames, or (k,) fixed.
    ``kind`` is ``"link"`` (drawn like a link), ``"frame"`` (fixed structure, drawn in black) or
    ``"thin"`` (a rope or a rod: thin line)."""

    name: str
    x: Any
    y: Any
    kind: str = "link"


@dataclass(frozen=True)
class Sketch:
    """A mechanism at ``n`` frames.

    Attributes
    ----------
    points : ``{name: (x, y)}``, each an array of shape (n,) (m).
    bars : the links, drawn in the given order.
    ground : names of the points fixed to the frame (drawn as hatched pivots).
    sliders : blocks and their guides.
    outlines : other polylines.
    angles : the crank angle shown for each frame (rad, in the mechanism's own convention).
    angle_label : how that angle is measured (e.g. ``"crank angle φ from +x, ccw"``);
        ``angle_symbol`` its symbol (``"φ"``); ``angle_unit`` ``"rad"``, or ``"m"`` when the
        input is a length (a driving slider's displacement, shown in display length units).
    name : the mechanism and its design, for titles.
    xlabel : label of the x axis (without unit; default ``"x"``).
    labels : names of the points to label (default: the joints and the ground points).
    joints : names of the moving points drawn as pins (default: every point of a bar).
    """

    points: dict[str, tuple[np.ndarray, np.ndarray]]
    bars: tuple[Bar, ...]
    ground: tuple[str, ...] = ()
    sliders: tuple[Slider, ...] = ()
    outlines: tuple[Outline, ...] = ()
    angles: Any = None
    angle_label: str = "crank angle φ"
    angle_symbol: str = "φ"
    angle_unit: str = "rad"
    name: str = ""
    xlabel: str = "x"
    labels: tuple[str, ...] | None = None
    joints: tuple[str, ...] | None = None

    def __post_init__(self):
        pts = {}
        n = None
        for k, (x, y) in self.points.items():
            x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
            if x.ndim != 1:
                raise MechanismError(
                    f"sketch point {k!r}: expected one position per frame (1-D), got shape "
                    f"{x.shape}; draw one design at a time"
                )
            pts[k] = (x, y)
            n = x.size if n is None else n
        if n is None:
            raise MechanismError("a sketch needs at least one point")
        pts = {k: (np.broadcast_to(x, (n,)), np.broadcast_to(y, (n,))) for k, (x, y) in pts.items()}
        object.__setattr__(self, "points", pts)
        names = set(pts)
        for bar in self.bars:
            missing = [p for p in bar.points if p not in names]
            if missing:
                raise MechanismError(f"bar {bar.name!r} names unknown points {missing}")
        for s in self.sliders:
            for p in (s.point, s.through):
                if p is not None and p not in names:
                    raise MechanismError(f"slider at {s.point!r} names the unknown point {p!r}")
        for g in (*self.ground, *(self.labels or ()), *(self.joints or ())):
            if g not in names:
                raise MechanismError(f"{g!r} is not a point of the sketch")
        if self.angles is None:
            object.__setattr__(self, "angles", np.zeros(n))

    @property
    def frames(self) -> int:
        return next(iter(self.points.values()))[0].size

    def slider_angle(self, slider: Slider, frame: int) -> float:
        a = np.asarray(slider.angle, dtype=float)
        return float(a) if a.ndim == 0 else float(np.broadcast_to(a, (self.frames,))[frame])

    def outline_xy(self, outline: Outline, frame: int):
        x, y = np.asarray(outline.x, dtype=float), np.asarray(outline.y, dtype=float)
        if x.ndim == 2:
            return x[frame], y[frame]
        return x, y

    def extent(self) -> tuple[float, float, float, float]:
        """(xmin, xmax, ymin, ymax) over every point and outline of every frame (m)."""
        xs = [x for x, _ in self.points.values()]
        ys = [y for _, y in self.points.values()]
        for o in self.outlines:
            xs.append(np.ravel(o.x))
            ys.append(np.ravel(o.y))
        x, y = np.concatenate(xs), np.concatenate(ys)
        return float(np.nanmin(x)), float(np.nanmax(x)), float(np.nanmin(y)), float(np.nanmax(y))


def as_frames(motion_points, names=None) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """``{name: (x, y)}`` from a Motion's point tracks (one design)."""
    names = names or list(motion_points)
    return {k: (np.asarray(motion_points[k].x), np.asarray(motion_points[k].y)) for k in names}
