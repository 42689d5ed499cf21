"""From a :class:`~mechsynth.synthesis.Problem` to a smooth nonlinear program on a crank-angle grid.

A measure expression (a :class:`~mechsynth.objectives.Combination` or a single measure) is
flattened into ``constant + sum(weight * atom)``. Atoms are

* ``peak``   -- a ``max``/``min`` :class:`~mechsynth.objectives.CycleMeasure`: a maximum over the
  crank-angle grid and the measure's smooth branches;
* ``scalar`` -- a closed-form :class:`~mechsynth.objectives.ScalarMeasure` (possibly a max over
  smooth branches, like the time ratio);
* ``average``-- a ``mean``/``rms`` cycle measure, a quadrature over the uniform base grid;
* ``opaque`` -- any other measure, evaluated symbolically through ``from_motion``.

A peak that the problem bounds from above (a minimized peak, ``peak <= bound``) becomes an
epigraph: a variable ``t`` with ``branch(phi_i) <= t`` at every grid angle -- smooth, and exact
on the grid. A peak on the other side (maximized, ``>=``, ``==``) uses the grid maximum
directly; its derivative is the derivative at the grid's arg-max, which is the true derivative
(Danskin) once certification has put the true arg-max into the grid.

The grid is ``N`` uniform base angles plus ``K`` slots for refinement angles. The angles are
*parameters* of the CasADi function, so refining the grid does not rebuild the solver; the
epigraph rows of the slots not yet used are left unbounded (:meth:`Transcription.g_bounds`).

Build once, solve many: the expression graph and its solvers belong to the problem's
*structure* (:func:`structure_key`: the mechanism, the variables' names, the fixed values, the
speed, the grid's size, the objective and the constraints' measures and comparisons), not to
one :class:`~mechsynth.synthesis.Problem`. The variables' bounds, the constraints' bounds (a
Pareto front's epsilon levels), the grid angles and the scales are parameters of the program,
so every start, refinement and Pareto point of one structure reuses one built solver. The
structures live in a small least-recently-used cache (:data:`CACHE_SIZE` of them), which keeps
memory flat across a front; :func:`cache_info` counts the builds.
"""

from __future__ import annotations

import weakref
from collections import OrderedDict
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import MechanismError, SolverError
from ..objectives.base import Combination, CycleMeasure, Measure, ScalarMeasure

__all__ = [
    "Atom",
    "LinearForm",
    "flatten",
    "NumericForms",
    "Transcription",
    "structure_key",
    "cache_info",
    "clear_cache",
]


@dataclass(frozen=True, eq=False)
class Atom:
    """One measure inside an objective or constraint (see the module notes)."""

    kind: str  # "peak", "scalar", "average", "opaque"
    measure: Measure

    @property
    def sign(self) -> float:
        """+1 when the atom is a max over its branches, -1 when it is a min."""
        m = self.measure
        return -1.0 if isinstance(m, CycleMeasure) and m.reduce == "min" else 1.0

    @property
    def sqrt(self) -> bool:
        return isinstance(self.measure, CycleMeasure) and self.measure.outer == "sqrt"

    @property
    def is_max_type(self) -> bool:
        """Value is (sign times) a maximum of smooth branches -> may use an epigraph."""
        if self.kind == "peak":
            return True
        return self.kind == "scalar" and self.measure.has_branches

    # numeric ------------------------------------------------------------------------
    def q(self, mechanism, motion):
        """Stacked per-angle branches ``q`` with ``value = sign * g(max q)`` (numpy:
        shape (n_branches, ..., n_angles))."""
        b = [np.asarray(x, dtype=float) for x in self.measure.branches(mechanism, motion)]
        shape = np.broadcast_shapes(np.shape(motion.phi), *(x.shape for x in b))
        return np.stack([self.sign * np.broadcast_to(x, shape) for x in b])

    def from_peak(self, peak):
        """The measure's value from ``max q``."""
        return self.sign * (np.sqrt(np.maximum(peak, 0.0)) if self.sqrt else peak)


@dataclass(frozen=True, eq=False)
class LinearForm:
    """``constant + sum(weight * atom)``; ``name`` for reports."""

    name: str
    terms: tuple[tuple[float, Atom], ...]
    constant: float
    unit: str = ""


