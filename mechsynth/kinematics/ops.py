"""Elementary functions that work on numpy arrays and on CasADi symbols alike.

Every model in mechsynth is written once with these functions (and plain arithmetic), so the same
code evaluates vectorized in numpy over crank angles and designs, and builds CasADi expressions
whose exact derivatives feed IPOPT. Dispatch is by argument type; numpy is the fast path.
"""

from __future__ import annotations

import numpy as np

from ..validate import finite  # noqa: F401  (the blocks' one-pass finite test)

__all__ = [
    "is_symbolic",
    "is_zero",
    "zeros_like",
    "zero_rows",
    "plus",
    "minus",
    "shifted",
    "full_like",
    "sin",
    "cos",
    "cos_sin",
    "tan",
    "sqrt",
    "arctan2",
    "arcsin",
    "arccos",
    "fabs",
    "where",
    "fmax",
    "fmin",
    "hypot",
]


#: types that are never symbolic (checked first: the numpy path is the hot one)
_NUMERIC = frozenset({np.ndarray, float, int, bool, np.float64, np.bool_, np.int64})


def is_symbolic(*values) -> bool:
    """True if any value is a CasADi SX/MX/DM object."""
    for v in values:
        t = type(v)
        if t not in _NUMERIC and t.__module__.startswith("casadi"):
            return True
    return False


def is_zero(x) -> bool:
    """True if ``x`` is the number 0 (not an array, not a symbol): lets a block skip the work a
    zero parameter makes void (a guide along +x needs no rotation into its frame)."""
    return (type(x) is float or type(x) is int) and x == 0


def zeros_like(x):
    """Zeros of the shape of ``x``: a fresh array for an array, ``0 * x`` otherwise (a number
    or a CasADi expression)."""
    if type(x) is np.ndarray:
        return np.zeros(x.shape)
    return 0.0 * x


def plus(c, x):
    """``c + x`` as a new array: a copy of ``x`` when ``c`` is the number 0 (cheaper than the
    addition, and never ``x`` itself, which another output may hold)."""
    if type(x) is np.ndarray and (type(c) is float or type(c) is int) and c == 0:  # is_zero
        if x.dtype is _FLOAT64 or x.dtype.kind == "f":  # numpy's float64 by identity first
            return x.copy()
    return c + x


def minus(a, b):
    """``a - b``, or ``-b`` when ``a`` is the number 0 (a frame pivot's coordinate or analog,
    for the blocks: ``is_zero`` inline)."""
    if (type(a) is float or type(a) is int) and a == 0:
        return -b
    return a - b


def shifted(x, c):
    """``x - c``, or ``x`` itself when ``c`` is the number 0 (for the blocks' own use only:
    ``x`` may be returned; ``is_zero`` inline)."""
    if (type(c) is float or type(c) is int) and c == 0:
        return x
    return x - c


def full_like(x, c):
    """A new array of the shape of ``x`` holding the number ``c``; ``c + 0 * x`` for anything
    else (an array of values broadcasts, a symbol stays one)."""
    if type(x) is np.ndarray and type(c) is float:
        out = np.empty(x.shape)
        out.fill(c)
        return out
    return c + zeros_like(x)


def zero_rows(x, k: int) -> list:
    """``k`` zeros of the shape of ``x``: for an array, separate arrays (the rows of one
    allocation: changing one leaves the others alone), else ``k`` times ``0 * x``."""
    if type(x) is np.ndarray:
        return list(np.zeros((k, *x.shape)))
    return [0.0 * x] * k


def _ca():
    import casadi

    return casadi


def sin(x):
    if type(x) in _NUMERIC:
        return np.sin(x)
    return _ca().sin(x) if is_symbolic(x) else np.sin(x)


def cos(x):
    if type(x) in _NUMERIC:
        return np.cos(x)
    return _ca().cos(x) if is_symbolic(x) else np.cos(x)


def cos_sin(phi):
    """``cos(phi), sin(phi)``. For a float array (of up to 65,536 angles) those of the last grid
    are remembered (a loop over designs or a sweep reuses one grid of crank angles): the grid is
    compared bit for bit, so an edited array is never mistaken for it. The arrays returned may
    be shared between calls: callers never change them in place."""
    if type(phi) is not np.ndarray or phi.dtype is not _FLOAT64 or phi.size > _GRID_MAX:
        return cos(phi), sin(phi)
    key = phi.tobytes()
    last = _GRID[0]
    if last is not None and last[1] == key and last[0] == phi.shape:  # bytes first: a new
        return last[2], last[3]  # grid differs in them at once
    c, s = np.cos(phi), np.sin(phi)
    _GRID[0] = (phi.shape, key, c, s)
    return c, s


#: the last grid's shape, bytes, cosines and sines (one tuple: replaced in one step)
_GRID: list = [None]
#: numpy's float64 (a float array of another dtype object, e.g. byte-swapped, is not
#: remembered)
_FLOAT64 = np.dtype(np.float64)
#: largest grid (angles) remembered: a grid of angles, not a batch's worth of memory
_GRID_MAX = 1 << 16


def tan(x):
    if type(x) in _NUMERIC:
        return np.tan(x)
    return _ca().tan(x) if is_symbolic(x) else np.tan(x)


def sqrt(x):
    if type(x) in _NUMERIC:
        return np.sqrt(x)
    return _ca().sqrt(x) if is_symbolic(x) else np.sqrt(x)


def arctan2(y, x):
    if type(y) in _NUMERIC and type(x) in _NUMERIC:
        return np.arctan2(y, x)
    return _ca().atan2(y, x) if is_symbolic(y, x) else np.arctan2(y, x)


def arcsin(x):
    if type(x) in _NUMERIC:
        return np.arcsin(x)
    return _ca().asin(x) if is_symbolic(x) else np.arcsin(x)


def arccos(x):
    if type(x) in _NUMERIC:
        return np.arccos(x)
    return _ca().acos(x) if is_symbolic(x) else np.arccos(x)


def fabs(x):
    if type(x) in _NUMERIC:
        return np.abs(x)
    return _ca().fabs(x) if is_symbolic(x) else np.abs(x)


def hypot(x, y):
    return _ca().sqrt(x * x + y * y) if is_symbolic(x, y) else np.hypot(x, y)


def fmax(a, b):
    return _ca().fmax(a, b) if is_symbolic(a, b) else np.maximum(a, b)


def fmin(a, b):
    return _ca().fmin(a, b) if is_symbolic(a, b) else np.minimum(a, b)


def where(cond, a, b):
    """``a`` where ``cond`` else ``b`` (``casadi.if_else`` for symbols)."""
    if is_symbolic(cond, a, b):
        return _ca().if_else(cond, a, b)
    return np.where(cond, a, b)
