"""Pareto fronts of two competing measures by the epsilon-constraint method.

For a :class:`~mechsynth.synthesis.Problem` (variables, fixed parameters, constraints) and two
measures ``first`` and ``second``:

1. the *anchors*: ``first`` optimized alone (its value of ``second`` is the worst end of the
   front), and ``second`` optimized alone, followed by ``first`` optimized subject to ``second``
   at that optimum (lexicographic, so the anchor is not weakly dominated);
2. for ``eps`` between the two anchors' values of ``second``: optimize ``first`` subject to
   ``second <= eps`` (``>= eps`` when ``second`` is maximized), each solve started from the
   previous point's design;
3. points that are dominated by another point are flagged (non-dominated filtering).

Every point is a certified :class:`~mechsynth.synthesis.Result` of the problem's solver, so the
values on the front are true peaks over the continuous crank angle.

>>> import mechsynth as ms
>>> from mechsynth import objectives as ob
>>> prob = ms.Problem(ms.SliderCrank, {"crank": (0.01, 0.2), "rod": (0.05, 0.2),
...                                    "offset": (-0.1, 0.1)}, speed=ms.rpm(600))
>>> _ = prob.subject_to(ob.stroke("slider") == 0.1)
>>> front = pareto_front(prob, ob.peak_acceleration("slider"), ob.max_pressure_angle(),
...                      n=7)                                        # doctest: +SKIP
>>> front.first, front.second, front.plot()                          # doctest: +SKIP
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import MechanismError
from ..fileio import output_dir, save_figure, write_text
from ..objectives.base import Measure
from ..options import Option, chart_options

__all__ = ["ParetoFront", "pareto_front", "true_value", "chart_pareto_slider_crank"]


def true_value(problem, measure: Measure, design, n_dense: int = 2048) -> float:
    """Value of ``measure`` at ``design`` with every peak taken over the continuous crank angle
    (dense evaluation + 1-D search, as the solvers certify), at the problem's speed."""
    from ..kinematics.mechanism import input_grid
    from .certify import true_peak
    from .transcription import evaluate_form, flatten

    form = flatten(measure, problem.mechanism)
    peaks = {}
    for _, atom in form.terms:
        if atom.kind == "peak":
            peaks[atom] = true_peak(atom, design, problem.speed, n_dense)[0]
    motion = design.motion(input_grid(design, n_dense), speed=problem.speed)
    return float(evaluate_form(form, design, motion, peaks))