def _atom(measure: Measure) -> Atom:
    if isinstance(measure, CycleMeasure):
        return Atom("peak" if measure.is_peak else "average", measure)
    if isinstance(measure, ScalarMeasure):
        return Atom("scalar", measure)
    return Atom("opaque", measure)


def flatten(measure: Measure, mechanism_class) -> LinearForm:
    """Bind ``measure`` to the mechanism class and flatten it into a :class:`LinearForm`."""
    if not isinstance(measure, Measure):
        raise TypeError(f"expected a Measure, got {type(measure).__name__}: {measure!r}")
    bound = measure.bind(mechanism_class)
    terms: list[tuple[float, Atom]] = []
    constant = 0.0

    def walk(m, w):
        nonlocal constant
        if isinstance(m, Combination):
            constant += w * m.constant
            for wi, mi in m.terms:
                walk(mi.bind(mechanism_class), w * wi)
        else:
            terms.append((w, _atom(m)))

    walk(bound, 1.0)
    return LinearForm(measure.name, tuple(terms), constant, getattr(measure, "unit", ""))


# ---------------------------------------------------------------------------------- numeric
def design_params(problem, values) -> dict[str, Any]:
    """Mechanism keyword arguments from variable values (a sequence in ``problem.names`` order;
    arrays give a batch)."""
    params = dict(problem.fixed)
    for name, v in zip(problem.names, values):
        params[name] = v
    return params


def evaluate_form(form: LinearForm, mechanism, motion, peaks: dict | None = None):
    """Numeric value of ``form``. ``peaks`` maps an atom to a known ``max q`` (e.g. the certified
    true peak); otherwise the maximum over ``motion``'s angles is used. Averages use ``motion``
    (give a uniform grid)."""
    total = form.constant
    for w, atom in form.terms:
        if atom.kind == "peak":
            if peaks is not None and atom in peaks:
                peak = peaks[atom]
            else:
                peak = np.max(atom.q(mechanism, motion), axis=0).max(axis=-1)
            value = atom.from_peak(peak)
        elif atom.kind == "scalar":
            value = atom.measure.fn(mechanism)
        else:
            value = atom.measure.from_motion(mechanism, motion)
        total = total + w * value
    return total


class NumericForms:
    """The numeric side of a problem: flattened objective and constraints and the scaling of the
    variables to their box, without CasADi. Differential evolution and the checks of a design
    use it, so measures that only evaluate with numpy (non-smooth ones such as the dwell
    metrics) can still be optimized by ``method="de"``.

    Attributes
    ----------
    n : number of variables; ``lo``, ``hi`` their bounds.
    objective : :class:`LinearForm` of the objective; ``constraints`` one per constraint.
    """

    def __init__(self, problem):
        self.problem = problem
        self.cls = problem.mechanism
        self.n = len(problem.names)
        self.n_base = len(problem.base_angles)
        self.objective = flatten(problem.objective, self.cls)
        self.constraints = [flatten(c.measure, self.cls) for c in problem.constraints]
        self.lo = np.array([problem.variables[k][0] for k in problem.names], dtype=float)
        self.hi = np.array([problem.variables[k][1] for k in problem.names], dtype=float)

    def params_of(self, z):
        return self.lo + (self.hi - self.lo) * np.asarray(z, dtype=float)

    def z_of(self, values):
        span = np.where(self.hi > self.lo, self.hi - self.lo, 1.0)
        return (np.asarray(values, dtype=float) - self.lo) / span


# ---------------------------------------------------------------------------------- symbolic
@dataclass
class _Epigraph:
    atom: Atom
    rows: Any  # SX column of q/T - tau


#: problem structures (expression graph and built solvers) kept for reuse, least recently used
#: dropped first. A Pareto front uses three (each anchor's objective, the epsilon points) plus
#: their refined grids
CACHE_SIZE = 4
#: and at most this many instructions of built IPOPT Hessians among them (the newest structure
#: is always kept): memory follows them, some 120 bytes each (the impact machine's program on
#: 64 angles: 0.9 million, 110 MB; on 112 angles after refinement some 1.6 million)
CACHE_INSTRUCTIONS = 3_000_000
_STRUCTURES: OrderedDict = OrderedDict()
_COUNTS = {"structures": 0, "solvers": 0, "variants": 0, "hits": 0}


