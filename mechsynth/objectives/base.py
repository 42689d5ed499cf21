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
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

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
        raise ValueError(f"unknown reduction {how!r}")
    values = np.asarray(values, dtype=float)
    if how == "max":
        return values.max(axis=-1)
    if how == "min":
        return values.min(axis=-1)
    if how == "mean":
        return values.mean(axis=-1)
    if how == "rms":
        return np.sqrt(np.mean(values * values, axis=-1))
    raise ValueError(f"unknown reduction {how!r}")


class Measure:
    """Base class: a named number of a design (``unit`` for reports)."""

    name: str = "measure"
    unit: str = ""

    def from_motion(self, mechanism, motion):
        """Value from a mechanism and its motion over a crank-angle grid."""
        raise NotImplementedError

    def evaluate(self, mechanism, phi=None, speed=None):
        """Value for ``mechanism`` over crank angles ``phi`` (default: 720 equal steps)."""
        from ..units import cycle

        phi = cycle(720) if phi is None else phi
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
    (``"max"``, ``"min"``, ``"mean"``, ``"rms"``)."""

    def __init__(
        self, name: str, per_angle: Callable[[Any, Any], Any], reduce: str = "max", unit: str = ""
    ):
        if reduce not in ("max", "min", "mean", "rms"):
            raise ValueError(f"reduce must be max, min, mean or rms, got {reduce!r}")
        self.name, self.per_angle, self.reduce, self.unit = name, per_angle, reduce, unit

    def samples(self, mechanism, motion):
        """The per-angle values (array over designs x angles, or a CasADi column)."""
        return self.per_angle(mechanism, motion)

    def from_motion(self, mechanism, motion):
        return reduce_cycle(self.samples(mechanism, motion), self.reduce)


class ScalarMeasure(Measure):
    """A closed-form property ``fn(mechanism)`` of the design."""

    def __init__(self, name: str, fn: Callable[[Any], Any], unit: str = ""):
        self.name, self.fn, self.unit = name, fn, unit

    def from_motion(self, mechanism, motion):
        return self.fn(mechanism)


@dataclass(frozen=True, eq=False)
class Combination(Measure):
    """``constant + sum(weight_i * measure_i)``."""

    terms: tuple[tuple[float, Measure], ...] = ()
    constant: float = 0.0
    unit: str = ""

    @staticmethod
    def of(measure: Measure) -> Combination:
        if isinstance(measure, Combination):
            return measure
        return Combination(((1.0, measure),), 0.0, measure.unit)

    @property
    def name(self) -> str:  # type: ignore[override]
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
            raise ValueError(f"constraint operator must be <=, >= or ==, got {self.op!r}")
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