@dataclass(frozen=True)
class ParetoFront:
    """The points of an epsilon-constraint sweep.

    Attributes
    ----------
    first_name, second_name : the two measures; ``senses`` ("min"/"max" each); ``units``.
    eps : the bound on ``second`` of each point (the anchors included: first and last).
    first, second : masked arrays of the two measures at each point's design (true peaks),
        masked where the solve failed.
    success : per point, the solve ended "optimal".
    nondominated : per point, successful and not dominated by another successful point.
    results : per point, the :class:`~mechsynth.synthesis.Result`.
    designs : per point, the design (mechanism instance) or None.
    variables : names of the decision variables.
    solve_time : wall-clock seconds of the whole sweep.
    """

    first_name: str
    second_name: str
    senses: tuple[str, str]
    units: tuple[str, str]
    eps: np.ndarray
    first: np.ma.MaskedArray
    second: np.ma.MaskedArray
    success: np.ndarray
    nondominated: np.ndarray
    results: tuple
    designs: tuple
    variables: tuple[str, ...]
    solve_time: float

    @property
    def n_points(self) -> int:
        return int(self.eps.size)

    def front(self):
        """``(first, second)`` of the non-dominated points, ordered by ``second``."""
        idx = np.flatnonzero(self.nondominated)
        idx = idx[np.argsort(self.second.data[idx])]
        return self.first.data[idx], self.second.data[idx]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict (``mechsynth.jsonutil.dumps``)."""
        pts = []
        for i, r in enumerate(self.results):
            pts.append(
                dict(
                    eps=float(self.eps[i]),
                    status=r.status,
                    success=bool(self.success[i]),
                    nondominated=bool(self.nondominated[i]),
                    first=None if self.first.mask[i] else float(self.first[i]),
                    second=None if self.second.mask[i] else float(self.second[i]),
                    design=None if r.design is None else r.design.params(),
                )
            )
        return dict(
            first=self.first_name,
            second=self.second_name,
            senses=list(self.senses),
            units=list(self.units),
            points=pts,
            solve_time=self.solve_time,
        )

    @property
    def mechanism(self):
        """The mechanism class of the front's designs (None when no solve produced one)."""
        return next((type(d) for d in self.designs if d is not None), None)

    def labels(self) -> tuple[str, str]:
        """The two measures in words (``"peak acceleration of the polished rod"``)."""
        from ..plotting import readable

        output = getattr(self.mechanism, "output_label", "slider")
        return readable(self.first_name, output), readable(self.second_name, output)

    def _table(self):
        from .. import tables

        u1, u2 = self.units
        ok = self.success
        cols = [
            (f"bound on {self.second_name}", u2, self.eps),
            ("status", "", np.array([r.status for r in self.results])),
            ("success", "", ok.astype(int)),
            ("nondominated", "", self.nondominated.astype(int)),
            (self.first_name, u1, np.ma.MaskedArray(self.first.data, ~ok)),
            (self.second_name, u2, np.ma.MaskedArray(self.second.data, ~ok)),
        ]
        mech = self.mechanism
        for k in self.variables:
            unit = mech.unit_of(k) if hasattr(mech, "unit_of") else ""
            vals = np.array(
                [r.variables.get(k, np.nan) if r.variables else np.nan for r in self.results]
            )
            cols.append((k, unit, np.ma.MaskedArray(vals, ~ok)))
        return tables.table(cols)

    def to_csv(self, path=None):
        """One row per point: the bound on ``second``, status, success, nondominated, both
        measures (empty where the solve failed) and the design variables, in display units
        with the unit in each column name. Written to ``path`` (returns it) or returned as
        text."""
        from .. import tables

        return tables.write_csv(self._table(), path)

    def plot(self, ax=None, title: str | None = None):
        """The front in display units: ``second`` on x, ``first`` on y, axes named in words;
        non-dominated points joined, dominated points hollow, the two anchors marked; the
        legend below the axes. Returns the figure."""
        import matplotlib.pyplot as plt

        from .. import display
        from ..plotting import PALETTE, style

        with style():
            own = ax is None
            fig = plt.figure(figsize=(7, 5.5), layout="constrained") if own else ax.figure
            ax = fig.add_subplot() if own else ax
            y, uy = display.convert(self.first.data, self.units[0])
            x, ux = display.convert(self.second.data, self.units[1])
            ly, lx = self.labels()
            nd = self.nondominated
            order = np.flatnonzero(nd)[np.argsort(x[nd])]
            ax.plot(x[order], y[order], "-o", color=PALETTE[4], ms=5, label="non-dominated designs")
            dom = self.success & ~nd
            if dom.any():
                ax.plot(x[dom], y[dom], "o", mfc="none", color="0.5", label="dominated")
            ends = [i for i in (0, self.n_points - 1) if self.success[i]]
            if ends:
                ax.plot(
                    x[ends],
                    y[ends],
                    "s",
                    ms=10,
                    mfc="none",
                    color=PALETTE[5],
                    label="anchors (one measure alone)",
                )
            if (~self.success).any():
                ax.plot(
                    [],
                    [],
                    "x",
                    color=PALETTE[5],
                    label=f"{int((~self.success).sum())} failed solves",
                )
            ax.set_xlabel(f"{lx}, {ux}" if ux else lx)
            ax.set_ylabel(f"{ly}, {uy}" if uy else ly)
            ax.margins(0.08)
            ax.set_title(
                title
                or f"Pareto front: {self.senses[0]}imize {ly} against {self.senses[1]}imize {lx}",
                fontsize=10,
            )
            if own:
                fig.legend(loc="outside lower center", ncol=2, fontsize=8)
            else:
                ax.legend(fontsize=8)
        return fig


def _dominance(f1, f2, ok, senses, rtol=1e-7):
    """Non-dominated mask among ``ok`` points (both measures made 'smaller is better')."""
    a = np.where(ok, f1 if senses[0] == "min" else -f1, np.inf)
    b = np.where(ok, f2 if senses[1] == "min" else -f2, np.inf)
    ta = rtol * max(float(np.ptp(a[ok])) if ok.any() else 0.0, 1e-300)
    tb = rtol * max(float(np.ptp(b[ok])) if ok.any() else 0.0, 1e-300)
    nd = ok.copy()
    for i in np.flatnonzero(ok):
        better_eq = (a <= a[i] + ta) & (b <= b[i] + tb) & ok
        strictly = (a < a[i] - ta) | (b < b[i] - tb)
        if np.any(better_eq & strictly):
            nd[i] = False
    return nd