def _value_key(v):
    """A fixed parameter's value in a cache key: the number, else the object's identity."""
    try:
        return ("v", float(v))
    except (TypeError, ValueError):
        return ("id", id(v))


def structure_key(problem, n_extra: int = 16) -> tuple:
    """What the symbolic program of ``problem`` depends on, as a hashable key: the mechanism,
    the variables' names, the fixed parameters' values, the speed, the base grid's size, the
    feasibility margin, the sense, the objective's and each constraint's measure (by identity)
    and comparison, and the ``n_extra`` refinement slots. The variables' and the constraints'
    bounds, the grid's angles and the scales are not in it: they are parameters of the
    program."""
    cons = []
    for c in problem.constraints:
        floor = getattr(c.measure, "floor", None)
        on_floor = (
            c.op == "=="
            and floor is not None
            and abs(c.bound - floor) <= 1e-12 * max(1.0, abs(floor))
        )
        cons.append((id(c.measure), c.op, bool(on_floor)))
    return (
        id(problem.mechanism),
        tuple(problem.names),
        tuple(sorted((k, _value_key(v)) for k, v in problem.fixed.items())),
        None if problem.speed is None else float(problem.speed),
        len(problem.base_angles),
        float(problem.feasibility_margin),
        problem.sense,
        id(problem.objective),
        tuple(cons),
        int(n_extra),
    )


def cache_info() -> dict[str, int]:
    """Counts since the start (or :func:`clear_cache`): ``structures`` (expression graphs
    built), ``solvers`` (IPOPT solvers and CasADi functions built with their derivatives),
    ``variants`` (IPOPT solvers for another options set, e.g. a warm start's, built on the
    derivatives of the structure's first), ``hits`` (transcriptions served from the cache)
    and ``cached`` (structures held now)."""
    return {**_COUNTS, "cached": len(_STRUCTURES)}


def clear_cache() -> None:
    """Drop every cached structure and reset the counts of :func:`cache_info`."""
    _STRUCTURES.clear()
    _COUNTS.update(structures=0, solvers=0, variants=0, hits=0)


def _structure(problem, n_extra: int) -> _Structure:
    key = structure_key(problem, n_extra)
    entry = _STRUCTURES.get(key)
    if entry is not None:
        _STRUCTURES.move_to_end(key)
        _COUNTS["hits"] += 1
        return entry
    entry = _Structure(problem, n_extra)
    _COUNTS["structures"] += 1
    _STRUCTURES[key] = entry
    _trim_cache()
    return entry


def _trim_cache() -> None:
    """Drop the least recently used structures beyond :data:`CACHE_SIZE` or
    :data:`CACHE_INSTRUCTIONS`, never the newest nor one a live :class:`Transcription` uses
    (a solve in progress holds it: dropping it would free nothing and build it again)."""
    count = len(_STRUCTURES)
    weight = sum(e.weight for e in _STRUCTURES.values())
    dropped = False
    for key in list(_STRUCTURES)[:-1]:
        if count <= CACHE_SIZE and weight <= CACHE_INSTRUCTIONS:
            break
        entry = _STRUCTURES[key]
        if len(entry.views):
            continue
        del _STRUCTURES[key]
        count, weight, dropped = count - 1, weight - entry.weight, True
    if dropped:
        _release_memory()


def _release_memory() -> None:
    """Give the memory of dropped structures back to the system (glibc keeps freed small
    blocks, the expression nodes, in its heap; the resident size would stay at its peak)."""
    import ctypes
    import gc

    gc.collect()
    try:
        ctypes.CDLL("libc.so.6").malloc_trim(0)
    except (OSError, AttributeError):  # not glibc: the allocator keeps its own policy
        pass


