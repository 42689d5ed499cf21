"""Fitted nomograms: curved scales for a relation ``w = f(u, v)`` with no exact nomographic form.

The approach is that of nomogen (pynomo): let the scales bend and choose their shapes so that
the alignment condition holds as well as it can over the whole domain. Here the output w lies
on a straight line (x = 0, graduated linearly or logarithmically), so it can also serve as the
turning axis of a compound chart; u and v lie on curves ``(x(t), y(t))``, each coordinate a
Chebyshev series in the scale's parameter ``t`` (0 at the low end, 1 at the high end). The
residual of a sample ``(u, v)`` is the reading error on the w line itself: where the line through
``P_u(u)`` and ``P_v(v)`` crosses x = 0, against where ``f(u, v)`` is graduated. The start is the
best additive chart (``G(w) ~ A(u) + B(v)``, a parallel-scale chart), then scipy's
``least_squares`` moves all the coefficients at once. Further outputs of the same inputs get
curved scales of their own, fitted in the same solve (their residual: the distance from their
point to the isopleth).

The accuracy of a fitted chart is what :meth:`Nomogram.check` measures by reading through the
geometry, never assumed from the fit.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ..errors import MechanismError
from .forms import Var, _as_var
from .nomogram import Nomogram
from .scales import homogeneous

__all__ = ["fitted", "Alignment"]

#: how near (base units: the output line is 1 long) the input curves may come to the line
GAP = 0.35


def _cheb(t, coef):
    return np.polynomial.chebyshev.chebval(2.0 * np.asarray(t, dtype=float) - 1.0, coef)


def _g(var: Var, values):
    """A variable's parameter in [0, 1] over its domain: its function F normalized when it
    has one (the output line's graduation), else linear or log by its spacing."""
    lo, hi = var.domain
    v = np.asarray(values, dtype=float)
    if var.fn is not None:
        a, b = var.F(np.float64(lo)), var.F(np.float64(hi))
        return (var.F(v) - a) / (b - a)
    if var.spacing == "log":
        return np.log(v / lo) / np.log(hi / lo)
    return (v - lo) / (hi - lo)


_param = _g


def _from_param(var: Var, t):
    lo, hi = var.domain
    if var.spacing == "log":
        return lo * (hi / lo) ** np.asarray(t)
    return lo + np.asarray(t) * (hi - lo)


def _with_spacing(var: Var) -> Var:
    lo, hi = (float(x) for x in var.domain)
    sp = var.spacing or ("log" if lo > 0 and hi / lo >= 10 else "linear")
    return Var(var.name, (lo, hi), var.fn, var.title, var.unit, sp, var.shown)


class Alignment:
    """The least-squares problem of a fitted chart: coefficients ``p`` = (x, y) Chebyshev
    coefficients of the u curve, then of the v curve.

    Residuals: the reading error on the output line of every lattice sample (where the line
    through ``P_u`` and ``P_v`` crosses x = 0, minus the graduation of ``f(u, v)``); barriers
    keeping u left (x <= -GAP) and v right (x >= GAP) of the line; ``even`` times each curve's
    steps between the lattice parameters minus ``1 / (grid - 1)`` (readable, evenly graduated
    scales about as long as the output line); ``1e-3 (p - p0)`` fixing the gauge. The Jacobian
    is analytic (tested against finite differences).
    """

    def __init__(self, Vu, Vv, V, Y, p0, even=0.01, reg=1e-3):
        self.Vu, self.Vv, self.V, self.Y, self.p0 = Vu, Vv, V, Y, p0
        self.n = V.shape[1]
        self.dV = np.diff(V, axis=0)
        self.even, self.reg = float(even), float(reg)

    def curves(self, p):
        n = self.n
        return (self.Vu @ p[:n], self.Vu @ p[n:2 * n], self.Vv @ p[2 * n:3 * n],
                self.Vv @ p[3 * n:])

    def _steps(self, p, k):
        n = self.n
        dx = self.dV @ p[2 * k * n:(2 * k + 1) * n]
        dy = self.dV @ p[(2 * k + 1) * n:(2 * k + 2) * n]
        return dx, dy, np.hypot(dx, dy)

    def residuals(self, p):
        xu, yu, xv, yv = self.curves(p)
        ystar = yu - xu * (yv - yu) / (xv - xu)
        target = 1.0 / len(self.dV)
        return np.concatenate([
            ystar - self.Y,
            10.0 * np.maximum(0.0, xu + GAP),
            10.0 * np.maximum(0.0, GAP - xv),
            self.even * (self._steps(p, 0)[2] - target),
            self.even * (self._steps(p, 1)[2] - target),
            self.reg * (p - self.p0),
        ])

    def jacobian(self, p):
        Vu, Vv, n = self.Vu, self.Vv, self.n
        xu, yu, xv, yv = self.curves(p)
        D, E = xv - xu, yv - yu
        J1 = np.concatenate([(-E * xv / D**2)[:, None] * Vu, (xv / D)[:, None] * Vu,
                             (xu * E / D**2)[:, None] * Vv, (-xu / D)[:, None] * Vv], axis=1)
        zu, zv = np.zeros_like(Vu), np.zeros_like(Vv)
        J2 = np.concatenate([10.0 * (xu + GAP > 0)[:, None] * Vu, zu, zv, zv], axis=1)
        J3 = np.concatenate([zu, zu, -10.0 * (GAP - xv > 0)[:, None] * Vv, zv], axis=1)
        rows = [J1, J2, J3]
        for k in (0, 1):
            dx, dy, s = self._steps(p, k)
            s = np.maximum(s, 1e-15)
            block = np.zeros((len(self.dV), 4 * n))
            block[:, 2 * k * n:(2 * k + 1) * n] = (dx / s)[:, None] * self.dV
            block[:, (2 * k + 1) * n:(2 * k + 2) * n] = (dy / s)[:, None] * self.dV
            rows.append(self.even * block)
        rows.append(self.reg * np.eye(4 * n))
        return np.concatenate(rows)


class _Block:
    """What :func:`_fit_block` gives: the scales and blocks, the output variable (its line at
    x = 0, graduated by :func:`_g` from 0 to 1), the model, the fit's report, the inputs and
    how far the curves reach from the line."""

    def __init__(self, scales, blocks, w0, model, info, inputs, reach):
        self.scales, self.blocks, self.w0, self.model = scales, blocks, w0, model
        self.info, self.inputs, self.reach = info, inputs, reach


def _fit_block(f, u, v, outputs, *, degree=6, grid=25, even=0.01, model=None) -> _Block:
    """Fit the block of ``f(u, v)`` (the arguments as :func:`fitted`'s)."""
    from scipy.optimize import least_squares

    u, v = _with_spacing(_as_var(u)), _with_spacing(_as_var(v))
    degree = int(degree)
    if not 2 <= degree <= 12:
        raise MechanismError(f"fitted: degree must be 2 to 12, got {degree}")
    outs_in = [o if isinstance(o, Var) else Var(*o) if isinstance(o, tuple) else Var(o, None)
               for o in outputs]
    if not outs_in:
        raise MechanismError("fitted: give at least one output")
    t = np.linspace(0.0, 1.0, grid)
    tu, tv = np.meshgrid(t, t, indexing="ij")
    tu, tv = tu.ravel(), tv.ravel()
    uu, vv = _from_param(u, tu), _from_param(v, tv)

    def values(a, b):
        with np.errstate(all="ignore"):  # a function undefined somewhere is refused below
            r = f(a, b)
        r = r if isinstance(r, tuple) else (r,)
        if len(r) != len(outs_in):
            raise MechanismError(f"fitted: f gives {len(r)} outputs for {len(outs_in)} scales")
        return [np.broadcast_to(np.asarray(x, dtype=float), np.shape(a)) for x in r]

    W = values(uu, vv)
    outs = []
    for o, w in zip(outs_in, W, strict=True):
        if not np.all(np.isfinite(w)):
            raise MechanismError(f"fitted: {o.name} = f(u, v) is not finite over the domain")
        if o.domain is None:
            lo, hi = float(w.min()), float(w.max())
            pad = (0.02 if o.fn is None else 1e-4) * (hi - lo)  # F may end near the range
            dom = (lo - pad, hi + pad)
            if o.fn is not None and not np.all(np.isfinite(o.F(np.array(dom)))):
                dom = (lo, hi)
        else:
            dom = o.domain
        if not dom[1] - dom[0] > 1e-12 * (abs(dom[0]) + abs(dom[1])):
            raise MechanismError(f"fitted: {o.name} does not vary over the domain")
        outs.append(_with_spacing(Var(o.name, dom, o.fn, o.title, o.unit, o.spacing, o.shown)))
    Y = _g(outs[0], W[0])
    # start: the best additive chart G(w) = A(u) + B(v) -> u at x = -1, v at x = +1
    Yg = Y.reshape(grid, grid)
    mu = Yg.mean()
    A = Yg.mean(axis=1) - mu / 2.0
    B = Yg.mean(axis=0) - mu / 2.0
    V = np.polynomial.chebyshev.chebvander(2.0 * t - 1.0, degree)
    cu = np.concatenate([np.linalg.lstsq(V, np.full(grid, -1.0), rcond=None)[0],
                         np.linalg.lstsq(V, 2.0 * A, rcond=None)[0]])
    cv = np.concatenate([np.linalg.lstsq(V, np.full(grid, 1.0), rcond=None)[0],
                         np.linalg.lstsq(V, 2.0 * B, rcond=None)[0]])
    n = degree + 1
    p0 = np.concatenate([cu, cv])
    problem = Alignment(
        np.polynomial.chebyshev.chebvander(2.0 * tu - 1.0, degree),
        np.polynomial.chebyshev.chebvander(2.0 * tv - 1.0, degree),
        V, Y, p0, even=even,
    )
    residuals, jacobian, curves = problem.residuals, problem.jacobian, problem.curves
    sol = least_squares(residuals, p0, jac=jacobian, method="lm", max_nfev=200)
    p = sol.x
    xu, yu, xv, yv = curves(p)
    if np.any(xu >= -0.05) or np.any(xv <= 0.05):
        raise MechanismError(
            "fitted: the u and v curves do not stay on their sides of the output line; try "
            "another degree or narrower domains"
        )
    # further outputs: with the isopleths fixed, each curve is a linear least-squares fit of
    # its points to their lines (normal . (P(w) - P_u) = 0)
    D, E = xv - xu, yv - yu
    N = np.hypot(D, E)
    nx, ny = -E / N, D / N
    extra = []
    for o, w in zip(outs[1:], W[1:], strict=True):
        Vw = np.polynomial.chebyshev.chebvander(2.0 * _param(o, w) - 1.0, degree)
        M = np.concatenate([nx[:, None] * Vw, ny[:, None] * Vw], axis=1)
        rhs = nx * xu + ny * yu
        extra.append(np.linalg.lstsq(M, rhs, rcond=None)[0])
    cu, cv = p[:2 * n], p[2 * n:4 * n]

    def curve_scale(var: Var, c):
        return var.scale(
            lambda x, c=c, var=var: homogeneous(
                _cheb(_param(var, x), c[:n]), _cheb(_param(var, x), c[n:])
            )
        )

    w0 = outs[0]
    scales = [
        curve_scale(u, cu),
        curve_scale(v, cv),
        w0.scale(lambda x: homogeneous(np.zeros(np.shape(x)), _g(w0, x))),
    ]
    blocks = [(u.name, v.name, w0.name)]
    for o, q in zip(outs[1:], extra, strict=True):
        scales.append(curve_scale(o, q))
        blocks.append((u.name, v.name, o.name))
    rms = float(np.sqrt(np.mean((residuals(p)[: len(Y)]) ** 2)))
    info = {
        "method": "Chebyshev curves for the inputs, straight output line; least squares on the "
        "alignment residual",
        "degree": degree,
        "samples": int(len(Y)),
        "evaluations": int(sol.nfev),
        "rms_residual_of_output_line": rms,
    }
    if model is None:
        def model(**k):
            return values(np.asarray(k[u.name], dtype=float),
                          np.asarray(k[v.name], dtype=float))[0]
    return _Block(scales, blocks, w0, model, info, (u.name, v.name),
                  float(max(xv.max(), np.abs(xu).max())))


def fitted(
    f: Callable,
    u,
    v,
    outputs: Sequence,
    *,
    degree: int = 6,
    grid: int = 25,
    even: float = 0.01,
    model: Callable | None = None,
    title: str = "",
    relation: str = "",
    paper="a4",
    **kwargs,
) -> Nomogram:
    """A fitted nomogram of ``f(u, v)`` (see the module notes).

    Parameters
    ----------
    f : ``f(u, v) -> w`` (numpy, broadcasting; SI), or a tuple of values for several outputs.
    u, v : the inputs (:class:`~mechsynth.nomograms.forms.Var` or ``(name, (lo, hi))``).
    outputs : the outputs' variables; a domain of None takes f's range over the inputs (with a
        2 % margin). The first output's scale is the straight line, graduated by its ``fn``
        when it has one (e.g. ``log(k - 2)`` for a quantity that grows from 2 like a power),
        else linearly or logarithmically; further outputs get curves.
    degree : degree of the Chebyshev series of each curve's coordinates.
    grid : the fit samples a ``grid x grid`` lattice of the inputs' parameters.
    even : weight of the readability terms: each input curve's steps between the lattice's
        parameters pulled towards one length (about as long as the output line, evenly
        graduated); 0 fits the alignment alone (accurate, often crowded).
    model : the model the accuracy report compares with (``f`` by default).

    Raises
    ------
    MechanismError when f is not finite over the domain, when the output does not vary, or
    when the fitted curves cross the output line (no readable chart).
    """
    b = _fit_block(f, u, v, outputs, degree=degree, grid=grid, even=even, model=model)
    kwargs.setdefault("search", "moduli")
    return Nomogram(
        b.scales, b.blocks, b.w0.name, b.model, title=title, relation=relation, paper=paper,
        fit=b.info, inputs=b.inputs, **kwargs,
    )


def fitted_chain(
    f: Callable,
    u,
    v,
    output,
    terms: Sequence,
    result,
    *,
    constant: float = 0.0,
    degree: int = 6,
    grid: int = 25,
    even: float = 0.01,
    model: Callable | None = None,
    title: str = "",
    relation: str = "",
    paper="a4",
    **kwargs,
) -> Nomogram:
    """A compound chart: the fitted block of ``output = f(u, v)`` (its straight line a turning
    axis, unlabelled) chained with parallel scales, ``F(output) + F1(x1) + ... + constant =
    F(result)``, where ``F(output)`` is the output's ``fn`` (the line's graduation, so it must
    be given). ``model(**inputs) -> result`` is the independent model of the whole chain."""
    from .forms import _chain, _range

    out = _as_var(output)
    if out.fn is None:
        raise MechanismError("fitted_chain: give the intermediate output's function F (its fn)")
    b = _fit_block(f, u, v, [out], degree=degree, grid=grid, even=even)
    w0 = b.w0
    fa, fb = float(w0.F(np.float64(w0.domain[0]))), float(w0.F(np.float64(w0.domain[1])))
    # the block's line: y = (F(w) - F(lo)) / (F(hi) - F(lo)) at x = 0, as a turning axis in F
    ma = 1.0 / (fb - fa)
    line = [s for s in b.scales if s.name == w0.name][0]
    scales = [s for s in b.scales if s.name != w0.name]
    from dataclasses import replace as _replace

    fr = (min(fa, fb), max(fa, fb))
    pad = 0.03 * (fr[1] - fr[0])  # a fitted isopleth may cross a little beyond the ends
    turning = _replace(
        line,
        xyz=lambda t: homogeneous(np.zeros(np.shape(t)), ma * (np.asarray(t, dtype=float) - fa)),
        domain=(fr[0] - pad, fr[1] + pad),
        spacing="linear",
        turning=True,
    )
    scales.append(turning)
    terms = [_as_var(t) for t in terms]
    result = _as_var(result)
    ranges = [_range(t) for t in terms]
    _range(result)
    xs = [-b.reach, 0.0, b.reach]
    more, blocks = _chain(terms, ranges, result, constant, (w0.name, 0.0, ma, fa, fr), xs)
    if model is None:
        raise MechanismError("fitted_chain: give the model of the result")
    kwargs.setdefault("search", "moduli")
    return Nomogram(
        scales + more, list(b.blocks) + blocks, result.name, model, title=title,
        relation=relation, paper=paper, fit=b.info,
        inputs=(*b.inputs, *(t.name for t in terms)), **kwargs,
    )

