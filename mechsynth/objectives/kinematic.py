"""Kinematic measures: peaks of velocity and acceleration, pressure and transmission angles,
stroke, swing, time ratio and Grashof margin.

Every function here returns a :class:`~mechsynth.objectives.Measure` that evaluates on numpy
(analysis, sweeps) and on CasADi (exact derivatives for IPOPT). Angles are in radians. Velocities
and accelerations are in m/s and m/s^2 (rad/s, rad/s^2 for links) when the motion has a crank
speed, and crank-angle analogs (m/rad, m/rad^2) when it has none.

Output names
------------
``"slider"`` is the mechanism's main slider along its guide (``motion.slider``); any other name is a
point of the motion (``"A"``, ``"B"``, coupler points) or, failing that, a named slider. ``None``
means the mechanism's ``default_output``. (A stroke of a name that is both a point and a slider
is the slider's travel along its guide.)

Binding
-------
``Measure.bind`` receives what a problem or a sweep varies: a mechanism class, or a
:class:`~mechsynth.kinematics.Linkage` (an instance that stands for its designs); closed forms are
looked up on the class (``_cls``).

Smoothness
----------
Peaks of a signed quantity ``x`` are written with the branches ``(x, -x)`` and peaks of a vector's
magnitude with the single branch ``x^2 + y^2`` (``outer="sqrt"``), so that IPOPT's epigraph
constraints are smooth everywhere, including where ``x`` changes sign or a velocity vanishes.
"""

from __future__ import annotations

import numpy as np

from ..errors import UsageError
from ..kinematics import ops
from .base import Combination, CycleMeasure, Measure, ScalarMeasure

__all__ = [
    "peak_velocity",
    "peak_acceleration",
    "max_pressure_angle",
    "min_transmission_angle",
    "stroke",
    "swing_angle",
    "time_ratio",
    "grashof_margin",
    "peak_angular_velocity",
    "peak_angular_acceleration",
    "assembly_margin",
    "KINEMATIC_MEASURES",
]


def _cls(target):
    """The class of what a measure is bound to (a mechanism class, or a linkage instance)."""
    return target if isinstance(target, type) else type(target)


# ------------------------------------------------------------------------------ helpers
def _resolve(mechanism, motion, point):
    """``("slider", track)`` or ``("point", track)`` for an output name."""
    name = point if point is not None else getattr(mechanism, "default_output", "slider")
    if name == "slider" and motion.sliders:
        return "slider", motion.slider
    if name in motion.points:
        return "point", motion.points[name]
    if name in motion.sliders:
        return "slider", motion.sliders[name]
    known = sorted(
        set(motion.points) | set(motion.sliders) | ({"slider"} if motion.sliders else set())
    )
    raise UsageError(f"unknown output {name!r}; this mechanism has {', '.join(known)}")


def _label(point) -> str:
    return "" if point is None else str(point)


def _signed_or_vector(kind: str, point, direction):
    """Per-angle value, branches and the signed component (None for a vector's magnitude) of
    |velocity| or |acceleration|."""

    def component(mechanism, motion):
        what, tr = _resolve(mechanism, motion, point)
        if what == "slider":
            if direction is not None:
                raise UsageError("direction applies to points, not to a slider (already 1-D)")
            return tr.velocity if kind == "v" else tr.acceleration
        if direction is None:
            return None
        v, a = tr.along(direction)
        return v if kind == "v" else a

    def xy(mechanism, motion):
        _, tr = _resolve(mechanism, motion, point)
        return (tr.vx, tr.vy) if kind == "v" else (tr.ax, tr.ay)

    def per_angle(mechanism, motion):
        c = component(mechanism, motion)
        if c is not None:
            return ops.fabs(c)
        x, y = xy(mechanism, motion)
        return ops.sqrt(x * x + y * y)

    def branches(mechanism, motion):
        c = component(mechanism, motion)
        if c is not None:
            return (c, -c)
        x, y = xy(mechanism, motion)
        return (x * x + y * y,)

    return per_angle, branches, component


class _SignedPeak(CycleMeasure):
    """Peak |component| of a signed per-angle value: on numbers, ``max(max c, -min c)`` -- the
    same bits as the maximum of ``|c|`` without a per-angle temporary of ``|c|`` (a pass over
    every design-angle of a chart's block)."""

    def __init__(self, name, per_angle, unit, branches, component):
        super().__init__(name, per_angle, "max", unit, branches=branches)
        self._component = component

    def from_motion(self, mechanism, motion):
        c = self._component(mechanism, motion)
        if type(c) is not np.ndarray or c.ndim == 0 or c.dtype != np.float64:
            return super().from_motion(mechanism, motion)
        return np.maximum(c.max(axis=-1), -c.min(axis=-1))


