"""Design charts (nomograms): measures swept over a grid of designs, vectorized.

:func:`sweep` evaluates measures of a mechanism over every point of a grid of design parameters
(or of any coordinates mapped to parameters, e.g. ratios at a fixed stroke). Designs are
evaluated in chunks as one batch each -- the parameters are arrays broadcast against the crank
angles -- so memory stays bounded and there is no Python loop over designs. Designs that cannot
be built (the mechanism's feasibility conditions, or a :class:`~mechsynth.errors.MechanismError`
on construction) are recorded in the boolean ``feasible`` mask; the values users see are masked
arrays, never NaN.

:class:`Chart` holds the result and draws a labelled contour nomogram (several measures
overlaid, infeasible and constraint-violating regions hatched, the best design marked), and
writes CSV and NPZ tables.

>>> import numpy as np, mechsynth as ms
>>> from mechsynth import objectives as ob
>>> ch = sweep(ms.SliderCrank, grid={"crank": np.linspace(0.02, 0.08, 4),
...                                  "offset": np.linspace(0.0, 0.05, 3)},
...            fixed={"rod": 0.12}, measures={"pressure": ob.max_pressure_angle()},
...            angles=90, progress=False)
>>> ch.values["pressure"].shape, int(ch.feasible.sum())
((4, 3), 11)

The slider-crank chart of ``mechsynth chart slider-crank``: peak slider acceleration, maximum
pressure angle and time ratio over the rod/crank ratio and the offset/crank ratio at a fixed
stroke (:func:`slider_crank_chart`).
"""

from __future__ import annotations

import contextlib
import contextvars
import json
import logging
import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import MechanismError, UsageError
from ..fileio import output_dir, save_figure, save_npz
from ..kinematics.compiled import BatchWorkspace, batch_motion
from ..kinematics.mechanism import input_grid
from ..objectives.base import Measure
from ..options import Option, chart_options

__all__ = ["Chart", "sweep", "sweep_executor", "slider_crank_chart", "chart_slider_crank"]

_log = logging.getLogger(__name__)

_OPS = {
    "<=": np.less_equal,
    "<": np.less,
    ">=": np.greater_equal,
    ">": np.greater,
}


