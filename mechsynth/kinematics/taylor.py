"""Truncated Taylor series (forward-mode derivatives to third order) for user-written curves.

A profile curve given by the user as a function ``sigma -> (x, y)`` written with
:mod:`~mechsynth.kinematics.ops` (or numpy) is evaluated once on a :class:`Taylor` variable
``sigma + t`` and returns ``x`` and ``y`` as series in ``t``; their coefficients give the first,
second and third derivatives with respect to ``sigma`` exactly (no finite differences). The
coefficients may be numbers, numpy arrays (many ``sigma`` at once) or CasADi symbols (a curve
with symbolic parameters inside an optimizer): every operation is written with ``ops``.

Supported: ``+ - * /``, ``**`` by a constant, and the ufuncs ``sin cos tan exp log sqrt arctan
arctan2 hypot abs`` (``ops.sin`` etc. or ``np.sin`` etc.).

>>> import numpy as np
>>> t = Taylor.variable(0.5)
>>> y = np.sin(t) * t
>>> [round(float(v), 12) for v in y.derivatives()]
[0.239712769302, 0.918216819549, 1.515452354479, -1.877067896758]
"""

from __future__ import annotations

import numpy as np

from . import ops

__all__ = ["Taylor", "ORDER"]

ORDER = 3  # derivatives carried: value, d1, d2, d3


def _series(x):
    """Coefficients of ``x`` (a Taylor or a constant)."""
    if isinstance(x, Taylor):
        return x.c
    return (x,) + (0.0,) * ORDER


class Taylor:
    """``c[0] + c[1] t + c[2] t^2 + c[3] t^3`` (Taylor coefficients: ``c[k] = f^(k) / k!``)."""

    __slots__ = ("c",)
    __array_priority__ = 1000

    def __init__(self, coefficients):
        self.c = tuple(coefficients)

    @classmethod
    def variable(cls, value):
        """The independent variable at ``value``: ``value + t``."""
        return cls((value, 1.0 + 0.0 * value) + (0.0,) * (ORDER - 1))

    def derivatives(self):
        """``(f, f', f'', f''')``."""
        c = self.c
        return c[0], c[1], 2.0 * c[2], 6.0 * c[3]

    # -------------------------------------------------------------- arithmetic
    def __add__(self, other):
        o = _series(other)
        return Taylor(a + b for a, b in zip(self.c, o))

    __radd__ = __add__

    def __neg__(self):
        return Taylor(-a for a in self.c)

    def __pos__(self):
        return self

    def __sub__(self, other):
        return self + (-other)

    def __rsub__(self, other):
        return (-self) + other

    def __mul__(self, other):
        if not isinstance(other, Taylor):
            return Taylor(a * other for a in self.c)
        a, b = self.c, other.c
        return Taylor(sum(a[j] * b[k - j] for j in range(k + 1)) for k in range(ORDER + 1))

    __rmul__ = __mul__

    def __truediv__(self, other):
        if not isinstance(other, Taylor):
            return Taylor(a / other for a in self.c)
        u, v = self.c, other.c
        q = []
        for k in range(ORDER + 1):
            acc = u[k]
            for j in range(1, k + 1):
                acc = acc - v[j] * q[k - j]
            q.append(acc / v[0])
        return Taylor(q)

    def __rtruediv__(self, other):
        return Taylor(_series(other)) / self

    def __pow__(self, p):
        if isinstance(p, Taylor):
            return _exp(_log(self) * p)
        if isinstance(p, int) and 0 <= p <= 4:
            out = Taylor(_series(1.0 + 0.0 * self.c[0]))
            for _ in range(p):
                out = out * self
            return out
        a = self.c
        y = [a[0] ** p]
        for k in range(1, ORDER + 1):
            acc = 0.0
            for j in range(1, k + 1):
                acc = acc + ((p + 1.0) * j - k) * a[j] * y[k - j]
            y.append(acc / (k * a[0]))
        return Taylor(y)

    # -------------------------------------------------------------- numpy ufuncs
    def __array_ufunc__(self, ufunc, method, *inputs, **kwargs):
        if method != "__call__" or kwargs:
            return NotImplemented
        fn = _UFUNCS.get(ufunc)
        if fn is None:
            raise TypeError(
                f"{ufunc.__name__} is not supported in a curve function (Taylor derivatives); "
                "use + - * / ** and sin, cos, tan, exp, log, sqrt, arctan, arctan2, hypot, abs"
            )
        return fn(*inputs)

    def __array_function__(self, func, types, args, kwargs):
        raise TypeError(
            f"numpy.{func.__name__} is not supported in a curve function (Taylor derivatives): "
            "write the curve as one smooth expression"
        )

    def __repr__(self) -> str:
        return f"Taylor{self.c!r}"


