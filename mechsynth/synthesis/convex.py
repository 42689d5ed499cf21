"""Convex synthesis: minimax of quantities that are affine in the decision variables.

For a fixed geometry, joint reactions, driving torques and shaking forces are affine in masses,
counterweight moments, spring preloads and loads. Over a grid of crank angles ``phi_i`` such a
quantity is

    y_i(x) = A_i x + b_i          (a number, or a 2-D force vector, per angle)

and minimizing its peak over the cycle, ``min_x max_i |y_i(x)|``, is a linear program (scalars,
``norm="abs"``) or a second-order-cone program (vectors, ``norm="euclidean"``): a convex problem
whose solution is the global optimum, with no multi-start.

* :func:`affine_map` builds ``A`` and ``b`` exactly from any function that is affine in ``x``
  (written with the ordinary numpy models) and checks the affinity numerically.
* :func:`minimax_affine` solves the minimax with cvxpy for given ``A``, ``b`` (bounds, linear
  constraints, or any further cvxpy constraints).
* :func:`minimax_cycle` does both and certifies the peak over the *continuous* crank angle: it
  evaluates the optimum densely, adds the angles where the grid missed the true peak and solves
  again (DESIGN principle 3).

Example: a 2-D bearing reaction ``R(phi) = A(phi) @ [m_slider, m_cw] + b(phi)``::

    amap = affine_map(lambda x, phi: reaction(x[0], x[1], phi), x0=[1.0, 0.5], angles=720)
    res = minimax_affine(amap, norm="euclidean", bounds=[(0.5, 2.0), (0.0, None)],
                         names=["m_slider", "m_cw"])
    res.x, res.value, res.active_angles, res.status

Statuses are those of :data:`mechsynth.synthesis.STATUSES`: ``"optimal"``, ``"infeasible"``,
``"max_iterations"``, ``"uncertified"`` (the solver reports an inaccurate solution, or the peak
refinement ran out of rounds) and ``"solver_failed"`` (also for unbounded problems: give bounds).
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import MechanismError
from ..units import cycle

__all__ = ["AffineMap", "ConvexResult", "affine_map", "minimax_affine", "minimax_cycle"]

NORMS = ("abs", "max", "euclidean")


# ------------------------------------------------------------------------------ affine map
@dataclass(frozen=True)
class AffineMap:
    """``y(phi_i) = A[i] @ x + b[i]`` over crank angles ``phi``.

    Attributes
    ----------
    A : shape ``(m, n)`` for a scalar per angle, ``(m, d, n)`` for a ``d``-vector per angle
        (``d = 2`` for a planar force).
    b : shape ``(m,)`` or ``(m, d)``.
    phi : the ``m`` crank angles (rad), or None when the rows are not angles.
    """

    A: np.ndarray
    b: np.ndarray
    phi: np.ndarray | None = None

    def __post_init__(self):
        A = np.asarray(self.A, dtype=float)
        b = np.asarray(self.b, dtype=float)
        if A.ndim not in (2, 3) or b.shape != A.shape[:-1]:
            raise MechanismError(
                f"A must have shape (m, n) or (m, d, n) and b shape A.shape[:-1]; got A "
                f"{A.shape}, b {b.shape}"
            )
        if not (np.all(np.isfinite(A)) and np.all(np.isfinite(b))):
            raise MechanismError("A and b must be finite")
        object.__setattr__(self, "A", A)
        object.__setattr__(self, "b", b)
        if self.phi is not None:
            phi = np.asarray(self.phi, dtype=float).ravel()
            if phi.size != A.shape[0]:
                raise MechanismError(f"phi has {phi.size} angles but A has {A.shape[0]} rows")
            object.__setattr__(self, "phi", phi)

    @property
    def n(self) -> int:
        """Number of decision variables."""
        return self.A.shape[-1]

    @property
    def is_vector(self) -> bool:
        return self.A.ndim == 3

    def __call__(self, x):
        """``A @ x + b`` (shape of ``b``)."""
        return self.A @ np.asarray(x, dtype=float) + self.b

    def concat(self, other: AffineMap) -> AffineMap:
        """The rows of both maps (e.g. refinement angles appended to a grid)."""
        phi = None
        if self.phi is not None and other.phi is not None:
            phi = np.concatenate([self.phi, other.phi])
        return AffineMap(np.concatenate([self.A, other.A]), np.concatenate([self.b, other.b]), phi)


def _call(func, x, phi):
    y = np.asarray(func(np.asarray(x, dtype=float), phi), dtype=float)
    return y


def affine_map(
    func: Callable[[np.ndarray, np.ndarray], Any],
    x0,
    angles=360,
    *,
    step=None,
    checks: int = 3,
    rtol: float = 1e-8,
    seed: int = 0,
) -> AffineMap:
    """The exact affine map ``y(phi) = A(phi) x + b(phi)`` of a function affine in ``x``.

    Parameters
    ----------
    func : ``func(x, phi) -> y`` with ``x`` the decision vector (shape ``(n,)``) and ``phi`` an
        array of ``m`` crank angles (rad); ``y`` of shape ``(m,)`` (a scalar per angle) or
        ``(m, d)`` (a vector per angle, e.g. a 2-D joint reaction in N). Write it with the
        ordinary (numpy) mechanism models.
    x0 : a reference decision vector (sets ``n`` and the scale of the finite steps).
    angles : a count of equal steps over one turn (``ms.cycle(angles)``) or an array of angles.
    step : finite steps per variable (default ``max(|x0_i|, 1)``); for an affine function any
        step gives the exact columns of ``A`` up to rounding.
    checks : random points (``x0 + step * U(0.05, 3)``, forward of ``x0`` like the finite
        steps) at which the affinity is verified.
    rtol : tolerance of that check, relative to the magnitude of ``y``.
    seed : seed of the check points.

    Returns
    -------
    AffineMap

    Raises
    ------
    ValueError
        if ``func`` returns non-finite values or a wrong shape, or is not affine in ``x`` (the
        message gives the largest deviation found).
    """
    x0 = np.atleast_1d(np.asarray(x0, dtype=float))
    if x0.ndim != 1 or x0.size == 0 or not np.all(np.isfinite(x0)):
        raise MechanismError(f"x0 must be a non-empty finite 1-D vector, got {x0!r}")
    phi = cycle(int(angles)) if np.ndim(angles) == 0 else np.asarray(angles, dtype=float).ravel()
    if phi.size == 0 or not np.all(np.isfinite(phi)):
        raise MechanismError("angles: need at least one finite crank angle")
    n = x0.size
    h = np.maximum(np.abs(x0), 1.0) if step is None else np.broadcast_to(step, (n,)).astype(float)
    if np.any(h <= 0) or not np.all(np.isfinite(h)):
        raise MechanismError(f"step must be positive and finite, got {step!r}")
    y0 = _call(func, x0, phi)
    if y0.ndim not in (1, 2) or y0.shape[0] != phi.size:
        raise MechanismError(
            f"func(x, phi) must return shape (m,) or (m, d) for m = {phi.size} angles, "
            f"got {y0.shape}"
        )
    if not np.all(np.isfinite(y0)):
        raise MechanismError("func(x0, phi) is not finite at every angle")
    cols = []
    for j in range(n):
        xj = x0.copy()
        xj[j] += h[j]
        cols.append((_call(func, xj, phi) - y0) / h[j])
    A = np.stack(cols, axis=-1)
    b = y0 - A @ x0
    amap = AffineMap(A, b, phi)
    rng = np.random.default_rng(seed)
    scale = max(float(np.max(np.abs(y0))), float(np.max(np.abs(A) * h)), 1e-300)
    worst = 0.0
    for _ in range(int(checks)):
        # forward of x0 only, like the finite steps: a model that rejects negative masses is
        # never called with one when x0 >= 0
        xc = x0 + h * rng.uniform(0.05, 3.0, n)
        yc = _call(func, xc, phi)
        if yc.shape != y0.shape:
            raise MechanismError(f"func returned shape {yc.shape} at another x (was {y0.shape})")
        dev = float(np.max(np.abs(yc - amap(xc)))) / max(scale, float(np.max(np.abs(yc))))
        worst = max(worst, dev)
    if not np.isfinite(worst) or worst > rtol:
        raise MechanismError(
            f"func is not affine in x: it deviates from its affine map by {worst:.3g} "
            f"(relative; tolerance {rtol:g}) at test points forward of x0"
        )
    return amap


# ------------------------------------------------------------------------------ result
@dataclass(frozen=True)
class ConvexResult:
    """The outcome of :func:`minimax_affine` / :func:`minimax_cycle`.

    Attributes
    ----------
    x : the optimal decision vector (NaN-free; None when the solver returned none).
    variables : ``{name: value}``.
    value : the peak ``max_i |A_i x + b_i|`` recomputed from ``x`` on the solver's rows (for
        :func:`minimax_cycle`: the certified true peak over the continuous crank angle).
    status : one of :data:`mechsynth.synthesis.STATUSES`; ``success`` only for "optimal".
    message : one line.
    solve_time : wall-clock seconds (problem build + solve, all rounds).
    norm : "abs", "max" or "euclidean"; ``kind`` "LP" or "SOCP".
    per_angle : the per-row magnitude at ``x`` (what the peak is taken over).
    active : row indices where the peak is attained (within ``1e-6`` relative).
    active_angles : their crank angles (rad) when the rows are angles, else None.
    phi : the rows' crank angles (rad) or None.
    solver : the cvxpy solver used; ``solver_status`` its raw status.
    extra : further information (refinement rounds and angles for :func:`minimax_cycle`).
    """

    x: np.ndarray | None
    variables: dict[str, float]
    value: float
    status: str
    success: bool
    message: str
    solve_time: float
    norm: str
    kind: str
    per_angle: np.ndarray | None
    active: np.ndarray
    active_angles: np.ndarray | None
    phi: np.ndarray | None
    solver: str
    solver_status: str
    extra: dict[str, Any] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict (``mechsynth.jsonutil.dumps``)."""
        return dict(
            variables=self.variables,
            value=self.value,
            status=self.status,
            success=self.success,
            message=self.message,
            solve_time=self.solve_time,
            norm=self.norm,
            kind=self.kind,
            active_angles_deg=(
                None if self.active_angles is None else np.rad2deg(self.active_angles)
            ),
            solver=self.solver,
            solver_status=self.solver_status,
            **{k: v for k, v in self.extra.items() if k != "map"},
        )

    def report(self) -> str:
        """Plain-text report."""
        lines = [
            f"status: {self.status} ({'success' if self.success else 'FAILED'}) - {self.message}",
            f"minimax ({self.kind}, norm {self.norm}): peak = {self.value:.10g}",
        ]
        for k, v in self.variables.items():
            lines.append(f"  {k:>14s} = {v:.10g}")
        if self.active_angles is not None and self.active_angles.size:
            deg = ", ".join(f"{a:.3f}" for a in np.rad2deg(self.active_angles[:12]))
            more = (
                f" and {self.active_angles.size - 12} more" if self.active_angles.size > 12 else ""
            )
            lines.append(f"peak attained at crank angles (deg): {deg}{more}")
        lines.append(f"solver {self.solver} ({self.solver_status}); {self.solve_time * 1e3:.1f} ms")
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.report()

    def plot(self, ax=None, reference=None, label="peak quantity", unit=""):
        """The per-angle magnitude at the optimum over the crank angle, its peak level and the
        active angles; ``reference`` (an array over the same rows, e.g. the magnitude before
        optimization) is drawn for comparison. Returns the matplotlib figure."""
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        if self.per_angle is None:
            raise MechanismError(f"nothing to plot (status {self.status})")
        fig = ax.figure if ax is not None else plt.figure(figsize=(7, 3.8))
        ax = ax if ax is not None else fig.add_subplot()
        if self.phi is not None:
            order = np.argsort(self.phi)
            xs, xlabel = np.rad2deg(self.phi[order]), "crank angle, deg"
        else:
            order = np.arange(self.per_angle.size)
            xs, xlabel = order, "row"
        u = f", {unit}" if unit else ""
        if reference is not None:
            ax.plot(xs, np.asarray(reference)[order], color="0.6", lw=1.2, label="reference")
        ax.plot(xs, self.per_angle[order], color="C0", lw=1.6, label="optimum")
        ax.axhline(self.value, color="C3", lw=0.9, ls="--", label=f"peak {self.value:.5g}")
        if self.active_angles is not None:
            for a in self.active_angles:
                ax.axvline(np.rad2deg(a), color="C3", lw=0.6, ls=":")
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"{label}{u}")
        ax.grid(True, alpha=0.4)
        ax.legend(loc="best", fontsize=8)
        ax.set_title(f"minimax {self.kind}: status {self.status}", fontsize=10)
        return fig


