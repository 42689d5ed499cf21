"""Unit helpers. mechsynth works in SI inside: m, kg, s, rad, N.

These helpers convert the units engineers type (degrees, rpm, strokes per minute, inches) into SI
and back. All accept scalars or arrays.
"""

from __future__ import annotations

import numpy as np

from .errors import MechanismError

__all__ = [
    "deg",
    "to_deg",
    "rpm",
    "to_rpm",
    "spm",
    "inch",
    "to_inch",
    "cycle",
    "dms",
    "to_dms",
    "format_dms",
]


def deg(value):
    """Degrees -> radians."""
    return _scale(value, np.pi / 180.0, "deg: degrees")


def to_deg(value):
    """Radians -> degrees."""
    return _scale(value, 180.0 / np.pi, "to_deg: an angle in rad")


def _scale(value, factor, what="a quantity"):
    """``value * factor`` as a float or a float array. Numbers only: a string ("30"), a
    boolean, None or a complex number is refused (``MechanismError``) rather than converted;
    NaN and infinities pass (results such as an infeasible chart cell convert too)."""
    if type(value) is float or type(value) is int:
        return float(value) * factor
    if isinstance(value, (str, bytes, bool, np.bool_)) or value is None or (
        isinstance(value, complex) or np.iscomplexobj(value)
    ):
        raise MechanismError(f"{what} must be a number or an array of numbers, got {value!r}")
    if np.ndim(value):
        arr = np.asarray(value)
        if arr.dtype.kind not in "iuf":
            raise MechanismError(
                f"{what} must be an array of real numbers, got {arr.dtype} values: {value!r}"
            )
        return arr.astype(float) * factor
    try:
        return float(value) * factor
    except (TypeError, ValueError):
        raise MechanismError(f"{what} must be a number, got {value!r}") from None


def rpm(value):
    """Revolutions per minute -> rad/s."""
    return _scale(value, 2.0 * np.pi / 60.0, "rpm: a speed in rpm")


def to_rpm(value):
    """rad/s -> revolutions per minute."""
    return _scale(value, 60.0 / (2.0 * np.pi), "to_rpm: a speed in rad/s")


def spm(value):
    """Strokes per minute of a pumping unit (one crank turn per stroke) -> crank speed in rad/s."""
    return rpm(value)


def inch(value):
    """Inches -> metres."""
    return _scale(value, 0.0254, "inch: a length in inches")


def to_inch(value):
    """Metres -> inches."""
    return _scale(value, 1.0 / 0.0254, "to_inch: a length in m")


def cycle(n: int = 360, *, start: float = 0.0, endpoint: bool = False) -> np.ndarray:
    """``n`` equally spaced crank angles over one turn, in radians, starting at ``start``.

    The end point (``start + 2*pi``) is left out by default, so that every angle of the cycle is
    counted once in peaks and means.
    """
    from .validate import MAX_ANGLES, integer, number

    n = integer("cycle: n (the number of angles)", n, lo=2, hi=MAX_ANGLES)
    start = number("cycle: start", start, "rad")
    return start + np.linspace(0.0, 2.0 * np.pi, n, endpoint=endpoint)


def dms(degrees: float, minutes: float = 0.0, seconds: float = 0.0) -> float:
    """Degrees, arc-minutes and arc-seconds -> radians (``dms(65, 59, 47)``)."""
    return float(np.deg2rad(degrees + minutes / 60.0 + seconds / 3600.0))


def to_dms(angle: float) -> tuple[int, int, float]:
    """Radians -> (degrees, arc-minutes, arc-seconds), the inverse of :func:`dms` (angle >= 0)."""
    total = float(np.rad2deg(angle)) * 3600.0
    if total < 0:
        raise MechanismError(f"to_dms expects a non-negative angle, got {angle} rad")
    d, rest = divmod(total, 3600.0)
    m, s = divmod(rest, 60.0)
    return int(d), int(m), s


def format_dms(angle: float) -> str:
    """Radians -> ``'67°41\\'50"'`` rounded to the arc-second."""
    seconds = round(float(np.rad2deg(angle)) * 3600.0)
    d, rest = divmod(seconds, 3600)
    m, s = divmod(rest, 60)
    return f"{d}°{m:02d}'{s:02d}\""
