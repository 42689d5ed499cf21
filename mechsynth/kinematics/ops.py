"""Elementary functions that work on numpy arrays and on CasADi symbols alike.

Every model in mechsynth is written once with these functions (and plain arithmetic), so the same
code evaluates vectorized in numpy over crank angles and designs, and builds CasADi expressions
whose exact derivatives feed IPOPT. Dispatch is by argument type; numpy is the fast path.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "is_symbolic",
    "sin",
    "cos",
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


def is_symbolic(*values) -> bool:
    """True if any value is a CasADi SX/MX/DM object."""
    return any(type(v).__module__.startswith("casadi") for v in values)


def _ca():
    import casadi

    return casadi


def sin(x):
    return _ca().sin(x) if is_symbolic(x) else np.sin(x)


def cos(x):
    return _ca().cos(x) if is_symbolic(x) else np.cos(x)


def tan(x):
    return _ca().tan(x) if is_symbolic(x) else np.tan(x)


def sqrt(x):
    return _ca().sqrt(x) if is_symbolic(x) else np.sqrt(x)


def arctan2(y, x):
    return _ca().atan2(y, x) if is_symbolic(y, x) else np.arctan2(y, x)


def arcsin(x):
    return _ca().asin(x) if is_symbolic(x) else np.arcsin(x)


def arccos(x):
    return _ca().acos(x) if is_symbolic(x) else np.arccos(x)


def fabs(x):
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