_CVXPY_STATUS = {
    "optimal": "optimal",
    "optimal_inaccurate": "uncertified",
    "infeasible": "infeasible",
    "infeasible_inaccurate": "infeasible",
    "unbounded": "solver_failed",
    "unbounded_inaccurate": "solver_failed",
    "infeasible_or_unbounded": "infeasible",
    "user_limit": "max_iterations",
    "solver_error": "solver_failed",
}


def _magnitude(y, norm):
    if norm == "euclidean":
        return np.sqrt(np.sum(y * y, axis=-1)) if y.ndim == 2 else np.abs(y)
    if norm == "abs":
        return np.max(np.abs(y), axis=-1) if y.ndim == 2 else np.abs(y)
    return np.max(y, axis=-1) if y.ndim == 2 else y


def _bounds(bounds, n):
    lo, hi = np.full(n, -np.inf), np.full(n, np.inf)
    if bounds is None:
        return lo, hi
    bounds = list(bounds)
    if len(bounds) != n:
        raise MechanismError(f"bounds: need {n} (lower, upper) pairs, got {len(bounds)}")
    for j, pair in enumerate(bounds):
        try:
            a, b = pair
        except (TypeError, ValueError) as exc:
            raise MechanismError(f"bounds[{j}] must be (lower, upper), got {pair!r}") from exc
        lo[j] = -np.inf if a is None else float(a)
        hi[j] = np.inf if b is None else float(b)
        if np.isnan(lo[j]) or np.isnan(hi[j]) or lo[j] > hi[j]:
            raise MechanismError(f"bounds[{j}]: need lower <= upper, got ({a}, {b})")
    return lo, hi


