"""Validation at the door: every public entry point checks its arguments here.

One rule set, one kind of error: each check returns the value as the model wants it (a float or
a float array) or raises :class:`~mechsynth.errors.MechanismError` (a ``ValueError``) naming the
parameter, the value it got and the rule it broke::

    crank must be a real number (m), got '0.1' (a str)
    rod must be finite, got inf
    speed must be positive (rad/s), got -3.0

The checks cost O(1) Python work per argument (numpy does the element tests), so they sit on
every call without slowing the hot paths. CasADi symbols pass through unchecked (optimizers build
expressions, not designs).

Resource limits are checked before anything large is allocated: :func:`check_size` refuses a
request whose arrays would exceed :data:`MAX_BYTES` and says how much memory it would need.
"""

from __future__ import annotations

import math
import numbers
import operator

import numpy as np

from .errors import MechanismError

__all__ = [
    "MAX_BYTES",
    "MAX_STARTS",
    "MAX_ANGLES",
    "MAX_LENGTH",
    "real",
    "number",
    "length",
    "positive",
    "nonnegative",
    "integer",
    "angles",
    "broadcast",
    "option",
    "check_size",
    "format_bytes",
]

#: largest working set (bytes) a single call may allocate before it is refused (4 GiB)
MAX_BYTES = 4 * 2**30
#: most multi-start local solves one solve may ask for
MAX_STARTS = 10_000
#: most crank angles in one grid or cycle
MAX_ANGLES = 1_000_000
#: largest length (m) a model accepts: its squares and products stay far from overflow
MAX_LENGTH = 1e100


def _symbolic(value) -> bool:
    return type(value).__module__.startswith("casadi")


def _unit(unit: str) -> str:
    return f" ({unit})" if unit else ""


def _describe(value) -> str:
    text = repr(value)
    if len(text) > 60:
        text = text[:57] + "..."
    return f"{text} (a {type(value).__name__})"


def real(name: str, value, unit: str = "", *, allow_empty: bool = False):
    """``value`` as a finite real float (or float array), else :class:`MechanismError`.

    Refuses strings, bytes, booleans, ``None``, complex numbers (even with a zero imaginary
    part), object arrays, empty arrays (unless ``allow_empty``), NaN and infinities. CasADi
    symbols are returned unchanged.
    """
    # fast path: a plain number
    if type(value) is float or type(value) is int:
        v = float(value)
        if not math.isfinite(v):
            raise MechanismError(f"{name} must be finite, got {value!r}")
        return v
    if _symbolic(value):
        return value
    if isinstance(value, (str, bytes, bool, np.bool_)) or value is None:
        raise MechanismError(f"{name} must be a number{_unit(unit)}, got {_describe(value)}")
    if isinstance(value, numbers.Complex) and not isinstance(value, numbers.Real):
        raise MechanismError(
            f"{name} must be a real number{_unit(unit)}, got the complex {value!r}"
        )
    try:
        arr = np.asarray(value)
    except (TypeError, ValueError) as exc:  # ragged nested lists
        raise MechanismError(
            f"{name} must be a number or an array of numbers{_unit(unit)}, got {_describe(value)}"
        ) from exc
    kind = arr.dtype.kind
    if kind not in "iuf":
        what = {
            "c": "complex numbers",
            "b": "booleans",
            "U": "strings",
            "S": "bytes",
            "O": "objects that are not numbers",
            "M": "dates",
            "m": "time deltas",
        }.get(kind, f"{arr.dtype} values")
        if kind == "O":
            flat = arr.ravel()
            if all(
                isinstance(v, numbers.Real) and not isinstance(v, (bool, np.bool_)) for v in flat
            ):  # real numbers held as objects (e.g. Fractions) are fine
                arr = np.array([float(v) for v in flat], dtype=float).reshape(arr.shape)
                kind = "f"
        if kind != "f":
            raise MechanismError(
                f"{name} must be real numbers{_unit(unit)}, got {what}: {_describe(value)}"
            )
    if arr.size == 0 and not allow_empty:
        raise MechanismError(f"{name} is empty (shape {arr.shape}): give at least one value")
    arr = arr.astype(float, copy=False)
    if arr.ndim == 0:
        v = float(arr)
        if not math.isfinite(v):
            raise MechanismError(f"{name} must be finite, got {v}")
        return v
    finite = np.isfinite(arr)
    if not finite.all():
        idx = np.unravel_index(int(np.argmin(finite)), arr.shape)
        raise MechanismError(
            f"{name} must be finite, got {arr[idx]} (design index {tuple(int(i) for i in idx)})"
        )
    return arr


