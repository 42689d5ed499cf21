"""The classical forms of the determinant theory of nomography, as :class:`Nomogram` builders.

Each form is a determinant whose rows are the scales' homogeneous coordinates; it vanishes
exactly when the relation holds, which is the condition for the three points to align:

* :func:`parallel` -- ``F1(u) + F2(v) + ... = F(w)``: three parallel straight scales, chained
  through turning axes for more than two terms (``|0 F1 1; 1 F2 1; 1/2 F3/2 1| = 0``, moduli
  chosen so every scale has about the same length);
* :func:`z_chart` -- ``F1(u) = F2(v) F3(w)``: the Z (N) chart, ``|0 F1 1; 1 -F2 1; F3 0 1+F3|``;
* :func:`proportional` -- ``F1(u) / F2(v) = F3(w) / F4(t)``: two Z blocks sharing their
  diagonal, the isopleths crossing on it;
* :func:`determinant` -- any three rows ``(f, g, h)`` of one variable each, straight or curved
  scales.

Compound charts chain blocks through unlabelled turning axes: the chained :func:`parallel`,
:func:`proportional`, and :func:`~mechsynth.nomograms.fitting.fitted_chain` (a fitted block
then a parallel chain). Products become sums of logarithms: give ``F = log`` (times the
exponent) to :func:`parallel`. The functions ``F`` are numpy callables; values are SI.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import MechanismError
from .nomogram import Nomogram
from .scales import Scale, homogeneous

__all__ = ["Var", "parallel", "z_chart", "proportional", "determinant"]


@dataclass(frozen=True)
class Var:
    """A variable of a form: ``name``, ``domain`` (SI), ``fn`` (its function ``F`` in the
    relation; identity when None), ``title``, ``unit``, ``spacing`` (``"log"`` for positive
    ranges over a decade), ``shown`` (see :class:`Scale`)."""

    name: str
    domain: tuple[float, float]
    fn: Callable | None = None
    title: str = ""
    unit: str = ""
    spacing: str = ""
    shown: Mapping[str, tuple[float, str]] = field(default_factory=dict)

    def F(self, v):
        v = np.asarray(v, dtype=float)
        return v if self.fn is None else np.asarray(self.fn(v), dtype=float)

    def scale(self, xyz) -> Scale:
        lo, hi = (float(x) for x in self.domain)
        spacing = self.spacing or ("log" if lo > 0 and hi / lo >= 10 else "linear")
        return Scale(self.name, xyz, (lo, hi), self.title, self.unit, spacing, shown=self.shown)


def _as_var(v) -> Var:
    if isinstance(v, Var):
        return v
    if isinstance(v, tuple) and len(v) >= 2:
        return Var(*v)
    raise MechanismError(f"a form's variable must be a Var or (name, (lo, hi)[, F]), got {v!r}")


def _range(var: Var, n: int = 201):
    """(min, max) of F over the variable's domain, and whether F is monotone there."""
    lo, hi = var.domain
    v = np.linspace(lo, hi, n) if var.spacing != "log" else np.geomspace(lo, hi, n)
    f = var.F(v)
    if not np.all(np.isfinite(f)):
        raise MechanismError(f"{var.name}: its function is not finite over {var.domain}")
    d = np.diff(f)
    if not (np.all(d > 0) or np.all(d < 0)):
        raise MechanismError(
            f"{var.name}: its function must be strictly monotone over {var.domain} for a "
            "straight scale"
        )
    return float(f.min()), float(f.max())


def _straight(var: Var, x, m, offset=0.0) -> Scale:
    """A vertical straight scale at abscissa ``x``: ``y = m F(v) + offset`` (``m`` < 0: values
    grow downwards)."""
    return var.scale(lambda v: homogeneous(np.full(np.shape(v), x), m * var.F(v) + offset))


def _turning(name, x, m, frange, offset) -> Scale:
    """An unlabelled vertical turning axis at ``x`` carrying the partial sum ``t``: ``y = m (t -
    offset)`` over the sums' range ``frange``."""
    lo, hi = frange
    pad = 1e-9 * (abs(lo) + abs(hi) + 1.0)
    return Scale(
        name,
        lambda t: homogeneous(
            np.full(np.shape(t), x), m * (np.asarray(t, dtype=float) - offset)
        ),
        (lo - pad, hi + pad),
        turning=True,
    )