def _linear(Am, bm, n, what):
    if Am is None:
        return None
    Am = np.atleast_2d(np.asarray(Am, dtype=float))
    bm = np.atleast_1d(np.asarray(bm, dtype=float))
    if Am.shape[1] != n or bm.shape != (Am.shape[0],):
        raise MechanismError(f"{what}: need A of shape (k, {n}) and b of shape (k,)")
    if not (np.all(np.isfinite(Am)) and np.all(np.isfinite(bm))):
        raise MechanismError(f"{what} must be finite")
    return Am, bm


def minimax_affine(
    A,
    b=None,
    *,
    angles=None,
    norm: str = "abs",
    bounds: Sequence[tuple[float | None, float | None]] | None = None,
    A_ub=None,
    b_ub=None,
    A_eq=None,
    b_eq=None,
    constraints: Callable[[Any], list] | None = None,
    names: Sequence[str] | None = None,
    solver: str | None = None,
    solver_options: dict | None = None,
    active_rtol: float = 1e-6,
) -> ConvexResult:
    """Minimize over ``x`` the peak over the rows (crank angles) of ``A x + b``.

    Parameters
    ----------
    A, b : an :class:`AffineMap` (then ``b`` and ``angles`` come from it), or arrays of shape
        ``(m, n)`` and ``(m,)`` (a scalar per angle) or ``(m, d, n)`` and ``(m, d)`` (a
        ``d``-vector per angle, e.g. a planar reaction force).
    angles : crank angles (rad) of the ``m`` rows, for reporting the active angles.
    norm : ``"abs"`` -- ``max_i |y_i|`` (for vectors: the largest absolute component), an LP;
        ``"max"`` -- ``max_i y_i`` (signed; for vectors the largest component), an LP;
        ``"euclidean"`` -- ``max_i ||y_i||_2`` of vectors, an SOCP.
    bounds : ``(lower, upper)`` per variable; None for an open side.
    A_ub, b_ub, A_eq, b_eq : linear constraints ``A_ub x <= b_ub``, ``A_eq x == b_eq``.
    constraints : optional ``fn(x) -> list of cvxpy constraints`` on the cvxpy expression ``x``
        (the decision vector in its own units) for anything else convex.
    names : variable names for the result (default ``x0, x1, ...``).
    solver, solver_options : a cvxpy solver name (default Clarabel; e.g. "HIGHS" for a simplex
        vertex solution of an LP) and its options.
    active_rtol : rows within this fraction of the peak are reported as active.

    Returns
    -------
    ConvexResult
        The peak ``value`` is recomputed from ``x``; failures and infeasibility are in
        ``status``/``success``, never raised.

    Notes
    -----
    Variables are scaled so that every column of ``A`` has unit maximum and the peak is of
    order one, which keeps the conic solvers' tolerances meaningful for forces in kN and masses
    in kg alike.
    """
    import cvxpy as cp

    t0 = time.perf_counter()
    if isinstance(A, AffineMap):
        amap = A
        if b is not None:
            raise MechanismError("give either an AffineMap or arrays A and b, not both")
        angles = amap.phi if angles is None else angles
    else:
        if b is None:
            raise MechanismError("b is required with an array A")
        amap = AffineMap(A, b)
    if norm not in NORMS:
        raise MechanismError(f"norm must be one of {', '.join(NORMS)}, got {norm!r}")
    if norm == "euclidean" and not amap.is_vector:
        raise MechanismError("norm='euclidean' needs vector rows: A of shape (m, d, n), b (m, d)")
    Amat, bvec = amap.A, amap.b
    m, n = Amat.shape[0], amap.n
    phi = None if angles is None else np.asarray(angles, dtype=float).ravel()
    if phi is not None and phi.size != m:
        raise MechanismError(f"angles has {phi.size} entries for {m} rows")
    names = [f"x{j}" for j in range(n)] if names is None else [str(s) for s in names]
    if len(names) != n:
        raise MechanismError(f"names: need {n} names, got {len(names)}")
    lo, hi = _bounds(bounds, n)
    ub = _linear(A_ub, b_ub, n, "A_ub, b_ub")
    eq = _linear(A_eq, b_eq, n, "A_eq, b_eq")

    # scaling: x = D z with D_j = s / c_j, so that A D / s has unit column maxima
    s = float(np.max(np.abs(bvec))) or 1.0
    c = np.max(np.abs(Amat.reshape(-1, n)), axis=0)
    c = np.where(c > 0, c, 1.0)
    D = s / c
    Ah = Amat / c  # = A D / s
    bh = bvec / s

    z = cp.Variable(n)
    t = cp.Variable()
    x_expr = cp.multiply(D, z)
    cons = []
    if amap.is_vector:
        d = Amat.shape[1]
        Y = [Ah[:, k, :] @ z + bh[:, k] for k in range(d)]
        if norm == "euclidean":
            cons.append(cp.SOC(t * np.ones(m), cp.vstack(Y), axis=0))
        else:
            for y in Y:
                cons.append(y <= t)
                if norm == "abs":
                    cons.append(-y <= t)
    else:
        y = Ah @ z + bh
        cons.append(y <= t)
        if norm == "abs":
            cons.append(-y <= t)
    fin_lo, fin_hi = np.isfinite(lo), np.isfinite(hi)
    if fin_lo.any():
        cons.append(z[np.flatnonzero(fin_lo)] >= lo[fin_lo] / D[fin_lo])
    if fin_hi.any():
        cons.append(z[np.flatnonzero(fin_hi)] <= hi[fin_hi] / D[fin_hi])
    if ub is not None:
        Au, bu = ub
        r = np.maximum(np.max(np.abs(Au * D), axis=1), 1e-300)
        cons.append(((Au * D) / r[:, None]) @ z <= bu / r)
    if eq is not None:
        Ae, be = eq
        r = np.maximum(np.max(np.abs(Ae * D), axis=1), 1e-300)
        cons.append(((Ae * D) / r[:, None]) @ z == be / r)
    if constraints is not None:
        cons.extend(constraints(x_expr))
    kind = "SOCP" if norm == "euclidean" else "LP"
    if solver is None:
        # the interior-point Clarabel is several times faster than HiGHS' simplex on these
        # tall problems (thousands of angle rows, a few variables)
        solver = "CLARABEL"
    prob = cp.Problem(cp.Minimize(t), cons)
    raw, failure = "solver_error", ""
    try:
        with warnings.catch_warnings():  # an inaccurate solution is reported in the status
            warnings.simplefilter("ignore", UserWarning)
            prob.solve(solver=solver, **(solver_options or {}))
        raw = str(prob.status)
    except cp.error.SolverError as exc:
        raw, failure = "solver_error", f"solver {solver} failed: {exc}"
    status = _CVXPY_STATUS.get(raw, "solver_failed")
    zval = None if z.value is None else np.asarray(z.value, dtype=float)
    x = None
    if zval is not None and np.all(np.isfinite(zval)) and status in ("optimal", "uncertified"):
        x = D * zval
        # an interior-point solution may sit outside a bound by the solver tolerance: put it
        # on the bound (only then; a larger violation is left visible)
        slack = 1e-7 * np.maximum(1.0, np.maximum(np.abs(lo), np.abs(hi)))
        x = np.where((x < lo) & (x >= lo - slack), lo, x)
        x = np.where((x > hi) & (x <= hi + slack), hi, x)
    per, value, active, active_angles = None, float("nan"), np.array([], dtype=int), None
    if x is not None:
        per = _magnitude(amap(x), norm)
        value = float(np.max(per))
        tol = active_rtol * max(abs(value), float(np.max(np.abs(per))), 1e-300)
        active = np.flatnonzero(per >= value - tol)
        active_angles = None if phi is None else phi[active]
    if status == "optimal":
        message = f"global optimum of the {kind} ({m} rows, {n} variables)"
    elif status == "uncertified":
        message = f"solver reports an inaccurate solution ({raw})"
    elif status == "infeasible":
        message = "infeasible: the bounds and constraints admit no x"
    elif raw.startswith("unbounded"):
        message = "unbounded: the peak can decrease without limit; bound the variables"
    elif failure:
        message = failure
    else:
        message = f"solver status {raw}"
    return ConvexResult(
        x=x,
        variables={} if x is None else dict(zip(names, map(float, x))),
        value=value,
        status=status,
        success=status == "optimal",
        message=message,
        solve_time=time.perf_counter() - t0,
        norm=norm,
        kind=kind,
        per_angle=per,
        active=active,
        active_angles=active_angles,
        phi=phi,
        solver=solver,
        solver_status=raw,
    )


