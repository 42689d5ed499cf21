"""Paper 000: axial vs desaxial one-armed (Mark II-type) beam pumping units, and their synthesis.

Base geometry (where every dimension comes from)
------------------------------------------------
The paper takes "the dimensions of the Lufkin Mark II" but prints only the crank ``r``, pitman
``l`` and pivot distance ``X_O2`` of its two desaxial variants (2a: r = 1.068 m, l = 4.3 m,
X_O2 = 5.0 m; 2b: r = 0.908 m, l = 5.048 m, X_O2 = 3.5 m). By eqs. (2)-(3) both follow from one
beam: rear arm ``k``, swing ``psi`` (``H = k1 psi``) and pivot height ``Y_O2``. Those three are
fitted here to the four printed numbers (least squares; the residuals are reported), so the
base beam is the one the paper's own numbers imply. The front arm ``k1`` is not recoverable
from them (it only scales the polished-rod motion); it is set from the public API 11E geometry
of the Lufkin Mark II M-912D-365-168 (A = 334 in, C = 270 in): ``k1 = k * 334 / 270``. The
crank speed (6 strokes/min) and the idealized rectangular card (80 kN up, 45 kN down) used for
the torque figure are assumptions of this study, not the paper's.

Variants: the axial unit (B's chord passes through the crankshaft: ``X_O2 = k cos(psi/2)``,
``r = h1/2``) and the desaxial 2a and 2b, all synthesized by eqs. (2)-(3) for the same stroke, so
their strokes are equal by construction. Each turns in the direction that makes its upstroke the
longer one (counter-clockwise with the well on the right, as the Mark II).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from ..fileio import atomic, write_text
from ..machines.pumping_unit import (
    BeamPumpingUnit,
    DynamometerCard,
    harmonic_approximation,
    optimal_counterbalance,
    paper_crank_and_pitman,
    peak_torque_factor,
    rod_clearance,
    torque_curve,
    torque_factor_table,
)
from ..objectives import max_pressure_angle, peak_acceleration, peak_velocity, stroke
from ..options import Option, takes_options
from ..progress import Stages
from ..units import cycle, deg, spm
from . import StudyResult

#: the paper's printed desaxial variants (Figs. 4-5 captions)
PUBLISHED = {
    "2a": {"r": 1.068, "l": 4.3, "X_O2": 5.0},
    "2b": {"r": 0.908, "l": 5.048, "X_O2": 3.5},
}
#: Lufkin Mark II M-912D-365-168, API 11E: A and C (in), for the ratio k1 / k
MARK_II_A_IN, MARK_II_C_IN = 334.0, 270.0
SPEED_SPM = 6.0
CARD_UP, CARD_DOWN = 80e3, 45e3  # N, idealized rectangular card (assumed)
PRESSURE_LIMIT_DEG = 30.0
TF_LIMIT = 1.5  # m/rad
#: the polished rod hangs this far outside the crank circle at least (m): room for the
#: counterweights beyond the crank pin and the rod's clamp (assumed); without it the
#: acceleration optimum hung the rod 0.47 m inside its own 1.12 m crank circle
ROD_CLEARANCE = 0.3
#: the design box of the synthesis (m): the centre bearing behind the crankshaft, as the Mark II
SYNTHESIS_BOUNDS = {
    "crank": (0.5, 1.6),
    "pitman": (3.0, 6.5),
    "pivot_x": (-7.5, -2.5),
    "pivot_y": (3.0, 5.0),
}


def fit_base_geometry():
    """Fit (k, psi, Y_O2) to the printed r, l of variants 2a and 2b via eqs. (2)-(3).

    Returns a dict with k, psi (rad), Y_O2, the relative residuals and the implied r, l."""
    from scipy.optimize import least_squares

    def model(p):
        k, psi, y = p
        out = []
        for v in PUBLISHED.values():
            r, l, _, _ = paper_crank_and_pitman(psi, 1.0, k, -v["X_O2"], y, "mark-ii")
            out.append((r, l))
        return out

    def residuals(p):
        return [
            (m - v[key]) / v[key]
            for (r, l), v in zip(model(p), PUBLISHED.values())
            for m, key in ((r, "r"), (l, "l"))
        ]

    sol = least_squares(residuals, x0=[6.0, 0.3, 4.0], xtol=1e-14, ftol=1e-14, gtol=1e-14)
    k, psi, y = (float(v) for v in sol.x)
    fitted = {name: {"r": r, "l": l} for name, (r, l) in zip(PUBLISHED, model(sol.x))}
    return {
        "k": k,
        "psi": psi,
        "Y_O2": y,
        "residuals": [float(r) for r in sol.fun],
        "max_rel_residual": float(np.max(np.abs(sol.fun))),
        "fitted": fitted,
        "success": bool(sol.success),
    }


def base_design():
    """The base beam: k, k1, Y_O2 and the stroke H (m)."""
    fit = fit_base_geometry()
    k = fit["k"]
    k1 = k * MARK_II_A_IN / MARK_II_C_IN
    return {"k": k, "k1": k1, "Y_O2": fit["Y_O2"], "H": k1 * fit["psi"], "fit": fit}


def _longer_upstroke(unit: BeamPumpingUnit) -> BeamPumpingUnit:
    return unit if float(unit.upstroke_span) >= np.pi - 1e-12 else unit.mirrored()


def variants(base):
    """The axial, 2a and 2b units (eqs. 2-3) plus 2a/2b with the printed r, l as given."""
    k, k1, y, h = base["k"], base["k1"], base["Y_O2"], base["H"]
    x_axial = k * np.cos(h / (2 * k1))
    out = {}
    for name, x in (("axial", x_axial), ("2a", 5.0), ("2b", 3.5)):
        u = BeamPumpingUnit.from_stroke(h, k1, k, -x, y, "mark-ii", "ccw")
        out[name] = _longer_upstroke(u)
    printed = {}
    for name, v in PUBLISHED.items():
        u = BeamPumpingUnit(v["r"], v["l"], k, k1, -v["X_O2"], y, "mark-ii", "ccw")
        printed[name] = _longer_upstroke(u)
    return out, printed


def extremes(unit: BeamPumpingUnit, theta, speed, card):
    m = unit.motion(theta, speed=speed)
    v, a = m.polished_rod.velocity, m.polished_rod.acceleration
    up = np.asarray(m.torque_factor) > 0  # the loaded stroke
    tc = torque_curve(unit, theta, card)
    cb = optimal_counterbalance(theta, tc.well, free_phase=True, cross_check=False)
    return {
        "crank_m": float(unit.crank),
        "pitman_m": float(unit.pitman),
        "X_O2_m": float(-unit.pivot_x),
        "rotation": unit.rotation,
        "stroke_m": float(unit.stroke),
        "upstroke_span_deg": float(np.rad2deg(unit.upstroke_span)),
        "max_velocity": float(v.max()),
        "min_velocity": float(v.min()),
        "peak_velocity": float(np.abs(v).max()),
        "max_acceleration": float(a.max()),
        "min_acceleration": float(a.min()),
        "peak_acceleration": float(np.abs(a).max()),
        "upstroke_peak_acceleration": float(np.abs(a[up]).max()),
        "mills_peak_acceleration_approximation": float(
            harmonic_approximation(unit, theta, speed)["mills_peak_acceleration"]
        ),
        "downstroke_peak_acceleration": float(np.abs(a[~up]).max()),
        "max_pressure_angle_deg": float(np.rad2deg(m.pressure_angle.max())),
        "min_pressure_angle_deg": float(np.rad2deg(m.pressure_angle.min())),
        "peak_torque_factor": float(np.abs(m.torque_factor).max()),
        "peak_crank_torque_no_cb": float(np.abs(tc.well).max()),
        "peak_net_torque_optimal_cb": cb.peak_torque,
        "optimal_cb_moment": cb.counterbalance.moment,
        "optimal_cb_phase_deg": float(np.rad2deg(cb.counterbalance.phase)),
    }


# ------------------------------------------------------------------------------ pitman force
def pitman_force_model(unit: BeamPumpingUnit, card: DynamometerCard):
    """Kinetostatic model of ``unit`` with massless links carrying the polished-rod load of
    ``card`` (N, down at the horsehead, moment arm ``front_arm`` about the centre bearing):
    bodies crank, pitman, beam; joints R10 (frame on crank at O1), R21 (crank on pitman at A),
    R32 (pitman on beam at B), R30 (frame on beam at O2)."""
    from ..dynamics.inertia import LinkInertia
    from ..dynamics.kinetostatics import FRAME, ForceModel, Revolute
    from ..dynamics.loads import PointForce

    def load(m):
        w = card.load_on(m, unit.stroke)
        return (0.0 * w, -w)

    bodies = {
        "crank": LinkInertia("crank", "O1", 0.0),
        "pitman": LinkInertia("pitman", "A", 0.0),
        "beam": LinkInertia("rear_arm", "O2", 0.0),
    }
    joints = (
        Revolute("R10", "crank", FRAME, "O1"),
        Revolute("R21", "pitman", "crank", "A"),
        Revolute("R32", "beam", "pitman", "B"),
        Revolute("R30", "beam", FRAME, "O2"),
    )
    return ForceModel(bodies, joints, (PointForce("beam", "PR", load, "well load"),), "crank")


def pitman_force(unit: BeamPumpingUnit, theta, speed, card: DynamometerCard):
    """The pitman force over the crank angles ``theta`` under the card's load (massless links).

    Returns a dict of arrays: ``force`` (N, |R21| from the kinetostatics), ``closed_form``
    (``W k1 / (k cos(pressure angle))`` from the beam's moment balance), ``load`` (N) and
    ``pressure_angle`` (rad), and the kinetostatic result as ``result``."""
    from ..dynamics.kinetostatics import kinetostatics

    m = unit.motion(theta, speed=speed)
    model = pitman_force_model(unit, card)
    res = kinetostatics(model, m)
    w = card.load_on(m, unit.stroke)
    pa = np.asarray(m.pressure_angle)
    return {
        "force": np.asarray(res.magnitude("R21")),
        "closed_form": w * unit.front_arm / (unit.rear_arm * np.cos(pa)),
        "load": w,
        "pressure_angle": pa,
        "result": res,
        "motion": m,
        "model": model,
    }


def pitman_table(units, theta, speed, card):
    """Peak pitman force of every variant under the same card, and where it occurs."""
    out = {}
    for name, u in units.items():
        pf = pitman_force(u, theta, speed, card)
        k = int(np.argmax(pf["force"]))
        up = np.asarray(pf["motion"].torque_factor) > 0
        out[name] = {
            "peak_pitman_force": float(pf["force"][k]),
            "at_theta_deg": float(np.rad2deg(theta[k])),
            "pressure_angle_there_deg": float(np.rad2deg(pf["pressure_angle"][k])),
            "load_there": float(pf["load"][k]),
            "upstroke_max_pressure_angle_deg": float(np.rad2deg(pf["pressure_angle"][up].max())),
            "mean_pitman_force": float(np.mean(pf["force"])),
            "closed_form_deviation": float(np.max(np.abs(pf["force"] - pf["closed_form"]))),
        }
    return out


# ------------------------------------------------------------------------------ synthesis
def _base_problem(base):
    """Crank, pitman and pivot position of a Mark II-type unit on the base beam, at 6 SPM, with
    the polished rod clear of the crank circle (:data:`ROD_CLEARANCE`)."""
    from ..synthesis import Problem

    prob = Problem(
        BeamPumpingUnit,
        variables=dict(SYNTHESIS_BOUNDS),
        fixed={
            "rear_arm": base["k"],
            "front_arm": base["k1"],
            "unit_class": "mark-ii",
            "rotation": "ccw",
        },
        speed=spm(SPEED_SPM),
    )
    prob.subject_to(rod_clearance() >= ROD_CLEARANCE)
    return prob


OBJECTIVES = {"acceleration": peak_acceleration, "velocity": peak_velocity}


def synthesis_problem(base, pressure_limit=None, tf_limit=TF_LIMIT, objective="acceleration"):
    """Choose crank, pitman and the pivot position for the base beam and stroke: minimize the
    peak polished-rod acceleration (or, ``objective="velocity"``, speed) at 6 SPM subject to the
    stroke, a pressure-angle limit and a torque-factor limit (Grashof full turn is added by the
    mechanism's feasibility hook). ``pressure_limit`` in rad (default 30 deg), ``tf_limit`` in
    m/rad. Paper 000's recommendation 1 asks for both objectives."""
    if pressure_limit is None:
        pressure_limit = deg(PRESSURE_LIMIT_DEG)

    prob = _base_problem(base)
    prob.minimize(OBJECTIVES[objective]("slider"))
    prob.subject_to(
        stroke("slider") == base["H"],
        max_pressure_angle() <= pressure_limit,
        peak_torque_factor() <= tf_limit,
    )
    return prob


def pareto(base, n=7, starts=3, anchor_starts=4, objective="acceleration"):
    """Peak acceleration (or speed, ``objective="velocity"``) against maximum pressure angle
    (paper 000's recommendation 2) by
    :func:`~mechsynth.synthesis.pareto.pareto_front` (epsilon-constraint on the pressure angle,
    anchors included), for the base beam and stroke with the torque-factor limit."""
    from ..synthesis.pareto import pareto_front

    prob = _base_problem(base)
    prob.subject_to(stroke("slider") == base["H"], peak_torque_factor() <= TF_LIMIT)
    return pareto_front(
        prob,
        OBJECTIVES[objective]("slider"),
        max_pressure_angle(),
        n=n,
        starts=starts,
        anchor_starts=anchor_starts,
        progress=False,
    )


def speed_acceleration_front(base, n=5, starts=3, anchor_starts=4, pressure_limit=None):
    """Recommendation 1's two objectives against each other: peak polished-rod speed against
    peak acceleration (epsilon-constraint on the acceleration, anchors included) for the base
    beam and stroke with the pressure-angle (default 30 deg) and torque-factor limits."""
    from ..synthesis.pareto import pareto_front

    if pressure_limit is None:
        pressure_limit = deg(PRESSURE_LIMIT_DEG)
    prob = _base_problem(base)
    prob.subject_to(
        stroke("slider") == base["H"],
        peak_torque_factor() <= TF_LIMIT,
        max_pressure_angle() <= pressure_limit,
    )
    return pareto_front(
        prob,
        peak_velocity("slider"),
        peak_acceleration("slider"),
        n=n,
        starts=starts,
        anchor_starts=anchor_starts,
        progress=False,
    )


# ------------------------------------------------------------------------------ run
STAGES = (
    "variants and the paper's findings",
    "synthesis (IPOPT and differential evolution)",
    "Pareto fronts",
    "figures, tables, animation",
)


@takes_options(
    Option("n_angles", 721, "crank angles of the curves", minimum=9, maximum=100_000),
    Option("pareto_points", 7, "points on the Pareto front", minimum=2, maximum=100),
    Option("starts", 3, "multi-starts of the synthesis", minimum=1, maximum=1000),
    owner="study 'beam-pump'",
)
def run(out=None, n_angles=721, pareto_points=7, starts=3):
    """Run the study (see the module notes); ``n_angles`` crank angles of the curves,
    ``pareto_points`` points on the front, ``starts`` multi-starts of the synthesis."""
    with Stages("beam-pump", STAGES if out is not None else STAGES[:-1]) as stages:
        return _run(out, n_angles, pareto_points, starts, stages)


def _run(out, n_angles, pareto_points, starts, stages):
    stages.next(STAGES[0])
    theta = cycle(n_angles - 1)
    base = base_design()
    fit = base["fit"]
    units, printed = variants(base)
    w = spm(SPEED_SPM)
    card = DynamometerCard(
        np.concatenate([np.linspace(0, 1, 50), np.linspace(1, 0, 50)]),
        np.concatenate([np.full(50, CARD_UP), np.full(50, CARD_DOWN)]),
        "idealized rectangular card (assumed)",
    )
    table = {name: extremes(u, theta, w, card) for name, u in units.items()}
    printed_table = {name: extremes(u, theta, w, card) for name, u in printed.items()}
    pitman = pitman_table(units, theta, w, card)
    rec1 = {
        "smallest_peak_velocity": min(table, key=lambda k: table[k]["peak_velocity"]),
        "smallest_peak_acceleration": min(table, key=lambda k: table[k]["peak_acceleration"]),
    }
    rec1["one_scheme_for_both"] = (
        rec1["smallest_peak_velocity"] == rec1["smallest_peak_acceleration"]
    )

    # the paper's findings, checked
    ax, a2, b2 = table["axial"], table["2a"], table["2b"]
    findings = {
        "stroke_equal_by_construction": bool(
            max(abs(t["stroke_m"] - base["H"]) for t in table.values()) <= 1e-9 * base["H"]
        ),
        "upstroke_span_grows_axial_2a_2b": bool(
            ax["upstroke_span_deg"] < a2["upstroke_span_deg"] < b2["upstroke_span_deg"]
        ),
        "peak_velocity_drops_axial_2a_2b": bool(
            ax["peak_velocity"] > a2["peak_velocity"] > b2["peak_velocity"]
        ),
        "peak_acceleration_drops_axial_2a_2b": bool(
            ax["peak_acceleration"] > a2["peak_acceleration"] > b2["peak_acceleration"]
        ),
        "upstroke_peak_acceleration_drops": bool(
            ax["upstroke_peak_acceleration"]
            > a2["upstroke_peak_acceleration"]
            > b2["upstroke_peak_acceleration"]
        ),
        "upstroke_max_velocity_drops": bool(
            ax["max_velocity"] > a2["max_velocity"] > b2["max_velocity"]
        ),
        "pressure_angle_grows_axial_2a_2b": bool(
            ax["max_pressure_angle_deg"]
            < a2["max_pressure_angle_deg"]
            < b2["max_pressure_angle_deg"]
        ),
        "pitman_force_grows_axial_2a_2b": bool(
            pitman["axial"]["peak_pitman_force"]
            < pitman["2a"]["peak_pitman_force"]
            < pitman["2b"]["peak_pitman_force"]
        ),
        "peak_net_torque_drops_axial_2a_2b": bool(
            ax["peak_net_torque_optimal_cb"]
            > a2["peak_net_torque_optimal_cb"]
            > b2["peak_net_torque_optimal_cb"]
        ),
    }
    errata = [
        "Eqs. (2)-(3) fix the stroke H for every pivot distance, so the axial and desaxial "
        "variants have the same stroke (here equal to 1e-9): the 'longer working stroke' of "
        "the desaxial units can only mean a longer upstroke in crank angle (time), which holds: "
        f"{ax['upstroke_span_deg']:.2f} / {a2['upstroke_span_deg']:.2f} / "
        f"{b2['upstroke_span_deg']:.2f} deg (axial / 2a / 2b).",
        "The printed r, l of 2a and 2b are not exactly consistent with one beam: the best fit "
        f"leaves relative residuals up to {fit['max_rel_residual']:.2e}; the printed values "
        "used as given produce strokes of "
        f"{printed_table['2a']['stroke_m']:.4f} and {printed_table['2b']['stroke_m']:.4f} m "
        f"instead of {base['H']:.4f} m.",
        "Eqs. (13)-(14) for U2', U3' are garbled in print (misplaced factor r and (U2 - 1) "
        "term); the acceleration here comes from the exact second analog of the dyad, checked "
        "against finite differences in the tests.",
        "Eqs. (9) and (11) print U2 with the wrong sign (it is r sin(phi3 - phi1) / (l sin(phi2 - "
        "phi3))), and (12) multiplies omega1^2 by U_i where U_i' belongs; corrected formulas in "
        "mechsynth.kinematics.four_bar_formulas, tested against the dyads.",
    ]
    if not findings["peak_acceleration_drops_axial_2a_2b"]:
        errata.append(
            "Not confirmed: the peak polished-rod acceleration does not fall steadily from the "
            f"axial to the desaxial units ({ax['peak_acceleration']:.4f} / "
            f"{a2['peak_acceleration']:.4f} / {b2['peak_acceleration']:.4f} m/s^2 at "
            f"{SPEED_SPM:g} SPM)."
        )
    if not findings["peak_velocity_drops_axial_2a_2b"]:
        errata.append(
            "Not confirmed: the peak polished-rod speed does not fall steadily from the axial to "
            f"the desaxial units ({ax['peak_velocity']:.4f} / {a2['peak_velocity']:.4f} / "
            f"{b2['peak_velocity']:.4f} m/s); the upstroke maximum "
            f"({ax['max_velocity']:.4f} / {a2['max_velocity']:.4f} / {b2['max_velocity']:.4f}) "
            "falls while the downstroke one rises."
        )

    # synthesis and Pareto front
    stages.next(STAGES[1])
    best = synthesis_problem(base).solve(starts=starts, progress=False)
    # global cross-check: differential evolution over the same box, polished and certified
    de = synthesis_problem(base).solve(method="de", seed=1, progress=False)
    # the speed optimum is the first anchor of the speed-acceleration front (lexicographic)
    front_va = speed_acceleration_front(base, starts=starts)
    ok = [i for i in range(len(front_va.results)) if front_va.success[i]]
    best_v = front_va.results[min(ok, key=lambda i: front_va.first[i])] if ok else None
    if best_v is None:
        best_v = synthesis_problem(base, objective="velocity").solve(starts=starts, progress=False)
    rec1["synthesis"] = _both_objectives(best, best_v, w)
    best_design = None
    if best.design is not None:
        d = best.design
        both = {r: d.replace(rotation=r) for r in ("ccw", "cw")}
        rot = max(both, key=lambda r: float(both[r].upstroke_span))
        best_design = both[rot]
    stages.next(STAGES[2])
    front = pareto(base, n=pareto_points, starts=starts)
    # the speed front is flat (0.6 % over its range): fewer points than the acceleration one
    front_v = pareto(base, n=max(3, pareto_points - 2), starts=starts, objective="velocity")

    data = {
        "success": bool(best.success),
        "base": {
            "k": base["k"],
            "k1": base["k1"],
            "Y_O2": base["Y_O2"],
            "stroke_H": base["H"],
            "swing_deg": float(np.rad2deg(fit["psi"])),
            "fit_residuals": fit["residuals"],
            "fit_r_l": fit["fitted"],
        },
        "speed_spm": SPEED_SPM,
        "variants": table,
        "printed_r_l_as_given": printed_table,
        "findings": findings,
        "synthesis": {
            **best.to_dict(),
            "chosen_rotation": None if best_design is None else best_design.rotation,
            "upstroke_span_deg": None
            if best_design is None
            else float(np.rad2deg(best_design.upstroke_span)),
            "active_bounds": list(best.on_bounds()),
            "de_cross_check": {"status": de.status, "success": bool(de.success), "value": de.value},
        },
        "pareto": {
            "method": "epsilon-constraint (synthesis.pareto.pareto_front)",
            **front.to_dict(),
        },
        "pareto_velocity": {
            "method": "epsilon-constraint (synthesis.pareto.pareto_front)",
            **front_v.to_dict(),
        },
        "pareto_velocity_acceleration": {
            "method": "epsilon-constraint on the peak acceleration, pressure angle <= 30 deg",
            **front_va.to_dict(),
        },
        "pitman_force": {
            "card": f"idealized rectangular card {CARD_UP:g} N up, {CARD_DOWN:g} N down",
            "links": "massless (the load's path through the linkage only)",
            "variants": pitman,
        },
        "recommendation_1": rec1,
        "tf_table_2b": torque_factor_table(units["2b"], 15.0),
    }

    files = []
    if out is not None:
        stages.next(STAGES[3])
        data["coverage"] = COVERAGE.to_dict()  # in beam_pump.json too
        files = _write(Path(out), theta, w, units, card, table, front, data, best_design)
        files += _write_recommendations(Path(out), theta, w, units, card, table, front_v, front_va)
    summary = _summary(base, fit, table, printed_table, findings, best, best_design, front)
    summary += "\n" + "\n".join(_recommendation_lines(pitman, rec1, front_v, table, front_va))
    syn = data["synthesis"]
    summary += (
        f"\nsynthesis: variables on a bound of the box: {', '.join(syn['active_bounds']) or 'none'}"
        f"; differential evolution cross-check: {de.status}, "
        f"{de.value:.6f} m/s^2 (IPOPT {best.value:.6f})"
    )
    return COVERAGE.attach(StudyResult("beam-pump", summary, data, files, errata), out)


def docs_tables(data) -> dict[str, str]:
    """The Markdown tables docs/pumping_unit.md prints from this study's run, rendered from
    ``data`` (``run(...).data`` or ``beam_pump.json``): ``"recommendation_1"`` (each
    objective's optimum), ``"speed_acceleration"`` and ``"pressure_front"`` (the fronts, one
    row a point). The run writes them to ``beam_pump_docs_tables.md``; a test holds the docs to
    them, so a changed model or solver shows up as a changed table, not a stale page."""
    syn = data["recommendation_1"]["synthesis"]
    rows = [
        "| objective | crank, m | pitman, m | X_O2, m | Y_O2, m | peak speed, m/s | "
        "peak acceleration, m/s^2 | max pressure angle, deg |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for key, name in (("acceleration_optimal", "peak acceleration"), ("velocity_optimal",
                                                                      "peak speed")):
        r = syn[key]
        if "crank" not in r:
            rows.append(f"| {name} | {r['status']} | | | | | | |")
            continue
        rows.append(
            f"| {name} | {r['crank']:.4f} | {r['pitman']:.5g} | {r['X_O2']:.5g} | "
            f"{r['Y_O2']:.5g} | {r['peak_velocity']:.4f} | {r['peak_acceleration']:.4f} | "
            f"{r['max_pressure_angle_deg']:.2f} |"
        )

    def front(points, bound_head, second, first, bound_fmt, anchor_words):
        out = [f"| {bound_head} | {second} | {first} |", "| --- | --- | --- |"]
        last = len(points) - 1
        for i, p in enumerate(points):
            if not p["success"]:
                out.append(f"| {bound_fmt(p['eps'])} | {p['status']} | |")
                continue
            bound = (
                "(free: anchor)" if i == 0 else
                f"(min {anchor_words}: anchor)" if i == last else bound_fmt(p["eps"])
            )
            out.append(f"| {bound} | {bound_fmt(p['second'])} | {p['first']:.5f} |")
        return "\n".join(out)

    return {
        "recommendation_1": "\n".join(rows),
        "speed_acceleration": front(
            data["pareto_velocity_acceleration"]["points"], "acceleration bound, m/s^2",
            "peak acceleration, m/s^2", "peak speed, m/s", lambda v: f"{v:.5f}", "acceleration",
        ),
        "pressure_front": front(
            data["pareto"]["points"], "pressure-angle bound, deg", "max pressure angle, deg",
            "peak acceleration, m/s^2", lambda v: f"{np.rad2deg(v):.2f}", "pressure angle",
        ),
    }


def _both_objectives(best_a, best_v, speed, n=3601):
    """Recommendation 1's two objectives: each optimum's peak speed and acceleration (dense)."""
    out = {}
    theta = cycle(n - 1)
    for key, res in (("acceleration_optimal", best_a), ("velocity_optimal", best_v)):
        row = {"status": res.status, "success": bool(res.success), "value": res.value}
        if res.design is not None:
            m = res.design.motion(theta, speed=speed)
            row.update(
                crank=float(res.design.crank),
                pitman=float(res.design.pitman),
                X_O2=float(-res.design.pivot_x),
                Y_O2=float(res.design.pivot_y),
                peak_velocity=float(np.abs(m.polished_rod.velocity).max()),
                peak_acceleration=float(np.abs(m.polished_rod.acceleration).max()),
                max_pressure_angle_deg=float(np.rad2deg(np.max(m.pressure_angle))),
            )
        out[key] = row
    a, v = out["acceleration_optimal"], out["velocity_optimal"]
    if "peak_velocity" in a and "peak_velocity" in v:
        # one design minimizes both when each optimum is within 0.1 % of the other's measure
        out["one_design_for_both"] = bool(
            a["peak_velocity"] <= v["peak_velocity"] * 1.001
            and v["peak_acceleration"] <= a["peak_acceleration"] * 1.001
        )
    return out


def _recommendation_lines(pitman, rec1, front_v, table, front_va):
    lines = [
        "",
        "pitman force under the same idealized card (80 kN up, 45 kN down; massless links; "
        "|R21| from the kinetostatics = W k1 / (k cos(pressure angle)) from the beam's moment "
        "balance):",
    ]
    for name, p in pitman.items():
        lines.append(
            f"  {name:6s} peak {p['peak_pitman_force'] / 1e3:7.2f} kN at theta "
            f"{p['at_theta_deg']:6.1f} deg (pressure angle {p['pressure_angle_there_deg']:5.2f} "
            f"deg), mean {p['mean_pitman_force'] / 1e3:6.2f} kN; closed form to "
            f"{p['closed_form_deviation']:.1e} N"
        )
    ax, b2 = pitman["axial"]["peak_pitman_force"], pitman["2b"]["peak_pitman_force"]
    lines.append(
        "  the desaxial unit's larger pressure angle loads the pitman more: 2b "
        f"{100 * (b2 / ax - 1):+.1f} % against the axial unit (the paper's finding holds)"
    )
    lines.append(
        f"recommendation 1 (smallest peak speed and acceleration): among the paper's variants the "
        f"smallest peak speed is {rec1['smallest_peak_velocity']}'s "
        f"({table[rec1['smallest_peak_velocity']]['peak_velocity']:.4f} m/s), the smallest peak "
        f"acceleration {rec1['smallest_peak_acceleration']}'s "
        f"({table[rec1['smallest_peak_acceleration']]['peak_acceleration']:.4f} m/s^2)"
        + ("" if rec1["one_scheme_for_both"] else ": no variant is best in both")
    )
    syn = rec1["synthesis"]
    for key, label in (
        ("acceleration_optimal", "min peak acceleration"),
        ("velocity_optimal", "min peak speed"),
    ):
        r = syn[key]
        if "peak_velocity" in r:
            lines.append(
                f"  synthesis, {label} ({r['status']}): crank {r['crank']:.4f} m, pitman "
                f"{r['pitman']:.4f} m, X_O2 {r['X_O2']:.4f} m, Y_O2 {r['Y_O2']:.4f} m: peak speed "
                f"{r['peak_velocity']:.4f} m/s, peak acceleration {r['peak_acceleration']:.4f} "
                f"m/s^2, max pressure angle {r['max_pressure_angle_deg']:.2f} deg"
            )
        else:
            lines.append(f"  synthesis, {label}: {r['status']}")
    if "one_design_for_both" in syn:
        lines.append(
            "  one design minimizes both: "
            + ("yes" if syn["one_design_for_both"] else "no (the two objectives conflict)")
        )
    lines.append(
        "Pareto front of recommendation 1's two objectives (pressure angle <= 30 deg; "
        "* non-dominated): acceleration bound m/s^2 -> peak |a| m/s^2, peak |v| m/s"
    )
    lines += _front_lines(front_va, degrees=False)
    lines.append(
        "Pareto front of the peak speed against the max pressure angle (recommendation 2 for "
        "the speed; * non-dominated): bound deg -> max pressure angle deg, peak |v| m/s"
    )
    lines += _front_lines(front_v)
    return lines


def _write_recommendations(out, theta, w, units, card, table, front_v, front_va):
    """The pitman force figure, the speed-pressure and speed-acceleration fronts' figures and
    CSV files."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..plotting import LINESTYLES, PALETTE, crank_axis, style
    from ..plotting import save as save_figure

    files = []
    x = np.rad2deg(theta)
    colours = dict(zip(units, (PALETTE[4], PALETTE[5], PALETTE[3])))
    names = {"axial": "axial", "2a": "desaxial 2a", "2b": "desaxial 2b"}
    with style():
        fig, axes = plt.subplots(2, 1, sharex=True, figsize=(8, 7), layout="constrained")
        for k, (name, u) in enumerate(units.items()):
            pf = pitman_force(u, theta, w, card)
            kw = dict(color=colours[name], ls=LINESTYLES[k], label=names[name])
            axes[0].plot(x, pf["force"] / 1e3, **kw)
            axes[1].plot(x, np.rad2deg(pf["pressure_angle"]), **kw)
        axes[0].set_ylabel("pitman force, kN")
        axes[1].set_ylabel("pressure angle at B, deg")
        axes[0].set_title(
            f"Pitman force at {SPEED_SPM:g} SPM under the same idealized card "
            f"{CARD_UP / 1e3:g}/{CARD_DOWN / 1e3:g} kN, massless links (paper 000)",
            fontsize=9,
        )
        crank_axis(axes[1], THETA_LABEL)
        handles, labels = axes[0].get_legend_handles_labels()
        fig.legend(handles, labels, loc="outside lower center", ncol=3)
        files.append(save_figure(fig, out / "beam_pump_pitman_force.png", dpi=110))

        fig = _front_with_variants(
            front_v,
            f"Peak speed against pressure angle at {SPEED_SPM:g} SPM, same stroke and beam "
            "(paper 000)",
            table,
            lambda t: (np.deg2rad(t["max_pressure_angle_deg"]), "rad", t["peak_velocity"], "m/s"),
            lambda name, t: f"paper 000: {names[name]}",
            colours,
            ncol=3,
        )
        files.append(save_figure(fig, out / "beam_pump_pareto_velocity.png", dpi=110))
        fig = _front_with_variants(
            front_va,
            f"Peak speed against peak acceleration at {SPEED_SPM:g} SPM, pressure angle "
            f"<= {PRESSURE_LIMIT_DEG:g} deg\n(paper 000, recommendation 1)",
            table,
            lambda t: (t["peak_acceleration"], "m/s^2", t["peak_velocity"], "m/s"),
            lambda name, t: f"paper 000: {names[name]} (max pressure angle "
            f"{t['max_pressure_angle_deg']:.0f} deg)",
            colours,
            ncol=2,
        )
        files.append(save_figure(fig, out / "beam_pump_speed_acceleration.png", dpi=110))
    front_v.to_csv(out / "beam_pump_pareto_velocity.csv")
    files.append(out / "beam_pump_pareto_velocity.csv")
    front_va.to_csv(out / "beam_pump_speed_acceleration.csv")
    files.append(out / "beam_pump_speed_acceleration.csv")
    return files


def _summary(base, fit, table, printed, findings, best, best_design, front):
    from ..display import fmt

    lines = [
        "Paper 000: one-armed (Mark II-type) beam pumping unit, axial vs desaxial",
        f"base beam (fitted to the printed r, l by eqs. 2-3): k = {base['k']:.4f} m, "
        f"swing = {np.rad2deg(fit['psi']):.3f} deg, Y_O2 = {base['Y_O2']:.4f} m; "
        f"k1 = {base['k1']:.4f} m (Mark II A/C); stroke H = {base['H']:.4f} m",
        "printed vs eqs. (2)-(3) on the fitted beam:",
    ]
    for name, v in PUBLISHED.items():
        f = fit["fitted"][name]
        lines.append(
            f"  {name}: r {v['r']:.4f} vs {f['r']:.4f} m ({(f['r'] / v['r'] - 1) * 100:+.3f} %), "
            f"l {v['l']:.4f} vs {f['l']:.4f} m ({(f['l'] / v['l'] - 1) * 100:+.3f} %)"
        )
    lines.append(
        f"\n{'variant':8s} {'r':>7s} {'l':>7s} {'X_O2':>6s} {'up,deg':>7s} {'|v|max':>7s} "
        f"{'|a|max':>7s} {'PA max':>7s} {'TFmax':>6s} {'T net':>9s}"
    )
    for name, t in list(table.items()) + [(f"{k}*", v) for k, v in printed.items()]:
        lines.append(
            f"{name:8s} {t['crank_m']:7.4f} {t['pitman_m']:7.4f} {t['X_O2_m']:6.3f} "
            f"{t['upstroke_span_deg']:7.2f} {t['peak_velocity']:7.4f} "
            f"{t['peak_acceleration']:7.4f} {t['max_pressure_angle_deg']:7.2f} "
            f"{t['peak_torque_factor']:6.3f} {t['peak_net_torque_optimal_cb']:9.0f}"
        )
    lines.append("  (* printed r, l used as given; velocity m/s, acceleration m/s^2 at 6 SPM)")
    parts = []
    for name, t in table.items():
        approx = t["mills_peak_acceleration_approximation"]
        parts.append(f"{name} {approx:.4f} ({(approx / t['peak_acceleration'] - 1) * 100:+.1f} %)")
    mills = ", ".join(parts)
    lines.append(f"  Mills' approximate peak acceleration (vs exact): {mills}")
    lines.append("\nfindings of the paper, checked:")
    for k, v in findings.items():
        lines.append(f"  {k}: {'holds' if v else 'does NOT hold'}")
    lines.append(f"\nsynthesis: {best.status}; {best.message}")
    if best_design is not None:
        lines.append(
            f"  crank {fmt(best_design.crank, 'm', 5)}, pitman {fmt(best_design.pitman, 'm', 5)}, "
            f"X_O2 {fmt(-best_design.pivot_x, 'm', 5)}, Y_O2 {fmt(best_design.pivot_y, 'm', 5)}, "
            f"rotation {best_design.rotation}, upstroke "
            f"{fmt(best_design.upstroke_span, 'rad', 5)}, peak acceleration "
            f"{fmt(best.value, 'm/s^2', 5)}"
        )
    lines.append(
        "Pareto front (epsilon-constraint on the pressure angle; * non-dominated): "
        "bound deg -> max pressure angle deg, peak |a| m/s^2"
    )
    lines += _front_lines(front)
    return "\n".join(lines)


THETA_LABEL = "crank angle θ from 12 o'clock in the direction of rotation"


def _write(out, theta, w, units, card, table, front, data, best_design=None):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .. import display
    from ..jsonutil import dumps
    from ..plotting import LINESTYLES, PALETTE, crank_axis, style, torque_unit
    from ..plotting import save as save_figure

    files = []

    def save(fig, name):
        files.append(save_figure(fig, out / name, dpi=110))

    x = np.rad2deg(theta)
    colours = dict(zip(units, (PALETTE[4], PALETTE[5], PALETTE[3])))
    styles = dict(zip(units, LINESTYLES))
    names = {"axial": "axial", "2a": "desaxial 2a", "2b": "desaxial 2b"}
    with style():
        fig, axes = plt.subplots(3, 1, sharex=True, figsize=(7.5, 8.5), layout="constrained")
        for name, u in units.items():
            m = u.motion(theta, speed=w)
            kw = dict(color=colours[name], ls=styles[name], label=names.get(name, name))
            for ax, (y, unit) in zip(
                axes,
                (
                    (m.polished_rod.position, "m"),
                    (m.polished_rod.velocity, "m/s"),
                    (m.polished_rod.acceleration, "m/s^2"),
                ),
            ):
                ax.plot(x, display.convert(np.asarray(y), unit)[0], **kw)
        for a, (lab, unit) in zip(
            axes,
            (("position up from the bottom", "m"), ("velocity", "m/s"), ("acceleration", "m/s^2")),
        ):
            a.set_ylabel(display.label(lab, unit))
        axes[0].set_title(
            f"Polished rod of the axial and desaxial units at {SPEED_SPM:g} SPM, same stroke "
            "(paper 000, Fig. 3)",
            fontsize=9,
        )
        crank_axis(axes[2], THETA_LABEL)
        handles, labels = axes[0].get_legend_handles_labels()
        fig.legend(handles, labels, loc="outside lower center", ncol=3)
        save(fig, "beam_pump_kinematics.png")

        fig, ax = plt.subplots(figsize=(8, 5), layout="constrained")
        curves = {}
        for name, u in units.items():
            tc = torque_curve(u, theta, card)
            cb = optimal_counterbalance(theta, tc.well, free_phase=True, cross_check=False)
            curves[name] = (tc.well - cb.counterbalance.torque(theta), tc.well)
        div, tunit = torque_unit(np.concatenate([c[1] for c in curves.values()]))
        for name, (net, well) in curves.items():
            c = colours[name]
            # variants by dash (and colour), net against no counterbalance by width
            ls = styles[name]
            net_label = f"{names[name]}: net, optimal counterbalance"
            ax.plot(x, net / div, color=c, ls=ls, lw=2.2, label=net_label)
            well_label = f"{names[name]}: no counterbalance"
            ax.plot(x, well / div, color=c, ls=ls, lw=0.9, label=well_label)
        ax.axhline(0.0, color="0.3", lw=0.7)
        ax.set_ylabel(f"crank torque, {tunit}")
        ax.set_title(
            f"Crank torque at {SPEED_SPM:g} SPM, idealized rectangular card "
            f"{CARD_UP / 1e3:g}/{CARD_DOWN / 1e3:g} kN (paper 000, Fig. 4)",
            fontsize=9,
        )
        crank_axis(ax, THETA_LABEL)
        fig.legend(loc="outside lower center", ncol=2)
        save(fig, "beam_pump_torque.png")

        fig, ax = plt.subplots(figsize=(8, 4.8), layout="constrained")
        for name, u in units.items():
            pa = display.convert(np.asarray(u.motion(theta).pressure_angle), "rad")[0]
            ax.plot(x, pa, color=colours[name], ls=styles[name], label=names[name])
        ax.axhline(
            display.convert(np.deg2rad(PRESSURE_LIMIT_DEG), "rad")[0],
            color="0.3",
            lw=0.8,
            ls="--",
            label=f"{PRESSURE_LIMIT_DEG:g} deg (the synthesis limit)",
        )
        ax.set_ylabel(display.label("pressure angle at the equalizer bearing B", "rad"))
        ax.set_title(
            "Pressure angle between the pitman force and the velocity of B (paper 000, Fig. 5)",
            fontsize=9,
        )
        crank_axis(ax, THETA_LABEL)
        fig.legend(loc="outside lower center", ncol=4)
        save(fig, "beam_pump_pressure_angle.png")

        fig = _front_with_variants(
            front,
            f"Pareto front at {SPEED_SPM:g} SPM, same stroke and beam (paper 000, "
            "recommendation 2)",
            table,
            lambda t: (
                np.deg2rad(t["max_pressure_angle_deg"]), "rad", t["peak_acceleration"], "m/s^2"
            ),
            lambda name, t: f"paper 000: {names[name]}",
            colours,
            ncol=3,
        )
        save(fig, "beam_pump_pareto.png")

    headline = best_design if best_design is not None else units["2b"]
    anim = headline.animate(frames=36, speed=w, dpi=60)
    files.append(anim.save(out / "beam_pump.gif"))

    keys = list(next(iter(table.values())).keys())
    with atomic(out / "beam_pump_extremes.csv", "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(["variant", *keys])
        for name, t in table.items():
            wr.writerow([name, *[t[k] for k in keys]])
    files.append(out / "beam_pump_extremes.csv")
    front.to_csv(out / "beam_pump_pareto.csv")
    files.append(out / "beam_pump_pareto.csv")
    write_text(out / "beam_pump.json", dumps(data) + "\n")
    files.append(out / "beam_pump.json")
    tables = docs_tables(data)
    write_text(out / "beam_pump_docs_tables.md", "\n\n".join(tables.values()) + "\n")
    files.append(out / "beam_pump_docs_tables.md")
    return files


def _front_lines(front, degrees=True):
    """One line per point of a Pareto front: ``bound -> second, first`` (``*``: non-dominated);
    the bound and the second measure in degrees when they are angles, else as they are."""

    def shown(v):
        return f"{np.rad2deg(v):6.2f}" if degrees else f"{v:.5f}"

    return [
        f"  {shown(front.eps[i])} -> {shown(front.second[i])}, {front.first[i]:.5f}"
        + (" *" if front.nondominated[i] else "")
        if front.success[i]
        else f"  {shown(front.eps[i])} -> {r.status}"
        for i, r in enumerate(front.results)
    ]


def _front_with_variants(front, title, table, xy, label, colours, ncol):
    """A Pareto front's figure with the paper's variants marked on it: ``xy(t)`` gives ``(x, x
    unit, y, y unit)`` of a variant's row ``t`` (SI), ``label(name, t)`` its legend entry."""
    from .. import display

    fig = front.plot(title=title)
    ax = fig.axes[0]
    for k, (name, t) in enumerate(table.items()):
        x, xu, y, yu = xy(t)
        ax.plot(
            display.convert(x, xu)[0],
            display.convert(y, yu)[0],
            "Ds^v"[k % 4],  # told apart by shape, not colour alone
            ms=8,
            color=colours[name],
            mec="k",
            label=label(name, t),
        )
    for leg in fig.legends:
        leg.remove()
    ax.margins(0.1)
    fig.legend(*ax.get_legend_handles_labels(), loc="outside lower center", ncol=ncol)
    return fig


# ------------------------------------------------------------------------------ coverage
def _coverage():
    from .coverage import Coverage, Item

    s = "tests/test_beam_pump_study.py::"
    pf = "tests/test_beam_pump_pitman.py::"
    f = "tests/test_four_bar_formulas.py::"
    u = "tests/test_pumping_unit.py::"
    unit = "machines.pumping_unit.BeamPumpingUnit"
    formulas = "kinematics.four_bar_formulas."
    missing = "the figure is missing from the text"
    return Coverage(
        "Paper 000: kinematics of the one-armed beam pumping unit (Mark II type)",
        "beam-pump",
        (
            Item(
                "Figs. 1-2",
                "figure",
                "scheme of the unit and its vector loop",
                "not reproducible",
                unit + ".sketch",
                note=f"{missing}; the unit is drawn and animated (beam_pump.gif)",
            ),
            Item(
                "eq. (1)",
                "equation",
                "Grashof full-turn condition r + d <= l + k",
                "reproduced",
                unit + ".feasibility_constraints",
                (u + "test_bad_inputs_are_named",),
            ),
            Item(
                "eqs. (2)-(3)",
                "equation",
                "crank and pitman from the stroke",
                "reproduced",
                "machines.pumping_unit.paper_crank_and_pitman",
                (
                    u + "test_paper_synthesis_gives_the_stroke",
                    s + "test_printed_variants_reproduced_by_eqs_2_3",
                ),
            ),
            Item(
                "eqs. (4)-(7)",
                "equation",
                "vector loop and position functions phi2, phi3",
                "reproduced",
                formulas + "position_functions",
                (
                    f + "test_formulas_agree_with_dyad",
                    pf + "test_position_functions_in_the_base_frame_15_and_polished_rod_16",
                ),
            ),
            Item(
                "eqs. (8), (10)",
                "equation",
                "velocity loop and omega3 = omega1 U3",
                "reproduced",
                formulas + "velocity_ratios",
                (
                    f + "test_ratios_and_derivatives_are_finite_differences",
                    f + "test_printed_u2_has_the_wrong_sign_and_u3_is_right",
                ),
            ),
            Item(
                "eqs. (9), (11): U2",
                "equation",
                "pitman velocity ratio U2",
                "erratum",
                formulas + "velocity_ratios",
                (f + "test_printed_u2_has_the_wrong_sign_and_u3_is_right",),
                "wrong sign: r sin(phi3 - phi1) / (l sin(phi2 - phi3))",
            ),
            Item(
                "eq. (12)",
                "equation",
                "angular accelerations eps_i = eps1 U_i + omega1^2 U_i'",
                "erratum",
                formulas + "velocity_ratio_derivatives",
                (f + "test_angular_accelerations_match_four_bar_motion",),
                "printed with U_i where U_i' belongs",
            ),
            Item(
                "eqs. (13)-(14)",
                "equation",
                "U2', U3'",
                "erratum",
                formulas + "velocity_ratio_derivatives",
                (
                    f + "test_printed_derivatives_are_wrong",
                    f + "test_ratios_and_derivatives_are_finite_differences",
                ),
                "garbled (misplaced r and (U2 - 1)); derived and tested against finite differences",
            ),
            Item(
                "eq. (15)",
                "equation",
                "angles in the base frame, alpha1 = direction of O1O2",
                "reproduced",
                unit + ".motion",
                (pf + "test_position_functions_in_the_base_frame_15_and_polished_rod_16",),
            ),
            Item(
                "eq. (16)",
                "equation",
                "polished-rod speed and acceleration",
                "reproduced",
                unit + ".motion",
                (
                    pf + "test_position_functions_in_the_base_frame_15_and_polished_rod_16",
                    u + "test_torque_factor_is_derivative_of_position",
                ),
            ),
            Item(
                "base dimensions",
                "data",
                "k, k1, Y_O2 of the Lufkin Mark II",
                "not reproducible",
                "studies.beam_pump.fit_base_geometry",
                note="not printed: k, swing and Y_O2 fitted to the printed r, l of 2a, 2b by "
                "(2)-(3); k1 from the API 11E geometry of a Mark II M-912D-365-168",
            ),
            Item(
                "variants 2a, 2b",
                "data",
                "r, l, X_O2 of the desaxial units",
                "erratum",
                "studies.beam_pump.variants",
                (s + "test_printed_variants_reproduced_by_eqs_2_3",),
                "reproduced by (2)-(3) on one beam to 0.048 %, not exactly",
            ),
            Item(
                "Fig. 3",
                "figure",
                "polished-rod position, speed, acceleration; axial, 2a, 2b",
                "not reproducible",
                "beam_pump_kinematics.png",
                note=f"{missing}; redrawn from (4)-(16)",
            ),
            Item(
                "Fig. 4",
                "figure",
                "crank torque",
                "not reproducible",
                "beam_pump_torque.png",
                note=f"{missing} and the load is not given; an idealized card (assumed)",
            ),
            Item(
                "Fig. 5",
                "figure",
                "pressure angle",
                "not reproducible",
                "beam_pump_pressure_angle.png",
                note=f"{missing}; redrawn",
            ),
            Item(
                "finding: stroke",
                "finding",
                "the working stroke lengthens from axial to desaxial",
                "erratum",
                "studies.beam_pump (findings)",
                (s + "test_findings",),
                "(2)-(3) fix the stroke for every variant; the upstroke's crank angle grows",
            ),
            Item(
                "finding: extrema",
                "finding",
                "the speed and acceleration extrema decrease",
                "refuted",
                "studies.beam_pump (findings)",
                (s + "test_findings",),
                "holds on the upstroke only; over the cycle the peak speed rises and the peak "
                "acceleration is not monotone",
            ),
            Item(
                "finding: torque",
                "finding",
                "Fig. 4 confirms the lower crank torque",
                "reproduced",
                "studies.beam_pump (findings)",
                (s + "test_findings",),
                "peak net torque with the optimal counterbalance falls axial > 2a > 2b",
            ),
            Item(
                "finding: pressure angle",
                "finding",
                "the pressure angle grows with the desaxial",
                "reproduced",
                "studies.beam_pump (findings)",
                (s + "test_findings",),
            ),
            Item(
                "finding: pitman",
                "finding",
                "the larger pressure angle loads the pitman more",
                "reproduced",
                "studies.beam_pump.pitman_force",
                (
                    pf + "test_desaxial_pressure_angle_loads_the_pitman_more",
                    pf + "test_pitman_force_equals_the_beam_moment_balance",
                    s + "test_findings",
                ),
                "same card: peak pitman force +5 % (2a), +23 % (2b)",
            ),
            Item(
                "recommendation 1",
                "recommendation",
                "the scheme with the smallest maximum speed and acceleration of the polished rod",
                "added",
                "studies.beam_pump.synthesis_problem",
                (
                    s + "test_recommendation_1_both_objectives",
                    s + "test_speed_acceleration_front",
                    s + "test_synthesis_beats_every_feasible_variant",
                ),
                "the two objectives conflict (no variant or design is best in both): their "
                "Pareto front with the pressure angle <= 30 deg",
            ),
            Item(
                "recommendation 2",
                "recommendation",
                "the best compromise of the kinematic extrema with the smallest pressure angle",
                "added",
                "studies.beam_pump.pareto",
                (s + "test_pareto_front", s + "test_velocity_pressure_front"),
                "Pareto fronts of peak acceleration and of peak speed against the pressure angle",
            ),
        ),
    )


COVERAGE = _coverage()
