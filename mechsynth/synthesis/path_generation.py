"""Path generation: a four-bar whose coupler point passes as near as possible to given points.

>>> import mechsynth as ms
>>> pg = ms.path_generation([(0, 0), (1, 0.2), (2, 0), (1, -0.6)], starts=4)  # doctest: +SKIP
>>> pg.error, pg.fourbar, pg.angles, pg.positions["P"]                       # doctest: +SKIP

Formulation (the literature's, e.g. Cabrera, Simon and Prado, *Optimal synthesis of mechanisms
with genetic algorithms*, Mech. Mach. Theory 37 (2002) 1165-1177):

* variables: the four-bar's ``crank`` (r2), ``coupler`` (r3), ``rocker`` (r4), ``ground``
  (r1), the coupler point ``u`` (along the coupler A -> B from A) and ``v`` (to its left)
  (rcx, rcy), the crank pivot ``x0, y0``, the ground line's direction ``angle`` (theta0, from
  +x to O1 -> O2) and the crank angle at each target ``phi_i`` (theta2, from the ground line,
  counter-clockwise);
* error: the sum over the targets of the squared distance between target and coupler point
  (``objective="squares"``), or the largest squared distance (``objective="max"``, min-max by
  an epigraph variable: exact, the targets are finitely many);
* timing: ``"free"`` -- the angles are variables, visited in the given order within one turn
  (``phi_{i+1} >= phi_i``, ``phi_N <= phi_1 + 2 pi``); ``"prescribed"`` -- the crank turns by
  the given angles from the first target (``phi_i = phi_1 + angles_i - angles_1``, ``phi_1``
  free);
* constraints: the crank turns fully (Grashof crank: ``crank + ground < coupler + rocker`` and
  ``|ground - crank| > |coupler - rocker|``, with the four-bar's own relative margin), so the
  dyad never reaches a toggle and the linkage stays on one assembly branch over the whole turn
  (no branch or circuit defect); optionally a smallest transmission angle over the turn (exact:
  its extremes are at crank angles 0 and pi); bounds on every variable.

The model is the library's four-bar (:func:`~mechsynth.kinematics.four_bar.four_bar_chain` and
:func:`~mechsynth.kinematics.blocks.coupler_point`), traced on CasADi symbols for IPOPT's exact
derivatives and evaluated in numpy for the checks. The global search starts IPOPT from the
atlas's nearest curves by shape (:mod:`mechsynth.synthesis.path_atlas`), both branches.

Beside the four-bar: any Linkage or the slider-crank (:mod:`.path_linkage`), the library's
measures as constraints (:mod:`.path_measures`), shape-only timing (:mod:`.path_shape`); the
results are :mod:`.path_result`'s, the cognates :mod:`.path_cognates`'s, the literature cases
:mod:`.path_cases`'s, the error-transmission front :mod:`.path_front`'s, the proved lower
bound with prescribed timing (``bound=``) :mod:`.path_bound`'s. See ``docs/path_generation.md``.
"""

from __future__ import annotations

import functools
import itertools
import time

import numpy as np

from .. import validate
from ..errors import MechanismError
from .path_result import ERROR_DEFINITION, NAMES, PathResult, PathSolution, placed_linkage
from .path_targets import read_targets

__all__ = ["path_generation", "PathResult", "PathSolution", "read_targets", "NAMES"]

_LENGTHS = ("crank", "coupler", "rocker", "ground")
TIMINGS = ("free", "prescribed", "shape")
OBJECTIVES = ("squares", "max")


# ------------------------------------------------------------------------------ NLP
_IPOPT = {
    "ipopt.print_level": 0,
    "print_time": False,
    "ipopt.sb": "yes",
    "ipopt.tol": 1e-12,
    "ipopt.acceptable_tol": 1e-8,
    "ipopt.constr_viol_tol": 1e-10,
    "ipopt.max_iter": 400,
    "ipopt.max_cpu_time": 60.0,  # a start that wanders ends rather than hangs
    "ipopt.mu_strategy": "adaptive",
    "error_on_fail": False,
    "show_eval_warnings": False,
}