# ------------------------------------------------------------------------------ certified
def _true_peak(func, x, norm, n_dense, top_window=1e-3, max_candidates=8):
    """True peak over the continuous crank angle of ``|func(x, phi)|`` at fixed ``x``: dense
    evaluation, then a bounded 1-D search around each local maximum near the top."""
    from scipy.optimize import minimize_scalar

    phi = cycle(n_dense)
    h = 2.0 * np.pi / n_dense
    mag = _magnitude(_call(func, x, phi), norm)
    left, right = np.roll(mag, 1), np.roll(mag, -1)
    rng = float(np.max(mag) - np.min(mag)) or 1.0
    cand = np.flatnonzero((mag >= left) & (mag >= right) & (mag >= mag.max() - top_window * rng))
    cand = cand[np.argsort(-mag[cand])][:max_candidates]
    found = []
    for i in cand:
        res = minimize_scalar(
            lambda p: -float(_magnitude(_call(func, x, np.array([p])), norm)[0]),
            bounds=(phi[i] - h, phi[i] + h),
            method="bounded",
            options={"xatol": 1e-11},
        )
        p, v = float(res.x), -float(res.fun)
        if v < mag[i]:
            p, v = float(phi[i]), float(mag[i])
        found.append((np.mod(p, 2.0 * np.pi), v))
    peak = max(v for _, v in found)
    return peak, found


