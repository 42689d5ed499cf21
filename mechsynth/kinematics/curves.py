"""Profile curves for higher pairs (cams): a circle, the involute of a circle, or a user's curve.

A curve lies in the frame of the link that carries it (origin at the link's base point, x axis
along the link) and is parametrized by ``sigma``; :meth:`Curve.jet` returns the point and its
first three derivatives with respect to ``sigma``, which the contact block needs (the normal of
a roller's centre curve involves the third derivative). Built-in curves have them in closed
form; a :class:`ParametricCurve` gets them from its function by forward-mode Taylor
arithmetic (:mod:`~mechsynth.kinematics.taylor`), exactly.

Orientation: a closed curve is traversed counter-clockwise (its material on the left); the
*right* normal of the direction of travel points out of a counter-clockwise closed profile.

Every dimension of a curve (its *roles*, e.g. ``radius``) becomes a named parameter of the
linkage that carries it; give a value, or :class:`~mechsynth.kinematics.linkage.Param` to name
it yourself.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from ..errors import MechanismError
from . import ops
from .taylor import Taylor

__all__ = ["Curve", "Circle", "Involute", "ParametricCurve"]


class Curve:
    """Base of the profile curves.

    Attributes
    ----------
    roles : ``{role: (raw value, kind)}`` of the curve's dimensions; ``kind`` is ``"length"``
        (positive), ``"coordinate"`` or ``"angle"``.
    domain : ``(lo, hi)`` of ``sigma``; ``closed`` curves repeat with period ``hi - lo``.
    """

    kind: str = "curve"
    closed: bool = False

    def __init__(self, roles: Mapping[str, tuple[Any, str]], domain, closed: bool):
        self.roles = dict(roles)
        lo, hi = (float(v) for v in domain)
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise MechanismError(
                f"{self.kind} domain must be finite (lo, hi) with lo < hi, got {domain}"
            )
        self.domain = (lo, hi)
        self.closed = bool(closed)

    def jet(self, sigma, p: Mapping[str, Any]):
        """``(x, y, x', y', x'', y'', x''', y''')`` at ``sigma`` for the role values ``p``."""
        raise NotImplementedError

    def describe(self) -> str:
        return self.kind

    def __repr__(self) -> str:
        roles = ", ".join(f"{k}={v[0]!r}" for k, v in self.roles.items())
        return f"{type(self).__name__}({roles}, domain={self.domain})"


class Circle(Curve):
    """Circle of ``radius`` (m) about ``center`` = (u, v) (m) in the carrying link's frame,
    counter-clockwise from the link's x axis: ``sigma`` is the polar angle about the centre.
    An eccentric circular cam is a circle whose centre is off the link's pivot."""

    kind = "circle"

    def __init__(self, radius, center=(0.0, 0.0)):
        cu, cv = center
        super().__init__(
            {
                "radius": (radius, "length"),
                "center_u": (cu, "coordinate"),
                "center_v": (cv, "coordinate"),
            },
            (0.0, 2.0 * np.pi),
            True,
        )

    def jet(self, sigma, p):
        r = p["radius"]
        c, s = ops.cos(sigma), ops.sin(sigma)
        rc, rs = r * c, r * s
        return p["center_u"] + rc, p["center_v"] + rs, -rs, rc, -rc, -rs, rs, -rc


class Involute(Curve):
    """Involute of the circle of ``base_radius`` (m) about ``center`` (u, v) in the carrying
    link's frame, unwound counter-clockwise from the polar angle ``phase`` (rad):

        x = u + rb (cos(sigma + phase) + sigma sin(sigma + phase))
        y = v + rb (sin(sigma + phase) - sigma cos(sigma + phase))

    ``sigma`` is the roll angle (rad), over ``roll = (lo, hi)`` with ``lo > 0`` (the cusp at
    ``sigma = 0`` has no tangent). Its normal is tangent to the base circle at every point, so a
    follower pushed along that tangent feels no side force (paper 001's five-link).
    """

    kind = "involute"

    def __init__(self, base_radius, center=(0.0, 0.0), phase=0.0, roll=(0.05, 2.0)):
        cu, cv = center
        if float(roll[0]) <= 0.0:
            raise MechanismError(
                f"involute roll angles must start above 0 (the cusp has no tangent), got {roll}"
            )
        super().__init__(
            {
                "base_radius": (base_radius, "length"),
                "center_u": (cu, "coordinate"),
                "center_v": (cv, "coordinate"),
                "phase": (phase, "angle"),
            },
            roll,
            False,
        )

    def jet(self, sigma, p):
        rb = p["base_radius"]
        a = sigma + p["phase"]
        c, s = rb * ops.cos(a), rb * ops.sin(a)
        return (
            p["center_u"] + c + sigma * s,
            p["center_v"] + s - sigma * c,
            sigma * c,
            sigma * s,
            c - sigma * s,
            s + sigma * c,
            -2.0 * s - sigma * c,
            2.0 * c - sigma * s,
        )


class ParametricCurve(Curve):
    """A user's smooth curve ``fn(sigma, **params) -> (x, y)`` (m, in the carrying link's
    frame), written with :mod:`~mechsynth.kinematics.ops` (or numpy ufuncs) and arithmetic.
    Its derivatives are exact (Taylor arithmetic on ``fn``).

    Parameters
    ----------
    fn : the curve.
    params : ``{name: value}`` of ``fn``'s keyword parameters (each a linkage parameter; kinds
        ``"coordinate"``: any finite value).
    domain : ``(lo, hi)`` of ``sigma``.
    closed : True when ``fn`` has period ``hi - lo`` and is traversed counter-clockwise.

    Examples
    --------
    An ellipse with half-axes a and b:

    >>> from mechsynth.kinematics import ops
    >>> ell = ParametricCurve(lambda t, a, b: (a * ops.cos(t), b * ops.sin(t)),
    ...                       params={"a": 0.04, "b": 0.03}, domain=(0, 2 * np.pi), closed=True)
    >>> [round(float(v), 6) for v in ell.jet(0.0, {"a": 0.04, "b": 0.03})]
    [0.04, 0.0, 0.0, 0.03, -0.04, 0.0, 0.0, -0.03]
    """

    kind = "parametric curve"

    def __init__(
        self,
        fn: Callable,
        params: Mapping[str, Any] | None = None,
        domain=(0.0, 2.0 * np.pi),
        closed: bool = False,
    ):
        if not callable(fn):
            raise TypeError(f"fn must be a function sigma -> (x, y), got {fn!r}")
        self.fn = fn
        super().__init__({k: (v, "coordinate") for k, v in (params or {}).items()}, domain, closed)

    def jet(self, sigma, p):
        out = self.fn(Taylor.variable(sigma), **{k: p[k] for k in self.roles})
        try:
            x, y = out
        except (TypeError, ValueError):
            raise MechanismError(f"the curve function must return (x, y), got {out!r}") from None
        # a coordinate that does not depend on sigma comes back as a plain value
        x = x if isinstance(x, Taylor) else Taylor((x + 0.0 * sigma,) + (0.0 * sigma,) * 3)
        y = y if isinstance(y, Taylor) else Taylor((y + 0.0 * sigma,) + (0.0 * sigma,) * 3)
        x0, x1, x2, x3 = x.derivatives()
        y0, y1, y2, y3 = y.derivatives()
        return x0, y0, x1, y1, x2, y2, x3, y3
