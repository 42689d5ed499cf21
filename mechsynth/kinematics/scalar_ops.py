"""Scalar, compiled stand-ins for :mod:`~mechsynth.kinematics.ops`, for the batch kernels.

:mod:`~mechsynth.kinematics.compiled` compiles the model's own block functions with numba after
rebinding their global ``ops`` to this module (and their assembly checks to the two functions at
the end), so the kernels run the very code of :mod:`~mechsynth.kinematics.blocks` on scalars. The
names and meanings match :mod:`ops` one for one. Imported only when numba is.

``arctan2`` is written out branch-free (a libm call would keep LLVM from vectorizing the loop
over crank angles): the rational approximation of Cephes' ``atan`` (S. L. Moshier) on the
reduced range, within 2 ulp of ``numpy.arctan2`` away from the signed zeros.
"""

from __future__ import annotations

import math

import numba

_jit = numba.njit(error_model="numpy", inline="always", cache=True)

_P0, _P1, _P2, _P3, _P4 = (
    -8.750608600031904122785e-1,
    -1.615753718733365076637e1,
    -7.500855792314704667340e1,
    -1.228866684490136173410e2,
    -6.485021904942025371773e1,
)
_Q0, _Q1, _Q2, _Q3, _Q4 = (
    2.485846490142306297962e1,
    1.650270098316988542046e2,
    4.328810604912902668951e2,
    4.853903996359136964868e2,
    1.945506571482613964425e2,
)
_MOREBITS = 6.123233995736765886130e-17  # pi/2 - float(pi/2)
_PIO4, _PIO2, _PI = math.pi / 4, math.pi / 2, math.pi


@_jit
def is_zero(x):
    return x == 0.0


@_jit
def zeros_like(x):
    return 0.0


@_jit
def full_like(x, c):
    return c


@_jit
def plus(c, x):
    return c + x


@_jit
def minus(a, b):
    return -b if a == 0.0 else a - b


@_jit
def shifted(x, c):
    return x if c == 0.0 else x - c


@_jit
def zero_rows(x, k):
    return [0.0] * k


@_jit
def cos_sin(x):
    return math.cos(x), math.sin(x)


@_jit
def sin(x):
    return math.sin(x)


@_jit
def cos(x):
    return math.cos(x)


@_jit
def tan(x):
    return math.tan(x)


@_jit
def sqrt(x):
    return math.sqrt(x)


@_jit
def arcsin(x):
    return math.asin(x)


@_jit
def arccos(x):
    return math.acos(x)


@_jit
def fabs(x):
    return abs(x)


@_jit
def hypot(x, y):
    return math.sqrt(x * x + y * y)


@_jit
def fmax(a, b):
    return a if a >= b else b


@_jit
def fmin(a, b):
    return a if a <= b else b


@_jit
def where(cond, a, b):
    return a if cond else b


@_jit
def arctan2(y, x):
    ax, ay = abs(x), abs(y)
    swap = ay > ax
    big = ay if swap else ax
    small = ax if swap else ay
    r = small / (big if big > 0.0 else 1.0)  # in [0, 1]
    red = r > 0.66
    u = (r - 1.0 if red else r) / (r + 1.0 if red else 1.0)
    z = u * u
    p = (((_P0 * z + _P1) * z + _P2) * z + _P3) * z + _P4
    q = ((((z + _Q0) * z + _Q1) * z + _Q2) * z + _Q3) * z + _Q4
    a = u + u * (z * p / q)
    a = (_PIO4 + (a + 0.5 * _MOREBITS)) if red else a
    a = (_PIO2 - a + _MOREBITS) if swap else a
    a = (_PI - a + 2.0 * _MOREBITS) if x < 0.0 else a
    return -a if y < 0.0 else a


# The kernels' stand-ins for the blocks' assembly checks. The checks cannot raise inside a
# parallel loop; compiled.py sends every design that could come near a failure to the numpy model
# (which raises with the crank angle) before trusting a kernel's rows.
@_jit
def check_nonnegative(value, scale, what, phi=None):
    return 0.0 if value < 0.0 else value


@_jit
def failed(phi, a1, a2=0.0):
    return False


@_jit
def check_toggle(what, phi, a1, a2=0.0, a3=0.0, a4=0.0):  # numba's inliner takes no *args
    return None