def _sign_check(name, value, unit, bad, rule):
    if _symbolic(value):
        return value
    if type(value) is float:
        if bad(value):
            raise MechanismError(f"{name} must be {rule}{_unit(unit)}, got {value!r}")
        return value
    arr = np.asarray(value)
    wrong = bad(arr)
    if np.any(wrong):
        idx = np.unravel_index(int(np.argmax(wrong)), arr.shape)
        at = f" (design index {tuple(int(i) for i in idx)})" if arr.ndim else ""
        raise MechanismError(f"{name} must be {rule}{_unit(unit)}, got {arr[idx]}{at}")
    return value


def number(name: str, value, unit: str = "") -> float:
    """One finite real number (not an array) as a float."""
    v = real(name, value, unit)
    if type(v) is not float:
        if _symbolic(v):
            return v
        raise MechanismError(
            f"{name} must be one number{_unit(unit)}, got an array of shape {np.shape(v)}"
        )
    return v


def radians_meant(name: str, value: float) -> None:
    """Refuse an angle beyond one turn: almost surely degrees typed as radians (``30`` for
    30 deg). The message gives the reading in radians it was probably meant to be."""
    v = float(value)
    if abs(v) > 2.0 * math.pi + 1e-9:
        raise MechanismError(
            f"{name} {v:g} rad is more than a turn ({math.degrees(v):.6g} deg): angles are in "
            f"radians; for {v:g} deg write ms.deg({v:g}) = {math.radians(v):.6g} rad "
            '(in a file or on the command line: "' + f'{v:g} deg")'
        )


def angle(name: str, value) -> float:
    """One finite angle in radians, within one turn (see :func:`radians_meant`)."""
    v = number(name, value, "rad")
    if type(v) is float:
        radians_meant(name, v)
    return v


def positive(name: str, value, unit: str = ""):
    """A finite real number (or array) > 0."""
    return _sign_check(name, real(name, value, unit), unit, lambda v: v <= 0.0, "positive")


def length(name: str, value):
    """A finite length > 0 in m (number or array of designs), at most :data:`MAX_LENGTH`."""
    value = real(name, value, "m")
    if type(value) is float:
        if value > 0.0 and value <= MAX_LENGTH:
            return value
    elif _symbolic(value) or bool(((value > 0.0) & (value <= MAX_LENGTH)).all()):
        return value
    _sign_check(name, value, "", lambda v: v <= 0.0, "positive (a length in m)")
    return _sign_check(
        name,
        value,
        "",
        lambda v: v > MAX_LENGTH,
        f"at most {MAX_LENGTH:g} m (larger lengths overflow the models' squares)",
    )


def nonnegative(name: str, value, unit: str = ""):
    """A finite real number (or array) >= 0."""
    return _sign_check(name, real(name, value, unit), unit, lambda v: v < 0.0, "at least 0")


def integer(name: str, value, lo: int | None = None, hi: int | None = None) -> int:
    """A whole number (``int``, numpy integer or a float with no fraction) within ``[lo, hi]``.

    Booleans, strings, ``None``, fractional and non-finite numbers are refused.
    """
    if isinstance(value, (bool, np.bool_)) or value is None or isinstance(value, (str, bytes)):
        raise MechanismError(f"{name} must be a whole number, got {_describe(value)}")
    try:
        n = operator.index(value)
    except TypeError:
        if isinstance(value, numbers.Real) and math.isfinite(value) and float(value).is_integer():
            n = int(value)
        else:
            raise MechanismError(f"{name} must be a whole number, got {_describe(value)}") from None
    if lo is not None and n < lo or hi is not None and n > hi:
        rng = (
            f"between {lo} and {hi}"
            if lo is not None and hi is not None
            else (f"at least {lo}" if lo is not None else f"at most {hi}")
        )
        raise MechanismError(f"{name} must be {rng}, got {n}")
    return n