class _PeakMagnitude(CycleMeasure):
    """Peak |velocity| or |acceleration|: signed branches for sliders/directions, squared
    magnitude for point vectors. Which one applies is known only from the motion, so ``outer`` is
    decided per call of :meth:`branches_outer`."""

    def __init__(self, name, kind, point, direction, unit):
        per_angle, branches, component = _signed_or_vector(kind, point, direction)
        super().__init__(name, per_angle, "max", unit, branches=branches)
        self._component = component
        self.point, self.direction = point, direction

    def bind(self, mechanism_class):
        # A point without a direction is a vector magnitude: squared branch + sqrt; a slider or a
        # direction gives a signed scalar. Decided from the name (default_output of the class or
        # of the linkage).
        vector = self.direction is None and not self._is_slider(mechanism_class)
        if not vector:
            return _SignedPeak(
                self.name, self.per_angle, self.unit, self._branches, self._component
            )
        return CycleMeasure(
            self.name,
            self.per_angle,
            "max",
            self.unit,
            branches=self._branches,
            outer="sqrt" if vector else None,
        )

    def _is_slider(self, mechanism_class) -> bool:
        name = self.point if self.point is not None else mechanism_class.default_output
        return name == "slider"


def _check_direction(direction):
    if direction is None:
        return None
    if ops.is_symbolic(direction):
        return direction
    d = float(direction)
    if not np.isfinite(d):
        raise UsageError(f"direction must be a finite angle in rad, got {direction!r}")
    return d


# ------------------------------------------------------------------------------ peaks
def peak_velocity(point=None, direction=None) -> CycleMeasure:
    """Peak over the cycle of the speed of ``point`` (m/s; m/rad as analogs).

    Parameters
    ----------
    point : ``"slider"`` (velocity along the guide), a point name (magnitude of its velocity
        vector) or None for the mechanism's main output.
    direction : optional angle (rad from +x): peak |component| of a point's velocity along it.

    Notes
    -----
    A point that is also the slider joint (``"B"`` of a slider-crank) moves along the guide, so
    its speed equals ``|slider velocity|``. Use ``"slider"`` for the smooth signed form.
    """
    direction = _check_direction(direction)
    suffix = "" if direction is None else f", {np.rad2deg(direction):g} deg"
    name = f"peak_velocity({_label(point)}{suffix})"
    return _PeakMagnitude(name, "v", point, direction, "m/s")


def peak_acceleration(point=None, direction=None) -> CycleMeasure:
    """Peak over the cycle of the magnitude of the acceleration of ``point`` (m/s^2; m/rad^2 as
    analogs). Arguments as :func:`peak_velocity`."""
    direction = _check_direction(direction)
    suffix = "" if direction is None else f", {np.rad2deg(direction):g} deg"
    name = f"peak_acceleration({_label(point)}{suffix})"
    return _PeakMagnitude(name, "a", point, direction, "m/s^2")


def _link(motion, link):
    if link not in motion.links:
        raise UsageError(f"unknown link {link!r}; this mechanism has {', '.join(motion.links)}")
    return motion.links[link]


def peak_angular_velocity(link="rocker") -> CycleMeasure:
    """Peak |angular velocity| of ``link`` over the cycle (rad/s; rad/rad as analogs)."""

    def per_angle(mechanism, motion):
        return ops.fabs(_link(motion, link).omega)

    def branches(mechanism, motion):
        w = _link(motion, link).omega
        return (w, -w)

    return CycleMeasure(
        f"peak_angular_velocity({link})", per_angle, "max", "rad/s", branches=branches
    )


def peak_angular_acceleration(link="rocker") -> CycleMeasure:
    """Peak |angular acceleration| of ``link`` over the cycle (rad/s^2; rad/rad^2 as analogs)."""

    def per_angle(mechanism, motion):
        return ops.fabs(_link(motion, link).epsilon)

    def branches(mechanism, motion):
        e = _link(motion, link).epsilon
        return (e, -e)

    return CycleMeasure(
        f"peak_angular_acceleration({link})", per_angle, "max", "rad/s^2", branches=branches
    )


