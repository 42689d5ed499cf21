"""Clearance and interference: how close a moving point, or the line it moves on, comes to a
circle, a moving link or another link over the cycle.

A design whose polished rod passes through its own crank circle, or whose links cross, is not a
design at all, however good its peaks. These measures make such collisions constraints of any
:class:`~mechsynth.synthesis.Problem` (``clearance(...) >= margin``), certified over the
continuous crank angle like every peak. All are written with ``ops``: numpy for analysis and
sweeps, CasADi for exact derivatives. Distances are in m; a negative value is an interference
(the depth by which the point or line enters the circle, or links that cross).

* :func:`clearance` -- from a point (or the straight line through it in a fixed direction, e.g.
  a polished rod hanging vertically) to a circle (a crank circle: centre a point of the motion,
  radius a parameter of the design), or from a point to a moving link (the segment between two
  points of the motion).
* :func:`link_separation` -- between two moving links: their smallest distance, negative when
  they cross.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..errors import MechanismError, UsageError
from ..kinematics import ops
from .base import CycleMeasure

__all__ = ["clearance", "link_separation"]


def _xy(motion, where, what):
    """``(x, y)`` per angle of a point name, or a fixed ``(x, y)``."""
    if isinstance(where, str):
        if where not in motion.points:
            raise UsageError(
                f"{what}: unknown point {where!r}; points: {', '.join(motion.points)}"
            )
        p = motion.points[where]
        return p.x, p.y
    return float(where[0]), float(where[1])


def _radius(mechanism, radius):
    """A radius: a number (m), the name of a parameter of the design, or ``fn(mechanism)``."""
    if callable(radius):
        return radius(mechanism)
    if isinstance(radius, str):
        params = mechanism.params() if hasattr(mechanism, "params") else {}
        if radius not in params:
            raise UsageError(
                f"clearance: the circle's radius {radius!r} is not a parameter of the design; "
                f"parameters: {', '.join(params)}"
            )
        return params[radius]
    return radius


def _check_point(name, what):
    if isinstance(name, str):
        if not name:
            raise MechanismError(f"{what} must be a point name, got ''")
        return name
    try:
        x, y = name
        return float(x), float(y)
    except (TypeError, ValueError):
        raise MechanismError(f"{what} must be a point name or (x, y), got {name!r}") from None


def _segment_distance(px, py, ax, ay, bx, by):
    """Distance from (px, py) to the segment a-b, per angle (ops: numpy or CasADi)."""
    ux, uy = bx - ax, by - ay
    t = ((px - ax) * ux + (py - ay) * uy) / (ux * ux + uy * uy)
    t = ops.fmin(ops.fmax(t, 0.0), 1.0)
    dx, dy = px - (ax + t * ux), py - (ay + t * uy)
    return ops.sqrt(dx * dx + dy * dy)


def clearance(
    point: str,
    *,
    circle: tuple | None = None,
    segment: tuple[str, str] | None = None,
    direction: float | None = None,
    name: str | None = None,
) -> CycleMeasure:
    """Smallest clearance over the cycle (m) between ``point`` and an obstacle; negative values
    are interferences.

    Parameters
    ----------
    point : a point of the motion (``"PR"``, ``"B"``, a coupler point).
    circle : ``(centre, radius)``: a disc to keep out of -- ``centre`` a point of the motion
        (``"O1"``, a crank pivot) or ``(x, y)`` in m, ``radius`` in m, the name of a parameter of
        the design (``"crank"``: the crank circle grows with the crank) or ``fn(mechanism)``.
    segment : ``(P, Q)``: a moving link, the segment between two points of the motion.
    direction : with ``circle``, measure from the straight line through ``point`` at this angle
        (rad from +x; ``pi/2`` for a vertical rod) instead of from the point itself.
    name : the measure's name in reports (default built from the arguments).

    Examples
    --------
    >>> import mechsynth as ms
    >>> from mechsynth.objectives.clearances import clearance
    >>> fb = ms.FourBar(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2)
    >>> c = clearance("B", circle=("O1", "crank"))   # B outside the crank circle
    >>> round(float(c.from_motion(fb, fb.motion(ms.cycle(720)))), 4)
    2.3
    """
    if (circle is None) == (segment is None):
        raise MechanismError("clearance: give one obstacle, circle=(centre, r) or segment=(P, Q)")
    point = _check_point(point, "clearance: point")
    if direction is not None:
        if circle is None:
            raise MechanismError("clearance: direction (a line through the point) needs circle")
        direction = float(direction)
        if not np.isfinite(direction):
            raise MechanismError(f"clearance: direction must be finite, got {direction}")
    if circle is not None:
        try:
            centre, radius = circle
        except (TypeError, ValueError):
            raise MechanismError(
                f"clearance: circle must be (centre, radius), got {circle!r}"
            ) from None
        centre = _check_point(centre, "clearance: the circle's centre")
        if not (isinstance(radius, str) or callable(radius)):
            radius = float(radius)
            if not (np.isfinite(radius) and radius >= 0.0):
                raise MechanismError(f"clearance: radius must be >= 0 m, got {radius}")
        label = name or (
            f"clearance({point}{'' if direction is None else ' line'}, circle "
            f"{centre if isinstance(centre, str) else tuple(centre)} r={_label(radius)})"
        )

        def per_angle(mechanism, motion):
            px, py = _xy(motion, point, "clearance")
            cx, cy = _xy(motion, centre, "clearance: the circle's centre")
            dx, dy = px - cx, py - cy
            if direction is None:
                d = ops.sqrt(dx * dx + dy * dy)
            else:  # distance of the centre from the line through the point
                d = ops.fabs(dx * np.sin(direction) - dy * np.cos(direction))
            return d - _radius(mechanism, radius)

        return CycleMeasure(label, per_angle, "min", "m")

    try:
        p, q = segment
    except (TypeError, ValueError):
        raise MechanismError(f"clearance: segment must be (P, Q), got {segment!r}") from None
    if point in (p, q):
        raise MechanismError(f"clearance: point {point!r} is an end of the segment {segment!r}")

    def per_angle(mechanism, motion):
        px, py = _xy(motion, point, "clearance")
        ax, ay = _xy(motion, p, "clearance: segment")
        bx, by = _xy(motion, q, "clearance: segment")
        return _segment_distance(px, py, ax, ay, bx, by)

    return CycleMeasure(name or f"clearance({point}, link {p}{q})", per_angle, "min", "m")


def link_separation(first: tuple[str, str], second: tuple[str, str], name=None) -> CycleMeasure:
    """Smallest distance between two moving links over the cycle (m), each the segment between
    two points of the motion; negative (minus that distance) where the links cross. Links that
    share a joint touch there by design: give links with four distinct points."""
    try:
        (a, b), (c, d) = first, second
    except (TypeError, ValueError):
        raise MechanismError(
            f"link_separation: give two links as (P, Q) pairs, got {first!r}, {second!r}"
        ) from None
    if len({a, b, c, d}) < 4:
        raise MechanismError(
            f"link_separation: links {a}{b} and {c}{d} share a point (they touch there by "
            "design)"
        )

    def per_angle(mechanism, motion):
        ax, ay = _xy(motion, a, "link_separation")
        bx, by = _xy(motion, b, "link_separation")
        cx, cy = _xy(motion, c, "link_separation")
        dx, dy = _xy(motion, d, "link_separation")
        dist = ops.fmin(
            ops.fmin(
                _segment_distance(ax, ay, cx, cy, dx, dy), _segment_distance(bx, by, cx, cy, dx, dy)
            ),
            ops.fmin(
                _segment_distance(cx, cy, ax, ay, bx, by), _segment_distance(dx, dy, ax, ay, bx, by)
            ),
        )

        def side(px, py, qx, qy, rx, ry):  # orientation of r relative to p->q
            return (qx - px) * (ry - py) - (qy - py) * (rx - px)

        # they cross where each link's ends lie on opposite sides of the other's line
        crossed = (
            ops.fmax(
                side(ax, ay, bx, by, cx, cy) * side(ax, ay, bx, by, dx, dy),
                side(cx, cy, dx, dy, ax, ay) * side(cx, cy, dx, dy, bx, by),
            )
            < 0.0
        )
        return ops.where(crossed, -dist, dist)

    return CycleMeasure(name or f"link_separation({a}{b}, {c}{d})", per_angle, "min", "m")


def _label(radius) -> str:
    if isinstance(radius, str):
        return radius
    if isinstance(radius, Callable):
        return getattr(radius, "__name__", "fn")
    return f"{radius:g}"
