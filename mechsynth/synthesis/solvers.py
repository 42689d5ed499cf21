"""Solvers behind :meth:`Problem.solve`: certified multi-start IPOPT or SLSQP, and differential
evolution as the global cross-check.

Local method (``"ipopt"``, ``"slsqp"``)
    1. Sobol sample of the variable box (:mod:`.sobol`: ``scipy.stats.qmc``'s points); points
       that are not valid designs
       (the mechanism raises :class:`~mechsynth.errors.MechanismError`, or violates its
       ``feasibility_constraints``) are skipped and replaced by the next point.
    2. Each start is solved on the base grid (IPOPT through CasADi with exact first and second
       derivatives, or scipy SLSQP with exact CasADi gradients).
    3. Every distinct feasible local optimum is *certified* on its own grid: for every peak
       measure the true continuous extremum is located (dense evaluation + 1-D local search);
       where the grid missed it, the angle is added to the grid and the problem re-solved from
       the current point, until every grid peak equals its true peak within ``rtol``.
    4. The candidates are compared by their true continuous objective (never by grid values:
       the grid problem is a relaxation, its value lies below the true one by a design-dependent
       amount). The outcome of a start does not depend on the other starts, so more starts
       never give a worse result; the true values of the distinct optima are the
       certification's ``local_optima``.

Global method (``"de"``)
    scipy's differential evolution over the box, every population evaluated in one vectorized
    numpy call on a uniform grid (invalid designs are masked and rejected by the feasibility
    constraints). Its best design then seeds a certified IPOPT solve (``polish=True``); the
    un-polished result is kept in ``certification.cross_check``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..errors import MechanismError
from .certify import check_peak
from .result import Certification, ConstraintValue, Result
from .transcription import Transcription, design_params, evaluate_form

__all__ = ["solve"]

_IPOPT_STATUS = {
    "Solve_Succeeded": "optimal",
    "Solved_To_Acceptable_Level": "optimal",
    "Infeasible_Problem_Detected": "infeasible",
    "Maximum_Iterations_Exceeded": "max_iterations",
    "Maximum_CpuTime_Exceeded": "max_iterations",
    "Maximum_WallTime_Exceeded": "max_iterations",
}


@dataclass
class _Run:
    """One local solve."""

    x: np.ndarray
    status: str
    raw: str
    iterations: int
    scales: tuple
    lam: Any = None  # multipliers for a warm re-start
    objective: float = np.nan  # sense-adjusted (smaller is better), base/current grid
    violation: float = np.inf  # max relative violation of user + feasibility constraints
    design: Any = None


def _flat(v, size=None):
    a = np.asarray(v, dtype=float)
    if a.ndim and a.shape[-1] == 1:
        a = a[..., 0]
    return a if size is None else np.broadcast_to(a, (size,)).copy()


# ------------------------------------------------------------------------------ evaluation
def _design(problem, tr, z):
    return problem.mechanism(**design_params(problem, tr.params_of(np.clip(z, 0.0, 1.0))))


def _hook_values(problem, params):
    hook = getattr(problem.mechanism, "feasibility_constraints", None)
    if hook is None:
        return []
    return [np.asarray(g, dtype=float) for _, g in hook(params, margin=problem.feasibility_margin)]


def _rel_violation(c, value):
    return float(c.violation(value)) / max(1.0, abs(c.bound))


def _assess(problem, tr, run: _Run, grid):
    """Objective and violation of a run's design on ``grid`` (numpy)."""
    z = run.x[: tr.n]
    try:
        mech = _design(problem, tr, z)
        motion = mech.motion(grid, speed=problem.speed)
        f = float(evaluate_form(tr.objective, mech, motion))
        viol = 0.0
        for c, form in zip(problem.constraints, tr.constraints):
            viol = max(viol, _rel_violation(c, float(evaluate_form(form, mech, motion))))
        for g in _hook_values(problem, mech.params()):
            viol = max(viol, float(-min(g, 0.0)))
    except (MechanismError, ValueError, ArithmeticError):
        run.design, run.objective, run.violation = None, np.nan, np.inf
        return run
    run.design = mech
    run.objective = f if problem.sense == "min" else -f
    run.violation = viol
    return run


def _scales(problem, tr: Transcription, z0, grid):
    """Objective, epigraph and constraint scales at a start, and the start's tau values."""
    mech = _design(problem, tr, z0)
    motion = mech.motion(grid, speed=problem.speed)
    f0 = float(evaluate_form(tr.objective, mech, motion))
    f_scale = max(abs(f0), 1e-12)
    t_scales, tau0 = [], []
    for atom in tr.epigraphs:
        if atom.kind == "peak":
            pk = float(np.max(atom.q(mech, motion)))
        else:
            pk = float(max(float(b) for b in atom.measure.branches(mech)))
        t = max(abs(pk), 1e-12)
        t_scales.append(t)
        tau0.append(pk / t)
    g_scales = []
    for c, form in zip(problem.constraints, tr.constraints):
        v0 = float(evaluate_form(form, mech, motion))
        g_scales.append(1.0 / max(abs(c.bound), abs(v0), 1e-9))
    return (f_scale, np.array(t_scales), np.array(g_scales)), np.array(tau0)


# ------------------------------------------------------------------------------ local solves
_WARM = {
    "warm_start_init_point": "yes",
    "mu_init": 1e-8,
    "warm_start_bound_push": 1e-9,
    "warm_start_slack_bound_push": 1e-9,
    "warm_start_mult_bound_push": 1e-9,
}