@functools.lru_cache(maxsize=32)
def _nlp(n: int, timing: str, objective: str, sigma: int, constraints=(), speed=None,
         centre=(0.0, 0.0), scale=1.0):  # fmt: skip
    """The CasADi NLP (cached per shape): variables ``NAMES`` + crank angles (+ epigraph),
    parameters: targets (2n, x y interleaved), cos of the smallest transmission angle, margin
    of the full turn, the prescribed angles (n). Returns ``(solver, rows, nz, fun)``: the
    IPOPT solver, the constraint rows' names, the variable count and ``fun(z, p) -> (f,
    grad f, g, residuals, their Jacobian)`` (residuals: the x then y differences)."""
    import casadi as ca

    from ..kinematics import ops
    from ..kinematics.blocks import coupler_point
    from ..kinematics.four_bar import FourBar, four_bar_chain
    from .path_measures import EXTRA, GRID

    nphi = n if timing == "free" else 1
    nz = len(NAMES) + nphi + (1 if objective == "max" else 0)
    z = ca.SX.sym("z", nz)
    p = ca.SX.sym("p", 3 * n + 2 + (GRID + EXTRA if constraints else 0))
    crank, coupler, rocker, ground, u, v, x0, y0, ang = (z[i] for i in range(len(NAMES)))
    k = len(NAMES)
    phi = z[k : k + n] if timing == "free" else z[k] + p[2 * n + 2 : 3 * n + 2]
    a, _, cpl, _ = four_bar_chain(ops.cos(phi), ops.sin(phi), crank, coupler, rocker, ground, sigma)
    q = coupler_point(a, cpl, u, v)
    ca_, sa = ops.cos(ang), ops.sin(ang)
    x = x0 + ca_ * q.x - sa * q.y
    y = y0 + sa * q.x + ca_ * q.y
    d2 = (x - p[0 : 2 * n : 2]) ** 2 + (y - p[1 : 2 * n : 2]) ** 2
    rows, g = [], []
    params = {"crank": crank, "coupler": coupler, "rocker": rocker, "ground": ground}
    for name, expr in FourBar.feasibility_constraints(params, margin=0.0):
        rows.append(name)
        g.append(expr - p[2 * n + 1])
    from .path_atlas import _transmission_extremes

    c0, c1 = _transmission_extremes(crank, coupler, rocker, ground)
    rows += ["transmission angle at crank angle 0", "transmission angle at crank angle 180 deg"]
    g += [p[2 * n] - c0, c1 + p[2 * n]]
    if timing == "free":
        rows += [f"order: angle {i + 2} >= angle {i + 1}" for i in range(n - 1)]
        g += [phi[i + 1] - phi[i] for i in range(n - 1)]
        rows.append("order: within one turn")
        g.append(2.0 * np.pi - (phi[n - 1] - phi[0]))
    if constraints:  # the library's measures, on the placed linkage in SI units
        from .path_measures import constraint_rows

        vals = {k: z[i] * scale for i, k in enumerate(NAMES)}
        vals["x0"], vals["y0"] = centre[0] + vals["x0"], centre[1] + vals["y0"]
        vals["angle"] = z[NAMES.index("angle")]
        design = placed_linkage(vals, "open" if sigma > 0 else "crossed")
        extra = constraint_rows(constraints, design, speed, p[3 * n + 2 :])
        count = sum(int(e.numel()) if hasattr(e, "numel") else 1 for e in extra)
        rows += [f"measure row {i + 1}" for i in range(count)]
        g += extra
    if objective == "max":
        t = z[nz - 1]
        rows += [f"epigraph {i + 1}" for i in range(n)]
        g += [t - d2[i] for i in range(n)]
        f = t
    else:
        f = ca.sum1(d2)
    gg = ca.vertcat(*g)
    solver = ca.nlpsol("path", "ipopt", {"x": z, "p": p, "f": f, "g": gg}, _IPOPT)
    res = ca.vertcat(x - p[0 : 2 * n : 2], y - p[1 : 2 * n : 2])
    fun = ca.Function("path_f", [z, p], [f, ca.gradient(f, z), gg, res, ca.jacobian(res, z)])
    return solver, tuple(rows), nz, fun


# ------------------------------------------------------------------------------ main
def _default_bounds(t: np.ndarray) -> dict[str, tuple[float, float]]:
    lo, hi = t.min(axis=0), t.max(axis=0)
    d = float(np.hypot(*(hi - lo)))
    return {
        "crank": (d / 200, 5 * d),
        "coupler": (d / 200, 10 * d),
        "rocker": (d / 200, 10 * d),
        "ground": (d / 200, 10 * d),
        "u": (-10 * d, 10 * d),
        "v": (-10 * d, 10 * d),
        "x0": (lo[0] - 5 * d, hi[0] + 5 * d),
        "y0": (lo[1] - 5 * d, hi[1] + 5 * d),
        "angle": (-4 * np.pi, 4 * np.pi),
    }


def _check_bounds(bounds, t):
    out = _default_bounds(t)
    if bounds is None:
        return out
    if not isinstance(bounds, dict):
        raise MechanismError(f"bounds must be a dict {{name: (lower, upper)}}, got {bounds!r}")
    for name, b in bounds.items():
        if name not in out:
            raise MechanismError(f"bounds: no variable {name!r}; the variables: {', '.join(NAMES)}")
        if not isinstance(b, (tuple, list, np.ndarray)) or len(b) != 2:
            raise MechanismError(f"bounds[{name!r}] must be (lower, upper), got {b!r}")
        lo = validate.number(f"bounds[{name!r}] lower", b[0])
        hi = validate.number(f"bounds[{name!r}] upper", b[1])
        if not lo < hi:
            raise MechanismError(f"bounds[{name!r}]: need lower < upper, got ({lo}, {hi})")
        if name in _LENGTHS and lo <= 0:
            raise MechanismError(f"bounds[{name!r}]: a length's lower bound must be > 0, got {lo}")
        out[name] = (lo, hi)
    return out