class _Structure:
    """The smooth NLP of one problem structure over ``n_base + n_extra`` grid angles, and its
    built solvers (see :class:`Transcription` for the vectors). Holds the measures and the
    mechanism its key names by identity, so those identities stay unique while it lives."""

    def __init__(self, problem, n_extra: int):
        import casadi as ca

        forms = NumericForms(problem)
        # what the key names by identity, held so no other object takes an identity while it lives
        self.keep = (
            problem.mechanism,
            problem.objective,
            [c.measure for c in problem.constraints],
            dict(problem.fixed),
        )
        self.objective, self.constraints = forms.objective, forms.constraints
        n, n_base = forms.n, forms.n_base
        self.n_extra = int(n_extra)
        cls = problem.mechanism
        n_user = len(problem.constraints)

        z = ca.SX.sym("z", n)
        phi = ca.SX.sym("phi", n_base + self.n_extra)
        f_scale = ca.SX.sym("f_scale")
        lo, hi = ca.SX.sym("lo", n), ca.SX.sym("hi", n)
        bounds = ca.SX.sym("bound", n_user)
        params = design_params(problem, [lo[i] + (hi[i] - lo[i]) * z[i] for i in range(n)])
        try:
            mech = cls(**params)
            motion = mech.motion(phi, speed=problem.speed)
        except Exception as exc:  # a model not written with ops
            raise SolverError(
                f"{getattr(cls, '__name__', type(cls).__name__)} cannot be evaluated with "
                f"CasADi symbols ({exc}); use method='de'"
            ) from exc

        epis: list[_Epigraph] = []
        taus: list[Any] = []
        t_scales: list[Any] = []
        sqrt_tau: list[bool] = []

        def column(x):
            x = ca.SX(x) if not isinstance(x, ca.SX) else x
            if x.numel() == 1:
                x = ca.repmat(x, phi.numel(), 1)
            return x

        def atom_q(atom: Atom):
            if atom.kind == "peak":
                return ca.vertcat(
                    *[atom.sign * column(b) for b in atom.measure.branches(mech, motion)]
                )
            return ca.vertcat(*[ca.SX(b) for b in atom.measure.branches(mech)])

        def atom_value(atom: Atom, orientation: float):
            """Symbolic value; an epigraph when ``orientation`` (+1: upper-bounded) agrees."""
            if atom.kind in ("peak", "scalar") and atom.is_max_type:
                q = atom_q(atom)
                if orientation * atom.sign > 0:
                    tau = ca.SX.sym(f"tau{len(taus)}")
                    T = ca.SX.sym(f"T{len(taus)}")
                    taus.append(tau)
                    t_scales.append(T)
                    sqrt_tau.append(atom.sqrt)
                    epis.append(_Epigraph(atom, q / T - tau))
                    peak = T * tau
                else:
                    peak = ca.mmax(q)
                if atom.sqrt:
                    return atom.sign * ca.sqrt(ca.fmax(peak, 1e-300))
                return atom.sign * peak
            if atom.kind == "scalar":
                return atom.measure.fn(mech)
            if atom.kind == "average":
                samples = column(atom.measure.samples(mech, motion))[:n_base]
                from ..objectives.base import reduce_cycle

                return reduce_cycle(samples, atom.measure.reduce)
            try:
                return atom.measure.from_motion(mech, motion)
            except Exception as exc:
                raise SolverError(
                    f"measure {atom.measure.name!r} cannot be evaluated with CasADi symbols "
                    f"({exc}); use method='de'"
                ) from exc

        def form_value(form: LinearForm, orientation: float):
            total = form.constant
            for w, atom in form.terms:
                total = total + w * atom_value(atom, orientation * np.sign(w))
            return total

        sense = 1.0 if problem.sense == "min" else -1.0
        f = sense * form_value(self.objective, sense) / f_scale

        g_rows, lbg, ubg, kinds = [], [], [], []
        g_scales = []
        for i, (c, form) in enumerate(zip(problem.constraints, self.constraints)):
            gs = ca.SX.sym(f"g_scale{i}")
            g_scales.append(gs)
            floor_form = Transcription._floor_equality(c, form)
            if floor_form is not None:
                q = atom_q(floor_form)
                rows = (q - bounds[i]) * gs
                g_rows.append(rows)
                lbg += [-np.inf] * rows.numel()
                ubg += [0.0] * rows.numel()
                kinds += [("user", i)] * rows.numel()
                continue
            orientation = {"<=": 1.0, ">=": -1.0, "==": 0.0}[c.op]
            v = form_value(form, orientation)
            g_rows.append((v - bounds[i]) * gs)
            lbg.append(0.0 if c.op in (">=", "==") else -np.inf)
            ubg.append(0.0 if c.op in ("<=", "==") else np.inf)
            kinds.append(("user", i))
        slots = [np.full(len(lbg), -1)]  # grid slot of each row (-1: not a per-angle row)
        for k, e in enumerate(epis):
            g_rows.append(e.rows)
            lbg += [-np.inf] * e.rows.numel()
            ubg += [0.0] * e.rows.numel()
            kinds += [("epigraph", k)] * e.rows.numel()
            rows = np.arange(e.rows.numel())
            slots.append(rows % phi.numel() if e.atom.kind == "peak" else np.full(rows.size, -1))
        hook = getattr(cls, "feasibility_constraints", None)
        self.feasibility_names: list[str] = []
        if hook is not None:
            for name, expr in hook(params, margin=problem.feasibility_margin):
                g_rows.append(ca.SX(expr))
                lbg.append(0.0)
                ubg.append(np.inf)
                kinds.append(("feasibility", name))
                self.feasibility_names.append(name)

        self.epigraphs = [e.atom for e in epis]
        self.n_epi = len(taus)
        self.n_user = n_user
        self.x = ca.vertcat(z, *taus)
        self.p = ca.vertcat(phi, f_scale, *t_scales, *g_scales, lo, hi, bounds)
        self.f = f
        self.g = ca.vertcat(*g_rows) if g_rows else ca.SX(0, 1)
        self.lbg, self.ubg = np.array(lbg, dtype=float), np.array(ubg, dtype=float)
        self.g_kinds = kinds
        # the epigraph each row belongs to (-1: none)
        self.g_epigraph = np.array([k[1] if k[0] == "epigraph" else -1 for k in kinds], dtype=int)
        self.g_slots = np.concatenate(slots + [np.full(len(lbg) - sum(map(len, slots)), -1)])
        self.lbx = np.concatenate([np.zeros(n), [0.0 if s else -np.inf for s in sqrt_tau]])
        self.ubx = np.concatenate([np.ones(n), np.full(self.n_epi, np.inf)])
        self.solvers: dict[Any, Any] = {}
        self.derivatives: dict | None = None  # of the first IPOPT build, for the others
        self.weight = 0  # instructions of the built IPOPT Hessian (memory, for the cache)
        self.views: weakref.WeakSet = weakref.WeakSet()  # the live transcriptions using it

    def solver(self, method: str, options: dict | None = None):
        """The cached CasADi solver ``method`` ("ipopt"), casadi Functions ("functions": the
        objective and constraints with their derivatives) or Function ("rows": the
        constraints alone)."""
        import casadi as ca

        key = (method, tuple(sorted((options or {}).items())))
        if key in self.solvers:
            return self.solvers[key]
        if method == "ipopt":
            opts = {
                "ipopt.print_level": 0,
                "print_time": False,
                "ipopt.sb": "yes",
                "ipopt.tol": 1e-10,
                "ipopt.acceptable_tol": 1e-7,
                "ipopt.constr_viol_tol": 1e-9,
                "ipopt.max_iter": 500,
                # a peak's epigraph has one row per grid angle and branch (48 to 288 of
                # them): their barrier terms hold the epigraph variable about mu times the
                # row count above the peak (scaled to 1). The adaptive rule raised mu to
                # 0.1-0.2 early on, the epigraph variables went tens of peaks high and the
                # solves wandered (the crank-rocker example: 14-57 iterations a start,
                # 16-20 with the cap). Over the reference problems, the examples and the
                # impact synthesis, caps of 1e-2 to 2e-3 did best; 1e-2 and above lost the
                # impact synthesis (benchmarks/bench_synthesis.py --iterations --options)
                "ipopt.mu_strategy": "adaptive",
                "ipopt.mu_max": 5e-3,
                "ipopt.mu_init": 1e-3,  # the monotone rule's start, if options choose it
                "error_on_fail": False,
                # designs outside the assemblable region give NaN; IPOPT backtracks
                "show_eval_warnings": False,
            }
            opts.update({f"ipopt.{k}": v for k, v in (options or {}).items()})
            if "ipopt.print_level" in opts and opts["ipopt.print_level"] > 0:
                opts["ipopt.sb"] = "no"
            nlp = {"x": self.x, "p": self.p, "f": self.f, "g": self.g}
            if self.derivatives is not None:  # another options set: its derivatives reused
                opts.update(self.derivatives)
                _COUNTS["variants"] += 1
            built = ca.nlpsol("mechsynth", "ipopt", nlp, opts)
            if self.derivatives is None:
                # generating the Lagrangian's Hessian is most of a build (6 s of 7 for the
                # impact machine, and 100 MB); a warm start's options reuse it (1 s, 4 MB)
                self.derivatives = {
                    k: built.get_function(f"nlp_{v}")
                    for k, v in (("hess_lag", "hess_l"), ("jac_g", "jac_g"), ("grad_f", "grad_f"))
                }
                self.weight = int(self.derivatives["hess_lag"].n_instructions())
                _COUNTS["solvers"] += 1
                self.solvers[key] = built
                _trim_cache()
                return built
        elif method == "rows":  # g(x, p) alone: a warm start's epigraph lift
            built = ca.Function("g", [self.x, self.p], [self.g])
        elif method == "functions":
            grad = ca.gradient(self.f, self.x)
            jac = ca.jacobian(self.g, self.x)
            built = (
                ca.Function("f", [self.x, self.p], [self.f, grad]),
                ca.Function("g", [self.x, self.p], [self.g, jac]),
            )
            _COUNTS["solvers"] += 1
        else:
            raise MechanismError(f"unknown transcription solver {method!r}")
        self.solvers[key] = built
        return built