def _ipopt(tr: Transcription, x0, P, options, warm=None, n_grid=None):
    """IPOPT from ``x0`` on the first ``n_grid`` grid angles of ``P`` (all slots when None);
    ``warm`` = (lam_x, lam_g) of a previous solve re-starts close to it (small barrier
    parameter) instead of from the centre of the box."""
    opts = dict(options or {})
    lbg, ubg = (tr.lbg, tr.ubg) if n_grid is None else tr.g_bounds(n_grid)
    args = dict(x0=x0, p=P, lbx=tr.lbx, ubx=tr.ubx, lbg=lbg, ubg=ubg)
    if warm is not None:
        opts = {**_WARM, **opts}
        args.update(lam_x0=warm[0], lam_g0=warm[1])
    solver = tr.solver("ipopt", opts)
    try:
        sol = solver(**args)
    except RuntimeError as exc:  # evaluation error at the start point
        return np.asarray(x0, dtype=float), "solver_failed", str(exc).splitlines()[0], 0, None
    stats = solver.stats()
    raw = stats.get("return_status", "unknown")
    x = np.asarray(sol["x"], dtype=float).ravel()
    lam = (
        np.asarray(sol["lam_x"], dtype=float).ravel(),
        np.asarray(sol["lam_g"], dtype=float).ravel(),
    )
    status = _IPOPT_STATUS.get(raw, "solver_failed")
    return x, status, raw, int(stats.get("iter_count", 0)), lam


def _slsqp(tr: Transcription, x0, P, options, warm=None, n_grid=None):
    from scipy.optimize import minimize

    lbg, ubg = (tr.lbg, tr.ubg) if n_grid is None else tr.g_bounds(n_grid)

    f_fun, g_fun = tr.solver("functions")
    cache: dict[str, Any] = {}

    def fg(x):
        key = x.tobytes()
        if cache.get("key") != key:
            f, df = f_fun(x, P)
            g, jg = g_fun(x, P)
            cache.update(
                key=key,
                f=float(f),
                df=np.asarray(df, dtype=float).ravel(),
                g=np.asarray(g, dtype=float).ravel(),
                jg=np.asarray(jg, dtype=float).reshape(len(lbg), -1),
            )
        return cache

    eq = np.isfinite(lbg) & (lbg == ubg)
    up = np.isfinite(ubg) & ~eq
    lo = np.isfinite(lbg) & ~eq
    cons = []
    if eq.any():
        cons.append(
            dict(
                type="eq",
                fun=lambda x: fg(x)["g"][eq] - lbg[eq],
                jac=lambda x: fg(x)["jg"][eq],
            )
        )
    if up.any():
        cons.append(
            dict(
                type="ineq",
                fun=lambda x: ubg[up] - fg(x)["g"][up],
                jac=lambda x: -fg(x)["jg"][up],
            )
        )
    if lo.any():
        cons.append(
            dict(
                type="ineq",
                fun=lambda x: fg(x)["g"][lo] - lbg[lo],
                jac=lambda x: fg(x)["jg"][lo],
            )
        )
    bounds = [
        (lb if np.isfinite(lb) else None, ub if np.isfinite(ub) else None)
        for lb, ub in zip(tr.lbx, tr.ubx)
    ]
    opts = {"maxiter": 500, "ftol": 1e-12}
    opts.update(options or {})
    try:
        res = minimize(
            lambda x: fg(x)["f"],
            np.asarray(x0, dtype=float),
            jac=lambda x: fg(x)["df"],
            method="SLSQP",
            bounds=bounds,
            constraints=cons,
            options=opts,
        )
    except (ValueError, FloatingPointError) as exc:
        return np.asarray(x0, dtype=float), "solver_failed", str(exc), 0, None
    status = {0: "optimal", 9: "max_iterations", 4: "infeasible"}.get(res.status, "solver_failed")
    return np.asarray(res.x, dtype=float), status, str(res.message), int(res.nit), None


_LOCAL = {"ipopt": _ipopt, "slsqp": _slsqp}


# ------------------------------------------------------------------------------ starts
#: Sobol points tried per start asked (at least ``_MIN_CANDIDATES``) before the solve gives up
#: looking for valid start designs
START_BUDGET = 8
_MIN_CANDIDATES = 16
#: points tried before a solve that found no valid start at all gives up: a box that is mostly
#: invalid (a four-bar box of mostly non-crank-rockers) still yields its first start
_FIRST_BUDGET = 256


def _start_points(problem, tr: Transcription, starts, seed, x0, grid):
    """Up to ``starts`` valid start points (scaled to the box) with their scales, the number of
    points skipped, the first reason a point was invalid and the number of points tried.

    A point is valid when the mechanism builds, moves over the grid, meets its
    ``feasibility_constraints`` and every measure of the problem evaluates to a finite number
    there (a swing angle of a double-crank does not); invalid points are replaced by the next
    Sobol point, up to ``START_BUDGET`` points per start asked (at least 16), and on to
    ``_FIRST_BUDGET`` points while none was valid (one start asked in a mostly invalid box was
    reported as a failed solve after 16 points).
    """
    from .sobol import sobol

    points, skipped, reason, tried = [], 0, "", 0
    candidates = []
    if x0 is not None:
        vals = [x0[k] if isinstance(x0, dict) else x0[i] for i, k in enumerate(problem.names)]
        candidates.append(tr.z_of(vals))
    budget = max(START_BUDGET * starts, _MIN_CANDIDATES)
    m = int(2 ** np.ceil(np.log2(max(budget, _FIRST_BUDGET))))
    sob = sobol(tr.n, m, seed)
    candidates.extend(sob)
    for z in candidates:
        # the budget per start asked, past it only while no valid start was found at all
        if len(points) >= starts or (tried >= budget and points):
            break
        tried += 1
        try:
            mech = _design(problem, tr, z)
            bad = [g for g in _hook_values(problem, mech.params()) if float(g) < 0.0]
            if bad:
                raise MechanismError("violates the mechanism's feasibility constraints")
            scales, tau0 = _scales(problem, tr, z, grid)
            if not (np.all(np.isfinite(tau0)) and all(np.all(np.isfinite(s)) for s in scales)):
                raise MechanismError("a measure is not finite at this design")
        except (MechanismError, ValueError, ArithmeticError) as exc:
            skipped += 1
            reason = reason or str(exc)
            continue
        points.append((np.asarray(z, dtype=float), scales, tau0))
    return points, skipped, reason, tried