def evaluate(design, angles, targets, branch="open"):
    """Squared distances ``(N,)`` between the targets and the coupler point of ``design``
    (``{name: value}`` of :data:`NAMES`) at crank angles ``angles`` (rad), by the numpy
    four-bar model (validated: the crank must turn fully)."""
    sol = PathSolution(
        **{k: float(design[k]) for k in NAMES},
        branch=branch,
        angles=np.asarray(angles, dtype=float),
        error=np.nan,
        sum_squares=np.nan,
        max_distance=np.nan,
        transmission=(np.nan, np.nan),
    )
    p = sol.trace(sol.angles)
    return np.sum((p - np.asarray(targets, dtype=float)) ** 2, axis=1)


def _transmission_range(fb, n=3600):
    from ..units import cycle

    mu = fb.motion(cycle(n)).transmission_angle
    acute = np.minimum(mu, np.pi - mu)
    return float(acute.min()), float(mu.max())


def _solution(z, sigma, n, timing, given, centre, scale, targets, objective, note=""):
    """A PathSolution from a solver vector ``z`` (normalized units), re-evaluated in numpy;
    None when the design is not one (the crank cannot turn fully)."""
    k = len(NAMES)
    vals = dict(zip(NAMES, z[:k]))
    for name in (*_LENGTHS, "u", "v"):
        vals[name] = float(vals[name] * scale)
    vals["x0"] = float(centre[0] + scale * vals["x0"])
    vals["y0"] = float(centre[1] + scale * vals["y0"])
    vals["angle"] = float(vals["angle"])
    phi = np.asarray(z[k : k + n] if timing == "free" else z[k] + given, dtype=float)
    phi = phi - 2.0 * np.pi * np.floor(phi[0] / (2.0 * np.pi))  # the first in [0, 2 pi)
    return evaluated(vals, "open" if sigma > 0 else "crossed", phi, targets, objective, note)


def evaluated(vals, branch, phi, targets, objective="squares", note=""):
    """The :class:`PathSolution` of the design ``vals`` (``{name: value}`` of :data:`NAMES`,
    SI) with crank angles ``phi`` at the ``targets``, evaluated by the numpy model: the
    errors, and the transmission range over 3600 crank angles. None when the crank cannot
    turn fully (the four-bar's check)."""
    vals = {k: float(vals[k]) for k in NAMES}
    phi = np.asarray(phi, dtype=float)
    try:
        d2 = evaluate(vals, phi, targets, branch)
        fb = PathSolution(**vals, branch=branch, angles=phi, error=0.0, sum_squares=0.0,
                          max_distance=0.0, transmission=(0.0, 0.0)).fourbar  # fmt: skip
        tr = _transmission_range(fb)
    except MechanismError:
        return None
    ss = float(d2.sum())
    return PathSolution(
        **vals,
        branch=branch,
        angles=phi,
        error=ss if objective == "squares" else float(d2.max()),
        sum_squares=ss,
        max_distance=float(np.sqrt(d2.max())),
        transmission=tr,
        note=note,
    )


def _feasible(sol: PathSolution, timing, min_mu, bounds, tol=1e-6) -> str:
    """Why ``sol`` breaks the problem's constraints ('' when it does not)."""
    if sol.transmission[0] < min_mu - 1e-6:
        return (
            f"transmission angle {np.rad2deg(sol.transmission[0]):.4f} deg below "
            f"{np.rad2deg(min_mu):.4f} deg"
        )
    if timing == "free":
        step = np.diff(sol.angles)
        if step.min(initial=0.0) < -tol or sol.angles[-1] - sol.angles[0] > 2 * np.pi + tol:
            return "crank angles out of order"
    for name, (lo, hi) in bounds.items():
        x = getattr(sol, name)
        if not lo - tol * max(1.0, abs(lo)) <= x <= hi + tol * max(1.0, abs(hi)):
            return f"{name} = {x:.6g} outside its bounds ({lo:.6g}, {hi:.6g})"
    return ""


def _same(a: PathSolution, b: PathSolution, rtol=1e-4) -> bool:
    if abs(a.error - b.error) > rtol * max(abs(a.error), abs(b.error)) + 1e-14:
        return False
    x = np.array([getattr(a, k) for k in (*_LENGTHS, "u", "v", "x0", "y0")])
    y = np.array([getattr(b, k) for k in (*_LENGTHS, "u", "v", "x0", "y0")])
    size = max(np.abs(x).max(), 1e-300)
    return a.branch == b.branch and bool(np.abs(x - y).max() <= 1e-3 * size)


