"""The library's measures as constraints of path generation (``constraints=[...]``).

A peak (``CycleMeasure`` reduced by ``max`` or ``min``) is bounded through its smooth branches at
each of ``GRID`` crank angles over the turn, as :class:`~mechsynth.synthesis.Problem` bounds
them on its base grid; a ``ScalarMeasure`` through its branches. The returned designs are then
checked on 3600 crank angles (a constraint broken there between the grid angles drops the
design, with the reason), and the designs returned are certified by the library's certifier
(:func:`~mechsynth.synthesis.certify.true_peak`: each peak over the continuous crank angle, a
dense evaluation refined by a bounded 1-D search), their certificates
(:class:`MeasureCertificate`) reported with them; a design the certifier finds beyond a bound
is dropped. Means, RMS values, equalities and sums of measures are not accepted.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..errors import MechanismError

__all__ = ["check_constraints", "constraint_rows", "GRID", "MeasureCertificate",
           "certify_constraints", "certified", "solve_with_peaks"]

#: crank angles at which a peak's branches are bounded in the NLP (a parameter: ``GRID`` equal
#: steps, then ``EXTRA`` slots for the angles where a dense check found a peak beyond its bound)
GRID = 72
EXTRA = 24


def _kind(c):
    from ..objectives.base import Constraint, CycleMeasure, ScalarMeasure

    if not isinstance(c, Constraint):
        raise MechanismError(
            f"constraints: expected measures compared with a bound (e.g. "
            f"ms.objectives.max_pressure_angle() <= ms.deg(40)), got {c!r}"
        )
    m = c.measure
    if isinstance(m, CycleMeasure) and (
        (m.reduce == "max" and c.op == "<=") or (m.reduce == "min" and c.op == ">=")
    ):
        return "cycle"
    if isinstance(m, ScalarMeasure) and (c.op == "<=" or (c.op == ">=" and not m.has_branches)):
        return "scalar"
    raise MechanismError(
        f"constraints: {c.name} is not accepted in path generation (a peak bounded from its "
        "side, max <= bound or min >= bound, or a closed-form measure <= or >= a bound)"
    )


def check_types(constraints) -> tuple:
    """The constraints as a tuple, each checked to be one path generation accepts."""
    from ..objectives.base import Constraint

    if constraints is None:
        return ()
    if isinstance(constraints, Constraint):
        constraints = [constraints]
    if not isinstance(constraints, (list, tuple)):
        raise MechanismError(
            "constraints must be a list of measures compared with bounds, e.g. "
            f"[ms.objectives.max_pressure_angle() <= ms.deg(40)], got {constraints!r}"
        )
    out = tuple(constraints)
    for c in out:
        _kind(c)
    return out


def base_angles() -> np.ndarray:
    """The ``GRID + EXTRA`` angle slots at the start (the extra slots repeat grid angles)."""
    grid = np.linspace(0.0, 2.0 * np.pi, GRID, endpoint=False)
    return np.concatenate([grid, grid[:EXTRA]])


def constraint_rows(constraints, design, speed, phi):
    """``g >= 0`` rows (CasADi) of ``constraints`` on the symbolic ``design`` (a Linkage) at the
    crank angles ``phi`` (a CasADi parameter vector of ``GRID + EXTRA`` angles)."""
    import casadi as ca

    from ..objectives.base import CycleMeasure

    rows = []
    if not constraints:
        return rows
    motion = design.motion(phi, speed=speed)
    for c in constraints:
        m = c.measure.bind(design)
        scale = max(1.0, abs(c.bound))
        # a relative 1e-7 inside the bound: the dense check's 1e-6 then holds where the peak
        # drifts between the angles the NLP bounds it at
        inner = c.bound - 1e-7 * max(1.0, abs(c.bound)) * (1 if c.op == "<=" else -1)
        if isinstance(m, CycleMeasure):
            bound = inner**2 if m.outer == "sqrt" else inner
            scale = max(1.0, abs(bound))
            for br in m.branches(design, motion):
                br = ca.vec(br) if not isinstance(br, (float, int)) else br
                rows.append(((bound - br) if c.op == "<=" else (br - bound)) / scale)
        else:
            for br in m.branches(design):
                rows.append(((inner - br) if c.op == "<=" else (br - inner)) / scale)
    return rows


def _peaks(constraint, design, speed, n):
    """``(angles, excess)`` of the local peaks of a cycle constraint's excess over its bound on
    ``n`` crank angles, each refined by a parabola through its neighbours (the samples are
    smooth between grid angles)."""
    from ..units import cycle

    m = constraint.measure.bind(design)
    phi = cycle(n)
    v = np.asarray(m.samples(design, design.motion(phi, speed=speed)), dtype=float).ravel()
    e = v - constraint.bound if constraint.op == "<=" else constraint.bound - v
    y0, y2 = np.roll(e, 1), np.roll(e, -1)
    idx = np.flatnonzero((e >= y0) & (e >= y2))
    curv = y0[idx] - 2.0 * e[idx] + y2[idx]
    off = np.where(curv < 0, 0.5 * (y0[idx] - y2[idx]) / np.where(curv < 0, curv, -1.0), 0.0)
    off = np.clip(off, -0.5, 0.5)
    peak = e[idx] - 0.25 * (y0[idx] - y2[idx]) * off
    return phi[idx] + off * (2.0 * np.pi / n), peak


def solve_with_peaks(solver, fun, x0, P, ng, lbx, ubx, objective, build, constraints, speed):
    """One start of path generation: IPOPT from ``x0`` with parameters ``P``, the polish of a
    sum of squares, the solution ``build(z)``; with ``constraints``, up to eight rounds that put
    the angles where a dense check finds a peak beyond its bound into the NLP's angle slots
    (after ``P``: ``GRID`` equal steps, then the ``EXTRA`` slots) and solve again from the last
    point. Returns ``(solution, z)``; the solution is what ``build`` returns (a failure is
    anything without a ``linkage``)."""
    from .path_generation import _polish

    Pm = np.concatenate([P, base_angles()]) if constraints else np.asarray(P, dtype=float)
    s, z = None, np.asarray(x0, dtype=float)
    for _ in range(8 if constraints else 1):
        sol = solver(x0=z, p=Pm, lbx=lbx, ubx=ubx, lbg=np.zeros(ng), ubg=np.full(ng, np.inf))
        z = np.asarray(sol["x"], dtype=float).ravel()
        if objective == "squares":
            z = _polish(fun, z, Pm, lbx, ubx)
        s = build(z)
        if not hasattr(s, "linkage") or not constraints:
            break
        worst = worst_angles(constraints, s.linkage, speed)
        if worst.size == 0:
            break
        slots = Pm[len(P) + GRID :]
        Pm[len(P) + GRID :] = np.concatenate([worst, slots])[: len(slots)]
    return s, z


def worst_angles(constraints, design, speed, n: int = 3600, k: int = 4) -> np.ndarray:
    """The crank angles (rad) of the ``k`` largest excesses of each peak over its bound on ``n``
    angles (parabola-refined local extremes), to add to the NLP's angle slots."""
    from ..objectives.base import CycleMeasure

    out = []
    for c in constraints or ():
        if not isinstance(c.measure.bind(design), CycleMeasure):
            continue
        ang, peak = _peaks(c, design, speed, n)
        bad = peak > 0
        out.extend(ang[bad][np.argsort(-peak[bad])][:k])
    return np.asarray(out, dtype=float)