def _progress(iterable, total, progress, desc):
    from ..progress import bar

    return bar(iterable, total=total, desc=desc, enabled=progress)


# ------------------------------------------------------------------------------ certification
def _peak_atoms(tr: Transcription):
    seen, atoms = set(), []
    for form in [tr.objective, *tr.constraints]:
        for _, atom in form.terms:
            if atom.kind == "peak" and id(atom.measure) not in seen:
                seen.add(id(atom.measure))
                atoms.append(atom)
    return atoms


class _Unassembled(Exception):
    """A candidate that cannot be assembled at some crank angle the grid does not hold, and
    whose error names no angle to add: it is treated as infeasible."""


#: refinement angles (rad) closer than this share a slot when the slots run out
_SAME_ANGLE = 1e-7


class _Certifier:
    """Refines the grid around one candidate until its peaks are certified.

    A design that cannot be assembled between the grid's angles (a general linkage, whose
    assembly is a per-angle condition) raises in the dense evaluation; the angles its
    :class:`MechanismError` names are added to the grid, where the problem's assembly
    constraints then hold, and the problem is re-solved, like a missed peak.
    """

    def __init__(self, problem, method, options, rtol, max_rounds, n_dense, tr=None):
        self.problem, self.method, self.options = problem, method, options
        self.rtol, self.max_rounds, self.n_dense = rtol, max_rounds, n_dense
        self.extra: list[float] = []
        # the peaks (indices in atoms; None: where the design did not assemble) of each angle
        self.owners: list[set] = []
        self.merged = None  # new slot of each old one after a merge (fixed slots), for run()
        # numeric forms suffice to check peaks without re-solving (max_rounds 0)
        self.tr = problem._transcription() if tr is None else tr
        self.atoms = _peak_atoms(self.tr)
        self.rounds = 0
        self.iterations = 0  # of the re-solves after refinement

    @property
    def grid(self):
        return np.concatenate([self.problem.base_angles, self.extra])

    def checks(self, mech):
        """The peak checks at ``mech``, the angles to add and the true peaks by measure
        identity."""
        checks, found, true_q = self.found(mech)
        return checks, [a for a, _ in found], true_q

    def found(self, mech):
        """:meth:`checks` with each angle to add as ``(angle, index of its peak in atoms, or
        None for an angle where the design does not assemble)``."""
        checks, new, true_q = [], [], {}
        for k, atom in enumerate(self.atoms):
            try:
                chk, angles, tq = check_peak(
                    atom, mech, self.grid, self.problem.speed, self.rtol, self.n_dense
                )
            except MechanismError as exc:
                where = list(getattr(exc, "angles", ()))
                if not where:
                    raise _Unassembled(str(exc)) from exc
                return [], [(a, None) for a in where], {}
            checks.append(chk)
            new.extend((a, k) for a in angles)
            true_q[id(atom.measure)] = tq
        return checks, new, true_q

    def _add(self, found):
        """Add the angles ``found`` (``(angle, peak index or None)``) to the grid; True when
        the program had to grow (a new, larger transcription).

        With a fixed slot count (``problem.slots``), an angle found within half a base step of
        an earlier refinement angle of the same peak replaces it in the first half of the
        rounds (the peak moved with the design: its slot, and the slot's multipliers, follow
        it), so the slots hold about one angle per active peak; after that angles are only
        added, as always without a slot count (a minimized peak can slide along a single
        angle round after round; the angles kept on both sides then hold it). The program
        grows (twice its slots) only when the angles outnumber its slots. The certificate is
        the same: the final grid's peaks against the true peaks."""
        from ..kinematics.mechanism import input_domain

        periodic = input_domain(self.problem.mechanism)[2]

        def dist(a, b):
            return abs(np.angle(np.exp(1j * (a - b)))) if periodic else abs(a - b)

        base = np.asarray(self.problem.base_angles, dtype=float)
        step = 2.0 * np.pi / base.size if periodic else float(np.ptp(base)) / (base.size - 1)
        moving = self.problem.slots is not None and self.rounds < self.max_rounds // 2
        moved: set[int] = set()
        for a, k in found:
            if any(dist(a, b) <= 1e-12 for b in self.extra):
                continue
            if moving and k is not None:
                near = [
                    i
                    for i, (b, o) in enumerate(zip(self.extra, self.owners))
                    if k in o and i not in moved and dist(a, b) < 0.5 * step
                ]
                if near:
                    i = min(near, key=lambda i: dist(a, self.extra[i]))
                    self.extra[i] = a
                    self.owners[i] = {k}
                    moved.add(i)
                    continue
            self.extra.append(a)
            self.owners.append({k})
            moved.add(len(self.extra) - 1)
        if len(self.extra) > self.tr.n_extra and self.problem.slots is not None:
            self._merge(dist)
        if len(self.extra) > self.tr.n_extra:
            n = int(2 ** np.ceil(np.log2(len(self.extra))))
            if self.problem.slots is not None:
                n = max(n, 2 * self.tr.n_extra)
            self.tr = self.problem._transcription(n)
            # the new transcription binds its own measure objects: the true peaks found from
            # now on must be keyed by them, or the final values miss them (dense-grid values)
            self.atoms = _peak_atoms(self.tr)
            return True
        return False

    def _merge(self, dist):
        """Angles closer than :data:`_SAME_ANGLE` take one slot (the first's): peaks at one
        angle (the dead centres: a stroke's end, the joints' nearest approach to a wall) find
        it each to the 1-D search's tolerance (some 1e-7 rad), not to 1e-12, and kept a slot
        each (five for one angle in the impact synthesis). Only when the angles outnumber the
        slots, before the program grows: their grid values there differ from their peaks by
        some 1e-14 relative, and a peak the merged angle does not certify finds its own
        again. Sets :attr:`merged` (the new slot of each old one) for the multipliers."""
        keep: list[int] = []
        where = np.empty(len(self.extra), dtype=int)
        for i, a in enumerate(self.extra):
            j = next((j for j, b in enumerate(keep) if dist(a, self.extra[b]) <= _SAME_ANGLE), None)
            if j is None:
                where[i] = len(keep)
                keep.append(i)
            else:
                where[i] = j
        if len(keep) == len(self.extra):
            return
        owners = [set() for _ in keep]
        for i, o in enumerate(self.owners):
            owners[where[i]] |= o
        self.extra = [self.extra[i] for i in keep]
        self.owners = owners
        self.merged = where

    def run(self, run: _Run):
        """Certify ``run``; returns (run, checks, certified, true_q)."""
        local = _LOCAL[self.method]
        while True:
            if run.design is None:
                return run, (), False, {}
            try:
                checks, new, true_q = self.found(run.design)
            except _Unassembled:
                return replace(run, design=None, violation=np.inf), (), False, {}
            if not new:
                return run, tuple(checks), True, true_q
            if self.rounds >= self.max_rounds:
                return run, tuple(checks), False, true_q
            before = self.tr
            self.merged = None
            rebuilt = self._add(new)
            self.rounds += 1
            P = self.tr.parameter_vector(self.grid, *run.scales)
            warm = run.lam
            if self.problem.slots is not None and self.rounds == 1:
                # the first refinement adds every peak the base grid missed: its solve goes
                # far from the base grid's optimum, which the multipliers (and the small
                # barrier parameter of a warm start) would hold it near (the impact
                # synthesis: a worse local optimum, 29.73 against 30.01 J). Later rounds move
                # the angles little: warm
                warm = None
            if self.merged is not None and warm is not None:  # merged slots: their rows'
                warm = (warm[0], before.merge_slots(warm[1], self.merged))
            if rebuilt:  # the multipliers have the old program's rows
                fixed = self.problem.slots is not None and warm is not None
                warm = self.tr.carry(warm, before) if fixed else None
            del before
            n_grid = len(self.grid)
            x0 = run.x
            if self.problem.slots is not None and warm is not None:
                # the epigraph variables raised to their rows' largest over the new grid: a
                # warm start (a small barrier parameter) from a point that violates the added
                # angles' rows crawled back to feasibility (the impact synthesis: its
                # re-solves 30 % fewer iterations, the same certified optima)
                x0 = self.tr.lift_epigraphs(run.x, P, n_grid)
            x, status, raw, it, lam = local(self.tr, x0, P, self.options, warm, n_grid)
            # a warm start that failed is solved again cold; with fixed slots not when IPOPT
            # found the round's program locally infeasible: the cold solve from the same
            # point found it so too (17-19 s each, a nearly interior-less lexicographic
            # anchor of the impact front), and the next round's warm start solved it
            retry = not (self.problem.slots is not None and status == "infeasible")
            if status != "optimal" and warm is not None and retry:
                self.iterations += it
                x, status, raw, it, lam = local(self.tr, run.x, P, self.options, None, n_grid)
            self.iterations += it
            new = _Run(x, status, raw, it, run.scales, lam)
            run = _assess(self.problem, self.tr, new, self.grid)