# ------------------------------------------------------------------------------ chart
@dataclass(frozen=True)
class Chart:
    """Measures over a grid of designs.

    Attributes
    ----------
    mechanism : the mechanism class.
    grid : ``{name: 1-D values}``, the chart's axes in order; arrays below have the shape
        ``tuple(len(v) for v in grid.values())`` (``indexing="ij"``).
    values : ``{label: masked array}`` of each measure (SI units, see ``units``); masked where
        the design is infeasible.
    feasible : boolean array: the design can be built and every measure is finite there.
    params : ``{name: masked array}`` of the mechanism parameters of each design.
    units : ``{label: unit}`` of the measures.
    labels : ``{grid name: axis label with unit}``.
    angles : crank angles per cycle; ``speed`` the crank speed (rad/s) or None for analogs.
    elapsed : seconds of the sweep.
    reason : the first reason a design was infeasible (empty when all are feasible).
    ran_on : where the chunks were evaluated and, for an executor, why: its tasks, or this
        process when the executor was predicted slower than this process (with both
        predictions, in seconds; :func:`sweep`'s ``executor``).
    """

    mechanism: Any
    grid: dict[str, np.ndarray]
    values: dict[str, np.ma.MaskedArray]
    feasible: np.ndarray
    params: dict[str, np.ma.MaskedArray]
    units: dict[str, str]
    labels: dict[str, str]
    angles: int
    speed: float | None
    elapsed: float
    reason: str = ""
    measures: dict[str, Any] = field(default_factory=dict, repr=False)
    ran_on: str = "this process"

    @property
    def shape(self) -> tuple[int, ...]:
        return self.feasible.shape

    @property
    def size(self) -> int:
        return int(self.feasible.size)

    # -------------------------------------------------------------- selection
    def satisfied(self, where=None) -> np.ndarray:
        """Boolean array: feasible designs that satisfy ``where``.

        ``where`` is None, a boolean array of the grid's shape, or ``{label: (op, bound)}``
        with ``op`` one of ``<=``, ``<``, ``>=``, ``>`` and ``bound`` in the measure's SI unit
        (e.g. ``{"max pressure angle": ("<=", ms.deg(30))}``).
        """
        ok = self.feasible.copy()
        if where is None:
            return ok
        if isinstance(where, np.ndarray):
            if where.shape != self.shape:
                raise MechanismError(f"where has shape {where.shape}, the chart {self.shape}")
            return ok & where.astype(bool)
        for label, (op, bound) in where.items():
            if label not in self.values:
                raise MechanismError(
                    f"unknown measure {label!r}; chart has {', '.join(self.values)}"
                )
            if op not in _OPS:
                raise MechanismError(f"op must be one of {', '.join(_OPS)}, got {op!r}")
            data = self.values[label].filled(np.nan)
            with np.errstate(invalid="ignore"):
                ok &= _OPS[op](data, float(bound))
        return ok

    def argbest(self, measure: str, where=None, sense: str = "min") -> dict[str, Any]:
        """The best grid design for ``measure`` among the feasible designs satisfying ``where``.

        Returns ``{"index", "grid": {name: value}, "params": {name: value}, "values": {label:
        value}, "on_edge": {grid name: "lower" | "upper"}}`` (``on_edge`` names the axes on
        whose first or last value the best design sits: the optimum may lie outside the chart);
        raises ValueError when no grid design qualifies.
        """
        if measure not in self.values:
            raise MechanismError(f"unknown measure {measure!r}; chart has {', '.join(self.values)}")
        if sense not in ("min", "max"):
            raise MechanismError(f"sense must be 'min' or 'max', got {sense!r}")
        ok = self.satisfied(where)
        if not ok.any():
            raise MechanismError(f"no feasible grid design satisfies {where!r}")
        data = self.values[measure].filled(0.0)
        score = np.where(ok, data if sense == "min" else -data, np.inf)
        idx = np.unravel_index(int(np.argmin(score)), self.shape)
        edge = {}
        for (n, v), i in zip(self.grid.items(), idx):
            if v.size > 1 and i == 0:
                edge[n] = "lower"
            elif v.size > 1 and i == v.size - 1:
                edge[n] = "upper"
        return dict(
            index=tuple(int(i) for i in idx),
            grid={n: float(v[i]) for (n, v), i in zip(self.grid.items(), idx)},
            params={k: float(v[idx]) for k, v in self.params.items()},
            values={k: float(v[idx]) for k, v in self.values.items()},
            on_edge=edge,
        )

    # -------------------------------------------------------------- tables
    def _unit_of(self, name: str) -> str:
        """SI unit of a grid axis or parameter (ratios and unknown names: none)."""
        fields = getattr(self.mechanism, "__dataclass_fields__", None) or getattr(
            self.mechanism, "parameters", {}
        )
        if name in fields and hasattr(self.mechanism, "unit_of"):
            return self.mechanism.unit_of(name)
        return ""

    def _table(self):
        from .. import tables

        mesh = np.meshgrid(*self.grid.values(), indexing="ij")
        cols = [(n, self._unit_of(n), m.ravel()) for n, m in zip(self.grid, mesh)]
        # parameters that are also grid axes appear once, as axes
        cols += [
            (n, self._unit_of(n), v.ravel()) for n, v in self.params.items() if n not in self.grid
        ]
        cols.append(("feasible", "", self.feasible.ravel().astype(int)))
        cols += [(k, self.units.get(k, ""), v.ravel()) for k, v in self.values.items()]
        return tables.table(cols)

    def to_dict(self) -> dict[str, list]:
        """One column per grid axis, mechanism parameter (once) and measure, one entry per
        design, in display units (``"name [unit]"``; None where infeasible)."""
        from .. import tables

        return tables.as_lists(self._table())

    def to_csv(self, path=None):
        """One row per design: grid coordinates, the other mechanism parameters, ``feasible``
        (1/0) and the measures, in display units with the unit in each column name (empty
        cells where infeasible). Written to ``path`` (returns it) or returned as text."""
        from .. import tables

        return tables.write_csv(self._table(), path)

    def to_npz(self, path) -> Path:
        """Arrays: ``grid/<name>`` (axes), ``value/<label>`` (zero where infeasible),
        ``param/<name>``, ``feasible`` and ``meta`` (JSON: units, labels, angles, speed)."""
        path = Path(path)
        arrays: dict[str, np.ndarray] = {"feasible": self.feasible}
        for n, v in self.grid.items():
            arrays[f"grid/{n}"] = v
        for n, v in self.params.items():
            arrays[f"param/{n}"] = v.filled(0.0)
        for n, v in self.values.items():
            arrays[f"value/{n}"] = v.filled(0.0)
        meta = dict(
            mechanism=getattr(self.mechanism, "__name__", str(self.mechanism)),
            units=self.units,
            labels=self.labels,
            angles=self.angles,
            speed=self.speed,
            grid=list(self.grid),
            values=list(self.values),
        )
        arrays["meta"] = np.array(json.dumps(meta))
        save_npz(path, **arrays)
        return path

    # -------------------------------------------------------------- figure
    def _display(self, label):
        """Values, unit and converter for display (the display units; radians in degrees)."""
        from .. import display

        unit = self.units.get(label, "")
        factor, shown = display.current().factor(unit), display.current().unit(unit)
        v = self.values[label] / factor
        if shown and display.thousands(v, shown)[1] != shown:  # labels of at most four digits
            factor, shown = factor * 1e3, display.thousands(v, shown)[1]
            v = v / 1e3
        return v, shown, lambda x: np.asarray(x) / factor

    def plot(
        self,
        ax=None,
        measures=None,
        limits=None,
        best: str | None = None,
        best_sense: str = "min",
        levels: int = 12,
        fill: bool = True,
        title: str | None = None,
    ):
        """Contour nomogram over the two grid axes, in the house style (colour-blind-safe
        colours, labels in display units).

        Parameters
        ----------
        ax : a matplotlib axes (default: a new figure with the legend below the chart).
        measures : labels to draw (default all); the first is filled with a colour bar, the
            others are labelled contour lines, each in its own colour and line style.
        limits : ``{label: (op, bound)}`` (SI units) -- the regions that violate a limit are
            hatched in grey and its boundary drawn as a thick line.
        best : mark the grid design minimizing (``best_sense``) this measure among the feasible
            designs within ``limits`` (default: the first measure; ``""`` marks none). A best
            design on the grid's edge is flagged: the optimum may lie outside the chart.
        levels : contour levels per measure.

        Infeasible designs (cannot be built) are shaded grey and cross-hatched. Contour labels
        that would overlap other text are left out. Returns the figure.
        """
        import matplotlib.pyplot as plt
        from matplotlib.lines import Line2D
        from matplotlib.patches import Patch

        from ..plotting import PALETTE, label_contours, prune_labels, style

        if len(self.grid) != 2:
            raise MechanismError(f"plot needs a 2-D grid; this chart has axes {list(self.grid)}")
        labels = list(self.values) if measures is None else list(measures)
        for lab in labels:
            if lab not in self.values:
                raise MechanismError(f"unknown measure {lab!r}; chart has {', '.join(self.values)}")
        colours = [PALETTE[0], PALETTE[5], PALETTE[4], PALETTE[3], PALETTE[1], PALETTE[6]]
        styles = ["-", "--", "-.", ":", "-", "--"]
        limit_colours = [PALETTE[6], PALETTE[1], PALETTE[2], PALETTE[7]]
        with style():
            own = ax is None
            fig = plt.figure(figsize=(8.5, 8.0), layout="constrained") if own else ax.figure
            ax = fig.add_subplot() if own else ax
            (xn, xv), (yn, yv) = self.grid.items()
            X, Y = np.meshgrid(xv, yv, indexing="ij")
            region = self.satisfied(limits) if limits else self.feasible
            handles = []
            for i, lab in enumerate(labels):
                z, unit, _ = self._display(lab)
                lv = _levels(z, region, levels if i == 0 else 8, by_area=i > 0)
                colour, ls = colours[i % len(colours)], styles[i % len(styles)]
                if lv is not None:
                    if i == 0 and fill:
                        cf = ax.contourf(
                            X, Y, z, levels=lv, cmap="viridis", alpha=0.75, extend="both"
                        )
                        cb = fig.colorbar(cf, ax=ax)
                        cb.set_label(f"{lab}, {unit}" if unit else lab)
                    cs = ax.contour(
                        X,
                        Y,
                        z,
                        levels=lv,
                        colors=colour,
                        linewidths=0.7 if i == 0 else 1.1,
                        linestyles=ls,
                    )
                    label_contours(ax, cs, fmt="%.4g", fontsize=7, every=1 if i == 0 else 2)
                name = f"{lab}, {unit}" if unit else lab
                handles.append(Line2D([], [], color=colour, ls=ls, label=name))
            infeasible = ~self.feasible
            if infeasible.any():
                with plt.rc_context({"hatch.color": "0.35", "hatch.linewidth": 0.6}):
                    ax.contourf(
                        X,
                        Y,
                        infeasible.astype(float),
                        levels=[0.5, 1.5],
                        colors=["0.82"],
                        hatches=["xx"],
                    )
                handles.append(
                    Patch(facecolor="0.82", hatch="xx", edgecolor="0.35", label="infeasible design")
                )
            for j, (lab, (op, bound)) in enumerate((limits or {}).items()):
                ok = self.satisfied({lab: (op, bound)})
                bad = self.feasible & ~ok
                colour = limit_colours[j % len(limit_colours)]
                hatch = ["//", "\\\\", "||", "--"][j % 4]
                z, unit, conv = self._display(lab)
                shown = float(conv(bound))
                if bad.any():
                    with plt.rc_context({"hatch.color": "0.25", "hatch.linewidth": 0.5}):
                        ax.contourf(
                            X,
                            Y,
                            bad.astype(float),
                            levels=[0.5, 1.5],
                            colors="none",
                            hatches=[hatch],
                        )
                    zmin, zmax = float(z.min()), float(z.max())
                    if zmin < shown < zmax:
                        ax.contour(X, Y, z, levels=[shown], colors=colour, linewidths=2.6)
                inv = {"<=": ">", "<": ">=", ">=": "<", ">": "<="}[op]
                handles.append(
                    Patch(
                        facecolor="none",
                        hatch=hatch,
                        edgecolor="0.25",
                        label=f"{lab} {inv} {shown:g} {unit}".rstrip(),
                    )
                )
                handles.append(
                    Line2D([], [], color=colour, lw=2.6, label=f"limit {lab} = {shown:g} {unit}")
                )
            # a margin around the grid, so that a design on its edge is drawn whole
            for setter, v in ((ax.set_xlim, xv), (ax.set_ylim, yv)):
                pad = 0.02 * float(np.ptp(v)) if v.size > 1 else 0.5
                setter(float(v.min()) - pad, float(v.max()) + pad)
            best = labels[0] if best is None else best
            if best:
                try:
                    b = self.argbest(best, where=limits, sense=best_sense)
                except ValueError:
                    b = None
                if b is not None:
                    bx, by = b["grid"][xn], b["grid"][yn]
                    z, unit, conv = self._display(best)
                    val = float(conv(b["values"][best]))
                    ax.plot(
                        bx,
                        by,
                        marker="*",
                        ms=16,
                        color="gold",
                        mec="k",
                        zorder=6,
                        clip_on=False,
                        ls="none",
                    )
                    note = ""
                    if b["on_edge"]:
                        note = " (on the grid's edge)"
                        # the note points into the chart, away from the edges the design is on
                        x0, x1 = float(np.min(xv)), float(np.max(xv))
                        y0, y1 = float(np.min(yv)), float(np.max(yv))
                        right = float(bx) - x0 < 0.5 * (x1 - x0)
                        up = float(by) - y0 < 0.5 * (y1 - y0)
                        ax.annotate(
                            "on the grid's edge",
                            (bx, by),
                            xytext=(12 if right else -12, 14 if up else -14),
                            textcoords="offset points",
                            ha="left" if right else "right",
                            va="bottom" if up else "top",
                            fontsize=8,
                            bbox=dict(boxstyle="round,pad=0.2", fc="white", ec="0.3"),
                        )
                    handles.append(
                        Line2D(
                            [],
                            [],
                            marker="*",
                            ms=12,
                            color="gold",
                            mec="k",
                            ls="none",
                            label=f"best grid design: {best} = {val:.5g} {unit}{note}".rstrip(),
                        )
                    )
            ax.set_xlabel(self.labels.get(xn, xn))
            ax.set_ylabel(self.labels.get(yn, yn))
            ax.grid(True, alpha=0.3, ls=":")
            if own:
                fig.legend(handles=handles, loc="outside lower center", ncol=2, fontsize=8)
            else:
                ax.legend(handles=handles, loc="best", fontsize=7, framealpha=0.9)
            name = getattr(self.mechanism, "__name__", "")
            ax.set_title(
                title
                or f"{name} design chart: {self.shape[0]} x {self.shape[1]} designs, "
                f"{self.angles} crank angles",
                fontsize=10,
            )
            prune_labels(fig)
        return fig