def finite(x) -> bool:
    """True if every entry of the float array ``x`` is finite, in one pass: its sum is finite,
    or for up to 8,192 entries (one design's grid of angles) its dot product with itself (a
    BLAS call, quicker there than a sum; BLAS may thread a longer one). False also for a sum
    or a square that overflows (entries past about 1e154): a caller then tests entry by
    entry."""
    if x.size <= 8192:
        return math.isfinite(_vdot(x, x))
    return math.isfinite(np.add.reduce(x, axis=None))


#: numpy's dot product itself, without the ``__array_function__`` dispatch ``np.vdot`` wraps it
#: in (a third of its cost on one design's grid; ``finite`` sees numpy arrays only)
_vdot = getattr(np.vdot, "__wrapped__", np.vdot)


def angles(value, name: str = "crank angles"):
    """Crank angles (rad): a number or an array of finite real numbers (any array-like: a list,
    a tuple, a ``range``). Empty arrays are allowed (a motion over no angles is empty)."""
    if type(value) is float:
        if not math.isfinite(value):
            raise MechanismError(f"{name} must be finite (rad), got {value!r}")
        return value
    if type(value) is np.ndarray and value.dtype == np.float64:
        # one pass proves every angle finite; only its failure (a bad angle, or a sum or a
        # square past 1e308) takes the exact test
        if finite(value):
            return value
        if not np.isfinite(value).all():
            ok = np.isfinite(value)
            idx = np.unravel_index(int(np.argmin(ok)), value.shape)
            raise MechanismError(
                f"{name} must be finite (rad), got {value[idx]} at index "
                f"{tuple(int(i) for i in idx)}"
            )
        return value
    return real(name, value, "rad", allow_empty=True)


def broadcast(**arrays):
    """The common shape of the named parameters, or an error naming each one's shape."""
    shapes = {k: np.shape(v) for k, v in arrays.items() if not _symbolic(v)}
    try:
        return np.broadcast_shapes(*shapes.values())
    except ValueError:
        listed = ", ".join(f"{k} {s}" for k, s in shapes.items())
        raise MechanismError(
            f"parameter shapes do not broadcast: {listed} (a batch of designs is a column, e.g. "
            "crank=np.linspace(.05, .1, 100)[:, None])"
        ) from None


def option(name: str, value, choices):
    """``value`` if it is one of ``choices``, else an error listing them."""
    ok = isinstance(value, (str, int, float, type(None))) and any(
        type(value) is type(c) and value == c for c in choices
    )
    if not ok:
        listed = ", ".join(repr(c) for c in choices)
        raise MechanismError(f"{name} must be one of {listed}, got {_describe(value)}")
    return value


def format_bytes(n: float) -> str:
    """``n`` bytes in words: ``"7.5 GiB"``."""
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(n) < 1024 or unit == "PiB":
            return f"{n:.3g} {unit}" if unit != "B" else f"{int(n)} B"
        n /= 1024.0
    return f"{n:.3g} PiB"  # pragma: no cover


def check_size(what: str, elements: float, bytes_per_element: float = 8.0, limit=None):
    """Refuse, before allocating, a request of ``elements`` numbers that would need more than
    ``limit`` bytes (default :data:`MAX_BYTES`)."""
    limit = MAX_BYTES if limit is None else limit
    need = float(elements) * float(bytes_per_element)
    if need > limit:
        raise MechanismError(
            f"{what} would need about {format_bytes(need)} of memory (limit "
            f"{format_bytes(limit)}): split it into smaller batches"
        )
    return need