def path_generation(
    targets,
    *,
    timing: str = "free",
    angles=None,
    closed: bool = True,
    min_transmission: float | None = None,
    objective: str = "squares",
    bounds: dict | None = None,
    starts: int = 12,
    time_limit: float | None = None,
    feasibility_margin: float = 1e-3,
    progress: bool | None = None,
    mechanism="four-bar",
    trace: str | None = None,
    variables: dict | None = None,
    seed: int = 0,
    constraints=None,
    speed: float | None = None,
    direction: str = "ccw",
    bound=False,
) -> PathResult:
    """A four-bar whose coupler point passes as near as possible to ``targets``.

    Parameters
    ----------
    targets : ``(N, 2)`` points (m) in the order the coupler point should visit them, or a CSV
        file of ``x, y`` rows (see :func:`read_targets`).
    timing : ``"free"`` (crank angles are variables, in order within one turn),
        ``"prescribed"`` (``angles`` gives the crank angle at each target, rad; only the
        differences from the first count: the start is free), or ``"shape"`` (a closed path's
        shape only: the curves compared by their normalized elliptic Fourier descriptors,
        position, orientation, size and timing free; a four-bar, see
        :mod:`~mechsynth.synthesis.path_shape`).
    angles : the prescribed crank angles (rad), with ``timing="prescribed"``.
    closed : the targets lie on a closed path (the default; it matters for the shape seeds).
    min_transmission : smallest transmission angle over the whole turn (rad), e.g.
        ``ms.deg(30)``; None for none.
    objective : ``"squares"`` (the sum of squared distances, the literature's error) or
        ``"max"`` (the largest squared distance, min-max).
    bounds : ``{name: (lower, upper)}`` (m, rad) for the variables of :data:`NAMES`; defaults
        scale with the targets' extent ``D`` (lengths D/200 to 10 D, the crank to 5 D; pivot
        within 5 D of the targets).
    starts : number of local solves (IPOPT, exact derivatives), started from the atlas's
        nearest curves by shape.
    time_limit : stop starting new solves after this many seconds (the best so far is kept).
    feasibility_margin : relative margin of the full-turn conditions (as ``FourBar``'s).
    progress : a progress bar (None: on a terminal only).
    constraints : the library's measures bounded, e.g. ``[ms.objectives.max_pressure_angle()
        <= ms.deg(40), ms.objectives.peak_acceleration("P") <= 50.0]`` (the tracing point is
        ``"P"`` on a four-bar; see :mod:`~mechsynth.synthesis.path_measures`), at ``speed``
        (rad/s; None: crank-angle analogs).
    mechanism : ``"four-bar"`` (the default: its coupler point, placed anywhere in the plane),
        ``"slider-crank"`` (a point on the rod of a slider-crank whose guide is anywhere:
        :func:`~mechsynth.synthesis.path_linkage.slider_crank_template`), or any
        :class:`~mechsynth.Linkage` driven by a crank, with ``trace`` (its tracing point;
        default its output) and ``variables`` (``{parameter: (lower, upper)}``, the dimensions
        to vary; for the slider-crank, bounds that replace the defaults). A general linkage
        starts from its own values and random designs that assemble; ``seed`` fixes those.

    direction : the crank's turn with free (or shape) timing: ``"ccw"`` (counter-clockwise,
        the crank angles increase from target to target: the literature's), ``"cw"`` (they
        decrease), or ``"either"`` (both searched, ``starts`` each).
    bound : with prescribed timing on a four-bar (sum of squares), a proved lower bound on
        the error of every four-bar in a region (:func:`~mechsynth.synthesis.path_bound.
        path_bound`), reported as ``result.bound`` with the gap to the best design: ``True``
        searches the problem's bounds; a dict sets ``around`` (m: the box within that
        distance of the best design in every coordinate instead), ``max_boxes``,
        ``time_limit`` (s, default 20), ``rtol``, ``branch``.

    Returns
    -------
    PathResult : the best design, its error, crank angles, joint positions and transmission
        range, the distinct solutions, the number of starts. Ctrl-C stops the search and keeps
        the best design found so far (status ``"interrupted"``).
    """
    validate.option("direction", direction, ("ccw", "cw", "either"))
    kw = dict(timing=timing, angles=angles, closed=closed, min_transmission=min_transmission,
              objective=objective, bounds=bounds, starts=starts, time_limit=time_limit,
              feasibility_margin=feasibility_margin, progress=progress, mechanism=mechanism,
              trace=trace, variables=variables, seed=seed, constraints=constraints,
              speed=speed)  # fmt: skip
    if bound is not False:
        opts = _bound_options(bound, timing, objective, mechanism)
    if direction == "ccw":
        res = _path_generation(targets, **kw)
        return res if bound is False else _with_bound(res, angles, bounds, opts)
    if timing == "prescribed":
        raise MechanismError(
            "direction is for free or shape timing: prescribed angles give the crank's turn"
        )
    t = read_targets(targets, closed=bool(closed)) if isinstance(closed, bool) else targets
    results = [] if direction == "cw" else [_path_generation(t, **kw)]
    results.append(_reversed(_path_generation(t[::-1], **kw), t))
    if len(results) == 1:
        return results[0]
    return _merged(results, t)