# ------------------------------------------------------------------------------ angles
def _group_angle(motion, group, table, what):
    if group is None:
        value = motion.pressure_angle if table == "pressure" else motion.raw_transmission_angle
        if value is None:
            raise UsageError(f"this mechanism defines no {what}")
        return value
    angles = motion.pressure_angles if table == "pressure" else motion.raw_transmission_angles
    if group not in angles:
        known = ", ".join(angles) or "none (name no group for a named mechanism)"
        raise UsageError(f"no {what} of group {group!r}; groups with one: {known}")
    return angles[group]


def max_pressure_angle(group=None) -> CycleMeasure:
    """Largest pressure angle over the cycle (rad): the angle between the force the driving link
    transmits to the output and the output's velocity (``motion.pressure_angle``), or that of
    the linkage group ``group`` (``motion.pressure_angles[group]``, e.g. ``"N"``).

    The per-angle value has kinks where the pressure angle is zero; they are never at the peak,
    so the epigraph constraints are smooth where they are active."""
    name = "max_pressure_angle" if group is None else f"max_pressure_angle({group})"
    return CycleMeasure(
        name,
        lambda mech, motion: _group_angle(motion, group, "pressure", "pressure angle"),
        "max",
        "rad",
    )


def min_transmission_angle(group=None) -> CycleMeasure:
    """Smallest transmission angle over the cycle (rad), counting an obtuse angle ``mu`` as its
    supplement ``pi - mu`` (the classical definition: worst deviation from 90 deg is
    ``pi/2 - min_transmission_angle``); of the main output, or of the linkage group ``group``."""

    def mu_of(motion):
        return _group_angle(motion, group, "transmission", "transmission angle")

    def per_angle(mechanism, motion):
        mu = mu_of(motion)
        return ops.fmin(mu, np.pi - mu)

    def branches(mechanism, motion):
        mu = mu_of(motion)
        return (mu, np.pi - mu)

    name = "min_transmission_angle" if group is None else f"min_transmission_angle({group})"
    return CycleMeasure(name, per_angle, "min", "rad", branches=branches)


def assembly_margin(condition) -> CycleMeasure:
    """Smallest assembly margin of a linkage's group over the cycle (dimensionless; see
    :meth:`~mechsynth.kinematics.Linkage.assembly_margins`): ``sin^2`` of the angle between an
    RRR dyad's links, ``cos^2`` of an RRP rod's angle to its guide, ... -- zero at a toggle,
    negative where the group cannot be assembled. A :class:`~mechsynth.synthesis.Problem` over
    a linkage bounds every condition's margin from below, certified over the continuous crank
    angle like any peak."""

    def per_angle(mechanism, motion):
        margins = motion.extra.get("assembly margins")
        if margins is None:
            raise UsageError("this mechanism reports no assembly margins (a Linkage does)")
        if condition not in margins:
            raise UsageError(
                f"no assembly condition {condition!r}; conditions: {', '.join(margins)}"
            )
        return margins[condition]

    return CycleMeasure(f"assembly_margin({condition})", per_angle, "min", "")


# ------------------------------------------------------------------------------ ranges
class _Range(Measure):
    """``max - min`` of a per-angle quantity, or a closed form for the mechanisms that have one."""

    def __init__(self, name, unit, quantity, closed_form=None):
        self.name, self.unit = name, unit
        self._quantity = quantity  # (mechanism, motion) -> per-angle values
        self._closed_form = closed_form  # mechanism_class -> fn(mechanism) or None

    def bind(self, mechanism_class) -> Measure:
        fn = self._closed_form(_cls(mechanism_class)) if self._closed_form else None
        if fn is not None:
            return ScalarMeasure(self.name, fn, self.unit)
        hi = CycleMeasure(f"max {self.name}", self._quantity, "max", self.unit)
        lo = CycleMeasure(f"min {self.name}", self._quantity, "min", self.unit)
        return Combination(((1.0, hi), (-1.0, lo)), 0.0, self.unit, label=self.name)

    def from_motion(self, mechanism, motion):
        return self.bind(type(mechanism)).from_motion(mechanism, motion)