def _chain(terms, ranges, result, constant, start, xs, first_gap=None):
    """Scales and blocks adding ``terms`` one block at a time to a running sum on a vertical
    axis ``start = (name, x, modulus, offset, (low, high))`` (its ``y = modulus (sum -
    offset)``): each block puts the running sum A and the new term B outside and their sum C
    between them, moduli giving every scale a length of 1 in base units (C's modulus
    ``m_a m_b / (m_a + m_b)`` over the range ``R_a + R_b``), offsets starting each at y = 0;
    the last sum is the result (``F(result) - constant``). ``xs``: the supports taken."""
    name_a, xa, ma, oa, acc = start
    xs = list(xs)
    scales, blocks = [], []
    for k, (t, r) in enumerate(zip(terms, ranges, strict=True), start=1):
        last = k == len(terms)
        mb = 1.0 / (r[1] - r[0])
        mc = ma * mb / (ma + mb)
        xb = xa + first_gap if (k == 1 and first_gap) else max(xs) + 1.0
        while any(abs((mb * xa + ma * xb) / (ma + mb) - x) < 0.4 for x in xs):
            xb += 0.25  # keep C's support off the others
        xc = (mb * xa + ma * xb) / (ma + mb)
        scales.append(_straight(t, xb, mb, -mb * r[0]))
        oc = oa + r[0]
        acc = (acc[0] + r[0], acc[1] + r[1])
        cname = result.name if last else f"_t{k}"
        if last:
            scales.append(_straight(result, xc, mc, -mc * (oc + constant)))
        else:
            scales.append(_turning(cname, xc, mc, acc, oc))
        blocks.append((name_a, t.name, cname))
        name_a, xa, ma, oa = cname, xc, mc, oc
        xs += [xb, xc]
    return scales, blocks


def parallel(
    terms: Sequence,
    result,
    *,
    constant: float = 0.0,
    model: Callable | None = None,
    title: str = "",
    relation: str = "",
    paper="a4",
    **kwargs,
) -> Nomogram:
    """Parallel-scale nomogram of ``F1(x1) + F2(x2) + ... + constant = F(result)``.

    Parameters
    ----------
    terms : the input variables (:class:`Var` or ``(name, (lo, hi), F)``), at least two; more
        than two are chained through turning axes, one block per added term.
    result : the output variable, its ``F`` strictly monotone over its domain.
    constant : added to the sum of the terms.
    model : ``model(**inputs) -> result`` (SI) for the accuracy report; by default the relation
        itself solved for the result numerically (no independent model).

    The first two terms sit at x = 0 and x = 2 with their sum between them; each later term on
    a new support to the right, the new sum between it and the running sum (a turning axis).
    Moduli make every scale equally long, supports are kept apart.
    """
    terms = [_as_var(t) for t in terms]
    result = _as_var(result)
    if len(terms) < 2:
        raise MechanismError("parallel: give at least two input terms")
    ranges = [_range(t) for t in terms]
    _range(result)
    ma = 1.0 / (ranges[0][1] - ranges[0][0])
    scales = [_straight(terms[0], 0.0, ma, -ma * ranges[0][0])]
    more, blocks = _chain(
        terms[1:], ranges[1:], result, constant, (terms[0].name, 0.0, ma, ranges[0][0],
                                                  ranges[0]), [0.0], first_gap=2.0,
    )
    scales += more
    if model is None:
        model = _solved_model(terms, result, constant)
    kwargs.setdefault("search", "moduli")
    return Nomogram(
        scales, blocks, result.name, model, title=title, relation=relation, paper=paper, **kwargs
    )


def _solved_model(terms, result, constant):
    """``result`` solved from ``sum F_i + constant = F(result)`` on its domain (used when no
    independent model is given)."""

    def model(**values):
        return _invert(result, sum(t.F(values[t.name]) for t in terms) + constant)

    return model


def _z_scales(u: Var, v: Var, w: Var, direction=1.0):
    """The three scales of ``F1(u) = F2(v) F3(w)`` in base coordinates: u on x = 0, v on
    x = 1 (reversed), w on the segment y = 0 between them; ``direction`` -1 mirrors the
    outer scales (for the second block of a proportional chart)."""
    s = float(direction)
    return [
        u.scale(lambda x: homogeneous(np.zeros(np.shape(x)), s * u.F(x))),
        v.scale(lambda x: homogeneous(np.ones(np.shape(x)), -s * v.F(x))),
        w.scale(lambda x: homogeneous(w.F(x), np.zeros(np.shape(x)), 1.0 + w.F(x))),
    ]


def _positive(var: Var):
    lo, hi = _range(var)
    if lo <= 0.0:
        raise MechanismError(
            f"{var.name}: a Z chart needs F > 0 over the domain (F from {lo:g} to {hi:g})"
        )
    return lo, hi


