"""Measures: functions that reduce a mechanism's cycle to a number.

A :class:`Measure` is evaluated from a mechanism and its :class:`~mechsynth.kinematics.Motion`
over a grid of crank angles. The same measure runs on numpy (analysis, sweeps: parameters may be
batches, the cycle is the last axis) and on CasADi (exact derivatives for IPOPT).

Two kinds:

* :class:`CycleMeasure` — a per-angle quantity reduced over the cycle (``max``, ``min``, ``mean``,
  ``rms``). Optimizers use :meth:`CycleMeasure.samples` to write a peak as an epigraph over the
  angle grid (``samples <= t`` at every angle) and then certify it on a dense grid.
* :class:`ScalarMeasure` — a closed-form property of the design (stroke, time ratio, ...).

Measures combine with ``+``, ``-``, ``*`` / ``/`` by numbers into :class:`Combination`, and compare
with ``<=``, ``>=``, ``==`` against numbers into :class:`Constraint`.

Smooth epigraphs
----------------
A peak such as ``max |v|`` is not differentiable where the sign of ``v`` changes. For gradient
solvers a measure may therefore say how its per-angle value is the pointwise maximum of smooth
*branches*: ``|v| = max(v, -v)`` has the branches ``(v, -v)``, a magnitude ``sqrt(vx^2 + vy^2)``
the single branch ``vx^2 + vy^2`` with ``outer="sqrt"``. The optimizer then writes
``t >= branch`` for every branch and grid angle, all smooth. ``min`` reductions work the same way
with the per-angle value the pointwise *minimum* of the branches. Measures that give no branches
use their per-angle value as the only branch (fine when it is smooth near the peak).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import MechanismError
from ..kinematics import ops

__all__ = ["Measure", "CycleMeasure", "ScalarMeasure", "Combination", "Constraint", "reduce_cycle"]


def reduce_cycle(values, how: str):
    """Reduce per-angle ``values`` over the cycle (last numpy axis, or a whole CasADi column)."""
    if ops.is_symbolic(values):
        import casadi as ca

        n = values.numel()
        if how == "max":
            return ca.mmax(values)
        if how == "min":
            return ca.mmin(values)
        if how == "mean":
            return ca.sum1(values) / n
        if how == "rms":
            return ca.sqrt(ca.sum1(values * values) / n)
        raise MechanismError(f"unknown reduction {how!r}")
    values = np.asarray(values, dtype=float)
    if how == "max":
        return values.max(axis=-1)
    if how == "min":
        return values.min(axis=-1)
    if how == "mean":
        return values.mean(axis=-1)
    if how == "rms":
        return np.sqrt(np.mean(values * values, axis=-1))
    raise MechanismError(f"unknown reduction {how!r}")


class Measure:
    """Base class: a named number of a design (``unit`` for reports)."""

    name: str = "measure"
    unit: str = ""

    def bind(self, mechanism_class) -> Measure:
        """The concrete measure for designs of ``mechanism_class``.

        Measures with a closed form for some mechanisms (e.g. the stroke of a slider-crank)
        return it here; the default is the measure itself. Optimizers call this once per problem.
        """
        return self

    def from_motion(self, mechanism, motion):
        """Value from a mechanism and its motion over a crank-angle grid."""
        raise NotImplementedError

    def evaluate(self, mechanism, phi=None, speed=None):
        """Value for ``mechanism`` over crank angles ``phi`` (default: 720 equal steps)."""
        from ..kinematics.mechanism import input_grid

        phi = input_grid(mechanism, 720) if phi is None else phi
        return self.from_motion(mechanism, mechanism.motion(phi, speed=speed))

    # -- algebra -------------------------------------------------------------------------
    def __add__(self, other):
        return Combination.of(self) + other

    __radd__ = __add__

    def __sub__(self, other):
        return Combination.of(self) - other

    def __rsub__(self, other):
        return -Combination.of(self) + other

    def __neg__(self):
        return -Combination.of(self)

    def __mul__(self, k):
        return Combination.of(self) * k

    __rmul__ = __mul__

    def __truediv__(self, k):
        return Combination.of(self) * (1.0 / k)

    def __le__(self, bound):
        return Constraint(self, "<=", bound)

    def __ge__(self, bound):
        return Constraint(self, ">=", bound)

    def __eq__(self, bound):  # noqa: D105 - builds a constraint, like cvxpy
        if isinstance(bound, Measure):
            return self is bound
        return Constraint(self, "==", bound)

    __hash__ = object.__hash__

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.name}>"


class CycleMeasure(Measure):
    """A per-angle quantity ``per_angle(mechanism, motion)`` reduced over the cycle by ``reduce``
    (``"max"``, ``"min"``, ``"mean"``, ``"rms"``).

    Parameters
    ----------
    name, unit : for reports.
    per_angle : ``(mechanism, motion) -> values`` over the angles (numpy or CasADi).
    reduce : ``"max"``, ``"min"``, ``"mean"`` or ``"rms"`` over the cycle.
    branches : optional ``(mechanism, motion) -> tuple of per-angle arrays``, smooth, whose
        pointwise maximum (``reduce="max"``) or minimum (``"min"``) is ``outer^-1(per_angle)``; see
        the module notes. Default: the per-angle value itself.
    outer : None, or ``"sqrt"`` when the branches are squares (``per_angle = sqrt(max branch)``);
        only with ``reduce="max"``.
    """

    def __init__(
        self,
        name: str,
        per_angle: Callable[[Any, Any], Any],
        reduce: str = "max",
        unit: str = "",
        branches: Callable[[Any, Any], tuple] | None = None,
        outer: str | None = None,
    ):
        if reduce not in ("max", "min", "mean", "rms"):
            raise MechanismError(f"reduce must be max, min, mean or rms, got {reduce!r}")
        if outer not in (None, "sqrt"):
            raise MechanismError(f"outer must be None or 'sqrt', got {outer!r}")
        if outer is not None and reduce != "max":
            raise MechanismError("outer='sqrt' needs reduce='max'")
        self.name, self.per_angle, self.reduce, self.unit = name, per_angle, reduce, unit
        self._branches, self.outer = branches, outer

    @property
    def is_peak(self) -> bool:
        """True for ``max``/``min`` reductions (semi-infinite: epigraph and certification)."""
        return self.reduce in ("max", "min")

    def samples(self, mechanism, motion):
        """The per-angle values (array over designs x angles, or a CasADi column)."""
        return self.per_angle(mechanism, motion)

    def branches(self, mechanism, motion) -> tuple:
        """Smooth per-angle branches (see the class notes)."""
        if self._branches is None:
            return (self.samples(mechanism, motion),)
        return tuple(self._branches(mechanism, motion))

    def from_motion(self, mechanism, motion):
        return reduce_cycle(self.samples(mechanism, motion), self.reduce)


class ScalarMeasure(Measure):
    """A closed-form property ``fn(mechanism)`` of the design.

    ``branches`` (optional) gives smooth expressions whose maximum is ``fn`` (e.g. a time ratio
    ``max(r, 1/r)`` has the branches ``(r, 1/r)``), and ``floor`` a value the measure can never go
    below (1 for a time ratio), so that ``== floor`` is written as ``every branch <= floor``.
    """

    def __init__(
        self,
        name: str,
        fn: Callable[[Any], Any],
        unit: str = "",
        branches: Callable[[Any], tuple] | None = None,
        floor: float | None = None,
    ):
        self.name, self.fn, self.unit = name, fn, unit
        self._branches, self.floor = branches, floor

    @property
    def has_branches(self) -> bool:
        return self._branches is not None

    def branches(self, mechanism) -> tuple:
        """Smooth branches whose maximum is the value (the value itself by default)."""
        if self._branches is None:
            return (self.fn(mechanism),)
        return tuple(self._branches(mechanism))

    def from_motion(self, mechanism, motion):
        return self.fn(mechanism)


@dataclass(frozen=True, eq=False)
class Combination(Measure):
    """``constant + sum(weight_i * measure_i)``."""

    terms: tuple[tuple[float, Measure], ...] = ()
    constant: float = 0.0
    unit: str = ""
    #: a display name replacing the generated one (e.g. "stroke(C)" for max x - min x)
    label: str = ""

    @staticmethod
    def of(measure: Measure) -> Combination:
        if isinstance(measure, Combination):
            return measure
        return Combination(((1.0, measure),), 0.0, measure.unit)

    @property
    def name(self) -> str:  # type: ignore[override]
        if self.label:
            return self.label
        parts = [f"{w:g}*{m.name}" if w != 1.0 else m.name for w, m in self.terms]
        if self.constant:
            parts.append(f"{self.constant:g}")
        return " + ".join(parts) or "0"

    def __add__(self, other):
        if isinstance(other, Measure):
            o = Combination.of(other)
            return Combination(self.terms + o.terms, self.constant + o.constant, self.unit)
        return Combination(self.terms, self.constant + float(other), self.unit)

    __radd__ = __add__

    def __neg__(self):
        return self * -1.0

    def __mul__(self, k):
        k = float(k)
        return Combination(tuple((w * k, m) for w, m in self.terms), self.constant * k, self.unit)

    __rmul__ = __mul__

    def bind(self, mechanism_class) -> Combination:
        terms = tuple((w, m.bind(mechanism_class)) for w, m in self.terms)
        return Combination(terms, self.constant, self.unit, self.label)

    def from_motion(self, mechanism, motion):
        total = self.constant
        for w, m in self.terms:
            total = total + w * m.from_motion(mechanism, motion)
        return total


@dataclass(frozen=True, eq=False)
class Constraint:
    """``measure <op> bound`` with op one of ``<=``, ``>=``, ``==``."""

    measure: Measure
    op: str
    bound: float
    tol: float = field(default=1e-6)

    def __post_init__(self):
        if self.op not in ("<=", ">=", "=="):
            raise MechanismError(f"constraint operator must be <=, >= or ==, got {self.op!r}")
        object.__setattr__(self, "bound", float(self.bound))

    @property
    def name(self) -> str:
        return f"{self.measure.name} {self.op} {self.bound:g}"

    def violation(self, value):
        """How far ``value`` is outside the constraint (0 when satisfied)."""
        if self.op == "<=":
            return np.maximum(value - self.bound, 0.0)
        if self.op == ">=":
            return np.maximum(self.bound - value, 0.0)
        return np.abs(value - self.bound)

    def __bool__(self):
        raise TypeError("a Constraint has no truth value; pass it to Problem.subject_to")