def _levels(z, region, n, by_area=False):
    """Contour levels spanning the 1st-99th percentile of ``z`` inside ``region`` (all feasible
    values when the region is empty), so that a few extreme designs near an infeasible boundary
    do not flatten the chart. None when ``z`` is constant. ``by_area``: levels at equal
    fractions of the designs (rounded to a power of ten below their spacing), so that a
    measure which changes fast in a corner of the chart (a time ratio near the toggle) spreads
    its lines over the chart instead of bundling them there."""
    from matplotlib.ticker import MaxNLocator

    data = np.ma.getdata(z)[region & ~np.ma.getmaskarray(z)]
    if data.size < 2:
        data = np.ma.compressed(z)
    if data.size < 2:
        return None
    lo, hi = np.percentile(data, [1.0, 99.0])
    if not hi > lo:
        return None
    if by_area:
        q = np.percentile(data, np.linspace(4.0, 96.0, n))
        unit = 10.0 ** np.floor(np.log10((hi - lo) / n))  # rounded to the levels' spacing
        q = np.unique(np.round(q / unit) * unit)
        if q.size >= 3:
            return q
    return MaxNLocator(n).tick_values(lo, hi)


# ------------------------------------------------------------------------------ sweep
def _flat(v, k):
    a = np.asarray(v, dtype=float)
    if a.ndim and a.shape[-1] == 1:
        a = a[..., 0]
    return np.broadcast_to(a, (k,))


def _substitute(values: dict, ok: np.ndarray) -> dict:
    """Rows that are not ``ok`` take the values of the first ``ok`` row (so the batch builds)."""
    first = int(np.argmax(ok))
    out = {}
    for k, v in values.items():
        if isinstance(v, np.ndarray) and v.ndim == 1 and v.size == ok.size:
            out[k] = np.where(ok, v, v[first])
        else:
            out[k] = v
    return out


def _column(params: dict, rows=None) -> dict:
    """Numeric 1-D parameters become (k, 1) columns (broadcast against the angles)."""
    out = {}
    for k, v in params.items():
        if isinstance(v, np.ndarray) and v.ndim == 1:
            out[k] = (v if rows is None else v[rows])[:, None]
        else:
            out[k] = v
    return out


@dataclass(frozen=True)
class _SweepSpec:
    """Everything a chunk of a sweep needs, sent once to each worker."""

    mechanism: Any
    axes: dict
    shape: tuple
    chunk: int
    fixed: dict
    design: Any
    feasible: Any
    measures: dict
    phi: np.ndarray
    speed: Any
    kernels: bool
    linkage_kernel: bool = False  # a Linkage's sweep that runs on its kernel once it is ready


@dataclass(frozen=True)
class _BlockResult:
    """One chunk's reduced results: feasibility, measures and varied parameters per design."""

    start: int
    ok: np.ndarray
    values: dict
    params: dict
    reason: str


_LOCAL = threading.local()  # one reused kinematics workspace per thread


def _chunk_designs(spec: _SweepSpec, c: int):
    """The designs of chunk ``c`` (designs ``c * chunk`` ... of the flattened grid) before
    their motion: ``(start, ok, params, params_out, reason)`` -- the designs that pass
    ``feasible`` and the mechanism's feasibility hook, the parameters of the chunk (None when no
    design passes; the others' rows take the first good row's values) and the varied ones as
    the chart records them."""
    total = int(np.prod(spec.shape))
    start = c * spec.chunk
    idx = np.arange(start, min(total, start + spec.chunk))
    k = idx.size
    reason = ""
    sub = np.unravel_index(idx, spec.shape)
    vals = {n: a[s] for (n, a), s in zip(spec.axes.items(), sub)}
    ok = np.ones(k, dtype=bool)
    if spec.feasible is not None:
        ok &= np.broadcast_to(np.asarray(spec.feasible(vals), dtype=bool), (k,))
        if not ok.all():
            reason = "outside the chart's feasible region (feasible=...)"
    if not ok.any():
        return start, ok, None, {}, reason
    vals = _substitute(vals, ok)
    mapped = spec.design(dict(vals)) if spec.design is not None else vals
    clash = set(mapped) & set(spec.fixed)
    if clash:
        raise MechanismError(f"parameters {sorted(clash)} are both on the grid and fixed")
    params = {**spec.fixed}
    for name, v in mapped.items():
        params[name] = (
            np.broadcast_to(np.asarray(v, dtype=float), (k,)).copy()
            if np.ndim(v) or isinstance(v, (int, float, np.floating))
            else v
        )
    hook = getattr(spec.mechanism, "feasibility_constraints", None)
    if hook is not None:
        for cname, g in hook(params, margin=0.0):
            good = np.broadcast_to(np.asarray(g, dtype=float) > 0.0, (k,))
            if not good.all() and (ok & ~good).any() and not reason:
                reason = f"violates {cname}"
            ok &= good
    if not ok.any():
        return start, ok, None, {}, reason
    params = _substitute(params, ok)
    params_out = {n: v for n, v in params.items() if isinstance(v, np.ndarray) and v.ndim == 1}
    return start, ok, params, params_out, reason


def _sweep_block(spec: _SweepSpec, c: int, build: bool = True) -> _BlockResult | None:
    """Evaluate chunk ``c`` of a sweep: designs ``c * chunk`` ... of the flattened grid (a
    Linkage's on its kernel if it is ready, else on the model; ``build``: as
    :func:`_kernel_now`)."""
    start, ok, params, params_out, first = _chunk_designs(spec, c)
    k = ok.size
    reason = [first]

    def note(msg):
        if not reason[0]:
            reason[0] = msg

    values = {label: np.zeros(k) for label in spec.measures}

    def result():
        return _BlockResult(start, ok, values, params_out, reason[0])

    if params is None:
        return result()
    compiled = [spec.kernels]  # cleared when a measure needs what the compiled motion lacks
    kernel = _kernel_now(spec, build)

    def motion_of(mech):
        if compiled[0]:
            if not hasattr(_LOCAL, "ws"):
                _LOCAL.ws = BatchWorkspace()
            motion = batch_motion(mech, spec.phi, spec.speed, _LOCAL.ws)
            if motion is not None:
                return motion
        return mech.motion(spec.phi, speed=spec.speed)

    def measure_all(mech, motion, n):
        out = {}
        for label, m in spec.measures.items():
            v = m.from_motion(mech, motion) if isinstance(m, Measure) else m(mech, motion)
            out[label] = _flat(v, n)
        return out

    def evaluate(rows):
        """Build and evaluate designs ``rows`` of the chunk; split on MechanismError."""
        try:
            mech = spec.mechanism(**_column(params, rows))
            motion = motion_of(mech)
        except MechanismError as exc:
            if rows.size == 1:
                ok[rows] = False
                note(str(exc))
                return
            half = rows.size // 2
            evaluate(rows[:half])
            evaluate(rows[half:])
            return
        n = rows.size
        if motion.points or not compiled[0]:
            got = measure_all(mech, motion, n)
        else:
            try:
                got = measure_all(mech, motion, n)
            except (KeyError, ValueError, AttributeError, TypeError):
                # a measure needs more than the compiled kernels give (a point's track):
                # this chunk evaluates on the model from here on
                compiled[0] = False
                got = measure_all(mech, mech.motion(spec.phi, speed=spec.speed), n)
        store(rows, got)

    def store(rows, got):
        finite = np.ones(rows.size, dtype=bool)
        for v in got.values():
            finite &= np.isfinite(v)
        if not finite.all():
            note("a measure is not finite at some designs")
        for label, v in got.items():
            values[label][rows] = np.where(finite, v, 0.0)
        ok[rows] &= finite

    def evaluate_linkage(rows):
        """A linkage's designs on its compiled kernel; the model judges the designs the kernel
        cannot vouch for (and names why a failed design cannot be assembled)."""
        from ..kinematics.linkage_kernels import linkage_batch

        try:
            mech = spec.mechanism(**_column(params, rows))
        except MechanismError:
            return evaluate(rows)
        if not hasattr(_LOCAL, "ws"):
            _LOCAL.ws = BatchWorkspace()
        motion, good, failed = linkage_batch(mech, spec.phi, spec.speed, _LOCAL.ws, kernel)
        if good.any():
            with np.errstate(all="ignore"):
                got = measure_all(mech, motion, rows.size)
            store(rows[good], {label: v[good] for label, v in got.items()})
        lost = rows[failed]
        if lost.size and not reason[0]:
            evaluate(lost[:1])  # the model's verdict and message for the first
            lost = lost[1:]
        ok[lost] = False
        rest = rows[~good & ~failed]
        if rest.size:
            evaluate(rest)

    (evaluate if kernel is None else evaluate_linkage)(np.flatnonzero(ok))
    return result()


