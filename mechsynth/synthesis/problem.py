"""Optimization problems over a mechanism's parameters.

>>> import mechsynth as ms
>>> prob = ms.Problem(ms.SliderCrank,
...                   variables={"crank": (0.01, 0.2), "rod": (0.05, 1.0), "offset": (-0.1, 0.1)},
...                   speed=ms.rpm(600))
>>> _ = prob.minimize(ms.objectives.peak_acceleration("slider"))
>>> _ = prob.subject_to(ms.objectives.stroke("slider") == 0.10,
...                     ms.objectives.max_pressure_angle() <= ms.deg(30))
>>> res = prob.solve(starts=2)                                       # doctest: +SKIP

``minimize``, ``maximize`` and ``subject_to`` change the problem in place and return it (so they
chain); :meth:`Problem.copy` gives an independent copy.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Mapping

import numpy as np

from .. import validate
from ..errors import MechanismError, UsageError
from ..kinematics.mechanism import input_grid
from ..objectives.base import Constraint, Measure
from ..objectives.kinematic import assembly_margin

__all__ = ["Problem"]


def _parameters(mechanism) -> dict[str, bool]:
    """``{parameter: required}`` of a mechanism class (its dataclass fields: required when
    without a default), or of a design family such as a :class:`~mechsynth.kinematics.Linkage`
    (an instance callable with parameter values, whose ``parameters`` are all set)."""
    if isinstance(mechanism, type):
        if not dataclasses.is_dataclass(mechanism):
            raise UsageError(f"{mechanism!r} is not a mechanism class (a dataclass of parameters)")
        return {
            f.name: f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
            for f in dataclasses.fields(mechanism)
        }
    params = getattr(mechanism, "parameters", None)
    if callable(mechanism) and isinstance(params, Mapping):
        return {name: False for name in params}
    if dataclasses.is_dataclass(mechanism) and isinstance(params, tuple):
        cls = type(mechanism).__name__
        raise UsageError(
            f"Problem takes the mechanism class (ms.{cls}), not a design {mechanism!r}; vary "
            f"its parameters with variables={{name: (lower, upper)}} and keep the others with "
            f"fixed={{name: value}}"
        )
    raise UsageError(
        f"{mechanism!r} is neither a mechanism class (e.g. ms.SliderCrank) nor a Linkage"
    )


class Problem:
    """Choose a mechanism's parameters within bounds to minimize or maximize a measure subject to
    constraints.

    Parameters
    ----------
    mechanism : a mechanism class (e.g. ``ms.SliderCrank``), or a
        :class:`~mechsynth.kinematics.Linkage`: its named dimensions are the parameters, those
        not varied keep the linkage's values. A linkage's assembly is a per-angle condition:
        the problem adds ``assembly_margin(c) >= feasibility_margin`` for each of its
        conditions (certified over the continuous crank angle like every peak).
    variables : ``{name: (lower, upper)}`` in SI units (m, rad): the decision variables.
    fixed : ``{name: value}`` for the other parameters (defaults of the class apply otherwise).
    speed : crank speed (rad/s, e.g. ``ms.rpm(600)``) at which velocities and accelerations are
        measured; None measures crank-angle analogs (m/rad, m/rad^2).
    angles : the base crank-angle grid of the gradient solvers: a count of equal steps over one
        turn (default 64) or an array of angles (rad). Peaks are certified on the continuous
        angle regardless (grid refinement). For a linkage driven by a slider the grid covers its
        travel (both ends) and angles are its displacements (m); ``speed`` is then the
        slider's speed (m/s).
    feasibility_margin : relative margin of the mechanism's ``feasibility_constraints`` (full
        turn of the crank, assembly), which are added automatically.
    tol : relative constraint tolerance for success: ``violation <= tol * max(1, |bound|)``.
    slots : refinement slots of the gradient solvers' program (angles the certification may
        add to the grid). None (default): 16, then a new program of 32, 64, ... when the
        refinement needs more. A number: that many from the start, one program for the
        starts and every refinement round (multipliers carried across rounds, a refinement
        angle moved along its peak instead of a new one added beside it); grown only if the
        refinement still needs more. For problems whose program is costly to build (the
        impact machine's kinetostatics).
    """

    def __init__(
        self,
        mechanism,
        variables: Mapping[str, tuple[float, float]],
        fixed: Mapping | None = None,
        speed: float | None = None,
        angles=64,
        feasibility_margin: float = 1e-3,
        tol: float = 1e-6,
        slots: int | None = None,
    ):
        fields = _parameters(mechanism)
        kinds = {} if isinstance(mechanism, type) else getattr(mechanism, "parameter_kinds", {})
        self.mechanism = mechanism
        self.variables: dict[str, tuple[float, float]] = {}
        if not isinstance(variables, Mapping) or len(variables) == 0:
            raise MechanismError(
                "variables must name at least one parameter with its (lower, upper), got "
                f"{variables!r}"
            )
        if fixed is not None and not isinstance(fixed, Mapping):
            raise MechanismError(f"fixed must be a dict {{name: value}}, got {fixed!r}")
        for name, bounds in variables.items():
            if name not in fields:
                raise MechanismError(
                    f"{mechanism.__name__} has no parameter {name!r}; "
                    f"its parameters: {', '.join(fields)}"
                )
            if not isinstance(bounds, (list, tuple, np.ndarray)) or len(bounds) != 2:
                raise MechanismError(
                    f"variable {name!r}: bounds must be (lower, upper), got {bounds!r}"
                )
            lo = validate.number(f"variable {name!r}: lower bound", bounds[0])
            hi = validate.number(f"variable {name!r}: upper bound", bounds[1])
            if not lo < hi:
                raise MechanismError(
                    f"variable {name!r}: need finite lower < upper, got ({lo}, {hi})"
                )
            is_length = kinds.get(name) == "length" or name in getattr(
                mechanism, "length_parameters", ()
            )
            if is_length and lo <= 0.0:
                raise MechanismError(
                    f"variable {name!r} is a length: its lower bound must be positive, got {lo}"
                )
            if kinds.get(name) == "angle":
                _check_radians(f"variable {name!r}: bounds", (lo, hi))
            self.variables[name] = (lo, hi)
        self.fixed = dict(fixed or {})
        for name in self.fixed:
            if name not in fields:
                raise MechanismError(f"{mechanism.__name__} has no parameter {name!r} (in fixed)")
            if name in self.variables:
                raise MechanismError(f"{name!r} is both a variable and fixed")
        missing = [
            n
            for n, required in fields.items()
            if required and n not in self.variables and n not in self.fixed
        ]
        if missing:
            raise MechanismError(
                f"{mechanism.__name__}: give {', '.join(missing)} as variables or fixed"
            )
        if speed is not None:
            speed = validate.number("speed", speed, "rad/s")
            if speed == 0.0:
                raise MechanismError(
                    "speed must be a finite non-zero crank speed in rad/s, got 0 (None measures "
                    "crank-angle analogs)"
                )
        self.speed = speed
        if isinstance(angles, (int, float, np.integer, np.floating)):
            n = validate.integer("angles", angles, 8, validate.MAX_ANGLES)
            self.base_angles = input_grid(mechanism, n)
        else:
            a = np.ravel(validate.real("angles", angles, "rad"))
            if a.size < 8 or a.size > validate.MAX_ANGLES:
                raise MechanismError(
                    f"angles: need 8 to {validate.MAX_ANGLES} grid angles (rad), got {a.size}"
                )
            self.base_angles = a
        self.feasibility_margin = validate.nonnegative(
            "feasibility_margin", validate.number("feasibility_margin", feasibility_margin)
        )
        if self.feasibility_margin >= 1.0:
            raise MechanismError(
                f"feasibility_margin is relative: it must be below 1, got {feasibility_margin}"
            )
        self.tol = validate.positive("tol", validate.number("tol", tol))
        self.slots = None if slots is None else validate.integer("slots", slots, 1, 4096)
        self.objective: Measure | None = None
        self.sense = "min"
        self.constraints: list[Constraint] = []
        if not isinstance(mechanism, type):
            for condition in getattr(mechanism, "assembly_conditions", ()):
                self.constraints.append(assembly_margin(condition) >= self.feasibility_margin)
        self._cache: dict = {}

    @property
    def names(self) -> tuple[str, ...]:
        """Variable names, in the order of ``variables``."""
        return tuple(self.variables)

    # ------------------------------------------------------------------ building
    def minimize(self, measure: Measure) -> Problem:
        """Set the objective to minimize ``measure``; returns the problem."""
        return self._set_objective(measure, "min")

    def maximize(self, measure: Measure) -> Problem:
        """Set the objective to maximize ``measure``; returns the problem."""
        return self._set_objective(measure, "max")

    def _set_objective(self, measure, sense):
        if not isinstance(measure, Measure):
            raise UsageError(f"the objective must be a Measure, got {type(measure).__name__}")
        self._probe(measure, "objective")
        self.objective, self.sense = measure, sense
        self._cache.clear()
        return self

    def subject_to(self, *constraints) -> Problem:
        """Add constraints (``measure <= bound``, ``>=``, ``==``, or lists of them)."""
        for c in constraints:
            items = c if isinstance(c, Iterable) and not isinstance(c, Constraint) else [c]
            for item in items:
                if not isinstance(item, Constraint):
                    raise UsageError(
                        f"subject_to expects constraints such as `measure <= bound`, got {item!r}"
                    )
                if not np.isfinite(item.bound):
                    raise MechanismError(f"constraint {item.name}: the bound must be finite")
                if getattr(item.measure, "unit", "") == "rad":
                    _check_radians(f"constraint {item.name}: bound", (item.bound,))
                self._probe(item.measure, f"constraint {item.name}")
                self.constraints.append(item)
        self._cache.clear()
        return self

    def _probe(self, measure: Measure, what: str, tries: int = 16) -> None:
        """Evaluate ``measure`` on a few designs within the bounds (their centre, then random
        points) at 16 crank angles and raise :class:`UsageError` if it asks for something the
        mechanism does not have (an output, a joint, a force model): an error that no choice of
        dimensions removes, reported here rather than deep in a solve. Designs that cannot be
        built or moved, and measures undefined at a design (a swing angle of a double-crank),
        are skipped: the solvers treat those points as infeasible. O(tries) small evaluations."""
        lo = np.array([b[0] for b in self.variables.values()])
        hi = np.array([b[1] for b in self.variables.values()])
        points = [(lo + hi) / 2]
        if tries > 1:
            sample = np.random.default_rng(12345).random((tries - 1, len(lo)))
            points += list(lo + sample * (hi - lo))
        phi = input_grid(self.mechanism, 16)
        for x in points:
            try:
                design = self.design(**dict(zip(self.variables, map(float, x), strict=True)))
                motion = design.motion(phi, speed=self.speed)
            except (ValueError, ArithmeticError):
                continue
            try:
                measure.from_motion(design, motion)
                return
            except UsageError as exc:
                raise UsageError(f"{what} cannot be evaluated on this mechanism: {exc}") from None
            except (ValueError, ArithmeticError):
                continue
            except (AttributeError, KeyError, TypeError, IndexError) as exc:
                raise UsageError(
                    f"{what} cannot be evaluated on this mechanism ({type(exc).__name__}: {exc})"
                ) from None

    def copy(self) -> Problem:
        """An independent copy (same objective and constraints)."""
        new = Problem(
            self.mechanism,
            self.variables,
            self.fixed,
            self.speed,
            self.base_angles,
            self.feasibility_margin,
            self.tol,
            self.slots,
        )
        new.objective, new.sense, new.constraints = (
            self.objective,
            self.sense,
            list(self.constraints),
        )
        return new

    def _transcription(self, n_extra: int | None = None):
        """The smooth program over the base grid and ``n_extra`` refinement slots (default
        :attr:`slots`, else 16): this
        problem's bounds over the expression graph and solvers of its structure, which are
        built once and shared by every problem of the same structure (a module-level cache of
        a few structures, :mod:`.transcription`; none is held by the problem, so memory stays
        flat over many problems)."""
        from .transcription import Transcription

        if n_extra is None:
            n_extra = 16 if self.slots is None else self.slots
        return Transcription(self, n_extra)

    def _numeric(self):
        """The problem's forms for numpy evaluation (no CasADi)."""
        from .transcription import NumericForms

        if "numeric" not in self._cache:
            self._cache["numeric"] = NumericForms(self)
        return self._cache["numeric"]

    def _smooth_error(self):
        """None when the CasADi transcription builds, else the SolverError explaining why."""
        from ..errors import SolverError

        try:
            self._transcription()
        except SolverError as exc:
            return exc
        return None

    # ------------------------------------------------------------------ analysis
    def design(self, **values):
        """The mechanism for variable values ``values`` (and the fixed parameters)."""
        return self.mechanism(**{**self.fixed, **values})

    def evaluate(self, design, n: int = 2048) -> dict[str, float]:
        """Objective and constraint measures of ``design`` (a mechanism or ``{name: value}``),
        evaluated on ``n`` equal crank-angle steps (no certification)."""
        if isinstance(design, Mapping):
            design = self.design(**design)
        motion = design.motion(input_grid(design, n), speed=self.speed)
        out = {}
        if self.objective is not None:
            out[self.objective.name] = float(self.objective.from_motion(design, motion))
        for c in self.constraints:
            out[c.measure.name] = float(c.measure.from_motion(design, motion))
        return out

    # ------------------------------------------------------------------ solving
    def solve(
        self,
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
    ):
        """Solve the problem.

        Parameters
        ----------
        method : ``"ipopt"`` (default; CasADi exact derivatives), ``"slsqp"`` (scipy, exact CasADi
            gradients) or ``"de"`` (scipy differential evolution, then a certified IPOPT polish
            unless ``polish=False``). Measures that evaluate only with numpy (non-smooth ones,
            e.g. the dwell metrics) work with ``"de"`` alone: the polish is then skipped and the
            result is ``"uncertified"`` (never ``"optimal"``), with the reason in its message.
        starts : number of valid Sobol start points of the local methods.
        seed : seed of the Sobol sample and of differential evolution.
        progress : show a tqdm bar over the starts (None: only on a terminal).
        rtol : certification tolerance: grid peak vs true peak, relative.
        max_rounds : limit of grid-refinement re-solves.
        n_dense : angles of the dense evaluation that locates the true peaks; the reported
            values of the other cycle measures (averages, numpy-only measures) use this uniform
            grid too.
        options : options for the local solver (IPOPT options without the ``ipopt.`` prefix, or
            scipy SLSQP options).
        x0 : optional start design ``{name: value}`` tried first.
        polish, de_options : for ``"de"``: local polish, and options of
            ``scipy.optimize.differential_evolution`` plus ``angles`` (uniform grid, default 256)
            and ``eq_rtol`` (equality tolerance, default 1e-4).
        time_limit : seconds; no new start begins once it is spent (the first always runs):
            the starts run so far are certified and reported, the message says how many.

        Returns
        -------
        Result
        """
        from .solvers import solve

        res = solve(
            self,
            method=method,
            starts=starts,
            seed=seed,
            progress=progress,
            rtol=rtol,
            max_rounds=max_rounds,
            n_dense=n_dense,
            options=options,
            x0=x0,
            polish=polish,
            de_options=de_options,
            time_limit=time_limit,
        )
        return self._annotate(res)

    def _annotate(self, res):
        """The result with the problem's variable bounds and measure units (for reports)."""
        import dataclasses

        by_name = {c.name: c for c in self.constraints}
        cons = tuple(
            dataclasses.replace(
                cv, measure=by_name[cv.name].measure.name, unit=by_name[cv.name].measure.unit
            )
            if cv.name in by_name
            else cv
            for cv in res.constraints
        )
        measures = [c.measure for c in self.constraints]
        if self.objective is not None:
            measures.append(self.objective)
        units = {m.name: getattr(m, "unit", "") for m in measures}
        return dataclasses.replace(res, bounds=dict(self.variables), units=units, constraints=cons)

    def __repr__(self) -> str:
        obj = "no objective" if self.objective is None else f"{self.sense} {self.objective.name}"
        cons = ", ".join(c.name for c in self.constraints) or "none"
        return f"Problem({self.mechanism.__name__}, {obj}; subject to: {cons})"


def _check_radians(what: str, values) -> None:
    """Angles are radians: a value beyond one turn is almost surely degrees typed as radians
    (``30`` for 30 deg); refused with the reading in radians it was probably meant to be."""
    for v in values:
        validate.radians_meant(what, v)
