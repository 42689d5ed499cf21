"""Design of the spatial drive: deviation tolerances, design charts, counterbalance sizing.

The measure is :attr:`SpatialForces.peak_split`: the largest difference between the two pitman
forces over the cycle divided by the largest mean pitman force. Every function evaluates many
designs (deviation values, equalizer widths, pitman sections) as one batch of the vectorized
model, in chunks that bound the memory of the batched linear algebra.

* :func:`split_curve`, :func:`split_curves` -- the peak split for a list of values of one
  deviation (or of several, in one batch);
* :func:`tolerance` -- the largest value of each deviation (acting alone) that keeps the split
  within a limit (5 % by default), by bracketing and a secant/bisection refinement on the exact
  model;
* :func:`split_map` -- the peak split over a grid of two deviations acting together (the
  tolerance chart; its ``limit`` contour is the tolerance region);
* :func:`limit_contour` -- that contour itself, solved on rays from the ideal drive (each point
  where the split equals the limit to ``rtol``), for a smooth and exact boundary;
* :func:`tolerance_design_chart` -- the tolerance of one deviation as a function of the
  equalizer width and the pitmans' bending stiffness (a design chart: how to build a drive that
  forgives assembly errors);
* :func:`size_counterbalance` -- the counterbalance moment (and phase) that minimizes the peak
  crank torque of the spatial drive, as a certified convex (linear) program, reporting the
  pitman load split of the result.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ...errors import MechanismError
from .spatial_forces import SpatialMasses, spatial_forces
from .spatial_unit import DEVIATIONS, SpatialPumpingUnit
from .torque import Counterbalance

__all__ = [
    "split_curve",
    "split_curves",
    "tolerance",
    "split_map",
    "limit_contour",
    "tolerance_design_chart",
    "size_counterbalance",
    "CounterbalanceSizing",
    "SAMPLES_PER_CHUNK",
]

#: designs x crank angles evaluated in one batch
SAMPLES_PER_CHUNK = 4000


def _check_deviation(name):
    if name not in DEVIATIONS:
        raise MechanismError(f"unknown deviation {name!r}; known: {', '.join(DEVIATIONS)}")


def _peak_splits(units: list[dict], base: SpatialPumpingUnit, theta, speed, load, masses):
    """Peak split of ``base.replace(**changes)`` for every dict of changes, batched."""
    theta = np.asarray(theta, dtype=float)
    per = max(1, SAMPLES_PER_CHUNK // theta.size)
    out = []
    for i in range(0, len(units), per):
        chunk = units[i : i + per]
        keys = sorted({k for c in chunk for k in c})
        changes = {}
        for k in keys:
            if k == "pitman_section":
                sections = [c.get(k, base.pitman_section) for c in chunk]
                fields = ("E", "G", "area", "J_y", "J_z", "J_p")
                changes[k] = replace(
                    base.pitman_section,
                    **{f: np.array([getattr(s, f) for s in sections])[:, None] for f in fields},
                )
            else:
                changes[k] = np.array([c.get(k, getattr(base, k)) for c in chunk], dtype=float)[
                    :, None
                ]
        unit = base.replace(**changes)
        f = spatial_forces(unit, theta, speed, load=load, masses=masses)
        out.append(np.atleast_1d(f.peak_split))
    return np.concatenate(out) if out else np.zeros(0)


def split_curve(unit: SpatialPumpingUnit, deviation: str, values, theta, speed, load, masses=None):
    """Peak split of ``unit`` with ``deviation`` set to each of ``values`` (the others as in
    ``unit``)."""
    return split_curves(unit, {deviation: values}, theta, speed, load, masses)[deviation]


def split_curves(unit: SpatialPumpingUnit, values: dict, theta, speed, load, masses=None):
    """:func:`split_curve` for several deviations (``{name: values}``) in one batch."""
    designs, index = [], {}
    for name, vals in values.items():
        _check_deviation(name)
        vals = np.asarray(vals, dtype=float).ravel()
        index[name] = slice(len(designs), len(designs) + vals.size)
        designs += [{name: v} for v in vals]
    splits = _peak_splits(designs, unit, theta, speed, load, masses)
    return {name: splits[sl] for name, sl in index.items()}


def tolerance(
    unit: SpatialPumpingUnit,
    deviations,
    theta,
    speed,
    load,
    masses=None,
    limit=0.05,
    start: dict[str, float] | None = None,
    maximum: dict[str, float] | None = None,
    rtol=1e-3,
    max_rounds=30,
) -> dict[str, dict[str, Any]]:
    """The largest value of each deviation, acting alone on ``unit.ideal()``, for which the peak
    split stays within ``limit``.

    Each deviation starts at ``start[name]`` and is doubled until the split exceeds the limit
    or the value reaches ``maximum[name]`` (then the tolerance is reported as not reached:
    ``value`` None); the bracket is then refined by secant and bisection steps (the split grows
    almost linearly) to ``rtol`` of the limit. All deviations advance together, as one batch.

    Returns ``{name: {"value", "split", "bracket", "evaluations"}}``.
    """
    names = list(deviations)
    for n in names:
        _check_deviation(n)
    base = unit.ideal()
    start = start or {}
    maximum = maximum or {}
    lo = {n: 0.0 for n in names}
    s_lo = {n: 0.0 for n in names}
    hi: dict[str, float | None] = {n: None for n in names}
    s_hi: dict[str, float] = {}
    x = {n: min(float(start.get(n, 1e-3)), float(maximum.get(n, np.inf))) for n in names}
    evals = {n: 0 for n in names}
    open_ = list(names)
    for _ in range(max_rounds):  # bracketing
        if not open_:
            break
        splits = _peak_splits([{n: x[n]} for n in open_], base, theta, speed, load, masses)
        nxt = []
        for n, s in zip(open_, splits):
            evals[n] += 1
            if s > limit:
                hi[n], s_hi[n] = x[n], float(s)
            else:
                lo[n], s_lo[n] = x[n], float(s)
                top = maximum.get(n, np.inf)
                if x[n] >= top:
                    continue
                x[n] = min(2.0 * x[n], top)
                nxt.append(n)
        open_ = nxt
    active = [n for n in names if hi[n] is not None]
    for _ in range(max_rounds):  # refinement (secant, safeguarded by bisection)
        todo = [n for n in active if min(abs(s_lo[n] - limit), abs(s_hi[n] - limit)) > rtol * limit]
        if not todo:
            break
        trial = {}
        for n in todo:
            t = lo[n] + (limit - s_lo[n]) * (hi[n] - lo[n]) / (s_hi[n] - s_lo[n])
            if not lo[n] < t < hi[n]:
                t = 0.5 * (lo[n] + hi[n])
            trial[n] = t
        splits = _peak_splits([{n: trial[n]} for n in todo], base, theta, speed, load, masses)
        for n, s in zip(todo, splits):
            evals[n] += 1
            if s > limit:
                hi[n], s_hi[n] = trial[n], float(s)
            else:
                lo[n], s_lo[n] = trial[n], float(s)
    out = {}
    for n in names:
        if hi[n] is None:
            out[n] = {
                "value": None,
                "split": s_lo[n],
                "bracket": (lo[n], None),
                "evaluations": evals[n],
            }
            continue
        # the end nearer the limit
        if abs(s_hi[n] - limit) < abs(s_lo[n] - limit):
            val, s = hi[n], s_hi[n]
        else:
            val, s = lo[n], s_lo[n]
        out[n] = {"value": val, "split": s, "bracket": (lo[n], hi[n]), "evaluations": evals[n]}
    return out


def split_map(
    unit: SpatialPumpingUnit,
    first: str,
    values1,
    second: str,
    values2,
    theta,
    speed,
    load,
    masses=None,
):
    """Peak split over the grid ``values1 x values2`` of two deviations acting together (the
    others as in ``unit``). Returns an array of shape ``(len(values2), len(values1))``."""
    _check_deviation(first)
    _check_deviation(second)
    v1 = np.asarray(values1, dtype=float).ravel()
    v2 = np.asarray(values2, dtype=float).ravel()
    designs = [{first: a, second: b} for b in v2 for a in v1]
    return _peak_splits(designs, unit, theta, speed, load, masses).reshape(v2.size, v1.size)


def limit_contour(
    unit: SpatialPumpingUnit,
    first: str,
    reach1: float,
    second: str,
    reach2: float,
    theta,
    speed,
    load,
    masses=None,
    limit=0.05,
    rays=25,
    rtol=1e-3,
    max_rounds=12,
):
    """The ``limit`` contour of the peak split in the box ``[0, reach1] x [0, reach2]`` of two
    deviations acting together (the boundary of the tolerance region of :func:`split_map`).

    Along ``rays`` rays from the unit's own deviations (the corner ``(0, 0)``; its split must
    be within ``limit``) to the far sides of the box, the point where the split equals
    ``limit`` is solved by regula falsi (Illinois), all rays as one batch per round, to
    ``rtol`` of the limit: the contour's points are on the exact model, not interpolated from
    a grid. A ray whose far end is within the limit leaves the region through the box: its
    point is NaN. The region must be star-shaped from the corner (the split growing along every
    ray), as the split of small deviations is.

    Returns
    -------
    (values1, values2, splits) : arrays of length ``rays`` (the deviations in their units, m or
        rad; the split found at each point).
    """
    _check_deviation(first)
    _check_deviation(second)
    reach = []
    for name, r in (("reach1", reach1), ("reach2", reach2)):
        r = float(r)
        if not (np.isfinite(r) and r > 0.0):
            raise MechanismError(f"{name} must be a positive finite number, got {r!r}")
        reach.append(r)
    if int(rays) < 2:
        raise MechanismError(f"rays must be at least 2, got {rays!r}")
    psi = np.linspace(0.0, np.pi / 2.0, int(rays))
    c, s = np.cos(psi), np.sin(psi)
    far = 1.0 / np.maximum(c, s)  # where each ray leaves the box (scaled coordinates)

    def split(t):
        designs = [{first: reach[0] * a, second: reach[1] * b} for a, b in zip(t * c, t * s)]
        return _peak_splits(designs, unit, theta, speed, load, masses) - limit

    f0 = float(split(np.zeros(1))[0] + limit)
    if not f0 < limit:
        raise MechanismError(
            f"the unit's own split ({f0:.4g}) is not within the limit ({limit:g}): no region"
        )
    lo, hi = np.zeros(psi.size), far.copy()
    f_lo, f_hi = np.full(psi.size, f0 - limit), split(far)
    out = f_hi <= 0.0
    t, ft = np.where(out, np.nan, hi), f_hi.copy()
    side = np.zeros(psi.size, dtype=int)  # which end stayed twice (Illinois halves its value)
    for _ in range(int(max_rounds)):
        todo = ~out & (np.abs(ft) > rtol * limit)
        if not todo.any():
            break
        idx = np.flatnonzero(todo)
        guess = hi[idx] - f_hi[idx] * (hi[idx] - lo[idx]) / (f_hi[idx] - f_lo[idx])
        guess = np.clip(guess, lo[idx] + 1e-9 * far[idx], hi[idx] - 1e-9 * far[idx])
        fg = split(guess)
        t[idx], ft[idx] = guess, fg
        up = fg > 0.0
        f_lo[idx] *= np.where(up & (side[idx] == 1), 0.5, 1.0)
        f_hi[idx] *= np.where(~up & (side[idx] == -1), 0.5, 1.0)
        hi[idx], f_hi[idx] = np.where(up, guess, hi[idx]), np.where(up, fg, f_hi[idx])
        lo[idx], f_lo[idx] = np.where(up, lo[idx], guess), np.where(up, f_lo[idx], fg)
        side[idx] = np.where(up, 1, -1)
    return reach[0] * t * c, reach[1] * t * s, ft + limit


def tolerance_design_chart(
    unit: SpatialPumpingUnit,
    deviation: str,
    widths,
    stiffness_factors,
    theta,
    speed,
    load,
    masses=None,
    limit=0.05,
    probe=None,
    maximum=None,
):
    """Tolerance of ``deviation`` (alone) for each equalizer width (the crank spacing follows:
    parallel pitmans) and each factor on the pitmans' bending stiffness (``J_y`` and ``J_z``).

    The split is first measured at a small ``probe`` value of the deviation (default 1e-3, in
    its unit: m or rad); the tolerance is the value where the (nearly linear) split reaches
    ``limit``, extrapolated from the probe, and one evaluation at that value checks it (the
    split found there is returned as ``check``). A tolerance beyond ``maximum`` (the largest
    deviation the model should be asked about) is reported as ``inf``, unchecked. Returns
    ``(tol, check)`` arrays of shape ``(len(factors), len(widths))``.
    """
    _check_deviation(deviation)
    widths = np.asarray(widths, dtype=float).ravel()
    factors = np.asarray(stiffness_factors, dtype=float).ravel()
    if np.any(widths <= 0) or np.any(factors <= 0):
        raise MechanismError("widths and stiffness factors must be positive")
    probe = 1e-3 if probe is None else float(probe)
    sec = unit.pitman_section
    base = unit.ideal()
    designs = []
    for f in factors:
        s = replace(sec, J_y=sec.J_y * f, J_z=sec.J_z * f)
        for w in widths:
            designs.append({"equalizer_width": w, "crank_spacing": w, "pitman_section": s})
    with_probe = [dict(d, **{deviation: probe}) for d in designs]
    s_probe = _peak_splits(with_probe, base, theta, speed, load, masses)
    tol = np.where(s_probe > 0, probe * limit / np.where(s_probe > 0, s_probe, 1.0), np.inf)
    if maximum is not None:
        tol = np.where(tol > maximum, np.inf, tol)
    checks = [dict(d, **{deviation: t}) for d, t in zip(designs, tol) if np.isfinite(t)]
    s_chk = np.full(tol.shape, np.nan)
    s_chk[np.isfinite(tol)] = _peak_splits(checks, base, theta, speed, load, masses)
    shape = (factors.size, widths.size)
    return tol.reshape(shape), s_chk.reshape(shape)


@dataclass(frozen=True)
class CounterbalanceSizing:
    """The counterbalance that minimizes the peak crank torque of a spatial drive.

    Attributes
    ----------
    counterbalance : the optimum :class:`Counterbalance` (moment N m, phase rad).
    peak_torque : the peak |crank torque| with it over the continuous crank angle (N m),
        certified by :func:`~mechsynth.synthesis.convex.minimax_cycle`.
    peak_torque_without : the peak with no counterbalance (N m).
    peak_split : the pitman load split of the drive (the counterbalance acts on the crank only,
        so it cannot change the split: reported to show what the design leaves to the pitmans).
    status, success, message, certified : from the convex solve.
    """

    counterbalance: Counterbalance
    peak_torque: float
    peak_torque_without: float
    peak_split: float
    status: str
    success: bool
    message: str
    certified: bool

    def to_dict(self) -> dict[str, Any]:
        return {
            "counterbalance_moment": self.counterbalance.moment,
            "phase": self.counterbalance.phase,
            "peak_torque": self.peak_torque,
            "peak_torque_without": self.peak_torque_without,
            "peak_split": self.peak_split,
            "status": self.status,
            "success": self.success,
            "certified": self.certified,
            "message": self.message,
        }


def size_counterbalance(
    unit: SpatialPumpingUnit,
    speed,
    load,
    masses: SpatialMasses | None = None,
    phase: float | None = 0.0,
    angles=360,
    n_dense=1440,
) -> CounterbalanceSizing:
    """Size the crank counterbalance of ``unit`` for the minimum peak crank torque.

    The crank torque of the spatial drive (redundant or rational, with its deviations) is
    affine in the counterbalance: ``T(theta) = T0(theta) - M sin(theta - tau)``, and with a free
    phase affine in ``(a, b) = (M cos tau, M sin tau)``. Minimizing its peak over the cycle is a
    linear program: :func:`~mechsynth.synthesis.convex.minimax_cycle` solves it on ``angles``
    crank angles with cvxpy, checks the optimum on ``n_dense`` angles and a 1-D search, and adds
    the angles the grid missed until the grid peak is the true peak. ``phase`` fixes ``tau``
    (rad); None frees it. The torque without counterbalance ``T0`` comes from the full
    kinetostatics of the drive at every crank angle the solver asks for, so the optimum is that
    of the spatial model. The counterweights' rotary inertia belongs in
    ``masses.crank_inertia`` (point-mass counterweights would make the torque non-affine).
    """
    from ...synthesis.convex import minimax_cycle

    masses = SpatialMasses() if masses is None else masses
    if masses.counterweight > 0.0:
        raise MechanismError(
            "size_counterbalance: give the counterweights' rotary inertia in crank_inertia "
            "(masses.counterweight = 0): with point masses the torque is not affine in M"
        )

    def cb_of(x):
        if phase is None:
            return Counterbalance(float(np.hypot(x[0], x[1])), float(np.arctan2(x[1], x[0])))
        return Counterbalance(float(x[0]), float(phase))

    cache: dict[bytes, np.ndarray] = {}

    def base_torque(phi):
        key = np.asarray(phi, dtype=float).tobytes()
        if key not in cache:
            f = spatial_forces(unit, phi, speed, load=load, masses=masses)
            cache[key] = np.asarray(f.crank_torque)
        return cache[key]

    def torque(x, phi):
        # the counterbalance is a moment on the crank alone: T = T0 - M sin(theta - tau)
        # (exactly; tests compare it with the full solve including the counterbalance)
        return base_torque(phi) - cb_of(x).torque(phi)

    x0 = [1e4] if phase is not None else [1e4, 0.0]
    res = minimax_cycle(torque, x0, angles, norm="abs", n_dense=n_dense)
    th = np.linspace(0.0, 2.0 * np.pi, int(n_dense), endpoint=False)
    free = spatial_forces(unit, th, speed, load=load, masses=masses)
    cb = cb_of(res.x) if res.x is not None else Counterbalance(0.0, 0.0 if phase is None else phase)
    return CounterbalanceSizing(
        counterbalance=cb,
        peak_torque=float(res.value) if res.x is not None else float("nan"),
        peak_torque_without=float(np.max(np.abs(free.crank_torque))),
        peak_split=float(free.peak_split),
        status=res.status,
        success=bool(res.success),
        message=res.message,
        certified=bool(res.extra.get("certified", False)) if res.extra else False,
    )