#: seconds measured for a Linkage's sweep on this 2-core machine while shared (load average
#: about 9; ``benchmarks/bench_sweep_switch.py``: paper 001's six-link, 360 crank angles, two
#: measures, chunks of the sweep's size), per kernel backend (``linkage_kernels.kernel_backend``;
#: numba's where there is none): ``"model"`` and ``"kernel"``, CPU per
#: design-angle evaluation of a chunk (motion and measures) on the numpy model and on the
#: compiled kernel; ``"compile"``, CPU of the first build of its kernel (the process's and the
#: C compiler's; ``"compile wall"`` its wall time, which the sweep does not wait for);
#: ``"load"``, CPU of a built kernel's load from the disk cache in a new process (numba's import
#: and start included; ``"load wall"`` its wall time). Wall times grow with the machine's load
#: (a numba load took 0.8-0.9 s at a load average of 2).
LINKAGE_COSTS = {
    "numba": {
        "model": 1.37e-7,
        "kernel": 8.9e-8,
        "compile": 5.6,
        "compile wall": 16.0,
        "load": 0.60,
        "load wall": 2.8,
    },
    "c": {
        "model": 1.27e-7,
        "kernel": 8.0e-8,
        "compile": 0.66,
        "compile wall": 2.5,
        "load": 0.0047,
        "load wall": 0.011,
    },
}


def _backend() -> str:
    """This process's kernel backend, without importing numba (numba's costs when there is
    none: no kernel is built then)."""
    from ..kinematics.linkage_kernels import kernel_backend

    return kernel_backend(probe=False) or "numba"


def _pays_back(build: str, costs: dict | None = None) -> float:
    """Design-angle evaluations from which a kernel's ``build`` (``"compile"`` or ``"load"``)
    pays for itself within one sweep: the sweep goes on with the model while the kernel is
    built (``build wall`` seconds, ``wall / model`` evaluations), and the evaluations left when
    it arrives save ``model - kernel`` seconds each, at least the build's CPU."""
    c = costs or LINKAGE_COSTS[_backend()]
    return c[build] / (c["model"] - c["kernel"]) + c[f"{build} wall"] / c["model"]


#: design-angle evaluations from which a Linkage's sweep has the kernel of its structure
#: built (:mod:`~mechsynth.kinematics.linkage_kernels`) when this machine has not built it yet;
#: None: :func:`_pays_back` on the costs of this process's backend (:data:`LINKAGE_COSTS`) --
#: the build pays for itself within the sweep that starts it, and such a sweep outlasts it on
#: the model alone (so a process never waits at its exit for a build it started for a chart):
#: 3.3e7 evaluations with a C compiler (0.66 s of CPU, 2.5 s, 47 ns saved per evaluation; a
#: 300 x 300 six-link chart from an empty cache ran 85 % of its chunks on the kernel, 12.7 s
#: against 14.2 s on the model alone), 2.3e8 with numba (5.6 s of CPU, 16 s; a chart of 3.2e7
#: evaluations ended before numba's kernel arrived). Below it, ``linkage_kernel(linkage)``
#: builds a structure's kernel once for the machine.
LINKAGE_KERNEL_MIN: float | None = None

#: design-angle evaluations from which a Linkage's sweep takes its kernel when it is built
#: already (in this process, or recorded in the disk cache); None: :func:`_pays_back` of a
#: load: 1.9e5 evaluations for a C kernel (5 ms of CPU), 3.3e7 for numba's (0.6 s, 2.8 s)
LINKAGE_KERNEL_CACHED_MIN: float | None = None


def linkage_kernel_thresholds() -> tuple[float, float]:
    """Design-angle evaluations from which a Linkage's sweep runs on its kernel: ``(when it
    must be built, when it is built already)`` (:data:`LINKAGE_KERNEL_MIN`,
    :data:`LINKAGE_KERNEL_CACHED_MIN`, else from the measured :data:`LINKAGE_COSTS`)."""
    build = LINKAGE_KERNEL_MIN if LINKAGE_KERNEL_MIN is not None else _pays_back("compile")
    cached = LINKAGE_KERNEL_CACHED_MIN
    return build, cached if cached is not None else _pays_back("load")


def _wants_kernel(spec) -> bool:
    """Whether a Linkage's sweep should run on its compiled kernel (the thresholds above; no
    numba import, nothing built)."""
    from ..kinematics.linkage import Linkage

    if not (spec.kernels and isinstance(spec.mechanism, Linkage)):
        return False
    from ..kinematics.linkage_groups import FollowerGroup

    if any(isinstance(g, FollowerGroup) for g in spec.mechanism.groups):
        return False  # no kernel for a cam follower
    evaluations = int(np.prod(spec.shape)) * spec.phi.size
    build, cached = linkage_kernel_thresholds()
    if evaluations < min(build, cached):
        return False
    from ..kinematics import linkage_kernels

    return evaluations >= build or linkage_kernels.is_compiled(spec.mechanism)


def _kernel_now(spec, build: bool = True):
    """The compiled kernel of a sweep that wants one (:func:`_wants_kernel`) if it is ready,
    else None at once: the model evaluates meanwhile. ``build``: start building it in the
    background if need be (the sweep's own process); else (an executor's task) only load it
    when the disk cache holds it -- the sweep's process has it built there once, instead of
    every worker compiling it."""
    if not spec.linkage_kernel:
        return None
    from ..kinematics import linkage_kernels

    mech = spec.mechanism
    if not build and not linkage_kernels.is_compiled(mech):
        return None
    return linkage_kernels.linkage_kernel(mech, wait=False)


def _dumps(spec) -> bytes:
    """The sweep's spec pickled for other processes: plain pickle, else cloudpickle (local
    functions and lambdas), else a clear error."""
    import pickle

    try:
        return pickle.dumps(spec)
    except (pickle.PicklingError, AttributeError, TypeError) as exc:
        try:
            import cloudpickle
        except ImportError:
            raise MechanismError(
                f"the sweep's functions cannot be sent to other processes ({exc}); define "
                "them at module level, or install cloudpickle"
            ) from exc
        return cloudpickle.dumps(spec)


_SPECS: dict = {}  # in a worker: the specs already unpickled, by their bytes' digest


def _remote_block(payload: bytes, c: int, count: int = 1) -> _BlockResult | None:
    """A worker's task: unpickle the spec once per process, evaluate chunks ``c`` ...
    ``c + count - 1`` (consecutive designs) as one result."""
    import hashlib
    import pickle

    key = hashlib.sha256(payload).hexdigest()
    spec = _SPECS.get(key)
    if spec is None:
        _keep_freed_memory()  # the worker's malloc, as the sweep's own process
        _SPECS.clear()
        spec = _SPECS[key] = pickle.loads(payload)
    res = _joined([_sweep_block(spec, i, build=False) for i in range(c, c + count)])
    # the parameters stay here: the sweep's process derives them itself (:func:`_chunk_designs`,
    # a small part of a chunk's work), which spares the transfer of 8 bytes per design each
    return res if res is None else replace(res, params={})


def _joined(blocks) -> _BlockResult | None:
    """Consecutive chunks' results as one."""
    blocks = [b for b in blocks if b is not None]
    if len(blocks) <= 1:
        return blocks[0] if blocks else None
    names = dict.fromkeys(name for b in blocks for name in b.params)
    # a chunk without a feasible design has no parameters: zeros there, as in one process
    params = {
        name: np.concatenate([b.params.get(name, np.zeros(b.ok.size)) for b in blocks])
        for name in names
    }
    return _BlockResult(
        start=blocks[0].start,
        ok=np.concatenate([b.ok for b in blocks]),
        values={k: np.concatenate([b.values[k] for b in blocks]) for k in blocks[0].values},
        params=params,
        reason=next((b.reason for b in blocks if b.reason), ""),
    )


#: doubles in a chunk's block of kinematics on the compiled kernels (128 MiB): per chunk the
#: sweep pays about 0.5 ms of Python (building the batch, the design functions, the measures'
#: calls), the same for any chunk size; on the kernels a chunk of 2**16 design-angle
#: evaluations (182 designs at 360 angles) is itself only 1-2 ms, so a 1e6-design slider-crank
#: chart took 2.0 x a hand-written loop. Blocks of 2**22, 2**23 and 2**24 doubles (1,456, 2,912
#: and 5,825 slider-cranks at 360 angles) gave 1.31, 1.23 and 1.16 x on a 600 x 600 chart (the
#: best of five runs each, interleaved, load average 12; bench_sweep_scaling.py for the sizes).
#: The numpy model keeps 2**16 evaluations per chunk: its dozens of temporaries stay in cache.
KERNEL_BLOCK = 2**24
MODEL_CHUNK = 2**16