def _bound_options(bound, timing, objective, mechanism) -> dict:
    """The checked options of ``bound=`` (True or a dict)."""
    if timing != "prescribed" or objective != "squares" or not (
        isinstance(mechanism, str) and mechanism == "four-bar"
    ):
        raise MechanismError(
            "bound is for a four-bar with timing='prescribed' and objective='squares', got "
            f"mechanism {mechanism!r}, timing {timing!r}, objective {objective!r}"
        )
    if bound is True:
        return {}
    if not isinstance(bound, dict):
        raise MechanismError(f"bound must be True, False or a dict of options, got {bound!r}")
    known = ("around", "max_boxes", "time_limit", "rtol", "branch")
    for k in bound:
        if k not in known:
            raise MechanismError(f"bound: no option {k!r}; the options: {', '.join(known)}")
    opts = dict(bound)
    if "around" in opts:
        opts["around"] = validate.number("bound['around']", opts["around"], "m")
        if not opts["around"] > 0:
            raise MechanismError(f"bound['around'] must be positive (m), got {opts['around']}")
    return opts


def _with_bound(res: PathResult, angles, bounds, opts) -> PathResult:
    """``res`` with the lower bound of :mod:`~mechsynth.synthesis.path_bound`."""
    from dataclasses import replace

    from .path_bound import path_bound, region_around

    opts = dict(opts)
    opts.setdefault("time_limit", 20.0)
    around = opts.pop("around", None)
    if res.best is None:
        return res
    if around is not None:
        b = res.best
        phi1 = float(b.angles[0])
        region = region_around({k: getattr(b, k) for k in NAMES}, phi1, around)
        pb = path_bound(res.targets, angles, region=region, best=res.error, **opts)
    else:
        pb = path_bound(res.targets, angles, bounds=bounds, best=res.error, **opts)
    return replace(res, bound=pb)


def _reversed(res: PathResult, t) -> PathResult:
    """A result on the reversed targets as one on ``t`` with the crank turning clockwise: each
    solution's angles back in the targets' order (decreasing)."""
    from dataclasses import replace

    sols = tuple(replace(s, angles=s.angles[::-1].copy()) for s in res.solutions)
    return replace(res, targets=t, solutions=sols, best=sols[0] if sols else None)


def _merged(results, t) -> PathResult:
    """Both turns' results as one, solutions ranked by error."""
    from dataclasses import replace

    sols = sorted((s for r in results for s in r.solutions), key=lambda s: s.error)
    rank = {id(s): k for k, s in enumerate(sols, start=1)}
    for r in results:  # a cognate's note names its original's rank in the merged list
        for s in r.solutions:
            if s.note == "cognate of #1" and r.best is not None:
                k = rank[id(s)]
                sols[k - 1] = replace(s, note=f"cognate of #{rank[id(r.best)]}")
    ok = [r for r in results if r.best is not None]
    status = "interrupted" if any(r.status == "interrupted" for r in results) else (
        "optimal" if sols else "infeasible"
    )  # fmt: skip
    return replace(
        results[0],
        targets=t,
        best=sols[0] if sols else None,
        solutions=tuple(sols),
        starts=sum(r.starts for r in results),
        distinct=sum(r.distinct for r in results),
        status=status,
        seconds=sum(r.seconds for r in results),
        message="" if ok else results[0].message,
    )