# ------------------------------------------------------------------------------ final numbers
def _final(problem, tr, mech, true_q, n_dense=2048):
    """Objective and constraint values at ``mech`` with true peaks (a uniform grid of
    ``n_dense`` angles for averages and numpy-only measures)."""
    from ..kinematics.mechanism import input_grid

    motion = mech.motion(input_grid(mech, n_dense), speed=problem.speed)
    peaks = {}
    for form in [tr.objective, *tr.constraints]:
        for _, atom in form.terms:
            if atom.kind == "peak" and id(atom.measure) in true_q:
                peaks[atom] = true_q[id(atom.measure)]
    value = float(evaluate_form(tr.objective, mech, motion, peaks))
    cvs = []
    for c, form in zip(problem.constraints, tr.constraints):
        v = float(evaluate_form(form, mech, motion, peaks))
        viol = float(c.violation(v))
        cvs.append(
            ConstraintValue(
                c.name, v, c.op, c.bound, viol, viol <= problem.tol * max(1.0, abs(c.bound))
            )
        )
    return value, tuple(cvs)


def _feasible(run: _Run, tol) -> bool:
    return run.status == "optimal" and run.design is not None and run.violation <= tol


def solve(
    problem,
    method: str = "ipopt",
    starts: int = 8,
    seed: int | None = 0,
    progress: bool | None = None,
    rtol: float = 1e-9,
    max_rounds: int = 12,
    n_dense: int = 2048,
    options: dict | None = None,
    x0=None,
    polish: bool = True,
    de_options: dict | None = None,
    time_limit: float | None = None,
) -> Result:
    """Solve ``problem``; see :meth:`Problem.solve` for the arguments."""
    t_start = time.perf_counter()
    if time_limit is not None:
        from .. import validate

        time_limit = validate.positive("time_limit", validate.number("time_limit", time_limit, "s"))
    if problem.objective is None:
        raise MechanismError("the problem has no objective: call minimize(...) or maximize(...)")
    if method not in ("ipopt", "slsqp", "de"):
        raise MechanismError(f"method must be 'ipopt', 'slsqp' or 'de', got {method!r}")
    if method != "de":
        why = problem._smooth_error()
        if why is not None:
            raise why
    starts, x0 = _check_options(
        problem, method, starts, seed, rtol, max_rounds, n_dense, options, x0, de_options
    )
    cross = None
    local_method = method
    if method == "de":
        cross, z_de = _differential_evolution(problem, seed, progress, de_options or {})
        if not polish:
            return _de_result(problem, cross, z_de, rtol, n_dense, t_start)
        why = problem._smooth_error()
        if why is not None:  # a numpy-only measure: no gradient polish, no certificate
            return _de_result(problem, cross, z_de, rtol, n_dense, t_start, skipped=str(why))
        local_method, starts = "ipopt", 1
        x0 = dict(zip(problem.names, problem._numeric().params_of(z_de)))

    tr = problem._transcription()
    grid = problem.base_angles
    points, skipped, reason, tried = _start_points(problem, tr, starts, seed, x0, grid)
    if not points:
        return _failed_result(problem, method, starts, skipped, reason, t_start)
    runs: list[_Run] = []
    local = _LOCAL[local_method]
    timed_out = False
    for z0, scales, tau0 in _progress(points, len(points), progress, f"{local_method} starts"):
        if time_limit is not None and runs and time.perf_counter() - t_start > time_limit:
            timed_out = True  # no new start past the budget; the runs so far are assessed
            break
        P = tr.parameter_vector(grid, *scales)
        start = np.concatenate([z0, tau0])
        x, status, raw, it, lam = local(tr, start, P, options, None, len(grid))
        runs.append(_assess(problem, tr, _Run(x, status, raw, it, scales, lam), grid))

    tol = problem.tol
    feasible = [r for r in runs if _feasible(r, tol)]
    if feasible:
        chosen, optima, hits = _certify_all(
            problem, feasible, local_method, options, rtol, max_rounds, n_dense
        )
        best, checks, certified, true_q, cert, value, cvs = chosen
    else:
        cert = _Certifier(problem, local_method, options, rtol, max_rounds, n_dense)
        best = min(
            runs, key=lambda r: (r.violation, r.objective if np.isfinite(r.objective) else np.inf)
        )
        checks, certified, true_q = (), False, {}
        optima, hits = (), 0
        value, cvs = np.nan, ()
        if best.design is not None:
            try:
                checks, _, true_q = cert.checks(best.design)
                checks = tuple(checks)
                value, cvs = _final(problem, cert.tr, best.design, true_q, n_dense)
            except (MechanismError, _Unassembled):  # not assembled over the whole cycle
                checks, true_q, value, cvs = (), {}, np.nan, ()
    tr = cert.tr
    violated = [c for c in cvs if not c.satisfied]
    if best.design is not None and _feasible(best, tol) and not violated:
        status = "optimal" if certified else "uncertified"
    elif best.status in ("optimal", "infeasible"):
        status = "infeasible"
    else:
        status = best.status
    message = _message(status, best, violated, cert, certified)
    if cross is not None and status not in ("optimal", "uncertified"):
        # the polish failed: report differential evolution's own design, uncertified
        return _de_result(
            problem, cross, z_de, rtol, n_dense, t_start, polish_failed=f"{status}: {best.raw}"
        )
    if timed_out:
        message += (
            f"; time limit {time_limit:g} s reached: {len(runs)} of {len(points)} starts ran"
        )
    elif len(runs) < starts:
        message += (
            f"; {len(runs)} of {starts} starts ran: only {len(runs)} valid start designs among "
            f"{tried} points tried (first invalid: {reason})"
        )
    local_optima = tuple(sorted(optima))
    spread = 0.0
    if len(local_optima) > 1:
        spread = (local_optima[-1] - local_optima[0]) / max(abs(local_optima[0]), 1e-300)
    if status == "optimal" and len(local_optima) > 1 and spread > 1e-6:
        message += (
            f"; best of {len(local_optima)} distinct local optima (spread {spread:.3g}), "
            "global optimality not proven"
        )
    certification = Certification(
        method=method,
        starts_requested=starts,
        starts_run=len(runs),
        starts_skipped=skipped,
        starts_converged=len(feasible),
        local_optima=local_optima,
        spread=float(spread),
        peaks=tuple(checks),
        refinement_rounds=cert.rounds,
        grid_angles=len(cert.grid),
        refined_angles=tuple(cert.extra),
        certified=bool(certified),
        rtol=rtol,
        cross_check=cross,
        distinct_optima=len(local_optima),
        best_hits=int(hits),
        iterations=tuple(int(r.iterations) for r in runs),
        refinement_iterations=int(cert.iterations),
    )
    variables = dict(zip(problem.names, map(float, tr.params_of(np.clip(best.x[: tr.n], 0, 1)))))
    return Result(
        design=best.design,
        variables=variables,
        value=value,
        objective=problem.objective.name,
        sense=problem.sense,
        constraints=cvs,
        success=status == "optimal",
        status=status,
        message=message,
        certification=certification,
        solve_time=time.perf_counter() - t_start,
        speed=problem.speed,
    )