def z_chart(
    u,
    v,
    w,
    *,
    output: str | None = None,
    model: Callable | None = None,
    title: str = "",
    relation: str = "",
    paper="a4",
    **kwargs,
) -> Nomogram:
    """Z (N) chart of ``F1(u) = F2(v) F3(w)``, all three F positive over their domains.

    u runs up the left support, v down the right one, w along the diagonal; the layout sends
    u's and v's ends to the drawing area's corners. ``output`` is the variable read (u by
    default); ``model`` the independent model of it (the relation solved otherwise).
    """
    u, v, w = (_as_var(x) for x in (u, v, w))
    for x in (u, v, w):
        _positive(x)
    scales = _z_scales(u, v, w)
    output = output or u.name
    if model is None:
        model = _z_model(u, v, w, output)
    corners = [(u.name, u.domain[0]), (u.name, u.domain[1]), (v.name, v.domain[0]),
               (v.name, v.domain[1])]
    kwargs.setdefault("search", False)
    return Nomogram(
        scales, [(u.name, v.name, w.name)], output, model, title=title, relation=relation,
        paper=paper, corners=corners, **kwargs,
    )


def _invert(var: Var, target):
    """The value of ``var`` whose F is ``target``, by bisection on its domain (F monotone)."""
    lo, hi = var.domain
    up = var.F(np.float64(hi)) > var.F(np.float64(lo))
    a = np.full(np.shape(target), lo, dtype=float)
    b = np.full(np.shape(target), hi, dtype=float)
    for _ in range(100):
        m = 0.5 * (a + b)
        below = (var.F(m) < target) == up
        a, b = np.where(below, m, a), np.where(below, b, m)
    return 0.5 * (a + b)


def _z_model(u, v, w, output):
    def model(**k):
        if output == u.name:
            return _invert(u, v.F(k[v.name]) * w.F(k[w.name]))
        if output == v.name:
            return _invert(v, u.F(k[u.name]) / w.F(k[w.name]))
        return _invert(w, u.F(k[u.name]) / v.F(k[v.name]))

    return model


def proportional(
    u, v, w, t, *, model: Callable | None = None, title="", relation="", paper="a4", **kwargs
) -> Nomogram:
    """Proportional chart of ``F1(u) / F2(v) = F3(w) / F4(t)`` (all F positive): u up the
    left support and v down the right one align through the ratio on the diagonal (an
    unlabelled turning axis), through which w (down the left) and t (up the right) align. The
    chart reads t."""
    u, v, w, t = (_as_var(x) for x in (u, v, w, t))
    for x in (u, v, w, t):
        _positive(x)
    r_lo = min(_range(u)[0] / _range(v)[1], _range(w)[0] / _range(t)[1])
    r_hi = max(_range(u)[1] / _range(v)[0], _range(w)[1] / _range(t)[0])
    ratio = Var("_ratio", (r_lo * (1 - 1e-9), r_hi * (1 + 1e-9)))
    su, sv, sr = _z_scales(u, v, ratio)
    sw, st, _ = _z_scales(w, t, ratio, direction=-1.0)
    sr = replace(sr, turning=True)
    if model is None:
        def model(**k):
            return _invert(t, v.F(k[v.name]) * w.F(k[w.name]) / u.F(k[u.name]))
    corners = [(w.name, w.domain[1]), (u.name, u.domain[1]), (t.name, t.domain[1]),
               (v.name, v.domain[1])]
    kwargs.setdefault("search", False)
    return Nomogram(
        [su, sv, sw, st, sr], [(u.name, v.name, "_ratio"), (w.name, t.name, "_ratio")], t.name,
        model, title=title, relation=relation, paper=paper, corners=corners, **kwargs,
    )


def determinant(
    rows: Mapping[str, Callable],
    domains: Mapping[str, tuple[float, float]],
    output: str,
    *,
    model: Callable | None = None,
    titles: Mapping[str, str] | None = None,
    units: Mapping[str, str] | None = None,
    title: str = "",
    relation: str = "",
    paper="a4",
    **kwargs,
) -> Nomogram:
    """The general three-scale form: ``rows[name](values) -> (f, g, h)`` for three
    variables, the determinant of the three rows vanishing exactly when the relation holds.
    Scales may be curved. ``model`` gives the output from the other two (SI) for the
    accuracy report."""
    if len(rows) != 3:
        raise MechanismError(f"determinant: give three rows, got {len(rows)}")
    titles, units = dict(titles or {}), dict(units or {})
    scales = []
    for name, fn in rows.items():
        if name not in domains:
            raise MechanismError(f"determinant: no domain for {name}")
        var = Var(name, domains[name], title=titles.get(name, ""), unit=units.get(name, ""))
        scales.append(var.scale(lambda x, fn=fn: homogeneous(*fn(np.asarray(x, dtype=float)))))
    return Nomogram(
        scales, [tuple(rows)], output, model, title=title, relation=relation, paper=paper,
        **kwargs,
    )