def stroke(point="slider", direction=None) -> Measure:
    """Stroke (m): travel of the slider between its dead centres, or of a point's coordinate
    along ``direction`` (rad from +x; default the x axis) over the cycle.

    Mechanisms with a closed-form ``stroke`` (slider-crank) use it for ``"slider"``; otherwise
    the stroke is ``max - min`` of the position over the cycle (a peak, certified by the solver).
    """
    direction = _check_direction(direction)

    def quantity(mechanism, motion):
        if direction is None and point in motion.sliders:
            return motion.sliders[point].position
        what, tr = _resolve(mechanism, motion, point)
        if what == "slider":
            return tr.position
        if direction is None:
            return tr.x
        return tr.x * ops.cos(direction) + tr.y * ops.sin(direction)

    def closed_form(cls):
        name = point if point is not None else cls.default_output
        if (
            name == "slider"
            and direction is None
            and isinstance(getattr(cls, "stroke", None), property)
        ):
            return lambda mech: mech.stroke
        return None

    return _Range(f"stroke({_label(point)})", "m", quantity, closed_form)


def swing_angle(link="rocker") -> Measure:
    """Swing angle (rad) of ``link`` between its extreme positions.

    A four-bar's rocker uses the closed form from the dead-centre positions; other links use the
    range over the cycle of the link angle measured from its angle at crank angle 0 (so the
    range is not broken where the absolute angle wraps through +-pi; a swing must stay below pi).
    """

    def quantity(mechanism, motion):
        th = _link(motion, link).angle
        if ops.is_symbolic(th):
            th0 = th[0]
        else:
            th0 = np.asarray(th)[..., :1]
        d = th - th0
        return ops.arctan2(ops.sin(d), ops.cos(d))

    def closed_form(cls):
        if link == "rocker" and isinstance(getattr(cls, "swing_angle", None), property):
            return lambda mech: mech.swing_angle
        return None

    return _Range(f"swing_angle({link})", "rad", quantity, closed_form)


# ------------------------------------------------------------------------------ scalars
class _TimeRatio(Measure):
    name = "time_ratio"
    unit = ""

    def bind(self, mechanism_class):
        if not isinstance(getattr(_cls(mechanism_class), "crank_spans", None), property):
            raise UsageError(f"{mechanism_class.__name__} has no time ratio (no crank_spans)")

        def fn(mech):
            return mech.time_ratio

        def branches(mech):
            first, second = mech.crank_spans
            return (first / second, second / first)

        return ScalarMeasure(self.name, fn, self.unit, branches=branches, floor=1.0)

    def from_motion(self, mechanism, motion):
        return mechanism.time_ratio


def time_ratio() -> Measure:
    """Time ratio: duration of the slower stroke (swing) over the quicker one at constant crank
    speed, ``>= 1`` (1 for a centric slider-crank). Uses the mechanism's ``crank_spans``.

    For optimizers it is ``max(r, 1/r)`` with ``r`` the ratio of the two crank spans, written
    with the smooth branches ``r`` and ``1/r``; ``time_ratio() == 1`` becomes ``r <= 1, 1/r <= 1``.
    """
    return _TimeRatio()


def _grashof_margin(mech):
    p = mech.params()
    if {"crank", "coupler", "rocker", "ground"} <= set(p):
        a, b, c, d = p["crank"], p["coupler"], p["rocker"], p["ground"]
        s = ops.fmin(ops.fmin(a, b), ops.fmin(c, d))
        l = ops.fmax(ops.fmax(a, b), ops.fmax(c, d))
        return (a + b + c + d) - 2.0 * (s + l)
    if {"crank", "rod", "offset"} <= set(p):
        return p["rod"] - p["crank"] - ops.fabs(p["offset"])
    margin = getattr(mech, "grashof_margin", None)
    if margin is None:
        raise UsageError(f"{type(mech).__name__} defines no Grashof margin")
    return margin


def grashof_margin() -> ScalarMeasure:
    """Grashof margin (m): ``(p + q) - (s + l)`` of a four-bar (positive: Grashof); for a
    slider-crank the full-turn margin ``rod - crank - |offset|``."""
    return ScalarMeasure("grashof_margin", _grashof_margin, "m")


#: name -> factory, for problem files (``"peak_acceleration(slider)"``)
KINEMATIC_MEASURES = {
    "peak_velocity": peak_velocity,
    "peak_acceleration": peak_acceleration,
    "max_pressure_angle": max_pressure_angle,
    "min_transmission_angle": min_transmission_angle,
    "stroke": stroke,
    "swing_angle": swing_angle,
    "time_ratio": time_ratio,
    "grashof_margin": grashof_margin,
    "peak_angular_velocity": peak_angular_velocity,
    "peak_angular_acceleration": peak_angular_acceleration,
    "assembly_margin": assembly_margin,
}