# ------------------------------------------------------------------------------ options
#: SLSQP options scipy knows
_SLSQP_OPTIONS = ("maxiter", "ftol", "eps", "disp", "iprint", "finite_diff_rel_step")


def _check_options(problem, method, starts, seed, rtol, max_rounds, n_dense, options, x0, de):
    """Every option of :meth:`Problem.solve` checked before any work: a clear MechanismError
    naming the option, its value and the rule. Returns ``(starts, x0)`` normalized."""
    from collections.abc import Mapping

    from .. import validate

    starts = validate.integer("starts", starts, 1, validate.MAX_STARTS)
    if seed is not None:
        validate.integer("seed", seed, 0)
    validate.positive("rtol", validate.number("rtol", rtol))
    validate.integer("max_rounds", max_rounds, 0, 1000)
    validate.integer("n_dense", n_dense, 16, validate.MAX_ANGLES)
    for name, value in (("options", options), ("de_options", de)):
        if value is None:
            continue
        if not isinstance(value, Mapping):
            raise MechanismError(f"{name} must be a dict of option names and values, got {value!r}")
        for k, v in value.items():
            if not isinstance(k, str):
                raise MechanismError(f"{name}: option names must be strings, got {k!r}")
            if name == "options" and not isinstance(v, (str, int, float)):
                raise MechanismError(f"options: {k} must be a number or a string, got {v!r}")
    if options is not None and method == "slsqp":
        unknown = sorted(set(options) - set(_SLSQP_OPTIONS))
        if unknown:
            raise MechanismError(
                f"options: unknown SLSQP option(s) {', '.join(unknown)}; valid: "
                + ", ".join(_SLSQP_OPTIONS)
            )
    if options is not None and method in ("ipopt", "de"):
        _check_ipopt_options(options)
    if x0 is not None:
        names = problem.names
        if isinstance(x0, Mapping):
            missing = [k for k in names if k not in x0]
            extra = sorted(set(x0) - set(names))
            if missing or extra:
                raise MechanismError(
                    "x0 must give every variable and nothing else: "
                    + (f"missing {', '.join(missing)}" if missing else "")
                    + ("; " if missing and extra else "")
                    + (f"not variables: {', '.join(extra)}" if extra else "")
                    + f" (variables: {', '.join(names)})"
                )
            values = [x0[k] for k in names]
        else:
            if not isinstance(x0, (list, tuple, np.ndarray)) or len(x0) != len(names):
                raise MechanismError(
                    f"x0 must be a dict {{name: value}} or {len(names)} values in the order "
                    f"{', '.join(names)}, got {x0!r}"
                )
            values = list(x0)
        for k, v in zip(names, values):
            v = validate.number(f"x0[{k!r}]", v)
            lo, hi = problem.variables[k]
            if not lo <= v <= hi:
                raise MechanismError(f"x0[{k!r}] = {v} is outside its bounds ({lo}, {hi})")
        x0 = dict(zip(names, map(float, values)))
    return starts, x0