def _path_generation(
    targets,
    *,
    timing,
    angles,
    closed,
    min_transmission,
    objective,
    bounds,
    starts,
    time_limit,
    feasibility_margin,
    progress,
    mechanism,
    trace,
    variables,
    seed,
    constraints,
    speed,
) -> PathResult:
    """:func:`path_generation` for a counter-clockwise crank."""
    t_start = time.perf_counter()
    from .path_measures import check_types

    measures = check_types(constraints)
    if speed is not None:
        speed = validate.number("speed", speed, "rad/s")
    general = not isinstance(mechanism, str)
    if not general:
        validate.option("mechanism", mechanism, ("four-bar", "slider-crank"))
    validate.option("timing", timing, TIMINGS)
    validate.option("objective", objective, OBJECTIVES)
    if not isinstance(closed, (bool, np.bool_)):
        raise MechanismError(f"closed must be True or False, got {closed!r}")
    t = read_targets(targets, closed=bool(closed))
    n = len(t)
    if timing == "prescribed":
        if angles is None:
            raise MechanismError("timing='prescribed' needs angles: the crank angle per target")
        given = validate.real("angles", angles, "rad")
        given = np.asarray(given, dtype=float).ravel()
        if given.size != n:
            raise MechanismError(f"angles: need one per target ({n}), got {given.size}")
        given = given - given[0]
    else:
        if angles is not None:
            raise MechanismError("angles are given only with timing='prescribed'")
        given = np.zeros(n)
        if n < 3:
            raise MechanismError(f"free timing needs at least 3 targets, got {n}")
    min_mu = 0.0
    if min_transmission is not None:
        min_mu = validate.angle("min_transmission", min_transmission)
        if not 0.0 <= min_mu < np.pi / 2:
            raise MechanismError(
                f"min_transmission must be in [0, 90) deg, got {np.rad2deg(min_mu):.6g} deg "
                f"({min_mu:g} rad)"
            )
    starts = validate.integer("starts", starts, lo=1, hi=10000)
    margin = validate.number("feasibility_margin", feasibility_margin)
    if not 0.0 <= margin < 0.1:
        raise MechanismError(
            f"feasibility_margin is relative to the links' sum: need [0, 0.1), got {margin:.6g}"
        )
    if time_limit is not None:
        time_limit = validate.number("time_limit", time_limit, "s")
        if not time_limit > 0:
            raise MechanismError(f"time_limit must be positive (s), got {time_limit:.6g}")
    if general or mechanism == "slider-crank":
        return _general(
            t,
            mechanism,
            trace,
            variables,
            bounds,
            timing,
            given,
            min_mu,
            objective,
            starts,
            time_limit,
            margin,
            progress,
            seed,
            closed,
            t_start,
            measures,
            speed,
        )
    if trace is not None or variables is not None:
        raise MechanismError(
            "trace and variables are for a Linkage or the slider-crank; the four-bar's "
            f"variables are {', '.join(NAMES)} (bounds=...)"
        )
    if timing == "shape":
        return _shape(t, closed, objective, measures, bounds, starts, min_mu, margin,
                      time_limit, t_start)  # fmt: skip
    bnds = _check_bounds(bounds, t)

    centre = t.mean(axis=0)
    scale = float(np.sqrt(np.mean(np.sum((t - centre) ** 2, axis=1))))
    tn = (t - centre) / scale
    nb = {}
    for name, (lo, hi) in bnds.items():
        if name in (*_LENGTHS, "u", "v"):
            nb[name] = (lo / scale, hi / scale)
        elif name in ("x0", "y0"):
            c = centre[0 if name == "x0" else 1]
            nb[name] = ((lo - c) / scale, (hi - c) / scale)
        else:
            nb[name] = (lo, hi)

    from .path_atlas import seed, seed_timed
    from .path_measures import check_constraints, solve_with_peaks

    mu_seed = max(0.0, min_mu - np.deg2rad(10.0))
    if timing == "prescribed":
        # shape matches and starts that keep the timing (the atlas curves at the prescribed
        # angle steps) in turn: each kind finds exact solutions the other misses
        shaped = seed(tn, count=starts, min_mu=mu_seed)
        timed = seed_timed(tn, given, count=starts, min_mu=mu_seed) if starts > 1 else []
        seeds = [s for pair in itertools.zip_longest(shaped, timed) for s in pair if s]
        seeds = seeds[:starts]
    else:
        seeds = seed(tn, count=starts, min_mu=mu_seed)
    nphi = n if timing == "free" else 1
    P = np.concatenate([tn.ravel(), [np.cos(min_mu), margin], given])
    found: list[PathSolution] = []
    ran, status, why = 0, "optimal", ""
    from ..progress import bar

    it = bar(seeds, total=len(seeds), desc="path generation", enabled=progress, unit="start")
    try:
        for sd in it:
            if time_limit is not None and time.perf_counter() - t_start > time_limit:
                break
            sigma = sd.branch
            solver, rows, nz, fun = _nlp(
                n, timing, objective, sigma, measures, speed,
                (float(centre[0]), float(centre[1])) if measures else (0.0, 0.0),
                scale if measures else 1.0,
            )  # fmt: skip
            x0 = np.concatenate(
                [
                    sd.design,
                    [sd.x0, sd.y0, sd.angle],
                    sd.angles if timing == "free" else sd.angles[:1],
                ]
            )
            lbx = [nb[k][0] for k in NAMES] + [-6 * np.pi] * nphi
            ubx = [nb[k][1] for k in NAMES] + [6 * np.pi] * nphi
            if objective == "max":
                lbx.append(0.0)
                ubx.append(np.inf)
                x0 = np.append(x0, 4.0)
            x0 = np.clip(x0, lbx, ubx)
            if measures:  # first the path alone, then the measures from its optimum
                plain, prow, _, _ = _nlp(n, timing, objective, sigma)
                npl = len(prow)
                x0 = np.asarray(
                    plain(x0=x0, p=P, lbx=lbx, ubx=ubx, lbg=np.zeros(npl),
                          ubg=np.full(npl, np.inf))["x"], dtype=float,
                ).ravel()  # fmt: skip
            s, _ = solve_with_peaks(
                solver, fun, x0, P, len(rows), lbx, ubx, objective,
                lambda z, sigma=sigma: _solution(z, sigma, n, timing, given, centre, scale, t,
                                                 objective),
                measures, speed,
            )  # fmt: skip
            ran += 1
            if s is None:
                continue
            reason = _feasible(s, timing, min_mu, bnds) or check_constraints(
                measures, s.linkage, speed
            )
            if reason:
                why = reason
                continue
            found.append(s)
            if hasattr(it, "set_postfix_str"):
                best = min(x.error for x in found)
                it.set_postfix_str(f"best {best:.4g}")
    except KeyboardInterrupt:
        status = "interrupted"
    finally:
        if hasattr(it, "close"):
            it.close()
    found.sort(key=lambda s: s.error)
    distinct: list[PathSolution] = []
    for s in found:
        if not any(_same(s, d) for d in distinct):
            distinct.append(s)
    n_distinct = len(distinct)
    if distinct:
        from .path_cognates import crank_cognate

        cog = crank_cognate(distinct[0], t, objective)
        if (
            cog is not None
            and not _feasible(cog, timing, min_mu, bnds)
            and not check_constraints(measures, cog.linkage, speed)
        ):
            match = [i for i, d in enumerate(distinct) if _same(cog, d, rtol=1e-3)]
            if match:
                i = match[0]
                distinct[i] = _with_note(distinct[i], "cognate of #1")
            else:
                distinct.insert(1, cog)
    if measures:  # the library's certifier confirms each measure over the continuous angle
        from .path_measures import certified

        kept, dropped = certified(distinct, measures, speed)
        n_distinct -= sum(1 for d in distinct if not d.note) - sum(1 for d in kept if not d.note)
        distinct, why = kept, why or dropped
    if not distinct and status != "interrupted":
        status = "infeasible"
    return PathResult(
        targets=t,
        best=distinct[0] if distinct else None,
        solutions=tuple(distinct),
        timing=timing,
        objective=objective,
        closed=bool(closed),
        min_transmission=min_mu,
        starts=ran,
        distinct=n_distinct,
        status=status,
        seconds=time.perf_counter() - t_start,
        error_definition=ERROR_DEFINITION[objective],
        bounds=bnds,
        message="" if distinct else (why or "no start ended on a design whose crank turns"),
    )


