"""Cognates of a path-generating four-bar (Roberts-Chebyshev).

Three four-bars trace the same coupler curve. With the crank vector ``a = A - O1``, the coupler
``b = B - A``, the rocker ``c = B - O2`` and the coupler point ``P = A + k b`` (``k`` complex,
the coupler triangle), the loop ``a + b = (O2 - O1) + c`` gives three ways to reach P:

* ``P = O1 + a + k b`` (the four-bar itself),
* ``P = O2 + c + (k - 1) b``,
* ``P = O3 + (1 - k) a + k c`` with ``O3 = O1 + k (O2 - O1)``.

Pairing the last two, the links ``O3 G = (1 - k) a`` (turning with the crank),
``O2 F = (k - 1) b`` and the coupler G F carrying P (turning with the rocker) form a four-bar
driven by a crank at O3 through the same angles: the *crank-driven cognate*, whose crank angle
is the original's plus a constant. The third cognate is driven by the original's coupler angle,
a double-rocker when the original is a crank-rocker; it is not returned.
"""

from __future__ import annotations

import numpy as np

__all__ = ["crank_cognate"]


def _c(xy) -> complex:
    return complex(xy[0], xy[1])


def crank_cognate(sol, targets, objective="squares"):
    """The crank-driven cognate of ``sol`` (a PathSolution) as a PathSolution evaluated at the
    ``targets`` (note ``"cognate of #1"``), or None when it is not a four-bar whose crank turns
    fully."""
    from .path_generation import evaluated

    pos = sol.positions(sol.angles[:1])
    o1, a, b, o2, p = (_c(pos[k][0]) for k in ("O1", "A", "B", "O2", "P"))
    k = (p - a) / (b - a)
    o3 = o1 + k * (o2 - o1)
    g = o3 + (1 - k) * (a - o1)
    f = o2 + (k - 1) * (b - a)
    angle = float(np.angle(o2 - o3))
    w = (p - g) * abs(f - g) / (f - g)
    vals = {
        "crank": abs(g - o3),
        "coupler": abs(f - g),
        "rocker": abs(f - o2),
        "ground": abs(o2 - o3),
        "u": w.real,
        "v": w.imag,
        "x0": o3.real,
        "y0": o3.imag,
        "angle": angle,
    }
    if min(vals["crank"], vals["coupler"], vals["rocker"], vals["ground"]) <= 0:
        return None
    branch = "open" if ((f - g) / (o2 - g)).imag > 0 else "crossed"
    shift = sol.angle + float(np.angle(1 - k)) - angle
    return evaluated(vals, branch, sol.angles + shift, targets, objective, "cognate of #1")