class _quiet_stdout:
    """Silence output written by C code to the process's stdout (file descriptor 1)."""

    def __enter__(self):
        import os
        import sys

        sys.stdout.flush()
        self._saved = os.dup(1)
        self._null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(self._null, 1)

    def __exit__(self, *exc):
        import os

        os.dup2(self._saved, 1)
        os.close(self._saved)
        os.close(self._null)
        return False


def _check_ipopt_options(options):
    """IPOPT refuses unknown names and bad values only when it runs (with a status the user
    cannot read): ask it here, on a one-variable problem, and name the offenders."""
    import casadi as ca

    x = ca.SX.sym("x")
    opts = {"ipopt.print_level": 0, "print_time": False, "ipopt.sb": "yes"}
    opts.update({f"ipopt.{k}": v for k, v in options.items()})
    try:
        with _quiet_stdout():  # IPOPT prints its option documentation on a bad value
            solver = ca.nlpsol("check", "ipopt", {"x": x, "f": x * x}, opts)
            solver(x0=1.0)
    except RuntimeError as exc:
        import re

        lines = [
            re.sub(r"^\S*\.(cpp|hpp):\d+:\s*", "", ln).strip()
            for ln in str(exc).splitlines()
            if ln.strip()
        ]
        why = lines[-1] if lines else "refused"
        raise MechanismError(
            f"options: IPOPT refuses {dict(options)!r}: {why} (IPOPT options go without the "
            "'ipopt.' prefix, e.g. {'max_iter': 200})"
        ) from None
    raw = solver.stats().get("return_status", "")
    if raw in ("Invalid_Option", "Invalid_Problem_Definition"):
        raise MechanismError(
            f"options: IPOPT refuses {dict(options)!r} (unknown option name or bad value; "
            "give IPOPT options without the 'ipopt.' prefix, e.g. {'max_iter': 200})"
        )


# ------------------------------------------------------------------------------ selection
def _same_design(a, b, n, atol=1e-4):
    """Two scaled designs closer than ``atol`` in every variable (box fractions)."""
    return bool(np.max(np.abs(np.asarray(a[:n]) - np.asarray(b[:n]))) <= atol)