def pareto_front(
    problem,
    first: Measure,
    second: Measure,
    n: int = 9,
    *,
    senses: tuple[str, str] = ("min", "min"),
    eps=None,
    method: str = "ipopt",
    starts: int = 4,
    anchor_starts: int = 8,
    seed: int | None = 0,
    progress: bool | None = None,
    solve_options: dict | None = None,
    lexicographic_rtol: float = 1e-7,
    anchor_x0: dict | None = None,
    polish_anchors: bool = True,
    first_anchor=None,
) -> ParetoFront:
    """Pareto front of ``first`` against ``second`` by the epsilon-constraint method.

    Parameters
    ----------
    problem : a :class:`~mechsynth.synthesis.Problem`; its variables, fixed parameters,
        speed and constraints define the feasible set (its objective is not used).
    first, second : the two measures (e.g. ``peak_acceleration("slider")`` and
        ``max_pressure_angle()``).
    n : points on the front, anchors included (>= 2).
    senses : ``("min", "min")`` by default; ``"max"`` for a measure to maximize.
    eps : optional bounds on ``second`` for the points between the anchors (SI units; e.g.
        pressure-angle limits in rad) instead of ``n - 2`` values evenly between the anchors'
        values of ``second``; ``n`` is then ignored.
    method, starts, seed, solve_options : passed to :meth:`Problem.solve` (``solve_options``
        as further keyword arguments). Points after the first start from the previous design
        (``x0``) plus ``starts - 1`` Sobol points.
    anchor_starts : multi-start count of the two single-objective anchors (they fix the
        extent of the front, so they get the wider search).
    progress : a tqdm bar over the points (None: only on a terminal).
    lexicographic_rtol : relative slack of ``second`` at its optimum in the second anchor.
    anchor_x0 : optional start design ``{variable: value}`` of the two anchors (their first
        start; the other starts are Sobol points), e.g. a known good design.
    first_anchor : an optional :class:`~mechsynth.synthesis.Result` of ``problem`` with
        ``first`` alone already solved (e.g. the synthesis the front extends): it is the first
        anchor instead of a new solve.
    polish_anchors : the anchors are local optima of multi-start solves; when a point of the
        sweep beats an anchor in its own objective (``first`` for the first anchor, ``second``
        for the second), the anchor is solved again from that point's design and kept if
        better (``ParetoFront.results`` then holds the re-solved anchor). (Independently of
        it, an inner point that fails from the previous point's design is tried once more from
        the next solved point's.)

    Returns
    -------
    ParetoFront
        Failed solves are recorded (``success``), never raised; when an anchor fails, the sweep
        stops there and the front holds what was solved.
    """
    from ..progress import bar as progress_bar

    t0 = time.perf_counter()
    if eps is not None:
        eps = np.atleast_1d(np.asarray(eps, dtype=float))
        if eps.ndim != 1 or not np.all(np.isfinite(eps)):
            raise MechanismError("eps must be finite bounds on the second measure")
        n = eps.size + 2
    if n < 2:
        raise MechanismError(f"n must be at least 2 (the two anchors), got {n}")
    for s in senses:
        if s not in ("min", "max"):
            raise MechanismError(f"senses must be 'min' or 'max', got {senses!r}")
    for m in (first, second):
        if not isinstance(m, Measure):
            raise TypeError(f"expected a Measure, got {type(m).__name__}")
    opts = dict(method=method, seed=seed, progress=False, **(solve_options or {}))

    def solve(objective, sense, bound=None, x0=None, n_starts=starts):
        p = problem.copy()
        (p.minimize if sense == "min" else p.maximize)(objective)
        if bound is not None:
            p.subject_to(second <= bound if senses[1] == "min" else second >= bound)
        return p, p.solve(x0=x0, starts=n_starts, **opts)

    def measured(p, res):
        """(first, second) at a result's design, true peaks."""
        if res.design is None:
            return np.nan, np.nan
        return true_value(p, first, res.design), true_value(p, second, res.design)

    def lexicographic(s_best):
        slack = lexicographic_rtol * max(abs(s_best), 1e-12)
        return s_best + slack if senses[1] == "min" else s_best - slack

    def anchor1(x0):
        """The first anchor (``first`` alone) from ``x0``, one start: (result, values)."""
        p, r = solve(first, senses[0], x0=x0, n_starts=1)
        return r, measured(p, r)

    def anchor2(x0):
        """The second anchor from ``x0``: ``second`` alone, then ``first`` at its optimum."""
        _, rs = solve(second, senses[1], x0=x0, n_starts=1)
        if not rs.success:
            return None, (np.nan, np.nan)
        p, r = solve(first, senses[0], lexicographic(float(rs.value)), x0=rs.variables, n_starts=1)
        return r, measured(p, r)

    def point(e, x0):
        """The point at bound ``e`` from ``x0``, one start: (result, values)."""
        p, r = solve(first, senses[0], float(e), x0=x0)
        return r, measured(p, r)

    results, eps_list, vals = [], [], []  # per point, anchors first and last
    bar = progress_bar(total=n, desc="Pareto front", enabled=progress, unit="point")
    # anchor 1: first alone
    if first_anchor is None:
        p1, r1 = solve(first, senses[0], x0=anchor_x0, n_starts=anchor_starts)
    else:
        if set(first_anchor.variables or {}) != set(problem.names):
            raise MechanismError(
                f"first_anchor's variables {sorted(first_anchor.variables or {})} are not the "
                f"problem's {sorted(problem.names)}"
            )
        p1, r1 = problem.copy(), first_anchor
        (p1.minimize if senses[0] == "min" else p1.maximize)(first)
    results.append(r1)
    vals.append(measured(p1, r1))
    eps_list.append(vals[-1][1])
    bar.update()
    if r1.success:
        # anchor 2: second alone, then first at that optimum
        _, r2s = solve(second, senses[1], x0=anchor_x0, n_starts=anchor_starts)
        if r2s.success:
            s_best = float(r2s.value)
            bound = lexicographic(s_best)
            p2, r2 = solve(first, senses[0], bound, x0=r2s.variables)
            s_worst = eps_list[0]
            if eps is None:
                inner = np.linspace(s_worst, s_best, n)[1:-1]
            else:  # from the first anchor's side towards the second's
                inner = np.sort(eps)[:: -1 if senses[1] == "min" else 1]
            x0 = r1.variables
            for e in inner:
                re, v = point(e, x0)
                results.append(re)
                vals.append(v)
                eps_list.append(float(e))
                if re.success:
                    x0 = re.variables
                bar.update()
            results.append(r2)
            vals.append(measured(p2, r2))
            eps_list.append(bound)
        else:
            results.append(r2s)
            vals.append((np.nan, np.nan))
            eps_list.append(np.nan)
    bar.update(n - bar.n)
    bar.close()
    if len(results) >= 3 and results[-1].success:
        _retry_failed(results, vals, eps_list, point)
    if polish_anchors and len(results) >= 3 and r1.success:
        _polish_anchors(results, vals, eps_list, anchor1, anchor2, senses)
    success = np.array([r.success for r in results], dtype=bool)
    f1 = np.array([v[0] for v in vals], dtype=float)
    f2 = np.array([v[1] for v in vals], dtype=float)
    success &= np.isfinite(f1) & np.isfinite(f2)
    nd = _dominance(np.where(success, f1, 0.0), np.where(success, f2, 0.0), success, senses)
    eps = np.array(eps_list, dtype=float)
    return ParetoFront(
        first_name=first.name,
        second_name=second.name,
        senses=tuple(senses),
        units=(getattr(first, "unit", ""), getattr(second, "unit", "")),
        eps=np.where(np.isfinite(eps), eps, 0.0),
        first=np.ma.MaskedArray(np.where(success, f1, 0.0), mask=~success),
        second=np.ma.MaskedArray(np.where(success, f2, 0.0), mask=~success),
        success=success,
        nondominated=nd,
        results=tuple(results),
        designs=tuple(r.design for r in results),
        variables=tuple(problem.names),
        solve_time=time.perf_counter() - t0,
    )


