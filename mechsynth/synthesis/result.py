"""Results of a synthesis: the design, its values, the status and how the optimum was certified.

Statuses (one vocabulary for every solver in :mod:`mechsynth.synthesis`):

``"optimal"``
    converged, every constraint holds within tolerance, and every peak is certified (the grid
    peak equals the true continuous peak). ``success`` is True only for this status.
``"infeasible"``
    no start reached a design satisfying the constraints; the violated ones are named.
``"max_iterations"``
    the iteration limit was reached before convergence.
``"uncertified"``
    converged on the grid, but the refinement rounds ran out before the grid peak equalled the
    true peak.
``"solver_failed"``
    any other failure (no valid start, evaluation errors, restoration failure).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import MechanismError

__all__ = ["STATUSES", "ConstraintValue", "Certification", "Result"]


def _name(design) -> str:
    """A design's name: a linkage's own name, else its class name."""
    return getattr(design, "__name__", type(design).__name__)


STATUSES = ("optimal", "infeasible", "max_iterations", "uncertified", "solver_failed")


@dataclass(frozen=True)
class ConstraintValue:
    """A constraint at the reported design.

    Attributes
    ----------
    name : e.g. ``"max_pressure_angle <= 0.523599"``.
    value : the measure's value (true peaks for peak measures), SI units.
    op, bound : the comparison and its right-hand side.
    violation : how far outside the constraint (0 when it holds).
    satisfied : ``violation <= tol * max(1, |bound|)``.
    measure, unit : the measure's name and SI unit (for reports in display units).
    """

    name: str
    value: float
    op: str
    bound: float
    violation: float
    satisfied: bool
    measure: str = ""
    unit: str = ""

    @property
    def active(self) -> bool:
        """True for an inequality that holds with equality (within its tolerance)."""
        return self.op != "==" and abs(self.value - self.bound) <= 1e-6 * max(1.0, abs(self.bound))

    def text(self) -> str:
        """``"max_pressure_angle <= 30 deg"`` in display units."""
        from .. import display

        if not self.measure:
            return self.name
        return f"{self.measure} {self.op} {display.fmt(self.bound, self.unit)}"

    def to_dict(self) -> dict[str, Any]:
        return dict(
            name=self.name,
            value=self.value,
            op=self.op,
            bound=self.bound,
            violation=self.violation,
            satisfied=self.satisfied,
            unit=self.unit,
        )


@dataclass(frozen=True)
class Certification:
    """How the reported optimum was established.

    Attributes
    ----------
    method : "ipopt", "slsqp" or "de".
    starts_requested, starts_run : multi-start count asked and run (a start that is not a valid
        design, e.g. a crank that cannot turn, is skipped and replaced by the next Sobol point).
    starts_skipped : invalid start points skipped.
    starts_converged : local solves that converged to a feasible point.
    local_optima : true objective values (continuous peaks) of the distinct certified local
        optima, ascending (converged starts ending at the same design count once).
    spread : ``max - min`` of ``local_optima`` relative to the smallest (0 with one optimum).
        A spread above zero means the starts found different local optima: the reported one is
        the best found, global optimality is not proven.
    peaks : :class:`~mechsynth.synthesis.certify.PeakCheck` per peak measure at the reported
        design: solver grid value vs true value from dense evaluation + 1-D search.
    refinement_rounds : re-solves after adding angles to the grid.
    grid_angles : number of crank angles in the final grid (base + refinement).
    refined_angles : the refinement angles added (rad).
    certified : every peak's grid value equals its true value within ``rtol``.
    rtol : certification tolerance.
    cross_check : optional dict from a global method (e.g. differential evolution: its design
        and value before the local polish).
    distinct_optima : number of distinct local optima (``len(local_optima)``).
    best_hits : converged starts that ended at the reported design.
    iterations : the local solver's iterations from each start (IPOPT's ``iter_count``,
        SLSQP's ``nit``), in start order.
    refinement_iterations : iterations of the reported design's re-solves after refinement.
    """

    method: str
    starts_requested: int
    starts_run: int
    starts_skipped: int
    starts_converged: int
    local_optima: tuple[float, ...]
    spread: float
    peaks: tuple
    refinement_rounds: int
    grid_angles: int
    refined_angles: tuple[float, ...]
    certified: bool
    rtol: float
    cross_check: dict | None = None
    distinct_optima: int = 0
    best_hits: int = 0
    iterations: tuple[int, ...] = ()
    refinement_iterations: int = 0

    @property
    def total_iterations(self) -> int:
        """Local solver iterations of every start and of the reported design's re-solves."""
        return int(sum(self.iterations)) + int(self.refinement_iterations)

    def to_dict(self) -> dict[str, Any]:
        return dict(
            method=self.method,
            starts_requested=self.starts_requested,
            starts_run=self.starts_run,
            starts_skipped=self.starts_skipped,
            starts_converged=self.starts_converged,
            local_optima=list(self.local_optima),
            spread=self.spread,
            peaks=[
                dict(
                    name=p.name,
                    grid_value=p.grid_value,
                    true_value=p.true_value,
                    angle=p.angle,
                    gap=p.gap,
                )
                for p in self.peaks
            ],
            refinement_rounds=self.refinement_rounds,
            grid_angles=self.grid_angles,
            refined_angles=list(self.refined_angles),
            certified=self.certified,
            rtol=self.rtol,
            cross_check=self.cross_check,
            distinct_optima=self.distinct_optima,
            best_hits=self.best_hits,
            iterations=list(self.iterations),
            refinement_iterations=self.refinement_iterations,
        )


