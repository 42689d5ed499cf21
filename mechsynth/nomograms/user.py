"""``ms.nomogram(f, u=..., v=...)``: a nomogram of a user's own relation ``w = f(u, v)``.

An exact form when the user states one -- :class:`Sum` (``W(w) = U(u) + V(v)``: three parallel
scales) or :class:`Product` (``W(w) = U(u) V(v)``: logarithmic parallel scales, or a Z chart) --
checked against ``f`` before it is drawn; a fitted chart (:mod:`mechsynth.nomograms.fitting`)
otherwise. Either way the chart's reading accuracy against ``f`` is measured.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from ..errors import MechanismError
from .forms import Var, parallel, z_chart
from .nomogram import Nomogram

__all__ = ["Sum", "Product", "nomogram"]


def _identity(x):
    return np.asarray(x, dtype=float)


@dataclass(frozen=True)
class Sum:
    """The stated form ``w_fn(w) = u_fn(u) + v_fn(v)`` (identity where not given; ``w_fn``
    strictly monotone)."""

    u: Callable | None = None
    v: Callable | None = None
    w: Callable | None = None


@dataclass(frozen=True)
class Product:
    """The stated form ``w_fn(w) = u_fn(u) v_fn(v)``; ``chart="log"`` draws logarithmic
    parallel scales, ``"z"`` a Z chart; both need the three functions positive."""

    u: Callable | None = None
    v: Callable | None = None
    w: Callable | None = None
    chart: str = "log"


def _domain(name, value):
    from .. import validate

    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 2:
        raise MechanismError(f"nomogram: {name} must be (low, high), got {value!r}")
    lo = validate.number(f"nomogram: {name}'s low end", value[0])
    hi = validate.number(f"nomogram: {name}'s high end", value[1])
    if not lo < hi:
        raise MechanismError(f"nomogram: {name} must be (low, high) with low < high, "
                             f"got {value!r}")
    return lo, hi


def nomogram(
    f: Callable,
    *,
    u,
    v,
    form: Sum | Product | None = None,
    names: tuple[str, str, str] = ("u", "v", "w"),
    titles: Mapping[str, str] | None = None,
    units: Mapping[str, str] | None = None,
    w=None,
    title: str = "",
    paper="a4",
    degree: int = 6,
) -> Nomogram:
    """A nomogram of ``w = f(u, v)``.

    Parameters
    ----------
    f : ``f(u, v) -> w``, numpy (broadcasting), SI values.
    u, v : ``(low, high)`` of the inputs.
    form : :class:`Sum` or :class:`Product` for an exact chart (checked against ``f`` at 1,681
        points to 1e-9 relative); None fits curved scales.
    names : the keywords of the three variables in :meth:`Nomogram.read`.
    titles, units : printed names and SI units by variable name.
    w : ``(low, high)`` of the output scale; f's range over the inputs by default.
    title, paper, degree : the sheet's title, ``"a4"`` or ``"letter"``, the fitted curves'
        degree.

    Examples
    --------
    >>> import mechsynth as ms
    >>> nm = ms.nomogram(lambda u, v: u * v**2, u=(1, 10), v=(1, 5),
    ...                  form=ms.nomograms.Product(v=lambda v: v**2))
    >>> round(nm.read(u=2, v=3), 9)
    18.0
    """
    if not callable(f):
        raise MechanismError(f"nomogram: f must be a function f(u, v), got {f!r}")
    if len(names) != 3 or len(set(names)) != 3 or not all(isinstance(n, str) for n in names):
        raise MechanismError(f"nomogram: names must be three different strings, got {names!r}")
    nu, nv, nw = names
    du, dv = _domain(nu, u), _domain(nv, v)
    titles, units = dict(titles or {}), dict(units or {})
    unknown = (set(titles) | set(units)) - set(names)
    if unknown:
        raise MechanismError(f"nomogram: titles/units for unknown variables {sorted(unknown)}; "
                             f"the variables are {list(names)}")
    uu, vv = np.meshgrid(np.linspace(*du, 41), np.linspace(*dv, 41))
    with np.errstate(all="ignore"):
        ww = np.broadcast_to(np.asarray(f(uu, vv), dtype=float), uu.shape)
    if not np.all(np.isfinite(ww)):
        raise MechanismError(f"nomogram: f({nu}, {nv}) is not finite over {nu} in {du}, {nv} "
                             f"in {dv}")
    if w is None:
        lo, hi = float(ww.min()), float(ww.max())
        span = hi - lo
        dw = (lo - 1e-6 * span, hi + 1e-6 * span) if form is not None else None
    else:
        dw = _domain(nw, w)

    def var(name, dom, fn=None):
        return Var(name, dom, fn, titles.get(name, ""), units.get(name, ""))

    def model(**k):
        return f(np.asarray(k[nu], dtype=float), np.asarray(k[nv], dtype=float))

    common = dict(model=model, title=title or f"{nw} = f({nu}, {nv})", paper=paper)
    if form is None:
        from .fitting import fitted

        return fitted(lambda a, b: f(a, b), var(nu, du), var(nv, dv), [var(nw, dw)],
                      degree=degree, relation=f"{nw} = f({nu}, {nv}), fitted", **common)
    if not isinstance(form, Sum | Product):
        raise MechanismError(f"nomogram: form must be Sum(...), Product(...) or None, got "
                             f"{form!r}")
    U, V, W = (fn or _identity for fn in (form.u, form.v, form.w))
    with np.errstate(all="ignore"):
        lhs = np.asarray(W(ww), dtype=float)
        rhs = U(uu) + V(vv) if isinstance(form, Sum) else U(uu) * V(vv)
    err = np.abs(lhs - rhs)
    scale = np.maximum(np.abs(lhs), np.abs(rhs)).max() + 1e-300
    if not np.all(np.isfinite(err)) or err.max() > 1e-9 * scale:
        k = np.unravel_index(np.nanargmax(np.where(np.isfinite(err), err, np.inf)), err.shape)
        raise MechanismError(
            f"nomogram: the stated form differs from f at {nu} = {uu[k]:g}, {nv} = {vv[k]:g}: "
            f"W(w) = {lhs[k]:.6g} against {rhs[k]:.6g}"
        )
    if isinstance(form, Sum):
        return parallel([var(nu, du, U), var(nv, dv, V)], var(nw, dw, W),
                        relation=f"W({nw}) = U({nu}) + V({nv})", **common)
    if form.chart == "z":
        return z_chart(var(nw, dw, W), var(nu, du, U), var(nv, dv, V), output=nw,
                       relation=f"W({nw}) = U({nu}) V({nv}) (Z chart)", **common)
    if form.chart != "log":
        raise MechanismError(f"nomogram: Product chart must be 'log' or 'z', got {form.chart!r}")
    for name, fn, dom in ((nu, U, du), (nv, V, dv), (nw, W, dw)):
        vals = np.asarray(fn(np.linspace(*dom, 201)), dtype=float)
        if not np.all(vals > 0):
            raise MechanismError(
                f"nomogram: a logarithmic product chart needs {name}'s function positive over "
                f"{dom}; state Sum of logarithms or choose chart='z'"
            )
    return parallel(
        [var(nu, du, lambda x: np.log(U(x))), var(nv, dv, lambda x: np.log(V(x)))],
        var(nw, dw, lambda x: np.log(W(x))),
        relation=f"W({nw}) = U({nu}) V({nv}) (logarithmic scales)",
        **common,
    )