def _integrate(value0, derivative: Taylor) -> Taylor:
    """The series whose value is ``value0`` and whose derivative is ``derivative``."""
    d = derivative.c
    return Taylor((value0,) + tuple(d[k - 1] / k for k in range(1, ORDER + 1)))


def _d(x: Taylor) -> Taylor:
    """Derivative series (the last coefficient is lost: truncated to order - 1, padded)."""
    c = x.c
    return Taylor(tuple((k + 1) * c[k + 1] for k in range(ORDER)) + (0.0 * c[0],))


def _exp(x):
    a = x.c
    e = [ops_exp(a[0])]
    for k in range(1, ORDER + 1):
        acc = 0.0
        for j in range(1, k + 1):
            acc = acc + j * a[j] * e[k - j]
        e.append(acc / k)
    return Taylor(e)


def ops_exp(v):
    if ops.is_symbolic(v):
        import casadi

        return casadi.exp(v)
    return np.exp(v)


def ops_log(v):
    if ops.is_symbolic(v):
        import casadi

        return casadi.log(v)
    return np.log(v)


def _log(x):
    return _integrate(ops_log(x.c[0]), _d(x) / x)


def _sincos(x):
    a = x.c
    s = [ops.sin(a[0])]
    c = [ops.cos(a[0])]
    for k in range(1, ORDER + 1):
        acc_s, acc_c = 0.0, 0.0
        for j in range(1, k + 1):
            acc_s = acc_s + j * a[j] * c[k - j]
            acc_c = acc_c - j * a[j] * s[k - j]
        s.append(acc_s / k)
        c.append(acc_c / k)
    return Taylor(s), Taylor(c)


def _sqrt(x):
    a = x.c
    r = [ops.sqrt(a[0])]
    for k in range(1, ORDER + 1):
        acc = a[k]
        for j in range(1, k):
            acc = acc - r[j] * r[k - j]
        r.append(acc / (2.0 * r[0]))
    return Taylor(r)


def _arctan2(y, x):
    y = y if isinstance(y, Taylor) else Taylor(_series(y))
    x = x if isinstance(x, Taylor) else Taylor(_series(x))
    return _integrate(ops.arctan2(y.c[0], x.c[0]), (x * _d(y) - y * _d(x)) / (x * x + y * y))


def _arctan(x):
    return _integrate(ops.arctan2(x.c[0], 1.0 + 0.0 * x.c[0]), _d(x) / (1.0 + x * x))


def _fabs(x):
    sign = ops.where(x.c[0] < 0, -1.0 + 0.0 * x.c[0], 1.0 + 0.0 * x.c[0])
    return Taylor(sign * a for a in x.c)


def _lift(x):
    return x if isinstance(x, Taylor) else Taylor(_series(x))


_UFUNCS = {
    np.add: lambda a, b: _lift(a) + b,
    np.subtract: lambda a, b: _lift(a) - b,
    np.multiply: lambda a, b: _lift(a) * b,
    np.true_divide: lambda a, b: _lift(a) / b,
    np.negative: lambda a: -a,
    np.power: lambda a, p: _lift(a) ** p,
    np.sin: lambda a: _sincos(a)[0],
    np.cos: lambda a: _sincos(a)[1],
    np.tan: lambda a: _sincos(a)[0] / _sincos(a)[1],
    np.exp: _exp,
    np.log: _log,
    np.sqrt: _sqrt,
    np.arctan: _arctan,
    np.arctan2: _arctan2,
    np.hypot: lambda a, b: _sqrt(_lift(a) * a + _lift(b) * b),
    np.absolute: _fabs,
}