def _retry_failed(results, vals, eps_list, point):
    """Solve a failed inner point again from the next solved point towards the second anchor
    (the sweep started it from the previous one), last to first, so a point solved again can
    start the one before it."""
    for k in range(len(results) - 2, 0, -1):
        if results[k].success:
            continue
        j = next(j for j in range(k + 1, len(results)) if results[j].success)
        r, v = point(eps_list[k], results[j].variables)
        if r.success:
            results[k], vals[k] = r, v


def _polish_anchors(results, vals, eps_list, anchor1, anchor2, senses):
    """Re-solve an anchor from the sweep point that beats it in the anchor's own objective."""
    sign = [1.0 if s == "min" else -1.0 for s in senses]

    def better(a, b, k):  # a strictly better than b in objective k (relative 1e-9)
        return sign[k] * (a - b) < -1e-9 * max(abs(a), abs(b), 1e-12)

    inner = range(1, len(results) - 1)
    ok = [k for k in inner if results[k].success and np.all(np.isfinite(vals[k]))]
    # the first anchor: `first` alone
    beat = [k for k in ok if better(vals[k][0], vals[0][0], 0)]
    if beat:
        k = min(beat, key=lambda k: sign[0] * vals[k][0])
        r, v = anchor1(results[k].variables)
        if r.success and better(v[0], vals[0][0], 0):
            results[0], vals[0], eps_list[0] = r, v, v[1]
    # the second anchor: the best `second`, then `first` at it
    last = len(results) - 1
    if results[last].success:
        beat = [k for k in ok if better(vals[k][1], vals[last][1], 1)]
        if beat:
            k = min(beat, key=lambda k: sign[1] * vals[k][1])
            r, v = anchor2(results[k].variables)
            if r is not None and r.success and better(v[1], vals[last][1], 1):
                results[last], vals[last], eps_list[last] = r, v, v[1]