def _certify_all(problem, feasible, method, options, rtol, max_rounds, n_dense):
    """Certify every distinct local optimum independently and pick the best true value.

    Each distinct converged start (in start order; a start landing on the design of an earlier
    one is a repeat) is refined on its *own* grid from the base angles and compared by the true
    continuous objective at its certified design. So the outcome of a start does not depend on
    the other starts, and adding starts can only add candidates: more starts never report a
    worse optimum. Comparing grid objectives instead would mix values on different grids (a
    base-grid value is a relaxation, below the true one).

    Returns
    -------
    chosen : (run, checks, certified, true_q, certifier, value, constraint values).
    optima : true objective values of the distinct certified designs (natural sense).
    hits : converged starts that ended at the chosen design.
    """
    tol = problem.tol
    n = len(problem.names)
    reps: list[_Run] = []
    owner: list[int] = []
    for r in feasible:
        for j, q in enumerate(reps):
            if _same_design(r.x, q.x, n):
                owner.append(j)
                break
        else:
            owner.append(len(reps))
            reps.append(r)
    sign = 1.0 if problem.sense == "min" else -1.0
    outcomes = []
    for rep in reps:
        cert = _Certifier(problem, method, options, rtol, max_rounds, n_dense)
        run, checks, certified, true_q = cert.run(rep)
        if run.design is None:
            outcomes.append(None)
            continue
        try:
            value, cvs = _final(problem, cert.tr, run.design, true_q, n_dense)
        except MechanismError:  # refinement rounds ran out before it assembled everywhere
            outcomes.append(None)
            continue
        ok = _feasible(run, tol) and all(c.satisfied for c in cvs)
        rank = 0 if (ok and certified) else (1 if ok else 2)
        key = (rank, sign * value if np.isfinite(value) else np.inf)
        outcomes.append((key, (run, tuple(checks), certified, true_q, cert, value, cvs)))
    valid = [(i, o) for i, o in enumerate(outcomes) if o is not None]
    if not valid:  # every certification lost the design: report the best start as found
        cert = _Certifier(problem, method, options, rtol, max_rounds, n_dense)
        rep = reps[0]
        try:
            checks, _, true_q = cert.checks(rep.design)
            value, cvs = _final(problem, cert.tr, rep.design, true_q, n_dense)
        except (MechanismError, _Unassembled):  # it cannot be assembled over the whole cycle
            rep = replace(rep, design=None, violation=np.inf)
            checks, true_q, value, cvs = (), {}, np.nan, ()
        return (rep, tuple(checks), False, true_q, cert, value, cvs), (), 0
    i_best, (_, chosen) = min(valid, key=lambda io: io[1][0])
    # distinct certified designs among the good outcomes, their true values
    rank0 = outcomes[i_best][0][0]
    designs, optima, where = [], [], {}
    for i, (key, out) in valid:
        if key[0] != rank0:
            continue
        x = out[0].x
        for j, d in enumerate(designs):
            if _same_design(x, d, n):
                where[i] = j
                break
        else:
            where[i] = len(designs)
            designs.append(x)
            optima.append(float(out[5]))
    best_cluster = where[i_best]
    hits = sum(1 for o in owner if where.get(o) == best_cluster)
    return chosen, tuple(optima), hits


def _message(status, run, violated, cert, certified):
    if status == "optimal":
        return f"converged and certified ({run.raw})"
    if status == "uncertified":
        return f"converged, but peaks not certified after {cert.rounds} refinement rounds"
    names = "; ".join(
        f"{c.name} (value {c.value:.6g}, violation {c.violation:.3g})" for c in violated
    )
    if status == "infeasible":
        return "infeasible: violated " + (names or "the mechanism's feasibility constraints")
    tail = f"; violated {names}" if names else ""
    return f"{status}: solver says {run.raw}{tail}"


def _failed_result(problem, method, starts, skipped, reason, t_start):
    cert = Certification(
        method, starts, 0, skipped, 0, (), 0.0, (), 0, len(problem.base_angles), (), False, 0.0
    )
    return Result(
        design=None,
        variables={},
        value=np.nan,
        objective=problem.objective.name,
        sense=problem.sense,
        constraints=(),
        success=False,
        status="solver_failed",
        message=(
            f"no valid start design found in the bounds: {skipped} points tried, none can be built "
            f"and evaluated (first: {reason})"
        ),
        certification=cert,
        solve_time=time.perf_counter() - t_start,
        speed=problem.speed,
    )


# ------------------------------------------------------------------------------ global
class _BatchEvaluator:
    """Objective and constraint rows of a whole population in one numpy call."""

    def __init__(self, problem, n_angles, eq_rtol):
        from ..kinematics.mechanism import input_grid

        self.problem = problem
        self.tr = problem._numeric()
        self.phi = input_grid(problem.mechanism, n_angles)
        self.eq_rtol = eq_rtol
        hook = getattr(problem.mechanism, "feasibility_constraints", None)
        n_hook = 0
        if hook is not None:
            mid = design_params(problem, self.tr.params_of(np.full(self.tr.n, 0.5)))
            n_hook = len(hook(mid, margin=problem.feasibility_margin))
        self.n_hook = n_hook
        lb, ub = [], []
        for c in problem.constraints:
            tol = eq_rtol * max(1.0, abs(c.bound)) if c.op == "==" else 0.0
            lb.append(c.bound - tol if c.op in (">=", "==") else -np.inf)
            ub.append(c.bound + tol if c.op in ("<=", "==") else np.inf)
        self.lb = np.array(lb + [0.0] * n_hook)
        self.ub = np.array(ub + [np.inf] * n_hook)
        self._key = None

    def __call__(self, Z):
        """Z: (S, n) scaled points -> (objective (S,), rows (M, S))."""
        key = Z.tobytes()
        if key == self._key:
            return self._val
        S = Z.shape[0]
        values = self.tr.params_of(np.clip(Z, 0.0, 1.0))
        params = design_params(self.problem, [values[:, i] for i in range(self.tr.n)])
        hook_rows = _hook_values(self.problem, params)
        hook_rows = [np.broadcast_to(g, (S,)) for g in hook_rows]
        valid = np.all(np.stack(hook_rows) >= 0.0, axis=0) if hook_rows else np.ones(S, bool)
        f = np.full(S, np.inf)
        rows = np.full((len(self.problem.constraints), S), np.nan)
        idx = np.flatnonzero(valid)
        if idx.size:
            sub = design_params(self.problem, [values[idx, i][:, None] for i in range(self.tr.n)])
            try:
                fi, ri = self._eval(sub, idx.size)
            except (MechanismError, ValueError):
                fi, ri = self._eval_each(values[idx])
            f[idx], rows[:, idx] = fi, ri
        bad = ~np.isfinite(f)
        f[bad] = np.inf
        # invalid designs: constraint rows far outside; the hook rows rank them
        rows[:, bad] = np.where(np.isfinite(self.ub[: rows.shape[0]]), 1e30, -1e30)[:, None]
        allrows = np.vstack([rows] + ([np.stack(hook_rows)] if hook_rows else []))
        sign = 1.0 if self.problem.sense == "min" else -1.0
        self._key, self._val = key, (sign * f, allrows)
        return self._val

    def _eval(self, params, S):
        mech = self.problem.mechanism(**params)
        motion = mech.motion(self.phi, speed=self.problem.speed)
        f = _flat(evaluate_form(self.tr.objective, mech, motion), S)
        rows = [_flat(evaluate_form(form, mech, motion), S) for form in self.tr.constraints]
        return f, np.array(rows).reshape(len(rows), S)

    def _eval_each(self, values):
        f = np.full(len(values), np.inf)
        rows = np.full((len(self.problem.constraints), len(values)), np.nan)
        for j, v in enumerate(values):
            try:
                fj, rj = self._eval(design_params(self.problem, list(v)), 1)
            except (MechanismError, ValueError):
                continue
            f[j], rows[:, j] = fj[0], rj[:, 0]
        return f, rows