def _shape(t, closed, objective, measures, bounds, starts, min_mu, margin, time_limit, t_start):
    """Shape-only timing (:mod:`~mechsynth.synthesis.path_shape`)."""
    from .path_shape import SHAPE_ERROR, shape_path_generation

    if not closed:
        raise MechanismError("timing='shape' compares closed curves: the targets' path must be "
                             "closed")  # fmt: skip
    if objective != "squares" or measures or bounds is not None:
        raise MechanismError(
            "timing='shape' takes no objective, constraints or bounds (the shape error; "
            "min_transmission applies)"
        )
    sols, ran, distinct, status, why = shape_path_generation(
        t, starts=starts, min_mu=min_mu, margin=margin, time_limit=time_limit, t_start=t_start
    )
    return PathResult(
        targets=t,
        best=sols[0] if sols else None,
        solutions=tuple(sols),
        timing="shape",
        objective=objective,
        closed=True,
        min_transmission=min_mu,
        starts=ran,
        distinct=distinct,
        status=status,
        seconds=time.perf_counter() - t_start,
        error_definition=SHAPE_ERROR,
        message="" if sols else why,
    )


def _general(t, mechanism, trace, variables, bounds, timing, given, min_mu, objective, starts,
             time_limit, margin, progress, seed, closed, t_start, measures=(),
             speed=None):  # fmt: skip
    """Path generation on a Linkage (or the slider-crank template)."""
    from .path_linkage import linkage_path_generation, slider_crank_template

    if bounds is not None:
        raise MechanismError("bounds are the four-bar's; give a linkage's as variables=...")
    if variables is not None and not isinstance(variables, dict):
        raise MechanismError(
            f"variables must be a dict {{parameter: (lower, upper)}}, got {variables!r}"
        )
    if trace is not None and not isinstance(trace, str):
        raise MechanismError(f"trace must be a point's name, got {trace!r}")
    if isinstance(mechanism, str) and mechanism == "slider-crank":
        lk = slider_crank_template()
        var = _slider_crank_variables(t)
        for k, b in (variables or {}).items():
            if k not in var:
                raise MechanismError(
                    f"variables: the slider-crank's dimensions are {', '.join(var)}, got {k!r}"
                )
            var[k] = b
        trace = trace or "P"
    else:
        lk, var = mechanism, dict(variables or {})
    checked = {}
    for k, b in var.items():
        if not isinstance(b, (tuple, list, np.ndarray)) or len(b) != 2:
            raise MechanismError(f"variables[{k!r}] must be (lower, upper), got {b!r}")
        lo = validate.number(f"variables[{k!r}] lower", b[0])
        hi = validate.number(f"variables[{k!r}] upper", b[1])
        if not lo < hi:
            raise MechanismError(f"variables[{k!r}]: need lower < upper, got ({lo}, {hi})")
        checked[k] = (lo, hi)
    sols, ran, distinct, status, why = linkage_path_generation(
        t, lk, trace=trace, variables=checked, timing=timing,
        given=given if timing == "prescribed" else None, min_mu=min_mu, objective=objective,
        starts=starts, time_limit=time_limit, margin=max(margin, 1e-9), progress=progress,
        seed=seed, constraints=measures, speed=speed,
    )  # fmt: skip
    return PathResult(
        targets=t,
        best=sols[0] if sols else None,
        solutions=tuple(sols),
        timing=timing,
        objective=objective,
        closed=bool(closed),
        min_transmission=min_mu,
        starts=ran,
        distinct=distinct,
        status=status,
        seconds=time.perf_counter() - t_start,
        error_definition=ERROR_DEFINITION[objective],
        bounds=checked,
        message="" if sols else (why or "no start ended on a design that assembles"),
    )