@chart_options(
    Option("stroke", 0.1, "required slider stroke H", unit="m", minimum=0.0, exclusive=True),
    Option("rpm", 600.0, "crank speed", unit="rpm", minimum=0.0, exclusive=True),
    Option("n", 7, "points on the front, anchors included", minimum=2, maximum=200),
    Option("starts", 4, "multi-starts per interior point", minimum=1, maximum=1000),
    Option("anchor_starts", 8, "multi-starts of each anchor", minimum=1, maximum=1000),
    Option(
        "crank",
        (0.01, 0.2),
        "bounds of the crank",
        unit="m",
        kind="span",
        minimum=0.0,
        exclusive=True,
    ),
    Option(
        "rod", (0.05, 0.2), "bounds of the rod", unit="m", kind="span", minimum=0.0, exclusive=True
    ),
    Option("offset", (-0.1, 0.1), "bounds of the offset", unit="m", kind="span"),
    owner="chart 'slider-crank-pareto'",
)
def chart_pareto_slider_crank(out, options):
    """``mechsynth chart slider-crank-pareto``: peak slider acceleration against max pressure
    angle at a fixed stroke; its options are ``chart_pareto_slider_crank.options``."""
    from .. import display
    from ..kinematics.slider_crank import SliderCrank
    from ..objectives.kinematic import max_pressure_angle, peak_acceleration, stroke
    from ..report import StudyResult
    from ..units import rpm
    from .problem import Problem

    H, speed_rpm, n = options["stroke"], options["rpm"], options["n"]
    starts, anchor_starts = options["starts"], options["anchor_starts"]
    variables = {k: options[k] for k in ("crank", "rod", "offset")}
    prob = Problem(SliderCrank, variables, speed=rpm(speed_rpm))
    prob.subject_to(stroke("slider") == H)
    fr = pareto_front(
        prob,
        peak_acceleration("slider"),
        max_pressure_angle(),
        n=n,
        starts=starts,
        anchor_starts=anchor_starts,
    )
    files = []
    if out is not None:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from ..jsonutil import dumps

        out = output_dir(out)
        files.append(fr.to_csv(out / "slider_crank_pareto.csv"))
        write_text(out / "slider_crank_pareto.json", dumps(fr.to_dict()) + "\n")
        files.append(out / "slider_crank_pareto.json")
        fig = fr.plot(
            title=f"Slider-crank, stroke {display.fmt(H, 'm', 4)} at {speed_rpm:g} rpm: "
            "Pareto front of peak acceleration and pressure angle"
        )
        save_figure(fig, out / "slider_crank_pareto.png", dpi=120)
        plt.close(fig)
        files.append(out / "slider_crank_pareto.png")
    du = display.current()
    acc_unit, ang_unit = du.unit("m/s^2"), du.unit("rad")
    lines = [
        f"Pareto front, slider-crank stroke {display.fmt(H, 'm')} at {speed_rpm:g} rpm "
        f"({fr.n_points} points, {fr.solve_time:.1f} s):",
        f"  {'max pressure angle, ' + ang_unit:>24s} {'peak acceleration, ' + acc_unit:>25s}"
        "  status",
    ]
    for i, r in enumerate(fr.results):
        if fr.success[i]:
            mark = "" if fr.nondominated[i] else " (dominated)"
            pa = display.convert(float(fr.second[i]), "rad")[0]
            acc = display.convert(float(fr.first[i]), "m/s^2")[0]
            lines.append(f"  {pa:24.4f} {acc:25.7g}  {r.status}{mark}")
        else:
            lines.append(f"  {'-':>24s} {'-':>25s}  {r.status}: {r.message}")
    data = fr.to_dict()
    data["success"] = bool(fr.success.all())
    return StudyResult("slider-crank-pareto", "\n".join(lines), data, [Path(f) for f in files])
