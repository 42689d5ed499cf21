"""Path generation for any :class:`~mechsynth.Linkage`: a named tracing point, the dimensions to
vary, the crank angles per target.

The linkage's own solve is traced on CasADi symbols (as :class:`~mechsynth.synthesis.Problem`
does) for IPOPT's exact derivatives. One assembly branch over the whole turn: every group's
assembly margin (``sin^2`` of an RRR dyad's transmission angle, ``cos^2`` of an RRP rod's angle
to its guide, ...; see :meth:`~mechsynth.Linkage.assembly_margins`) is bounded below on a grid of
crank angles over the turn, and the returned designs are checked on a fine grid; a smallest
transmission angle ``mu`` raises that bound to ``sin^2 mu``. Starts: the linkage's own values and
the best of a batch of random designs within the bounds that assemble over the whole turn,
ranked by the distance of their curves to the targets. A slider-crank's coupler point is such a
linkage (:func:`slider_crank_template`).
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass

import numpy as np

from ..errors import MechanismError

__all__ = ["LinkagePathSolution", "linkage_path_generation", "slider_crank_template"]

#: crank angles of the assembly-margin grid in the NLP
GRID = 72


@dataclass(frozen=True)
class LinkagePathSolution:
    """A design of a general linkage tracing the targets.

    Attributes
    ----------
    linkage : the design (a :class:`~mechsynth.Linkage`); ``trace_point`` its tracing point.
    values : ``{name: value}`` of the varied dimensions (SI).
    angles : crank angle at each target (rad, the linkage's input).
    error, sum_squares, max_distance, transmission, note, certificate : as
        :class:`~mechsynth.synthesis.path_generation.PathSolution`'s; the transmission range
        is over every group's transmission angle on 3600 crank angles.
    """

    linkage: object
    trace_point: str
    values: dict
    angles: np.ndarray
    error: float
    sum_squares: float
    max_distance: float
    transmission: tuple[float, float]
    note: str = ""
    branch: str = ""
    certificate: tuple = ()

    fourbar = None  # not a four-bar in its own frame
    coupler_point = None

    def trace(self, phi) -> np.ndarray:
        m = self.linkage.motion(np.atleast_1d(np.asarray(phi, dtype=float)))
        p = m.points[self.trace_point]
        return np.column_stack([p.x, p.y])

    def positions(self, phi=None) -> dict[str, np.ndarray]:
        phi = self.angles if phi is None else np.atleast_1d(np.asarray(phi, dtype=float))
        m = self.linkage.motion(phi)
        return {
            k: np.column_stack(np.broadcast_arrays(p.x + 0 * phi, p.y + 0 * phi))
            for k, p in m.points.items()
        }

    def as_dict(self) -> dict:
        return {
            **{k: float(v) for k, v in self.values.items()},
            "error": self.error,
            "sum_squares": self.sum_squares,
            "max_distance": self.max_distance,
            "angles": [float(a) for a in self.angles],
            "transmission_min": float(self.transmission[0]),
            "transmission_max": float(self.transmission[1]),
            "note": self.note,
            "certificate": [c.as_dict() for c in self.certificate],
        }


def slider_crank_template():
    """A slider-crank with a coupler point, as a linkage whose every dimension may vary:
    crank O-A (``OA``, ``phase``), rod A-B (``AB``) with B on the guide through ``(G_x, G_y)``
    at ``guide_angle``, tracing point P on the rod (``P_along`` from A towards B, ``P_left``)."""
    from ..kinematics.linkage import Linkage, Param

    return (
        Linkage(ground={"O": (0.0, 0.0), "G": (0.0, -0.2)}, name="slider-crank path generator")
        .crank("A", about="O", length=0.3)
        .rrp("B", ("A", 1.0), guide=("G", Param("guide_angle", 0.0)))
        .attach("P", on=("A", "B"), along=0.5, left=0.3)
        .with_output("P")
    )


def _transmission(lk, n=3600):
    """(smallest acute, largest) transmission angle over the turn, every group with one."""
    from ..units import cycle

    m = lk.motion(cycle(n))
    mus = [np.asarray(v, dtype=float) for v in m.transmission_angles.values()]
    if not mus:
        return (float("nan"), float("nan"))
    mu = np.concatenate([x.ravel() for x in mus])
    return float(np.minimum(mu, np.pi - mu).min()), float(mu.max())


def _margins_ok(lk, floor, n=3600) -> tuple[str, float]:
    """('', lowest) when every assembly margin stays above ``floor`` over ``n`` crank angles,
    else (why, lowest margin; -inf when the linkage does not assemble)."""
    from ..units import cycle

    try:
        margins = lk.assembly_margins(cycle(n))
    except MechanismError as exc:
        return str(exc), -np.inf
    low = np.inf
    for name, m in margins.items():
        m = np.asarray(m, dtype=float)
        if not np.all(np.isfinite(m)):
            return f"assembly margin {name} not finite over the turn", -np.inf
        low = min(low, float(m.min()))
        if m.min() < floor:
            return f"assembly margin {name} down to {m.min():.6g} (needs {floor:.6g})", low
    return "", low


@functools.lru_cache(maxsize=16)
def _nlp(lk, names, trace, n, timing, objective, constraints=(), speed=None):
    import casadi as ca

    k = len(names)
    nphi = n if timing == "free" else 1
    nz = k + nphi + (1 if objective == "max" else 0)
    from .path_measures import EXTRA
    from .path_measures import GRID as MGRID

    z = ca.SX.sym("z", nz)
    # targets, margin floor, prescribed angles (and the measures' angle slots)
    p = ca.SX.sym("p", 3 * n + 1 + (MGRID + EXTRA if constraints else 0))
    design = lk(**{nm: z[i] for i, nm in enumerate(names)})
    phi = z[k : k + n] if timing == "free" else z[k] + p[2 * n + 1 : 3 * n + 1]
    q = design.motion(phi).points[trace]
    d2 = (q.x - p[0 : 2 * n : 2]) ** 2 + (q.y - p[1 : 2 * n : 2]) ** 2
    grid = np.linspace(0.0, 2.0 * np.pi, GRID, endpoint=False)
    g = []
    for m in design.assembly_margins(grid).values():
        g.append(ca.vec(m) - p[2 * n])
    for _, expr in design.feasibility_constraints({nm: z[i] for i, nm in enumerate(names)}):
        g.append(expr)
    if timing == "free":
        g += [phi[i + 1] - phi[i] for i in range(n - 1)]
        g.append(2.0 * np.pi - (phi[n - 1] - phi[0]))
    if constraints:
        from .path_measures import constraint_rows

        g += constraint_rows(constraints, design, speed, p[3 * n + 1 :])
    if objective == "max":
        t = z[nz - 1]
        g += [t - d2[i] for i in range(n)]
        f = t
    else:
        f = ca.sum1(d2)
    gg = ca.vertcat(*g)
    from .path_generation import _IPOPT

    solver = ca.nlpsol("linkage_path", "ipopt", {"x": z, "p": p, "f": f, "g": gg}, _IPOPT)
    res = ca.vertcat(q.x - p[0 : 2 * n : 2], q.y - p[1 : 2 * n : 2])
    fun = ca.Function("lp_f", [z, p], [f, ca.gradient(f, z), gg, res, ca.jacobian(res, z)])
    return solver, int(gg.numel()), nz, fun


def _ordered_nearest(curve, phi, targets):
    """Crank angles (from the equal steps ``phi`` of a turn) for the targets, in order within
    one turn, that minimize the sum of squared distances to the curve's points there: dynamic
    programming over the targets for every first angle at once."""
    m = len(phi)
    d = ((targets[:, None, :] - curve[None, :, :]) ** 2).sum(-1)  # (N, M)
    # start s: the turn read from angle index s on; d_s[i, j] = d[i, (s + j) % M]
    idx = (np.arange(m)[:, None] + np.arange(m)[None, :]) % m  # (S, M)
    ds = d[:, idx].transpose(1, 0, 2)  # (S, N, M)
    cost = ds[:, 0, :].copy()
    for i in range(1, len(targets)):  # a target's angle at or after the previous one's
        cost = ds[:, i, :] + np.minimum.accumulate(cost, axis=1)
    s = int(np.argmin(cost.min(axis=1)))
    # back: each target at the cheapest angle not after the next one's
    j = int(np.argmin(cost[s]))
    picks = [j]
    acc = ds[s, 0, :].copy()
    costs = [acc]
    for i in range(1, len(targets) - 1):
        acc = ds[s, i, :] + np.minimum.accumulate(acc)
        costs.append(acc)
    for i in range(len(targets) - 2, -1, -1):
        j = int(np.argmin(costs[i][: j + 1]))
        picks.append(j)
    k = np.array(picks[::-1])
    return phi[(s + k) % m] + 2.0 * np.pi * ((s + k) >= m) + 0.0 * k


def linkage_path_generation(
    targets,
    linkage,
    *,
    trace: str | None = None,
    variables: dict | None = None,
    timing: str = "free",
    given=None,
    min_mu: float = 0.0,
    objective: str = "squares",
    starts: int = 12,
    time_limit: float | None = None,
    margin: float = 1e-3,
    progress=None,
    seed: int = 0,
    constraints=(),
    speed=None,
):
    """Path generation on ``linkage`` (see :func:`~mechsynth.path_generation`, which checks
    the arguments and calls this). Returns ``(solutions, starts_run, distinct, status, why)``."""
    from ..kinematics.linkage import Linkage
    from ..progress import bar
    from .path_generation import _same_values

    if not isinstance(linkage, Linkage):
        raise MechanismError(f"mechanism must be 'four-bar', 'slider-crank' or a Linkage, got "
                             f"{linkage!r}")  # fmt: skip
    t_start = time.perf_counter()
    trace = trace or linkage.default_output
    if trace not in linkage.points:
        raise MechanismError(
            f"trace: {linkage.name} has no point {trace!r}; its points: "
            + ", ".join(linkage.points)
        )
    if not variables:
        raise MechanismError(
            "variables: name the linkage's dimensions to vary with their (lower, upper), e.g. "
            "{'AB': (0.05, 0.2)}; its parameters: " + ", ".join(linkage.parameters)
        )
    names = tuple(variables)
    for k in names:
        if k not in linkage.parameters:
            raise MechanismError(
                f"variables: {linkage.name} has no parameter {k!r}; its parameters: "
                + ", ".join(linkage.parameters)
            )
    t = np.asarray(targets, dtype=float)
    n = len(t)
    floor = max(margin, float(np.sin(min_mu) ** 2))
    rng = np.random.default_rng(seed)
    lo = np.array([variables[k][0] for k in names], dtype=float)
    hi = np.array([variables[k][1] for k in names], dtype=float)
    own = np.clip([float(linkage.parameters[k]) for k in names], lo, hi)
    cand = np.vstack([own, lo + (hi - lo) * rng.uniform(size=(3000, len(names)))])
    phi = np.linspace(0.0, 2.0 * np.pi, 96, endpoint=False)
    design = linkage(**{k: cand[:, i : i + 1] for i, k in enumerate(names)})
    ok = np.ones(len(cand), dtype=bool)
    for v in design.assembly_margins(phi).values():
        v = np.asarray(v, dtype=float)
        ok &= np.all(np.isfinite(v) & (v > floor), axis=-1)
    idx = np.flatnonzero(ok)
    if idx.size == 0:
        return [], 0, 0, "infeasible", "no design within the bounds assembles over the turn"
    sub = linkage(**{k: cand[idx, i : i + 1] for i, k in enumerate(names)})
    pm = sub.motion(phi).points[trace]
    curves = np.stack(np.broadcast_arrays(pm.x, pm.y), axis=-1)  # (m, 96, 2)
    near = ((t[None, :, None, :] - curves[:, None, :, :]) ** 2).sum(-1).min(-1).sum(-1)
    order = idx[np.argsort(near)]
    pick = list(dict.fromkeys([0] * bool(ok[0]) + [int(i) for i in order]))[:starts]
    P = np.concatenate([t.ravel(), [floor], np.zeros(n) if given is None else given])
    solver, ng, nz, fun = _nlp(linkage, names, trace, n, timing, objective, constraints, speed)
    nphi = n if timing == "free" else 1
    lbx = list(lo) + [-6 * np.pi] * nphi
    ubx = list(hi) + [6 * np.pi] * nphi
    if objective == "max":
        lbx.append(0.0)
        ubx.append(np.inf)
    found, ran, status, why = [], 0, "optimal", ""
    it = bar(pick, total=len(pick), desc="path generation", enabled=progress, unit="start")
    from .path_measures import solve_with_peaks

    try:
        for j in it:
            if time_limit is not None and time.perf_counter() - t_start > time_limit:
                break
            row = int(np.flatnonzero(idx == j)[0])
            a0 = _ordered_nearest(curves[row], phi, t)
            x0 = np.concatenate([cand[j], a0 if timing == "free" else a0[:1]])
            if objective == "max":
                x0 = np.append(x0, float(((curves[row][None] - t[:, None]) ** 2).sum(-1).max()))
            x0 = np.clip(x0, lbx, ubx)
            from .path_measures import check_constraints

            # the NLP bounds the margins on GRID angles only: where they dip below the floor
            # between them, re-solve with the floor raised by twice the dip (up to 3 times)
            Pk = P.copy()
            for _ in range(4):
                s, _ = solve_with_peaks(
                    solver, fun, x0, Pk, ng, lbx, ubx, objective,
                    lambda z: _solution(linkage, names, trace, z, n, timing, given, t, objective),
                    constraints, speed,
                )  # fmt: skip
                if isinstance(s, str):
                    break
                bad, low = _margins_ok(s.linkage, floor * (1 - 1e-6) - 1e-12)
                if not bad or not np.isfinite(low) or floor - low > 0.5 * floor:
                    break
                Pk[2 * n] += 2.0 * (floor - low) + 1e-9
            ran += 1
            if isinstance(s, str):
                why = s
                continue
            bad = bad or check_constraints(constraints, s.linkage, speed)
            if bad:
                why = bad
                continue
            if timing == "free" and (
                np.diff(s.angles).min() < -1e-9 or s.angles[-1] - s.angles[0] > 2 * np.pi + 1e-9
            ):
                why = "crank angles out of order"
                continue
            found.append(s)
    except KeyboardInterrupt:
        status = "interrupted"
    finally:
        if hasattr(it, "close"):
            it.close()
    found.sort(key=lambda s: s.error)
    distinct = []
    for s in found:
        if not any(_same_values(s, d) for d in distinct):
            distinct.append(s)
    from .path_measures import certified

    distinct, dropped = certified(distinct, constraints, speed)
    why = why or dropped
    if not distinct and status != "interrupted":
        status = "infeasible"
    return distinct, ran, len(distinct), status, why


def _solution(linkage, names, trace, z, n, timing, given, targets, objective):
    k = len(names)
    values = {nm: float(z[i]) for i, nm in enumerate(names)}
    phi = np.asarray(z[k : k + n] if timing == "free" else z[k] + given, dtype=float)
    phi = phi - 2.0 * np.pi * np.floor(phi[0] / (2.0 * np.pi))  # the first in [0, 2 pi)
    try:
        lk = linkage(**values)
        q = lk.motion(phi).points[trace]
        tr = _transmission(lk)
    except MechanismError as exc:
        return str(exc)
    d2 = (q.x - targets[:, 0]) ** 2 + (q.y - targets[:, 1]) ** 2
    ss = float(d2.sum())
    return LinkagePathSolution(
        lk,
        trace,
        values,
        phi,
        ss if objective == "squares" else float(d2.max()),
        ss,
        float(np.sqrt(d2.max())),
        tr,
    )