class Transcription(NumericForms):
    """The smooth NLP of a problem over ``n_base + n_extra`` grid angles: the problem's numbers
    (bounds, scales) over its structure's shared expression graph and solvers.

    Decision vector ``x = [z, tau]``: the design variables scaled to [0, 1] in their box, then
    the epigraph variables (each scaled by a parameter ``T``). Parameter vector
    ``p = [phi (n_base + n_extra), f_scale, T (n_epi), g_scale (n_user), lo (n), hi (n),
    bound (n_user)]``: the grid, the scales, the variables' bounds and the constraints' bounds.

    Attributes
    ----------
    lbx, ubx, lbg, ubg : bounds.
    g_kinds : per row of ``g``: ``("user", i)``, ``("epigraph", k)``, ``("feasibility", name)``.
    structure : the shared symbolic program (expression graph and built solvers).
    """

    def __init__(self, problem, n_extra: int = 16):
        super().__init__(problem)
        self.n_extra = int(n_extra)
        s = _structure(problem, self.n_extra)
        self.structure = s
        s.views.add(self)
        # the structure's forms, so its epigraph atoms are this transcription's atoms
        self.objective, self.constraints = s.objective, s.constraints
        for name in (
            "epigraphs", "n_epi", "n_user", "x", "p", "f", "g", "lbg", "ubg", "g_kinds",
            "g_epigraph", "g_slots", "lbx", "ubx", "feasibility_names",
        ):  # fmt: skip
            setattr(self, name, getattr(s, name))
        self._bounds = np.array([c.bound for c in problem.constraints], dtype=float)

    @staticmethod
    def _floor_equality(c, form: LinearForm):
        """The atom of ``measure == floor`` for a branched scalar with that floor, else None."""
        if c.op != "==" or len(form.terms) != 1 or form.constant != 0.0:
            return None
        w, atom = form.terms[0]
        m = atom.measure
        if w == 1.0 and atom.kind == "scalar" and atom.is_max_type and m.floor is not None:
            if abs(c.bound - m.floor) <= 1e-12 * max(1.0, abs(m.floor)):
                return atom
        return None

    # ----------------------------------------------------------------- numeric helpers
    def parameter_vector(self, phi_grid, f_scale, t_scales, g_scales):
        grid = np.asarray(phi_grid, dtype=float)
        full = np.empty(self.n_base + self.n_extra)
        full[: grid.size] = grid
        full[grid.size :] = grid[0]  # unused slots repeat an angle already in the grid
        return np.concatenate([full, [f_scale], t_scales, g_scales, self.lo, self.hi, self._bounds])

    def g_bounds(self, n_grid: int):
        """``(lbg, ubg)`` for a grid of ``n_grid`` angles: the epigraph rows of the unused
        refinement slots are left free. (Those slots repeat an angle of the grid; bounding their
        rows would duplicate an active constraint up to ``n_extra`` times, a degenerate program
        that IPOPT crawls through.)"""
        unused = self.g_slots >= n_grid
        lbg, ubg = self.lbg.copy(), self.ubg.copy()
        lbg[unused], ubg[unused] = -np.inf, np.inf
        return lbg, ubg

    def solver(self, method: str, options: dict | None = None):
        """The structure's CasADi solver ``method`` ("ipopt") or casadi Functions
        ("functions"), built on first use."""
        return self.structure.solver(method, options)

    def lift_epigraphs(self, x, P, n_grid: int):
        """``x`` with each epigraph variable raised to the largest of its rows on the first
        ``n_grid`` grid angles of ``P`` (the rows ``q / T - tau <= 0`` of the angles added
        since ``x`` was solved then hold at ``x``; the design is unchanged)."""
        x = np.array(x, dtype=float)
        if not self.n_epi:
            return x
        g = np.asarray(self.solver("rows")(x, P), dtype=float).ravel()
        _, ubg = self.g_bounds(n_grid)
        g = g - ubg
        for k in range(self.n_epi):
            over = g[(self.g_epigraph == k) & np.isfinite(ubg)]
            over = over[np.isfinite(over)]  # an angle where the design does not assemble: NaN
            if over.size:
                x[self.n + k] += max(0.0, float(np.max(over)))
        return x

    def row_keys(self) -> list[tuple]:
        """A key per row of ``g`` that names the same constraint in a program of another slot
        count: ``(kind, branch, grid slot)`` for a per-angle epigraph row, ``(kind, ordinal,
        -1)`` for the others (the refinement slots follow the base angles, so a slot's index is
        the same in every program of the structure)."""
        n_phi = self.n_base + self.n_extra
        seen: dict = {}
        keys = []
        for kind, slot in zip(self.g_kinds, self.g_slots):
            j = seen.get(kind, 0)
            seen[kind] = j + 1
            keys.append((kind, j // n_phi, int(slot)) if slot >= 0 else (kind, j, -1))
        return keys

    def carry(self, lam, other: Transcription):
        """Multipliers ``(lam_x, lam_g)`` of a solve of ``other`` (the same problem with fewer
        refinement slots) for a warm start of this program: each row's multiplier from the
        same row of ``other``, zero for the new slots' rows."""
        lam_x, lam_g = lam
        where = {k: i for i, k in enumerate(other.row_keys())}
        out = np.zeros(self.lbg.size)
        for i, k in enumerate(self.row_keys()):
            j = where.get(k)
            if j is not None:
                out[i] = lam_g[j]
        return np.asarray(lam_x, dtype=float), out

    def merge_slots(self, lam_g, where):
        """Multipliers ``lam_g`` of this program after its refinement angles moved to other
        slots (``where[i]``: the new slot of the angle in slot ``i``; angles merged into one
        slot add their rows' multipliers, as their constraints' gradients are the same)."""
        lam_g = np.asarray(lam_g, dtype=float)
        where = np.asarray(where, dtype=int)
        out = lam_g.copy()
        e = self.g_slots - self.n_base  # refinement slot of each per-angle row
        rows = np.flatnonzero((self.g_slots >= 0) & (e >= 0) & (e < where.size))
        out[rows] = 0.0
        # a branch's rows run over the grid slots in order: slot e' is e' - e rows on
        np.add.at(out, rows + where[e[rows]] - e[rows], lam_g[rows])
        return out

    def replace_extra(self, n_extra: int) -> Transcription:
        """A new transcription with room for ``n_extra`` refinement angles."""
        return Transcription(self.problem, n_extra)