@dataclass(frozen=True)
class Result:
    """The outcome of :meth:`Problem.solve`.

    Attributes
    ----------
    design : the mechanism at the reported point (an instance of the problem's class), or None
        when no valid design was reached.
    variables : ``{name: value}`` of the decision variables.
    value : the objective at the design (true peaks), in the measure's units.
    objective : the objective's name; ``sense`` is "min" or "max".
    constraints : :class:`ConstraintValue` per constraint, in the order given.
    success : True only for status "optimal".
    status : one of :data:`STATUSES`.
    message : one line; names the violated constraints when infeasible.
    certification : :class:`Certification`.
    solve_time : wall-clock seconds of the whole solve (all starts, refinement, dense checks).
    speed : crank speed (rad/s) the measures use, None for analogs.
    bounds : ``{name: (lower, upper)}`` of the variables (SI).
    units : ``{measure name: SI unit}`` of the objective's and the constraints' measures.
    """

    design: Any
    variables: dict[str, float]
    value: float
    objective: str
    sense: str
    constraints: tuple[ConstraintValue, ...]
    success: bool
    status: str
    message: str
    certification: Certification
    solve_time: float
    speed: float | None = None
    extra: dict[str, Any] = field(default_factory=dict)
    bounds: dict[str, tuple[float, float]] = field(default_factory=dict)
    units: dict[str, str] = field(default_factory=dict)

    @property
    def objective_unit(self) -> str:
        """SI unit of the objective (empty when not known)."""
        return self.units.get(self.objective, "")

    @property
    def violated(self) -> list[ConstraintValue]:
        """The constraints that do not hold at the reported design."""
        return [c for c in self.constraints if not c.satisfied]

    @property
    def values(self) -> dict[str, Any] | None:
        """Every parameter of the design as a plain dict (SI numbers, and words such as
        ``branch``), so that ``type(res.design)(**res.values)`` builds it again; None without
        a design."""
        return None if self.design is None else self.design.as_dict()

    def on_bounds(self, rtol: float = 1e-6) -> dict[str, str]:
        """``{variable: "lower" | "upper"}`` for the variables that ended within ``rtol`` of the
        box width of a bound: the optimum may lie outside the box."""
        out = {}
        for name, (lo, hi) in self.bounds.items():
            v = self.variables.get(name)
            if v is None:
                continue
            tol = rtol * (hi - lo)
            if abs(v - lo) <= tol:
                out[name] = "lower"
            elif abs(v - hi) <= tol:
                out[name] = "upper"
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict (``mechsynth.jsonutil.dumps``)."""
        return dict(
            mechanism=_name(self.design) if self.design is not None else None,
            variables=self.variables,
            design=self.design.params() if self.design is not None else None,
            values=self.values,
            bounds={k: list(v) for k, v in self.bounds.items()},
            on_bounds=self.on_bounds(),
            value=self.value,
            units=dict(self.units),
            objective=self.objective,
            sense=self.sense,
            constraints=[c.to_dict() for c in self.constraints],
            success=self.success,
            status=self.status,
            message=self.message,
            certification=self.certification.to_dict(),
            solve_time=self.solve_time,
            speed=self.speed,
        )

    # ----------------------------------------------------------------------- text
    def report(self) -> str:
        """A plain-text report in display units (:func:`mechsynth.display_units`): status,
        design (variables on a bound of their box flagged), objective, constraints (active ones
        flagged), certification. Crank angles are given in [0, 360) deg."""
        from .. import display

        c = self.certification
        du = display.current()
        design = self.design

        def unit_of(name):
            return design.unit_of(name) if hasattr(design, "unit_of") else "m"

        def num(value, unit, digits=10):
            if not np.isfinite(value):
                return "nan"
            return display.fmt(value, unit, digits)

        lines = [
            f"status: {self.status} ({'success' if self.success else 'FAILED'}) - {self.message}",
            f"{self.sense}imize {self.objective} = {num(self.value, self.objective_unit)}",
        ]
        linear = _linear_input(design)
        if linear:
            speed = (
                "analogs (per m of the driving slider's travel)"
                if self.speed is None
                else f"{display.fmt(self.speed, 'm/s')}"
            )
            lines.append(f"driving slider speed: {speed}")
        else:
            speed = (
                "analogs (crank speed 1 rad/s)"
                if self.speed is None
                else (f"{self.speed:.6g} rad/s ({self.speed * 60 / (2 * np.pi):.6g} rpm)")
            )
            lines.append(f"crank speed: {speed}")
        lines.append(f"design ({du.name} units):")
        edges = self.on_bounds()
        if self.design is not None:
            for k, v in self.design.params().items():
                mark = ""
                if k in self.variables:
                    mark = " (variable)"
                    if k in edges:
                        lo, hi = self.bounds[k]
                        b = lo if edges[k] == "lower" else hi
                        mark = (
                            f" (variable, ON ITS {edges[k].upper()} BOUND {num(b, unit_of(k), 6)})"
                        )
                lines.append(f"  {k:>12s} = {num(float(v), unit_of(k))}{mark}")
        else:
            for k, v in self.variables.items():
                lines.append(f"  {k:>12s} = {num(v, unit_of(k))} (not a valid design)")
        if edges:
            lines.append(
                f"  on a bound: {', '.join(edges)} - the optimum may lie outside the box; "
                "widen it to check"
            )
        if self.constraints:
            lines.append("constraints:")
            for cv in self.constraints:
                if not cv.satisfied:
                    flag = f"VIOLATED by {num(cv.violation, cv.unit, 3)}"
                else:
                    flag = "ok, active" if cv.active else "ok"
                lines.append(f"  {cv.text():40s} value {num(cv.value, cv.unit)}  [{flag}]")
        lines.append(
            f"certification ({c.method}): {c.starts_run} starts run ({c.starts_skipped} invalid "
            f"skipped), {c.starts_converged} converged; {c.distinct_optima} distinct local "
            f"optima, spread {c.spread:.3g}; {c.best_hits} start(s) reached the reported one"
        )
        for p in c.peaks:
            if linear:
                where = f"input s = {display.fmt(p.angle, 'm', 6)}"
            else:
                at = display.angle_position(p.angle)
                shown = f"{at:.4f} deg" if du.angle == "deg" else f"{at:.6f} rad"
                where = f"crank angle {shown}"
            unit = self.units.get(p.name, "")
            lines.append(
                f"  peak {p.name}: grid {num(p.grid_value, unit, 12)}, true "
                f"{num(p.true_value, unit, 12)} at {where} (gap {p.gap:.2g})"
            )
        lines.append(
            f"  {c.refinement_rounds} refinement round(s); {c.grid_angles} "
            f"grid {'inputs' if linear else 'angles'}; "
            f"certified: {c.certified} (rtol {c.rtol:g})"
        )
        if c.iterations:
            lines.append(
                f"  {c.total_iterations} solver iterations ({'+'.join(map(str, c.iterations))}"
                f" from the starts, {c.refinement_iterations} in re-solves)"
            )
        if c.cross_check:
            cc = c.cross_check
            lines.append(f"  cross-check {cc.get('method')}: value {cc.get('value')}")
        lines.append(f"solve time: {self.solve_time * 1e3:.1f} ms")
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.report()

    # ----------------------------------------------------------------------- figure
    def plot(self, n=720, output=None):
        """Motion curves of the design over one crank turn in display units: position, velocity
        and acceleration of the main output (a slider; a link's angle, e.g. a four-bar's
        rocker; or a point) and the pressure angle, with the certified peak angles marked.
        Returns the matplotlib figure."""
        import matplotlib.pyplot as plt

        from .. import display
        from ..plotting import crank_axis, style
        from ..plotting import title as make_title

        if self.design is None:
            raise MechanismError(f"no valid design to plot (status {self.status})")
        from ..kinematics.mechanism import input_grid

        linear = _linear_input(self.design)
        phi = input_grid(self.design, n)
        m = self.design.motion(phi, speed=self.speed)
        deg = display.convert(phi, "m")[0] if linear else np.rad2deg(phi)
        analog = self.speed is None
        per = "m" if linear else "rad"  # analogs are per unit of the input
        if output is None and linear:  # the driving slider is the input: show the output
            output = self.design._stroke_output()
        if output is None:
            output = "slider" if m.sliders else ("rocker" if "rocker" in m.links else "B")
        if output in m.links:
            tr = m.links[output]
            series = (np.unwrap(np.asarray(tr.angle, dtype=float)), tr.omega, tr.epsilon)
            units = (
                "rad",
                f"rad/{per}" if analog else "rad/s",
                f"rad/{per}^2" if analog else "rad/s^2",
            )
            labels = (f"{output} angle", f"{output} angular velocity", f"{output} ang. acc.")
        elif output == "slider" or output in m.sliders:
            tr = m.slider if output == "slider" else m.sliders[output]
            series = (tr.position, tr.velocity, tr.acceleration)
            units = ("m", f"m/{per}" if analog else "m/s", f"m/{per}^2" if analog else "m/s^2")
            labels = ("slider position", "slider velocity", "slider acceleration")
        else:
            tr = m.points[output]
            series = (tr.x, tr.velocity, tr.acceleration)
            units = ("m", f"m/{per}" if analog else "m/s", f"m/{per}^2" if analog else "m/s^2")
            labels = (f"{output} x", f"speed |v| of {output}", f"acceleration |a| of {output}")
        with style():
            fig, axes = plt.subplots(4, 1, sharex=True, figsize=(7.5, 9), layout="constrained")
            for ax, y, u, lab in zip(axes, series, units, labels):
                yv, shown = display.thousands(*display.convert(np.asarray(y, dtype=float), u))
                ax.plot(deg, yv, lw=1.5)
                ax.set_ylabel(f"{lab}, {shown}")
            pa, shown = display.convert(np.asarray(m.pressure_angle, dtype=float), "rad")
            axes[3].plot(deg, pa, lw=1.5, color="#D55E00")
            axes[3].set_ylabel(f"pressure angle, {shown}")
            peaks = [
                display.convert(p.angle, "m")[0]
                if linear
                else display.angle_position(p.angle, "deg")
                for p in self.certification.peaks
            ]
            if linear:
                axes[-1].set_xlabel(display.label("input displacement s", "m"))
            elif getattr(self.design, "periodic", True) is False:  # a rotation over part of a turn
                axes[-1].set_xlim(float(deg[0]), float(deg[-1]))
                axes[-1].set_xlabel("input rotation, deg")
            else:
                crank_axis(axes[-1])
            lo, hi = axes[-1].get_xlim()
            for at in peaks:
                for ax in axes:
                    if min(abs(at - lo), abs(at - hi)) > 0.005 * abs(hi - lo):
                        ax.axvline(at, color="0.5", lw=0.8, ls="--")
                    else:  # a line on the frame would be hidden: a mark on the top edge
                        ax.plot(
                            [at],
                            [1.0],
                            "v",
                            color="0.35",
                            ms=6,
                            clip_on=False,
                            transform=ax.get_xaxis_transform(),
                        )
            value = (
                display.fmt(self.value, self.objective_unit, 6)
                if np.isfinite(self.value)
                else "nan"
            )
            head = f"{self.sense} {self.objective} = {value}; status {self.status}"
            described = self.design.describe()
            if "\n" in described:  # a linkage lists every dimension: name the varied ones
                varied = ", ".join(
                    f"{k} {display.fmt(v, self.design.unit_of(k), 4)}"
                    for k, v in self.variables.items()
                )
                described = f"{_name(self.design)}: {varied}"
            elif len(described) > 90:  # one long line would run off the figure
                lines = [""]
                for part in described.split(", "):
                    if lines[-1] and len(lines[-1]) + len(part) > 88:
                        lines.append(part)
                    else:
                        lines[-1] = f"{lines[-1]}, {part}" if lines[-1] else part
                described = ",\n".join(lines)
            fig.align_ylabels(axes)
            if linear:
                speed = "" if self.speed is None else display.fmt(self.speed, "m/s", 4)
                top = make_title(described, f"input speed {speed}" if speed else "", None, False)
            else:
                top = make_title(described, "", self.speed)
            marks = "inputs" if linear else "angles"
            note = f"(dashed, or \u25bc at an end: certified peak {marks})"
            sep = "\n" if len(head) + len(note) > 90 else " "
            axes[0].set_title(f"{top}\n{head}{sep}{note}", fontsize=9)
        return fig


def _linear_input(design) -> bool:
    """True for a design driven by a slider (its input is a displacement, not an angle)."""
    return design is not None and getattr(design, "input_unit", "rad") == "m"