#: seconds an executor spends per task beyond its work (send, schedule, receive), measured on
#: 2 cores (benchmarks/bench_sweep_dask.py): a spawned process pool 0.11-0.20 ms per task (and
#: any executor other than Dask's). A Dask cluster's is measured on the cluster itself, once
#: per scheduler (:func:`task_overhead`): 4-9 ms on a LocalCluster of this machine.
TASK_OVERHEAD = {"default": 2e-4}

#: the share of a task's time its overhead may take: tasks get enough chunks that the
#: executor's per-task overhead is at most 5 % of their work
TASK_OVERHEAD_SHARE = 0.05

#: seconds per design-angle evaluation of a chunk with its measures, measured on 2 cores, one
#: thread (bench_sweep_switch.py): the slider-crank chart on its kernel (``"named kernel"``)
#: and on the numpy model (``"model"``, the cheapest model measured: a task of model chunks
#: is never shorter than planned), paper 001's six-link on its generated kernel
EVALUATION_COST = {"named kernel": 7.2e-9, "linkage kernel": 8.3e-8, "model": 3.2e-8}


def _default_chunk(spec, kernel_rows: int | None) -> int:
    """Designs per chunk: a block of :data:`KERNEL_BLOCK` doubles on the kernels (``rows``
    outputs per evaluation), :data:`MODEL_CHUNK` evaluations on the model."""
    m = max(spec.phi.size, 1)
    if kernel_rows:
        return max(1, KERNEL_BLOCK // (kernel_rows * m))
    return max(1, MODEL_CHUNK // m)


def _kernel_rows(spec) -> int | None:
    """Rows of the kernels' block per evaluation when the sweep runs on compiled kernels (a
    Linkage's when its kernel is ready: a sweep that starts on the model keeps the model's
    chunks, about the size of a six-bar kernel's), else None. Starts a Linkage's kernel
    building in the background when the sweep wants it."""
    kernel = _kernel_now(spec)
    if kernel is not None:
        return kernel.outputs
    return 8 if _on_named_kernels(spec) else None


def _chunks_per_task(executor, spec, rows, n_chunks) -> int:
    """Chunks one executor task evaluates: enough that the executor's per-task overhead
    (:func:`task_overhead`) is at most :data:`TASK_OVERHEAD_SHARE` of the task's work
    (:data:`EVALUATION_COST`), while leaving two tasks per worker (:func:`executor_workers`)
    to share among them (a chart too small for that overhead: two tasks per worker)."""
    overhead = task_overhead(executor)
    if rows is None:
        cost = EVALUATION_COST["model"]
    else:
        cost = EVALUATION_COST["linkage kernel" if rows != 8 else "named kernel"]
    work = spec.chunk * spec.phi.size * cost  # seconds per chunk
    want = int(np.ceil(overhead / TASK_OVERHEAD_SHARE / max(work, 1e-12)))
    return int(max(1, min(want, n_chunks // (2 * executor_workers(executor)))))


def executor_workers(executor) -> int:
    """Tasks ``executor`` runs at once: a Dask cluster's worker threads (asked of its
    scheduler), a pool's workers, else 4."""
    client = getattr(executor, "_client", None)
    if _is_dask(executor) and client is not None:
        try:
            return max(1, sum(client.nthreads().values()))
        except Exception:  # noqa: BLE001 - a scheduler that does not answer: the default
            return 4
    return max(1, int(getattr(executor, "_max_workers", 4) or 4))


_OVERHEADS: dict = {}  # a Dask cluster's measured per-task overhead, by scheduler address


def _is_dask(executor) -> bool:
    return (type(executor).__module__ or "").startswith("distributed")


def task_overhead(executor) -> float:
    """Seconds ``executor`` spends per task beyond its work. A Dask cluster's executor
    (``Client(...).get_executor()``): measured on it the first time, as the median round trip
    of a task that does nothing (sent, run on a worker, its result back: :func:`round_trip`),
    then remembered for its scheduler's address. Other executors:
    :data:`TASK_OVERHEAD` ``["default"]``, a spawned process pool's, measured."""
    if not _is_dask(executor):
        return TASK_OVERHEAD["default"]
    key = _executor_key(executor)
    if key not in _OVERHEADS:
        _OVERHEADS[key] = round_trip(executor)
    return _OVERHEADS[key]


def _nothing(x):
    return x


def round_trip(executor, n: int = 7) -> float:
    """Median seconds of ``n`` tasks that do nothing, each sent through ``executor`` and its
    result awaited before the next (after one to warm up)."""
    executor.submit(_nothing, -1).result()
    times = []
    for i in range(n):
        t = time.perf_counter()
        executor.submit(_nothing, i).result()
        times.append(time.perf_counter() - t)
    return float(np.median(times))


def _zeros(n):
    return np.zeros(n)


#: seconds per byte of a task's results on their way back (pickled, sent, unpickled) through
#: an executor other than a Dask cluster (a Dask cluster's is measured on it: :func:`result_cost`)
RESULT_COST = {"default": 2e-9}

_RESULT_COSTS: dict = {}  # a Dask cluster's measured seconds per byte, by scheduler address

#: seconds a worker takes to load the compiled kernels the first time it evaluates a chunk on
#: them (numba's load from the disk cache: :data:`LINKAGE_COSTS`)
WORKER_KERNEL_LOAD = LINKAGE_COSTS["numba"]["load"]

#: True: a sweep given an executor sends it the tasks whatever the prediction (the tests and
#: benchmarks of the executors' own paths); False: only when it is predicted faster
ALWAYS_USE_EXECUTOR = False

_SEEN: set = set()  # executors (by scheduler address) that have evaluated a sweep's chunks


def _executor_key(executor):
    client = getattr(executor, "_client", None)
    return getattr(getattr(client, "scheduler", None), "address", None) or id(executor)


def result_cost(executor, n: int = 2**21) -> float:
    """Seconds per byte of a task's results on their way back from ``executor``. A Dask
    cluster's: measured on it the first time (the median over three pairs of the difference
    between a task returning ``n`` doubles and one returning nothing), then remembered for its
    scheduler's address; other executors: :data:`RESULT_COST` ``["default"]``."""
    if not _is_dask(executor):
        return RESULT_COST["default"]
    key = _executor_key(executor)
    if key not in _RESULT_COSTS:
        task_overhead(executor)  # the workers warmed up
        extra = []
        for i in range(3):  # arguments of their own: no task is a cached one
            t = time.perf_counter()
            executor.submit(_nothing, 100 + i).result()
            t1 = time.perf_counter()
            executor.submit(_zeros, n + i).result()
            extra.append(time.perf_counter() - t1 - (t1 - t))
        _RESULT_COSTS[key] = max(float(np.median(extra)), 0.0) / (8.0 * n)
    return _RESULT_COSTS[key]


def _on_this_host(executor) -> bool:
    """Whether ``executor``'s workers run on this machine (a pool; a Dask cluster whose
    workers' addresses are this host's), sharing its cores with this process."""
    if not _is_dask(executor):
        return True
    import socket

    try:
        addresses = list(executor._client.scheduler_info()["workers"])
        here = {"127.0.0.1", "localhost", socket.gethostname()}
        with contextlib.suppress(OSError):
            here.add(socket.gethostbyname(socket.gethostname()))
    except Exception:  # noqa: BLE001 - a scheduler that does not answer: count them remote
        return False
    hosts = {a.split("://")[-1].rsplit(":", 1)[0].strip("[]") for a in addresses}
    return all(a.startswith("inproc://") or h in here for a, h in zip(addresses, hosts))


#: speed of each of several workers that share this machine's cores, relative to one process
#: alone: a chunk streams its block of kinematics through memory, and two at once on the 2
#: cores took 1.4-1.75 x as long each (0.30-0.37 s for tasks of 15 chunks of 5,825
#: slider-cranks that take 0.21 s alone; benchmarks/bench_sweep_dask.py, load average 2-3)
SHARED_HOST_SPEED = 0.67


def _busy_elsewhere() -> float:
    """Threads running on this machine besides this one: the running count of
    ``/proc/loadavg``, the median of five readings 1 ms apart, less this reader; 0 where it
    cannot be read. (The load average itself lags by a minute and counts the sweep's own
    workers of the charts before.)"""
    counts = []
    for _ in range(5):
        try:
            with open("/proc/loadavg") as f:
                counts.append(int(f.read().split()[3].split("/")[0]) - 1)
        except (OSError, ValueError, IndexError):
            return 0.0
        time.sleep(0.001)
    return float(max(0.0, np.median(counts)))


def _executor_plan(executor, spec, rows, n_chunks, threads=1) -> tuple[int, str]:
    """Tasks for ``executor`` (of :func:`_chunks_per_task` chunks, their number rounded down to
    a multiple of its workers, the chunks shared among them evenly), or 0 when this process is
    predicted faster, and a line saying which and why. Predicted from the measured costs:
    here, the chunks' work (:data:`EVALUATION_COST`) on ``threads`` threads; on the executor,
    the first round trip (the sweep's description to the workers), the workers' first load of
    the kernels (:data:`WORKER_KERNEL_LOAD`, once per cluster), the tasks in rounds over the
    workers, each with its round trip (:func:`task_overhead`), and the results' bytes back
    (:func:`result_cost`, measured only when the rest leaves the executor ahead). Workers on
    this machine share its cores with this process and with whatever else runs there
    (:func:`_busy_elsewhere`), and run slower side by side (:data:`SHARED_HOST_SPEED`)."""
    workers = executor_workers(executor)
    tasks = -(-n_chunks // _chunks_per_task(executor, spec, rows, n_chunks))
    if tasks > workers:  # a whole number of tasks per worker: none idles for the last ones
        tasks -= tasks % workers
    per = -(-n_chunks // tasks)  # at most: the tasks differ by a chunk at most
    if rows is None:
        cost = EVALUATION_COST["model"]
    else:
        cost = EVALUATION_COST["linkage kernel" if rows != 8 else "named kernel"]
    chunk_s = spec.chunk * spec.phi.size * cost
    designs = int(np.prod(spec.shape))
    trip = task_overhead(executor)
    kind = "a Dask cluster" if _is_dask(executor) else type(executor).__name__
    if n_chunks * chunk_s <= trip and not ALWAYS_USE_EXECUTOR:  # no need to ask further
        return 0, (
            f"this process: {kind} of {workers} workers would not pay (its round trip "
            f"{trip:.2g} s, the work {n_chunks * chunk_s:.2g} s)"
        )
    n, others = cores(), _busy_elsewhere()
    here = n_chunks * chunk_s / min(threads, n * threads / (threads + others))
    speed = 1.0  # of a worker, relative to this process alone on a core
    if _on_this_host(executor):
        speed = (SHARED_HOST_SPEED if workers > 1 else 1.0) * min(1.0, n / (workers + others))
    start = trip
    if _on_kernels(spec) and _executor_key(executor) not in _SEEN:
        start += WORKER_KERNEL_LOAD
    there = start + -(-tasks // workers) * (per * chunk_s / speed + trip)
    if there < here or ALWAYS_USE_EXECUTOR:  # (else no need to measure the results' cost)
        there += designs * (8 * len(spec.measures) + 1) * result_cost(executor)
    if ALWAYS_USE_EXECUTOR or there < here:
        _SEEN.add(_executor_key(executor))
        return tasks, (
            f"{kind} of {workers} workers: {tasks} tasks of {n_chunks // tasks}-{per} chunks "
            f"(predicted {there:.2g} s against {here:.2g} s in this process)"
        )
    return 0, (
        f"this process: {kind} of {workers} workers would not pay (predicted {there:.2g} s "
        f"against {here:.2g} s here)"
    )


_EXECUTOR: contextvars.ContextVar = contextvars.ContextVar("sweep_executor", default=None)

#: design-angle evaluations on the numpy model (no compiled kernels) above which
#: ``executor="auto"`` evaluates the chunks in a pool of processes (measured on 2 cores: a
#: six-link chart of 2e7 evaluations takes 27 s in one process; starting two workers costs
#: about 2 s)
POOL_MIN_EVALUATIONS = 2e7


def cores() -> int:
    """Cores this process may run on."""
    import os

    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _on_named_kernels(spec) -> bool:
    """Whether the sweep's motion runs on the four-bar or slider-crank kernels."""
    from ..kinematics.compiled import numba_available
    from ..kinematics.four_bar import FourBar
    from ..kinematics.slider_crank import SliderCrank

    return spec.kernels and spec.mechanism in (SliderCrank, FourBar) and numba_available()


def _on_kernels(spec) -> bool:
    """Whether the sweep's motion runs on compiled kernels (a Linkage's: once it is ready)."""
    return _on_named_kernels(spec) or spec.linkage_kernel


def _pool_size(executor, spec, total, n_chunks) -> int:
    """Worker processes for ``executor="processes"`` or ``"auto"`` (0: this process)."""
    n = min(cores(), n_chunks)
    if executor == "processes":
        return max(n, 1)
    if _on_kernels(spec) or n < 2 or total * spec.phi.size < POOL_MIN_EVALUATIONS:
        return 0
    return n


def _process_pool(n):
    """A pool of ``n`` fresh interpreters (spawned: no threads or locks inherited from this
    process; a script that sweeps must guard its main code with ``if __name__ ==
    "__main__":``, as for any process pool)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    return ProcessPoolExecutor(
        max_workers=n, mp_context=multiprocessing.get_context("spawn"), initializer=_ignore_sigint
    )


def _ignore_sigint():
    """In a pool's worker: Ctrl-C is the parent's to handle (it cancels the pending chunks)."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)


@contextlib.contextmanager
def sweep_executor(executor):
    """Within the block, sweeps that are not given an ``executor`` use this one: an Executor or
    one of :func:`sweep`'s names (the command line runs its charts in ``"auto"``, or with
    ``--dask`` on the cluster's executor)."""
    token = _EXECUTOR.set(executor)
    try:
        yield executor
    finally:
        _EXECUTOR.reset(token)


def _keep_freed_memory(_done=[]):  # noqa: B006 - once per process
    """Ask glibc's malloc to keep freed blocks for reuse instead of handing them back to the
    system (its default trims the heap above 128 KiB and maps blocks above 128 KiB afresh): a
    sweep frees and allocates blocks of the same sizes chunk after chunk, and each block the
    system takes back costs a page fault per 4 KiB when it is touched again. Applied once per
    process (malloc's settings are the process's); nothing on other C libraries."""
    if _done:
        return
    _done.append(True)
    try:
        import ctypes

        libc = ctypes.CDLL(None)
        mallopt = libc.mallopt
    except (OSError, AttributeError):
        return
    m_trim_threshold, m_mmap_threshold = -1, -3
    mallopt(m_mmap_threshold, 32 << 20)  # blocks up to 32 MiB come from the heap
    mallopt(m_trim_threshold, 256 << 20)  # the heap keeps up to 256 MiB of freed memory


def sweep(
    mechanism,
    grid: Mapping[str, Any],
    measures: Mapping[str, Measure | Callable],
    fixed: Mapping[str, Any] | None = None,
    *,
    design: Callable[[dict], dict] | None = None,
    feasible: Callable[[dict], Any] | None = None,
    angles=360,
    speed: float | None = None,
    chunk: int | None = None,
    progress: bool = True,
    labels: Mapping[str, str] | None = None,
    workers: int = 1,
    kernels: bool = True,
    executor=None,
) -> Chart:
    """Evaluate ``measures`` over every design of a grid, vectorized in chunks.

    Parameters
    ----------
    mechanism : the mechanism class (e.g. ``ms.SliderCrank``).
    grid : ``{name: 1-D values}``; the chart's axes. Names are mechanism parameters, or any
        coordinates that ``design`` maps to parameters.
    measures : ``{label: measure}``: :class:`~mechsynth.objectives.Measure` objects, or
        functions ``(mechanism, motion) -> value per design``.
    fixed : the other mechanism parameters.
    design : optional ``fn({grid name: array}) -> {parameter: array}`` mapping grid coordinates
        to mechanism parameters (arrays of the chunk's length, or numbers).
    feasible : optional ``fn({grid name: array}) -> bool array``: designs known to be invalid
        before ``design`` is applied (``design`` only sees valid ones).
    angles : crank angles per cycle (count of equal steps, or an array in rad).
    speed : crank speed (rad/s) for velocities and accelerations; None gives analogs.
    chunk : designs per batch (default: on the compiled kernels, a block of
        :data:`KERNEL_BLOCK` doubles of their outputs -- 5,825 slider-cranks at 360 angles --
        which makes the Python cost per chunk small beside its work; on the numpy model,
        :data:`MODEL_CHUNK` design-angle points, which keep its temporaries in cache).
    progress : show a tqdm bar over the chunks (only on a terminal).
    labels : ``{grid name: axis label with unit}`` for the figure.
    workers : threads evaluating chunks in parallel (numpy releases the GIL in its array
        loops); 1 evaluates them one after the other.
    kernels : evaluate the motion on the compiled batch kernels when the mechanism has them
        (slider-crank, four-bar; a Linkage's kernel compiled for its structure when the sweep
        has at least :data:`LINKAGE_KERNEL_MIN` design-angle evaluations, or
        :data:`LINKAGE_KERNEL_CACHED_MIN` when this machine has compiled it; numba installed),
        streaming the chunks through one reused workspace; the model's ``motion`` evaluates the
        rest, the designs a linkage's kernel cannot vouch for, and every measure that needs
        more than the kernels give (a point's track). A sweep never waits for a Linkage's
        kernel: while it is loaded or compiled in the background
        (``linkage_kernel(..., wait=False)``) the chunks run on the model, and the next chunk
        after it is ready runs on it (the values equal to 1e-12 either way). False: always the
        model (the reference the tests compare with).
    executor : a :class:`concurrent.futures.Executor` that evaluates the chunks (e.g.
        ``ProcessPoolExecutor()``, or ``dask.distributed.Client(address).get_executor()`` for
        a cluster), used only when it is predicted faster than this process
        (:func:`_executor_plan`: the chunks' measured cost here against the executor's
        measured round trip and cost per byte of results, its workers -- as many at once as
        this machine's cores when they run on it -- and their first load of the kernels);
        otherwise the sweep runs here, and ``Chart.ran_on`` says so with both predictions
        (:data:`ALWAYS_USE_EXECUTOR` sends the tasks regardless). Each task evaluates a run of
        consecutive chunks where it runs -- enough that the executor's per-task overhead
        (:func:`task_overhead`: a Dask cluster's measured on it once) is at most 5 % of the
        task's work, at least two tasks per worker and the same number for every worker --
        and returns only their measures and feasibility (this process derives the parameters
        of the designs itself: fewer bytes to send back). A Linkage's kernel is built
        by this process, in the background, into the disk cache; a task loads it from there
        when it is there and otherwise evaluates on the model (workers never compile it:
        workers on other hosts use the kernel their host's cache holds). The
        sweep's functions travel by pickle (by cloudpickle when plain pickle cannot take them,
        e.g. local functions). ``"processes"``:
        a pool of fresh processes, one per core, for this sweep (a script must guard its main
        code with ``if __name__ == "__main__":``). ``"auto"``: that pool when the motion runs
        on the numpy model (``kernels=False``, or a Linkage without a kernel) and the sweep has
        more than :data:`POOL_MIN_EVALUATIONS` design-angle evaluations, else this process (on the
        compiled kernels a chart takes less than a pool of fresh processes needs to start); the
        command line's charts run this way. None
        (default): the executor of an enclosing :func:`sweep_executor` block, else this
        process on ``workers`` threads (``"local"`` likewise).

    Returns
    -------
    Chart

    Notes
    -----
    Infeasible designs: ``feasible`` is applied first, then the mechanism's
    ``feasibility_constraints`` hook (strictly positive margins), then construction; a batch
    whose construction still raises :class:`~mechsynth.errors.MechanismError` is split until the
    offending designs are isolated. Designs with a non-finite measure are infeasible too.
    Raises ValueError when no design of the grid is feasible (the message gives the first
    reason).
    """
    from ..progress import bar as progress_bar

    t0 = time.perf_counter()
    _keep_freed_memory()
    from .. import validate

    if not isinstance(grid, Mapping) or not grid:
        raise MechanismError("grid must name at least one axis: {name: values}")
    if not isinstance(measures, Mapping) or not measures:
        raise MechanismError("measures must hold at least one {label: measure}")
    axes = {}
    for name, values in grid.items():
        a = np.ravel(validate.real(f"grid axis {name!r}", values))
        axes[str(name)] = a
    for what, fn in (("design", design), ("feasible", feasible)):
        if fn is not None and not callable(fn):
            raise MechanismError(
                f"{what} must be a function of the design's values (a dict) or None, got {fn!r}"
            )
    if fixed is not None and not isinstance(fixed, Mapping):
        raise MechanismError(f"fixed must be a dict {{name: value}}, got {fixed!r}")
    fixed = dict(fixed or {})
    if isinstance(angles, (int, float, np.integer, np.floating)):
        phi = input_grid(mechanism, validate.integer("angles", angles, 2, validate.MAX_ANGLES))
    else:
        phi = np.ravel(validate.real("angles", angles, "rad"))
    validate.check_size(
        f"a sweep of {int(np.prod([a.size for a in axes.values()], dtype=float))} designs",
        float(np.prod([a.size for a in axes.values()], dtype=float)) * (2 + len(measures)),
    )
    bound = {}
    for label, m in measures.items():
        if isinstance(m, Measure):
            bound[label] = m.bind(mechanism)
        elif callable(m):
            bound[label] = m
        else:
            raise UsageError(f"measure {label!r} must be a Measure or a function, got {m!r}")
    shape = tuple(a.size for a in axes.values())
    total = int(np.prod(shape))
    if chunk is not None:
        chunk = validate.integer("chunk", chunk, 1)
    spec = _SweepSpec(
        mechanism=mechanism,
        axes=axes,
        shape=shape,
        chunk=chunk or 1,
        fixed=fixed,
        design=design,
        feasible=feasible,
        measures=bound,
        phi=phi,
        speed=speed,
        kernels=bool(kernels),
    )
    spec = replace(spec, linkage_kernel=_wants_kernel(spec))
    rows = _kernel_rows(spec)
    if chunk is None:
        spec = replace(spec, chunk=_default_chunk(spec, rows))
    chunk = spec.chunk
    ok_all = np.zeros(total, dtype=bool)
    out = {label: np.zeros(total) for label in bound}
    par_out: dict[str, np.ndarray] = {}
    reason = ""

    n_chunks = -(-total // chunk)
    bar = progress_bar(
        total=n_chunks, desc=f"sweep {total} designs", enabled=None if progress else False
    )
    workers = int(workers)
    if workers < 1:
        raise MechanismError(f"workers must be >= 1, got {workers}")
    if executor is None:
        executor = _EXECUTOR.get()
    pool = None
    if isinstance(executor, str):
        if executor not in ("auto", "processes", "local"):
            raise UsageError(
                f"executor must be an Executor, 'auto', 'processes' or 'local', got {executor!r}"
            )
        size = 0 if executor == "local" else _pool_size(executor, spec, total, n_chunks)
        executor = pool = _process_pool(size) if size else None
        ran_on = f"a pool of {size} processes" if size else "this process"
    elif executor is not None:
        tasks, ran_on = _executor_plan(executor, spec, rows, n_chunks, workers)
        if not tasks:
            executor = None
    else:
        ran_on = "this process"
    if executor is None and workers > 1:
        ran_on += f" on {workers} threads"
    _log.info("sweep of %d designs: %s", total, ran_on)
    remote = executor is not None
    if remote:
        # any concurrent.futures.Executor (a process pool, a Dask cluster's executor): each
        # task evaluates a run of chunks and sends back only their measures and feasibility
        payload = _dumps(spec)
        if pool is not None:
            tasks = -(-n_chunks // _chunks_per_task(executor, spec, rows, n_chunks))
        counts = [n_chunks // tasks + (i < n_chunks % tasks) for i in range(tasks)]
        firsts = np.cumsum([0, *counts[:-1]]).tolist()
        results = executor.map(_remote_block, [payload] * len(counts), firsts, counts)
    elif workers == 1:
        results = (_sweep_block(spec, c) for c in range(n_chunks))
    else:
        # numpy releases the GIL in its array loops: chunks run in parallel threads
        from concurrent.futures import ThreadPoolExecutor

        threads = ThreadPoolExecutor(max_workers=workers)
        results = threads.map(_sweep_block, [spec] * n_chunks, range(n_chunks))
    try:
        for res in results:
            if res is not None:
                idx = slice(res.start, res.start + res.ok.size)
                ok_all[idx] = res.ok
                for label, v in res.values.items():
                    out[label][idx] = v
                if remote:  # a task's parameters: derived here, chunk by chunk
                    first = res.start // chunk
                    parts = [
                        (c * chunk, _chunk_designs(spec, c)[3])
                        for c in range(first, -(-(res.start + res.ok.size) // chunk))
                    ]
                else:
                    parts = [(res.start, res.params)]
                for at, params in parts:
                    for name, v in params.items():
                        dest = par_out.get(name)
                        if dest is None:  # not setdefault: its default would be built each time
                            dest = par_out[name] = np.zeros(total)
                        dest[at : at + v.size] = v
                if res.reason and not reason:
                    reason = res.reason
            bar.update(1 if res is None else -(-res.ok.size // chunk))
    finally:
        if pool is not None:
            pool.shutdown(wait=True, cancel_futures=True)
        elif executor is None and workers > 1:
            threads.shutdown()
    bar.close()
    if not ok_all.any():
        raise MechanismError(f"no feasible design on the grid ({total} designs): {reason}")
    mask = ~ok_all.reshape(shape)
    units = {}
    for label, m in bound.items():
        units[label] = getattr(m, "unit", "") if isinstance(m, Measure) else ""
        orig = measures[label]
        if isinstance(orig, Measure) and getattr(orig, "unit", ""):
            units[label] = orig.unit
    params_ma = {
        n: np.ma.MaskedArray(v.reshape(shape), mask=mask.copy()) for n, v in par_out.items()
    }
    for n, v in fixed.items():
        if isinstance(v, (int, float, np.floating)) and n not in params_ma:
            params_ma[n] = np.ma.MaskedArray(np.full(shape, float(v)), mask=mask.copy())
    return Chart(
        mechanism=mechanism,
        grid=axes,
        values={
            lab: np.ma.MaskedArray(v.reshape(shape), mask=mask.copy()) for lab, v in out.items()
        },
        feasible=~mask,
        params=params_ma,
        units=units,
        labels={n: (labels or {}).get(n, n) for n in axes},
        angles=int(phi.size),
        speed=speed,
        elapsed=time.perf_counter() - t0,
        reason=reason,
        measures=dict(measures),
        ran_on=ran_on,
    )


# ------------------------------------------------------------------------------ slider-crank
def slider_crank_chart(
    stroke: float = 0.1,
    rod_crank=None,
    offset_crank=None,
    speed: float | None = None,
    angles: int = 360,
    progress: bool = True,
    chunk: int | None = None,
    workers: int = 1,
    executor=None,
) -> Chart:
    """Slider-crank chart at a fixed stroke: peak slider acceleration, maximum pressure angle,
    time ratio and rod length over ``lambda = rod / crank`` and ``e / r = offset / crank``.

    For each grid point the crank is the one giving the stroke ``H``: the stroke of an offset
    slider-crank is ``r * f(lambda, e/r)`` with ``f`` the stroke of the design scaled to a unit
    crank, so ``crank = H / f``. Designs with ``lambda <= 1 + |e/r|`` cannot make full turns
    and are infeasible.

    Parameters
    ----------
    stroke : H (m).
    rod_crank, offset_crank : grid values (default 200 values each over [1.5, 8] and [0, 2]).
    speed : crank speed (rad/s; default 600 rpm).
    angles : crank angles per cycle.
    progress, chunk, workers, executor : as :func:`sweep`.
    """
    from ..kinematics.slider_crank import SliderCrank
    from ..objectives.base import ScalarMeasure
    from ..objectives.kinematic import max_pressure_angle, peak_acceleration, time_ratio
    from ..units import rpm

    H = float(stroke)
    if not np.isfinite(H) or H <= 0:
        raise MechanismError(f"stroke must be a positive length in m, got {stroke}")
    lam = np.linspace(1.5, 8.0, 200) if rod_crank is None else np.asarray(rod_crank, float)
    eps = np.linspace(0.0, 2.0, 200) if offset_crank is None else np.asarray(offset_crank, float)
    speed = rpm(600) if speed is None else float(speed)

    def feasible(v):
        return v["rod/crank"] > 1.0 + np.abs(v["offset/crank"])

    def design(v):
        unit = SliderCrank(crank=1.0, rod=v["rod/crank"], offset=v["offset/crank"])
        crank = H / np.asarray(unit.stroke)
        return {"crank": crank, "rod": v["rod/crank"] * crank, "offset": v["offset/crank"] * crank}

    return sweep(
        SliderCrank,
        grid={"rod/crank": lam, "offset/crank": eps},
        measures={
            "peak slider acceleration": peak_acceleration("slider"),
            "max pressure angle": max_pressure_angle(),
            "time ratio": time_ratio(),
            "rod length": ScalarMeasure("rod length", lambda mech: mech.rod, "m"),
        },
        design=design,
        feasible=feasible,
        angles=angles,
        speed=speed,
        chunk=chunk,
        progress=progress,
        workers=workers,
        executor=executor,
        labels={
            "rod/crank": "λ = rod / crank (–)",
            "offset/crank": "e / r = offset / crank (–)",
        },
    )


@chart_options(
    Option("stroke", 0.1, "required slider stroke H", unit="m", minimum=0.0, exclusive=True),
    Option("rpm", 600.0, "crank speed", unit="rpm", minimum=0.0, exclusive=True),
    Option("n", 60, "grid points per axis", minimum=3, maximum=2000),
    Option("n_angles", 360, "crank angles per turn", minimum=8, maximum=100_000),
    Option("rod_crank", (1.5, 8.0), "range of rod/crank", kind="span", minimum=1.0, exclusive=True),
    Option("offset_crank", (0.0, 2.0), "range of offset/crank", kind="span"),
    Option(
        "pressure_limit_deg",
        30.0,
        "limit on the max pressure angle",
        unit="deg",
        minimum=0.0,
        exclusive=True,
        maximum=90.0,
    ),
    Option(
        "rod_max",
        None,
        "limit on the rod length (unset: none)",
        unit="m",
        kind="float",
        minimum=0.0,
        exclusive=True,
    ),
    owner="chart 'slider-crank'",
)
def chart_slider_crank(out, options):
    """``mechsynth chart slider-crank``: peak slider acceleration, max pressure angle and time
    ratio of offset slider-cranks of a given stroke over (rod/crank, offset/crank); its options
    are ``chart_slider_crank.options``."""
    from .. import display
    from ..report import StudyResult
    from ..units import deg, rpm

    H, speed_rpm, n = options["stroke"], options["rpm"], options["n"]
    n_angles, limit_deg = options["n_angles"], options["pressure_limit_deg"]
    rod_max = options["rod_max"]
    l_lo, l_hi = options["rod_crank"]
    e_lo, e_hi = options["offset_crank"]
    chart = slider_crank_chart(
        H,
        np.linspace(l_lo, l_hi, n),
        np.linspace(e_lo, e_hi, n),
        speed=rpm(speed_rpm),
        angles=n_angles,
    )
    limits = {"max pressure angle": ("<=", deg(limit_deg))}
    if rod_max is not None:
        limits["rod length"] = ("<=", float(rod_max))
    files = []
    if out is not None:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        out = output_dir(out)
        files.append(chart.to_csv(out / "slider_crank_chart.csv"))
        files.append(chart.to_npz(out / "slider_crank_chart.npz"))
        fig = chart.plot(
            measures=["peak slider acceleration", "max pressure angle", "time ratio"],
            limits=limits,
            best="peak slider acceleration",
            title=f"Offset slider-crank, stroke {display.fmt(H, 'm', 4)} at {speed_rpm:g} rpm: "
            f"{n} x {n} designs, {n_angles} crank angles",
        )
        save_figure(fig, out / "slider_crank_chart.png", dpi=130)
        plt.close(fig)
        files.append(out / "slider_crank_chart.png")
    best = chart.argbest("peak slider acceleration", where=limits)
    rod_text = "" if rod_max is None else f" and rod <= {display.fmt(float(rod_max), 'm')}"
    edge = best["on_edge"]
    ranges = {"rod/crank": (l_lo, l_hi), "offset/crank": (e_lo, e_hi)}
    edge_text = ""
    if edge:
        where = ", ".join(
            f"{k} = {ranges[k][0 if side == 'lower' else 1]:g} ({side} end)"
            for k, side in edge.items()
        )
        edge_text = (
            f"\nWARNING: the best grid design lies on the grid's edge ({where}): the optimum may "
            "lie outside the chart; widen the range (--set rod_crank=LOW:HIGH, "
            "offset_crank=LOW:HIGH)."
        )
    p, v = best["params"], best["values"]
    summary = (
        f"slider-crank chart: stroke {display.fmt(H, 'm')} at {speed_rpm:g} rpm, {n} x {n} "
        f"designs (rod/crank {l_lo:g}..{l_hi:g}, offset/crank {e_lo:g}..{e_hi:g}), {n_angles} "
        f"crank angles, {int(chart.feasible.sum())} feasible, {chart.elapsed:.2f} s.\n"
        f"Lowest peak slider acceleration with pressure angle <= {limit_deg:g} deg{rod_text} "
        "on the grid: "
        f"{display.fmt(v['peak slider acceleration'], 'm/s^2')} at rod/crank "
        f"{best['grid']['rod/crank']:.4g}, offset/crank {best['grid']['offset/crank']:.4g} "
        f"(crank {display.fmt(p['crank'], 'm', 4)}, rod {display.fmt(p['rod'], 'm', 4)}, "
        f"offset {display.fmt(p['offset'], 'm', 4)}; pressure angle "
        f"{display.fmt(v['max pressure angle'], 'rad', 4)}, time ratio "
        f"{v['time ratio']:.4g}){edge_text}"
    )
    data = dict(
        stroke=H,
        rpm=speed_rpm,
        grid=n,
        n_angles=n_angles,
        pressure_limit_deg=limit_deg,
        rod_max=None if rod_max is None else float(rod_max),
        feasible=int(chart.feasible.sum()),
        elapsed=chart.elapsed,
        best_on_grid=best,
        best_on_edge=bool(edge),
        ran_on=chart.ran_on,
    )
    return StudyResult("slider-crank-chart", summary, data, [Path(f) for f in files])