def _same_values(a, b, rtol=1e-4) -> bool:
    """Two general-linkage solutions are one optimum: same error, and the same dimensions or
    the same motion (every moving point on the same path at the same crank angles: a guide's
    reference point slid along its own line is the same mechanism)."""
    if abs(a.error - b.error) > rtol * max(abs(a.error), abs(b.error)) + 1e-14:
        return False
    x = np.array(list(a.values.values()))
    y = np.array(list(b.values.values()))
    if np.abs(x - y).max() <= 1e-3 * max(np.abs(x).max(), 1e-300):
        return True
    phi = np.linspace(0.0, 2.0 * np.pi, 36, endpoint=False)
    try:
        pa = a.linkage.motion(a.angles[0] + phi).points
        pb = b.linkage.motion(b.angles[0] + phi).points
    except MechanismError:
        return False
    size = max(float(np.abs(x).max()), 1e-300)
    for name in pa:
        if name not in pb:
            return False
        ax, ay = np.broadcast_to(pa[name].x, phi.shape), np.broadcast_to(pa[name].y, phi.shape)
        if np.ptp(ax) == 0.0 and np.ptp(ay) == 0.0:
            continue  # a ground point: its place is the dimensions', compared by the motion
        if max(np.abs(ax - pb[name].x).max(), np.abs(ay - pb[name].y).max()) > 1e-4 * size:
            return False
    return True


def _slider_crank_variables(t):
    """Bounds of the slider-crank template's dimensions, scaled with the targets."""
    lo, hi = t.min(axis=0), t.max(axis=0)
    d = float(np.hypot(*(hi - lo)))
    return {
        "O_x": (lo[0] - 5 * d, hi[0] + 5 * d),
        "O_y": (lo[1] - 5 * d, hi[1] + 5 * d),
        "OA": (d / 200, 5 * d),
        "AB": (d / 100, 10 * d),
        "G_x": (lo[0] - 5 * d, hi[0] + 5 * d),
        "G_y": (lo[1] - 5 * d, hi[1] + 5 * d),
        "guide_angle": (-np.pi, np.pi),
        "P_along": (-10 * d, 10 * d),
        "P_left": (-10 * d, 10 * d),
    }


def _polish(fun, z, P, lbx, ubx):
    """Gauss-Newton (scipy's trust region) on the residuals from IPOPT's point: an interior
    point stops a barrier's width (about 1e-11) inside its inequalities; where none of them is
    active the least-squares steps go on to round-off. Kept only when every constraint and
    bound still holds and the error fell."""
    from scipy.optimize import least_squares

    f0, _, _, _, _ = fun(z, P)

    def res(x):
        return np.asarray(fun(x, P)[3], dtype=float).ravel()

    def jac(x):
        return np.asarray(fun(x, P)[4], dtype=float)

    try:
        out = least_squares(res, z, jac=jac, method="trf", xtol=1e-15, ftol=1e-15,
                            gtol=1e-15, max_nfev=30)  # fmt: skip
    except (ValueError, np.linalg.LinAlgError):
        return z
    f1, _, g1, _, _ = fun(out.x, P)
    g1 = np.asarray(g1, dtype=float).ravel()
    ok = (
        np.all(np.isfinite(out.x))
        and float(f1) < float(f0)
        and g1.min(initial=0.0) >= -1e-12
        and np.all(out.x >= np.asarray(lbx)) and np.all(out.x <= np.asarray(ubx))
    )  # fmt: skip
    return out.x if ok else z


def _with_note(s: PathSolution, note: str) -> PathSolution:
    from dataclasses import replace

    return replace(s, note=note)