def check_constraints(constraints, design, speed, n: int = 3600) -> str:
    """'' when every constraint holds for the numeric ``design`` over the turn (relative
    tolerance 1e-6): a peak's value is its largest parabola-refined local extreme on ``n``
    crank angles; else the first one broken with its value."""
    from ..objectives.base import CycleMeasure

    for c in constraints or ():
        m = c.measure.bind(design)
        if isinstance(m, CycleMeasure):
            _, peak = _peaks(c, design, speed, n)
            excess = float(peak.max(initial=-np.inf))
            value = c.bound + excess if c.op == "<=" else c.bound - excess
        else:
            value = float(m.evaluate(design, speed=speed))
        if c.violation(value) > 1e-6 * max(1.0, abs(c.bound)):
            return f"{c.name} broken over the turn: {value:.8g}"
    return ""


@dataclass(frozen=True)
class MeasureCertificate:
    """A measure constraint checked on a design by the library's certifier.

    Attributes
    ----------
    name : the constraint (measure, operator, bound); ``op`` and ``bound`` (the measure's
        units, SI).
    value : the measure with every peak taken over the continuous crank angle (dense
        evaluation refined by a bounded 1-D search to 1e-11 rad).
    angles : crank angle (rad) of each peak (empty for a closed-form measure).
    holds : the value keeps the bound within a relative 1e-6 (the NLP bounds it 1e-7 inside).
    """

    name: str
    op: str
    bound: float
    value: float
    angles: tuple[float, ...]
    holds: bool

    def __str__(self) -> str:
        at = ", ".join(f"{np.rad2deg(a):.4f}" for a in self.angles)
        return (f"{self.name}: {self.value:.8g}" + (f" at crank angle {at} deg" if at else "")
                + (" (holds)" if self.holds else " (BROKEN)"))  # fmt: skip

    def as_dict(self) -> dict:
        return {"name": self.name, "op": self.op, "bound": self.bound, "value": self.value,
                "angles": list(self.angles), "holds": self.holds}  # fmt: skip


def certify_constraints(constraints, design, speed, n_dense: int = 2048) -> tuple:
    """:class:`MeasureCertificate` of each constraint on the numeric ``design`` (a Linkage),
    by :func:`~mechsynth.synthesis.certify.true_peak` and the library's evaluation of a
    measure from its peaks (as :func:`~mechsynth.synthesis.pareto.true_value`)."""
    from ..kinematics.mechanism import input_grid
    from .certify import true_peak
    from .transcription import evaluate_form, flatten

    out = []
    for c in constraints or ():
        form = flatten(c.measure, design)
        peaks, angles = {}, []
        for _, atom in form.terms:
            if atom.kind == "peak":
                peaks[atom], angle, _ = true_peak(atom, design, speed, n_dense)
                angles.append(float(angle))
        motion = design.motion(input_grid(design, n_dense), speed=speed)
        value = float(evaluate_form(form, design, motion, peaks))
        holds = bool(c.violation(value) <= 1e-6 * max(1.0, abs(c.bound)))
        out.append(MeasureCertificate(c.name, c.op, float(c.bound), value, tuple(angles), holds))
    return tuple(out)


def certified(solutions, constraints, speed):
    """The solutions whose every constraint the certifier confirms, each with its
    certificates (``certificate``), and the reason the first one dropped was dropped."""
    if not constraints:
        return list(solutions), ""
    kept, why = [], ""
    for s in solutions:
        certs = certify_constraints(constraints, s.linkage, speed)
        bad = [str(c) for c in certs if not c.holds]
        if bad:
            why = why or "certifier: " + "; ".join(bad)
            continue
        kept.append(replace(s, certificate=certs))
    return kept, why
