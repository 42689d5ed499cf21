"""The nomogram: placed scales, reading by the geometry, and the measured reading accuracy.

A :class:`Nomogram` is scales (:class:`~mechsynth.nomograms.scales.Scale`) on a page and the
*blocks* that tie them: three scales each, whose points align on one straight line (an
isopleth) exactly when their values satisfy the block's relation. A compound chart chains
blocks through unlabelled turning axes. :meth:`Nomogram.read` works as a reader with a ruler:
from two known points of a block it draws the line and finds where it crosses the third scale,
block after block, all on the page in millimetres. :meth:`Nomogram.check` compares such
readings with the model the chart stands for.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..errors import MechanismError
from .layout import Paper, apply, fit_page
from .layout import paper as paper_of
from .scales import Grid, Scale, shown_unit

__all__ = ["Nomogram", "PlacedScale", "PlacedGrid", "Accuracy"]


@dataclass(frozen=True)
class PlacedScale:
    """A scale on the page: ``position(values) -> (..., 2)`` mm and its inverse ``value``."""

    scale: Scale
    transform: np.ndarray = field(repr=False)

    @property
    def name(self) -> str:
        return self.scale.name

    @property
    def domain(self) -> tuple[float, float]:
        return self.scale.domain

    def position(self, values) -> np.ndarray:
        """Page points (mm) of ``values`` (SI): shape ``(2,)`` for a number, ``(n, 2)`` for
        an array."""
        v = np.asarray(values, dtype=float)
        p = apply(self.transform, self.scale.base(v.ravel()))
        return p[0] if v.ndim == 0 else p.reshape(v.shape + (2,))

    def value(self, points, samples: int = 2001) -> np.ndarray:
        """The value (SI) of the point of the scale nearest to each page point ``(..., 2)``
        mm: the inverse of :meth:`position` on the scale, a projection off it."""
        pts = np.asarray(points, dtype=float)
        flat = pts.reshape(-1, 2)
        t = np.linspace(0.0, 1.0, samples)
        curve = self.position(self.scale.from_param(t))
        d = ((flat[:, None, :] - curve[None]) ** 2).sum(-1)
        k = d.argmin(axis=1)
        # refine on the neighbouring segments by golden-section search in the parameter
        lo = t[np.maximum(k - 1, 0)]
        hi = t[np.minimum(k + 1, samples - 1)]
        g = (np.sqrt(5.0) - 1.0) / 2.0
        for _ in range(60):
            a = hi - g * (hi - lo)
            b = lo + g * (hi - lo)
            da = ((self.position(self.scale.from_param(a)) - flat) ** 2).sum(-1)
            db = ((self.position(self.scale.from_param(b)) - flat) ** 2).sum(-1)
            left = da < db
            hi = np.where(left, b, hi)
            lo = np.where(left, lo, a)
        out = self.scale.from_param(0.5 * (lo + hi))
        return out[0] if pts.ndim == 1 else out.reshape(pts.shape[:-1])

    def length(self) -> float:
        """Length of the drawn scale on the page, mm."""
        p = self.position(self.scale.sample(401))
        return float(np.hypot(*np.diff(p, axis=0).T).sum())


@dataclass(frozen=True)
class PlacedGrid:
    """A grid (two-variable) scale on the page: ``position(a, b) -> (..., 2)`` mm."""

    grid: Grid
    transform: np.ndarray = field(repr=False)

    @property
    def name(self) -> str:
        return self.grid.name

    @property
    def variables(self) -> tuple[str, str]:
        return self.grid.variables

    def position(self, a, b) -> np.ndarray:
        """Page points (mm) of the value pairs ``(a, b)`` (SI, broadcast)."""
        return apply(self.transform, self.grid.base(a, b))


@dataclass(frozen=True)
class Accuracy:
    """Reading errors of a nomogram against its model over sampled points of its domain.

    Attributes
    ----------
    variable : the read variable; ``unit`` its shown unit (errors in it).
    points : how many readings (random points and every corner of the inputs' box).
    max_error, rms_error : the largest and the RMS |read - model|, in ``unit``.
    max_relative : the largest error relative to the model's value.
    max_mm, rms_mm : the same errors as distances on the paper, mm, along the read scale.
    worst : the inputs (SI) of the worst reading, with ``read`` and ``model`` (SI).
    misses : readings whose isopleth missed the read scale (0 for a sound chart).
    """

    variable: str
    unit: str
    points: int
    max_error: float
    rms_error: float
    max_relative: float
    max_mm: float
    rms_mm: float
    worst: dict
    misses: int
    title: str = ""

    def text(self) -> str:
        """One line for the chart's margin and the summary."""
        u = f" {self.unit}" if self.unit else ""
        miss = f"; {self.misses} isopleths missed the scale" if self.misses else ""
        return (
            f"reading error of {self.title or self.variable} against the model, {self.points} "
            "points (random "
            f"and corners): max {self.max_error:.3g}{u} ({self.max_mm:.3g} mm on paper, "
            f"{100 * self.max_relative:.3g} %), RMS {self.rms_error:.3g}{u} "
            f"({self.rms_mm:.3g} mm){miss}"
        )

    def to_dict(self) -> dict:
        return {
            "variable": self.variable,
            "unit": self.unit,
            "points": self.points,
            "max_error": self.max_error,
            "rms_error": self.rms_error,
            "max_relative": self.max_relative,
            "max_mm": self.max_mm,
            "rms_mm": self.rms_mm,
            "worst": self.worst,
            "misses": self.misses,
            "title": self.title,
        }


class Nomogram:
    """An alignment chart on a sheet of paper.

    Parameters
    ----------
    scales : the :class:`Scale` objects in base coordinates (labelled and turning axes).
    blocks : triples of scale names whose points align on one isopleth.
    output : the variable the chart is read for (the default of :meth:`check`).
    model : ``model(**inputs) -> output`` (SI) for the accuracy report; None when there is no
        model to compare with; or a dict ``{variable: model}`` for a chart with several outputs
        (the output's model first).
    title, relation : the chart's title and its relation in words, printed on the sheet.
    paper : ``"a4"``, ``"letter"`` or a :class:`~mechsynth.nomograms.layout.Paper`.
    corners, search : the layout's start (four ``(scale, value)`` pairs) and search
        (:func:`~mechsynth.nomograms.layout.fit_page`).
    example : inputs (SI) of the isopleth drawn as an example; the middle of each input's
        domain when None.
    notes : extra lines printed in the margin (a constant derived, a source).
    fit : for a fitted chart, what the fit reported (kept for the summary and the JSON).
    inputs : the variables the chart is read from (all labelled scales but the output by
        default; a chart with several outputs names its inputs).
    """

    def __init__(
        self,
        scales: Sequence[Scale],
        blocks: Sequence[tuple[str, str, str]],
        output: str,
        model: Callable | None = None,
        *,
        title: str = "",
        relation: str = "",
        paper="a4",
        corners=None,
        search="full",
        example: Mapping[str, float] | None = None,
        notes: Sequence[str] = (),
        fit: Mapping | None = None,
        inputs: Sequence[str] | None = None,
    ):
        names = [s.name for s in scales]
        if len(set(names)) != len(names):
            raise MechanismError(f"nomogram: scale names repeat: {names}")
        known = set(names)
        for b in blocks:
            if len(b) != 3 or not set(b) <= known:
                raise MechanismError(
                    f"nomogram: each block names three of the scales {sorted(known)}, got {b}"
                )
        # every variable: a scale's own, or one of a grid's two
        self._vars: dict[str, Scale] = {}
        for item in scales:
            for axis in item.axes if isinstance(item, Grid) else (item,):
                if axis.name in self._vars or (isinstance(item, Grid) and axis.name in known):
                    raise MechanismError(f"nomogram: variable {axis.name!r} appears twice")
                self._vars[axis.name] = axis
        labelled = [n for n, v in self._vars.items() if not v.turning]
        if output not in labelled:
            raise MechanismError(f"nomogram: output {output!r} is none of {labelled}")
        self.paper: Paper = paper_of(paper)
        self.blocks = tuple(tuple(b) for b in blocks)
        self.output = output
        self.models = dict(model) if isinstance(model, Mapping) else (
            {} if model is None else {output: model}
        )
        self.model = self.models.get(output)
        self.title = title
        self.relation = relation
        self.notes = tuple(notes)
        self.fit = dict(fit or {})
        self.transform = fit_page(scales, self.paper.box, corners=corners, search=search)
        self.scales = {
            s.name: PlacedScale(s, self.transform) for s in scales if isinstance(s, Scale)
        }
        self.grids = {
            g.name: PlacedGrid(g, self.transform) for g in scales if isinstance(g, Grid)
        }
        self.inputs = tuple(inputs) if inputs is not None else tuple(
            n for n in labelled if n != output
        )
        if not set(self.inputs) <= set(labelled) - {output}:
            raise MechanismError(f"nomogram: inputs {self.inputs} must be variables other than "
                                 f"the output {output!r}")
        self.example = dict(example) if example else {
            n: float(self._vars[n].from_param(0.5)) for n in self.inputs
        }

    def variable(self, name: str) -> Scale:
        """The :class:`Scale` describing the variable ``name`` (domain, title, unit), a grid's
        variables included."""
        if name not in self._vars:
            raise MechanismError(f"nomogram: no variable {name!r}; variables: "
                                 f"{', '.join(self._vars)}")
        return self._vars[name]

    def __repr__(self) -> str:
        return (
            f"Nomogram({self.title!r}, scales={list(self.scales)}, output={self.output!r}, "
            f"paper={self.paper.name!r})"
        )

    # ------------------------------------------------------------------ reading
    def read(self, **known):
        """The value of the one unknown variable, read through the geometry.

        Give all but one of the inputs and the output (SI values, numbers or arrays that
        broadcast); the inputs alone give the output. Turning axes are found on the way; a
        chart's further outputs are in :meth:`isopleth`. Raises :class:`MechanismError` when a
        value lies off its scale or the isopleth misses the scale of the unknown.
        """
        labelled = [n for n, v in self._vars.items() if not v.turning]
        extra = sorted(set(known) - set(labelled))
        if set(self.inputs) <= set(known):
            unknown = [self.output] if self.output not in known else []
        else:
            unknown = [n for n in (*self.inputs, self.output) if n not in known]
        if extra or len(unknown) != 1:
            raise MechanismError(
                f"read: give all but one of {', '.join((*self.inputs, self.output))}"
                + (f" (unknown names: {', '.join(extra)})" if extra else "")
                + f"; got {', '.join(known) or 'none'}"
            )
        for name, v in known.items():
            arr = np.asarray(v, dtype=float)
            lo, hi = self._vars[name].domain
            tol = 1e-9 * (hi - lo)
            if not np.all(np.isfinite(arr)) or np.any(arr < lo - tol) or np.any(arr > hi + tol):
                raise MechanismError(
                    f"read: {name} = {v} is off its scale ({lo:g} to {hi:g})"
                )
        values = self._solve(known)
        out = values[unknown[0]]
        if np.any(np.isnan(out)):
            raise MechanismError(
                f"read: the isopleth misses the scale of {unknown[0]} for the values given "
                f"(it lies beyond the drawn range {self._vars[unknown[0]].domain})"
            )
        return float(out) if out.ndim == 0 else out

    def isopleth(self, **known) -> dict[str, np.ndarray]:
        """Every scale's value along the isopleths of ``known`` (turning axes included);
        NaN where an isopleth misses a scale."""
        return self._solve(known)

    def _members(self, member) -> tuple[str, ...]:
        g = self.grids.get(member)
        return g.variables if g is not None else (member,)

    def point(self, member, values) -> np.ndarray:
        """Page points (mm) of a block member (a scale or a grid) for ``values`` by variable."""
        g = self.grids.get(member)
        if g is not None:
            return g.position(values[g.variables[0]], values[g.variables[1]])
        return self.scales[member].position(values[member])

    def _solve(self, known) -> dict[str, np.ndarray]:
        arrays = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in known.values()))
        values = dict(zip(known, arrays, strict=True))
        pending = list(self.blocks)
        while pending:
            for b in pending:
                missing = [v for m in b for v in self._members(m) if v not in values]
                if len(missing) == 1:
                    var = missing[0]
                    um = next(m for m in b if var in self._members(m))
                    a, c = (m for m in b if m != um)
                    values[var] = self._cross(values, a, c, um, var)
                    pending.remove(b)
                    break
                if not missing:
                    pending.remove(b)
                    break
            else:
                break
        return values

    def _cross(self, values, a, c, member, var, samples: int = 400):
        """Where the lines through the points of the block members ``a`` and ``c`` cross the
        curve of ``var`` on ``member`` (a scale, or a grid with its other variable known):
        bracketed on ``samples`` points, refined by bisection. NaN where they do not cross
        it."""
        scale = self._vars[var]
        shape = np.shape(next(iter(values.values())))
        pa = self.point(a, values).reshape(-1, 2)
        pc = self.point(c, values).reshape(-1, 2)
        grid = self.grids.get(member)
        if grid is None:
            ps = self.scales[member]

            def curve(t):
                return ps.position(scale.from_param(t))
        else:
            i = grid.variables.index(var)
            other = np.broadcast_to(values[grid.variables[1 - i]], shape).reshape(-1)[:, None]

            def curve(t):
                v = scale.from_param(t)
                return grid.position(v, other) if i == 0 else grid.position(other, v)

        d = pc - pa

        def side(t):  # t: (n, m) parameters -> cross product sign function
            p = curve(t)
            return d[:, None, 0] * (p[..., 1] - pa[:, None, 1]) - d[:, None, 1] * (
                p[..., 0] - pa[:, None, 0]
            )

        t = np.linspace(0.0, 1.0, samples)
        norm = np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-300)[:, None]
        g = side(np.broadcast_to(t, (len(pa), samples))) / norm  # signed distance, mm
        sg = np.where(np.abs(g) < 1e-9, 0.0, np.sign(g))
        change = sg[:, :-1] * sg[:, 1:] < 0
        zero = sg == 0.0
        has_change, has_zero = change.any(axis=1), zero.any(axis=1)
        found = has_change | has_zero
        k = np.where(has_change, change.argmax(axis=1), 0)
        lo, hi = t[k], t[np.minimum(k + 1, samples - 1)]
        exact = has_zero & ~has_change
        lo = np.where(exact, t[zero.argmax(axis=1)], lo)
        hi = np.where(exact, lo, hi)
        glo = side(lo[:, None])[:, 0]
        for _ in range(55):
            mid = 0.5 * (lo + hi)
            gm = side(mid[:, None])[:, 0]
            same = np.signbit(gm) == np.signbit(glo)
            lo, glo = np.where(same, mid, lo), np.where(same, gm, glo)
            hi = np.where(same, hi, mid)
        out = np.where(found, scale.from_param(0.5 * (lo + hi)), np.nan)
        return out.reshape(shape)

    # ------------------------------------------------------------------ accuracy
    def check(self, n: int = 400, seed: int = 0, variable: str | None = None) -> Accuracy:
        """Sample the inputs' domain (``n`` random points and every corner), read each point
        through the geometry and compare with the model: the :class:`Accuracy` report."""
        variable = variable or self.output
        if variable not in self.models:
            raise MechanismError(
                f"nomogram {self.title!r} has no model of {variable!r} to check against"
            )
        inputs = list(self.inputs)
        rng = np.random.default_rng(seed)
        cols = {}
        corners = np.array(np.meshgrid(*([[0.0, 1.0]] * len(inputs)), indexing="ij"))
        corners = corners.reshape(len(inputs), -1)
        for i, name in enumerate(inputs):
            t = np.concatenate([rng.uniform(0.0, 1.0, n), corners[i]])
            cols[name] = self._vars[name].from_param(t)
        truth = np.asarray(self.models[variable](**cols), dtype=float)
        read = self._solve(cols)[variable]
        miss = np.isnan(read)
        scale = self._vars[variable]
        factor, unit = shown_unit(scale)
        ok = ~miss
        err = np.abs(read[ok] - truth[ok]) / factor
        span = scale.domain[1] - scale.domain[0]
        rel = np.abs(read[ok] - truth[ok]) / np.maximum(np.abs(truth[ok]), 1e-9 * span)
        member = next(m for b in self.blocks for m in b if variable in self._members(m))
        here = {k: v[ok] for k, v in cols.items()}
        mm = np.hypot(*(self.point(member, {**here, variable: read[ok]})
                        - self.point(member, {**here, variable: truth[ok]})).T)
        if not ok.any():
            raise MechanismError(f"check: every isopleth missed the scale of {variable}")
        k = int(np.argmax(err))
        idx = np.flatnonzero(ok)[k]
        worst = {name: float(col[idx]) for name, col in cols.items()}
        worst.update(read=float(read[idx]), model=float(truth[idx]))
        return Accuracy(
            variable=variable,
            unit=unit,
            points=int(len(truth)),
            max_error=float(err.max()),
            rms_error=float(np.sqrt(np.mean(err**2))),
            max_relative=float(rel.max()),
            max_mm=float(mm.max()),
            rms_mm=float(np.sqrt(np.mean(mm**2))),
            worst=worst,
            misses=int(miss.sum()),
            title=scale.title,
        )

    @functools.cached_property
    def accuracy(self) -> Accuracy:
        """The :meth:`check` report of the output with its defaults (computed once)."""
        return self.check()

    @functools.cached_property
    def accuracies(self) -> dict[str, Accuracy]:
        """The :meth:`check` report of every variable the chart has a model of."""
        return {k: (self.accuracy if k == self.output else self.check(variable=k))
                for k in self.models}

    # ------------------------------------------------------------------ output
    def draw(self, example: Mapping[str, float] | None = None, accuracy: bool = True):
        """The chart as a matplotlib Figure of the paper's size at 1:1
        (:mod:`mechsynth.nomograms.render`)."""
        from .render import draw

        return draw(self, example=example, accuracy=accuracy)

    def save(self, path, example=None, dpi: int = 200):
        """Write the chart to ``path`` (PDF, SVG or PNG by the suffix; PNG at ``dpi``),
        atomically; returns the path."""
        from .render import save

        return save(self, path, example=example, dpi=dpi)

    def to_dict(self) -> dict:
        """The chart's description, its scales' ends on the page and its accuracy (JSON)."""
        scales = {}
        for name, ps in self.scales.items():
            lo, hi = ps.domain
            scales[name] = {
                "title": ps.scale.title,
                "unit": ps.scale.unit,
                "domain": [lo, hi],
                "turning": ps.scale.turning,
                "ends_mm": ps.position(np.array([lo, hi])).round(3).tolist(),
                "length_mm": round(ps.length(), 2),
            }
        data = {
            "title": self.title,
            "relation": self.relation,
            "paper": self.paper.name,
            "scale": "1:1 (print at 100 %)",
            "output": self.output,
            "inputs": list(self.inputs),
            "scales": scales,
            "grids": {
                name: {"variables": list(g.variables),
                       "titles": [a.title for a in g.grid.axes],
                       "domains": [list(a.domain) for a in g.grid.axes]}
                for name, g in self.grids.items()
            },
            "blocks": [list(b) for b in self.blocks],
            "example": self.example,
            "notes": list(self.notes),
        }
        if self.fit:
            data["fit"] = self.fit
        if self.models:
            data["accuracy"] = self.accuracy.to_dict()
            data["accuracies"] = {k: a.to_dict() for k, a in self.accuracies.items()}
        return data