def _differential_evolution(problem, seed, progress, opts):
    from scipy.optimize import NonlinearConstraint, differential_evolution

    opts = dict(opts)
    ev = _BatchEvaluator(problem, int(opts.pop("angles", 256)), float(opts.pop("eq_rtol", 1e-4)))
    n = ev.tr.n

    def fun(Zt):
        return ev(np.atleast_2d(Zt.T))[0]

    def con(Zt):
        return ev(np.atleast_2d(Zt.T))[1]

    kwargs = dict(
        maxiter=300, popsize=20, tol=1e-10, atol=0.0, mutation=(0.5, 1.0), recombination=0.9
    )
    kwargs.update(opts)
    constraints = NonlinearConstraint(con, ev.lb, ev.ub) if len(ev.lb) else ()
    t0 = time.perf_counter()
    res = differential_evolution(
        fun,
        [(0.0, 1.0)] * n,
        constraints=constraints,
        vectorized=True,
        updating="deferred",
        seed=seed,
        polish=False,
        **kwargs,
    )
    z = np.asarray(res.x, dtype=float)
    f, rows = ev(z[None, :])
    viol = 0.0
    if len(ev.lb):
        r = rows[:, 0]
        viol = float(np.max(np.maximum(ev.lb - r, 0.0) + np.maximum(r - ev.ub, 0.0)))
    sign = 1.0 if problem.sense == "min" else -1.0
    cross = dict(
        method="de",
        value=float(sign * f[0]),
        design=dict(zip(problem.names, map(float, ev.tr.params_of(z)))),
        constraint_violation=viol,
        nfev=int(res.nfev),
        nit=int(res.nit),
        time=time.perf_counter() - t0,
        grid_angles=len(ev.phi),
        message=str(res.message),
    )
    return cross, z


def _de_result(problem, cross, z, rtol, n_dense, t_start, skipped=None, polish_failed=None):
    """Result of differential evolution alone (no local polish): true peaks at its design.
    ``skipped`` is the reason the polish could not run (a measure without a CasADi form),
    ``polish_failed`` how the polish ended when it ran and failed."""
    cert = _Certifier(problem, "ipopt", None, rtol, 0, n_dense, tr=problem._numeric())
    tr = cert.tr
    run = _assess(
        problem, tr, _Run(np.asarray(z), "optimal", "differential evolution", 0, ()), cert.grid
    )
    checks, true_q = (), {}
    if run.design is not None:
        checks, _, true_q = cert.checks(run.design)
        value, cvs = _final(problem, tr, run.design, true_q, n_dense)
    else:
        value, cvs = np.nan, ()
    violated = [c for c in cvs if not c.satisfied]
    # without the local polish there is no optimality certificate: never "optimal"
    status = "uncertified" if run.design is not None and not violated else "infeasible"
    certification = Certification(
        "de",
        1,
        1,
        0,
        int(status == "uncertified"),
        (float(cross["value"]),),
        0.0,
        tuple(checks),
        0,
        len(cert.grid),
        (),
        False,
        rtol,
        cross,
        distinct_optima=1,
        best_hits=1,
    )
    msg = "differential evolution without local polish: no optimality certificate"
    if skipped:
        msg = (
            "differential evolution only, local polish skipped (the problem has no smooth "
            f"CasADi form: {skipped.split(' (')[0]}): no optimality certificate"
        )
    if polish_failed:
        msg = (
            f"differential evolution's design; its IPOPT polish failed ({polish_failed}): no "
            "optimality certificate"
        )
    if violated:
        msg += "; violated " + "; ".join(f"{c.name} (value {c.value:.6g})" for c in violated)
    return Result(
        design=run.design,
        variables=dict(zip(problem.names, map(float, tr.params_of(z)))),
        value=value,
        objective=problem.objective.name,
        sense=problem.sense,
        constraints=cvs,
        success=False,
        status=status,
        message=msg,
        certification=certification,
        solve_time=time.perf_counter() - t_start,
        speed=problem.speed,
    )
