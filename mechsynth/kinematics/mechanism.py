"""Base class and parameter validation shared by all mechanisms.

A mechanism is a frozen dataclass of its parameters (SI units). A parameter may be a number, a
numpy array (a batch of designs, broadcast against the crank angles: give it a trailing axis of
length 1, e.g. ``crank=np.linspace(.05, .1, 100)[:, None]``) or a CasADi symbol (inside an
optimizer). Numeric parameters are validated on construction; symbolic ones are not.
"""

from __future__ import annotations

import dataclasses
from typing import Any, ClassVar

import numpy as np

from ..errors import MechanismError
from . import ops
from .tracks import Motion

__all__ = ["Mechanism", "check_length", "check_finite", "speed_pair", "fail_where"]


def _first_bad(arr, bad):
    idx = np.unravel_index(int(np.argmax(bad)), bad.shape)
    at = f" (design index {idx})" if arr.ndim else ""
    return arr[idx], at


def check_finite(name: str, value):
    """Return ``value`` (float or float array) or raise ValueError if any entry is not finite."""
    if ops.is_symbolic(value):
        return value
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a number, got {value!r}") from exc
    bad = ~np.isfinite(arr)
    if np.any(bad):
        v, at = _first_bad(arr, bad)
        raise ValueError(f"{name} must be finite, got {v}{at}")
    return float(arr) if arr.ndim == 0 else arr


def check_length(name: str, value):
    """Return ``value`` or raise ValueError if any entry is not finite and strictly positive."""
    value = check_finite(name, value)
    if ops.is_symbolic(value):
        return value
    arr = np.asarray(value)
    bad = arr <= 0.0
    if np.any(bad):
        v, at = _first_bad(arr, bad)
        raise ValueError(f"{name} must be positive (a length in m), got {v}{at}")
    return value


def speed_pair(speed, epsilon):
    """(omega, epsilon) for a motion: analogs (1, 0) when ``speed`` is None."""
    if speed is None:
        if not ops.is_symbolic(epsilon) and np.any(np.asarray(epsilon) != 0.0):
            raise ValueError("epsilon (crank angular acceleration) needs a speed")
        return 1.0, 0.0
    if not ops.is_symbolic(speed):
        speed = check_finite("speed", speed)
    if not ops.is_symbolic(epsilon):
        epsilon = check_finite("epsilon", epsilon)
    return speed, epsilon


def fail_where(condition, template: str, **values):
    """Raise MechanismError if ``condition`` holds for any design (numpy only; symbols pass).

    ``template`` is formatted with ``values`` taken at the first failing design (as ``.6g``) and
    ``{at}``, which names that design's index in a batch (empty for a single design).
    """
    if ops.is_symbolic(condition, *values.values()):
        return
    cond = np.asarray(condition)
    if not np.any(cond):
        return
    idx = np.unravel_index(int(np.argmax(cond)), cond.shape) if cond.ndim else ()
    picked = {
        k: f"{float(np.broadcast_to(np.asarray(v, dtype=float), cond.shape)[idx]):.6g}"
        for k, v in values.items()
    }
    at = f" (design index {tuple(int(i) for i in idx)})" if cond.ndim else ""
    raise MechanismError(template.format(at=at, **picked))


class Mechanism:
    """Base of the named mechanisms (frozen dataclasses of their parameters).

    Subclasses implement :meth:`motion`. ``parameters`` lists the numeric fields that a
    :class:`~mechsynth.synthesis.Problem` may vary.
    """

    parameters: ClassVar[tuple[str, ...]] = ()
    #: main output for objectives that name none ("slider" or a point name)
    default_output: ClassVar[str] = "slider"

    def motion(self, phi, speed=None, epsilon=0.0, **kwargs) -> Motion:  # pragma: no cover
        raise NotImplementedError

    def replace(self, **changes) -> Mechanism:
        """A copy with some parameters changed (validated again)."""
        return dataclasses.replace(self, **changes)

    def params(self) -> dict[str, Any]:
        """The parameters as a dict ``{name: value}``."""
        return {name: getattr(self, name) for name in self.parameters}

    @property
    def is_symbolic(self) -> bool:
        return ops.is_symbolic(*self.params().values())