def minimax_cycle(
    func: Callable[[np.ndarray, np.ndarray], Any],
    x0,
    angles=360,
    *,
    norm: str = "abs",
    rtol: float = 1e-9,
    max_rounds: int = 8,
    n_dense: int = 4096,
    **kwargs,
) -> ConvexResult:
    """Certified ``min_x max_phi |func(x, phi)|`` over the continuous crank angle, for ``func``
    affine in ``x``.

    The affine map is built on ``angles`` (:func:`affine_map`) and solved
    (:func:`minimax_affine`, further keyword arguments such as ``bounds`` go there). The grid
    optimum is a lower bound of the continuous one; the true peak at the grid optimum (dense
    evaluation on ``n_dense`` angles and a 1-D search) is an upper bound. Where the grid missed
    the true peak by more than ``rtol`` (relative), those angles are added and the problem is
    solved again, until both bounds agree. ``value`` is the certified true peak;
    ``extra`` holds ``rounds``, ``refined_angles``, ``grid_value`` and ``certified``.
    Status "uncertified" if the rounds run out.
    """
    t0 = time.perf_counter()
    amap = affine_map(func, x0, angles)
    extra_angles: list[float] = []
    rounds = 0
    while True:
        res = minimax_affine(amap, norm=norm, **kwargs)
        if res.x is None:
            return res
        peak, found = _true_peak(func, res.x, norm, n_dense)
        grid_value = res.value
        certified = peak <= grid_value * (1.0 + rtol) + 1e-300
        if certified or rounds >= max_rounds:
            break
        new = [p for p, v in found if v > grid_value * (1.0 + rtol)]
        new = [p for p in new if np.min(np.abs(np.angle(np.exp(1j * (amap.phi - p))))) > 1e-12]
        if not new:
            break
        amap = amap.concat(affine_map(func, res.x, np.array(new)))
        extra_angles.extend(new)
        rounds += 1
    status = res.status
    message = res.message
    if status == "optimal" and not certified:
        status = "uncertified"
        message = (
            f"grid peak {grid_value:.10g} below the true peak {peak:.10g} after {rounds} rounds"
        )
    elif status == "optimal":
        message += f"; certified over the continuous crank angle ({rounds} refinement rounds)"
    return ConvexResult(
        **{
            **res.__dict__,
            "value": float(max(peak, grid_value)),
            "status": status,
            "success": status == "optimal",
            "message": message,
            "solve_time": time.perf_counter() - t0,
            "extra": dict(
                rounds=rounds,
                refined_angles=np.array(extra_angles),
                grid_value=grid_value,
                true_peak=peak,
                certified=bool(certified),
                grid_angles=int(amap.phi.size),
            ),
        }
    )
