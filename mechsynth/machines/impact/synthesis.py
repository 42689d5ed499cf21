"""Synthesis of the six-link impact mechanism: the dimensions that maximize the energy of the
blow at a required blow rate and striker stroke, with transmission-angle, joint-force and motor
limits; and the Pareto front of the blow's energy against the peak load across the tool axis on
the housing.

The measures are written with the package's ``ops`` so that the same code gives numbers and
CasADi expressions (certified :class:`~mechsynth.synthesis.Problem`):

* :func:`blow_energy` -- the energy a blow at crank angle ``phi`` would give the tool,
  ``E(phi) = m_t (1 + e)^2 v^2 J^2 / (2 (J + m_t u^2)^2)`` (``v = u omega`` the striker's speed,
  ``J`` the reduced inertia with the drive's, Newton's law of :mod:`.impact` written without the
  effective mass ``J / u^2``, which is singular at the dead centres); its peak over the cycle is
  the blow with the anvil placed where it is largest;
* :func:`blow_work` -- the kinetic energy the machine loses in that blow (what the motor must
  give back every turn): ``J omega^2 (1 - ((J - e m_t u^2) / (J + m_t u^2))^2) / 2``;
* :func:`peak_transverse_force` -- the mechanism's load on the housing across the guide;
* :func:`peak_joint_force` -- the largest joint reaction;
* :func:`housing_clearances` -- the moving joints B and K kept inside the machine's case
  (:data:`HOUSING`), by :func:`mechsynth.objectives.clearances.clearance`: on by default.

The forces are the linkage's general kinetostatics (:func:`mechsynth.dynamics.kinetostatics`,
solved symbolically group by group), the model every other force figure of the package uses.
"""

from __future__ import annotations

import functools
import time
from collections import OrderedDict

import numpy as np

from ...dynamics.inertia import kinetic_energy
from ...dynamics.kinetostatics import kinetostatics
from ...dynamics.loads import Gravity
from ...kinematics import ops
from ...objectives import kinematic as ob
from ...objectives.base import CycleMeasure
from ...objectives.clearances import clearance
from ...units import deg
from .design import MASSES, inertias_for
from .forces import housing_load

__all__ = [
    "VARIABLES",
    "blow_energy",
    "blow_work",
    "peak_transverse_force",
    "peak_joint_force",
    "HOUSING",
    "housing_clearances",
    "impact_problem",
    "synthesize",
    "pareto_front",
    "summary_lines",
    "pareto_figure",
]

#: the design variables and their ranges (m, rad)
VARIABLES = {
    "OA": (0.006, 0.016),
    "AB": (0.045, 0.080),
    "DB": (0.025, 0.050),
    "K_along": (-0.070, 0.0),
    "K_left": (-0.070, 0.0),
    "KN": (0.040, 0.110),
    "N_guide_angle": (deg(60.0), deg(120.0)),
    "N_guide_offset": (-0.160, -0.110),
}


#: refinement slots of the problem's program, allocated once (``Problem(slots=...)``): the
#: program is costly to build (the symbolic kinetostatics, 1-3 s and 110-160 MB each), and the
#: ladder of 16, 32, 64, 128 slots built up to four programs per candidate, each solve after a
#: new one started cold. With the angles moved along their peaks the certified candidates hold
#: 17-34 refinement angles, some a few 1e-8 rad apart (peaks at one dead centre); those share
#: a slot when the angles outnumber the slots, so the 32 suffice for every candidate of the
#: synthesis and its front (one outgrew them and built a program of 64). The slots change the
#: program's size and so the solves' paths: with 48, the synthesis' third start certified the
#: 29.73 J optimum of the first instead of 30.01 J
SLOTS = 32


#: the force models of the last designs evaluated, by design and by (masses, tilt): the
#: measures of one design (the energy, the work, the joint forces; the certification evaluates
#: each over the dense grid and at every step of its 1-D searches) share one model instead of
#: building it for every call (a model is a function of these numbers alone). Each entry holds
#: its design, so the design's identity is not reused while it is cached
_MODELS: OrderedDict = OrderedDict()
_MODELS_SIZE = 4


def _model(mech, masses, tilt=None):
    """The force model of ``mech`` with the bodies' ``masses`` and, unless ``tilt`` is None,
    gravity at that tilt (built once per design and numbers; a symbolic design's model is
    built once per program anyway and is not kept)."""
    loads = () if tilt is None else [Gravity(tilt=tilt)]
    if ops.is_symbolic(*mech.parameters.values()):
        return mech.force_model(inertias_for(mech, masses), loads)
    entry = _MODELS.get(id(mech))
    if entry is None or entry[0] is not mech:
        entry = _MODELS[id(mech)] = (mech, {})
        while len(_MODELS) > _MODELS_SIZE:
            _MODELS.popitem(last=False)
    else:
        _MODELS.move_to_end(id(mech))
    key = (tuple(sorted(masses.items())), tilt)
    model = entry[1].get(key)
    if model is None:
        model = entry[1][key] = mech.force_model(inertias_for(mech, masses), loads)
    return model


def _bodies(mech, masses, drive_inertia):
    model = _model(mech, masses)
    return list(model.bodies.values()), model


def _j_and_u(mech, motion, masses, drive_inertia, striker="N"):
    bodies, _ = _bodies(mech, masses, drive_inertia)
    w = motion.omega
    j = 2.0 * kinetic_energy(motion, bodies) / (w * w) + drive_inertia
    v = motion.sliders[striker].velocity
    return j, v / w, v


def blow_energy(tool_mass, restitution, drive_inertia, masses=None) -> CycleMeasure:
    """Energy (J) a blow at each crank angle would give the tool; ``reduce="max"``."""
    masses = MASSES if masses is None else masses
    mt, e = float(tool_mass), float(restitution)

    def per_angle(mech, motion):
        j, u, v = _j_and_u(mech, motion, masses, drive_inertia)
        d = j + mt * u * u
        return 0.5 * mt * (1.0 + e) ** 2 * v * v * j * j / (d * d)

    return CycleMeasure("blow energy", per_angle, "max", "J")


def blow_work(tool_mass, restitution, drive_inertia, masses=None) -> CycleMeasure:
    """Kinetic energy (J) the machine loses in a blow at each crank angle; ``reduce="max"``."""
    masses = MASSES if masses is None else masses
    mt, e = float(tool_mass), float(restitution)

    def per_angle(mech, motion):
        j, u, _ = _j_and_u(mech, motion, masses, drive_inertia)
        w = motion.omega
        k = (j - e * mt * u * u) / (j + mt * u * u)
        return 0.5 * j * w * w * (1.0 - k * k)

    return CycleMeasure("energy per blow from the machine", per_angle, "max", "J")


def _forces(mech, motion, masses, tilt):
    model = _model(mech, masses, float(tilt))
    return model, kinetostatics(model, motion)


def _transverse(mech, motion, masses, tilt):
    model, res = _forces(mech, motion, masses, tilt)
    rho = mech.parameters["N_guide_angle"]
    hx, hy = housing_load(model, res)
    return -hx * ops.sin(rho) + hy * ops.cos(rho)


def peak_joint_force(masses=None, tilt=0.0, joints=("O", "A", "B", "D", "K", "N")):
    """Peak magnitude (N) of the joint forces over the cycle; smooth branches: the squared
    magnitudes."""
    masses = MASSES if masses is None else masses

    def squares(mech, motion):
        _, res = _forces(mech, motion, masses, tilt)
        f = res.reactions
        return tuple(f[j][0] * f[j][0] + f[j][1] * f[j][1] for j in joints)

    def per_angle(mech, motion):
        sq = squares(mech, motion)
        out = sq[0]
        for x in sq[1:]:
            out = ops.fmax(out, x)
        return ops.sqrt(out)

    return CycleMeasure(
        f"peak joint force {'/'.join(joints)}", per_angle, "max", "N", squares, outer="sqrt"
    )


def peak_transverse_force(masses=None, tilt=0.0) -> CycleMeasure:
    """Peak magnitude (N) of the mechanism's load on the housing across the striker's guide."""
    masses = MASSES if masses is None else masses

    def per_angle(mech, motion):
        return ops.fabs(_transverse(mech, motion, masses, tilt))

    def branches(mech, motion):
        t = _transverse(mech, motion, masses, tilt)
        return (t, -t)

    return CycleMeasure("peak transverse housing force", per_angle, "max", "N", branches)


#: The machine's case around the six-link (an assumption: paper 001 gives no dimensions, like
#: every number of the representative machine, :mod:`.design`). A rectangle in the mechanism's
#: frame (O at the origin, the rocker's pivot D on +x), m: the representative six-link's moving
#: joints A, B, K over a turn (x -11 to 140 mm, y -19.5 to 32.8 mm) with 16 mm all round (a
#: 6 mm pin boss and 10 mm free), rounded out to 190 x 85 mm -- the inner section of a
#: breaker's gear case of the 15-20 J class. The striker N runs on in its barrel through the
#: case's wall on the tool's side and is not bounded by it; A, on the crank circle of at most
#: 16 mm (:data:`VARIABLES`), cannot reach a wall.
HOUSING = {"x_min": -0.030, "x_max": 0.160, "y_min": -0.035, "y_max": 0.050, "boss": 0.006}

#: the housing walls' far centre: the distance of a joint from a wall is the clearance of the
#: straight line through it, parallel to the wall, from a circle of this radius tangent to the
#: wall on its outside (exact while the joint lies within this distance of the wall)
_FAR = 1.0


def housing_clearances(housing=None, points=("B", "K")) -> list:
    """Constraints keeping ``points`` at least ``housing["boss"]`` (m) inside the case
    :data:`HOUSING` (or ``housing``, a dict of the same keys): one
    :func:`~mechsynth.objectives.clearances.clearance` per point and wall, the signed distance
    of the point from the wall (positive inside), certified over the continuous crank angle
    like every peak."""
    from ...errors import MechanismError

    h = dict(HOUSING if housing is None else housing)
    missing = {"x_min", "x_max", "y_min", "y_max", "boss"} - set(h)
    if missing:
        raise MechanismError(f"housing: give {', '.join(sorted(missing))} (m)")
    if not (h["x_min"] < h["x_max"] and h["y_min"] < h["y_max"] and h["boss"] >= 0.0):
        raise MechanismError(f"housing: need x_min < x_max, y_min < y_max and boss >= 0 m, got {h}")
    walls = (  # (side, the far circle's centre, the wall's direction)
        ("left", (h["x_min"] - _FAR, 0.0), np.pi / 2),
        ("right", (h["x_max"] + _FAR, 0.0), np.pi / 2),
        ("bottom", (0.0, h["y_min"] - _FAR), 0.0),
        ("top", (0.0, h["y_max"] + _FAR), 0.0),
    )
    return [
        clearance(p, circle=(c, _FAR), direction=d, name=f"{p} from the housing's {side} wall")
        >= h["boss"]
        for p in points
        for side, c, d in walls
    ]


@functools.lru_cache(maxsize=8)
def _measures(tool_mass, restitution, jd, masses, tilt, housing):
    """The problem's measures, made once per set of numbers: problems built again with the same
    numbers (the synthesis, its re-solve, the Pareto front) then share their measures, so the
    synthesis engine builds their program once (it knows measures by identity)."""
    masses = dict(masses)
    return (
        blow_energy(tool_mass, restitution, jd, masses),
        blow_work(tool_mass, restitution, jd, masses),
        peak_joint_force(masses, tilt),
        peak_transverse_force(masses, tilt),
        ob.stroke("N"),
        ob.min_transmission_angle("B"),
        ob.max_pressure_angle("N"),
        tuple(housing_clearances(dict(housing))) if housing else (),
    )


def _measure_key(machine, masses, housing):
    """The numbers :func:`_measures` is made from (hashable)."""
    if housing is True:
        housing = HOUSING
    if housing:
        housing_clearances(housing)  # checked here, with its message
        housing = tuple(sorted((k, float(v)) for k, v in dict(housing).items()))
    return (
        float(machine.tool.mass),
        float(machine.tool.restitution),
        float(machine.drive_inertia()),
        tuple(sorted(masses.items())),
        float(machine.tilt),
        housing or None,
    )


def impact_problem(
    machine,
    *,
    stroke=0.040,
    min_transmission_deg=40.0,
    max_joint_force=9000.0,
    motor_power=None,
    angles=48,
    variables=None,
    exact_stroke=False,
    housing=True,
):
    """The certified problem over the six-link ``machine``'s dimensions (:data:`VARIABLES`):
    maximize :func:`blow_energy` at the machine's speed (blows per minute), subject to the
    striker's stroke, transmission angles at B and at the striker (``>=
    min_transmission_deg``), the peak joint force at O, A, B, D, K, N (``<= max_joint_force``
    N) and the motor: the energy a blow takes from the machine at most the motor's rated power
    times the time of a turn (``motor_power`` W; default the assumed motor's).

    The stroke is bounded from above (``<= stroke`` m), not fixed: a longer stroke gives a
    faster striker, so the bound is active at the optimum (:func:`synthesize` checks it and
    solves again with ``== stroke`` if not), and the upper bound is a smooth constraint (one
    row per grid angle) where an equality of the grid's max minus min is not: IPOPT reached
    its iteration limit on two of three starts with it. ``exact_stroke=True``: ``== stroke``.

    ``housing``: the moving joints inside the machine's case (:func:`housing_clearances`): True
    (default) for :data:`HOUSING`, a dict of its keys for another case, False for none."""
    from ... import validate
    from ...errors import MechanismError
    from ...synthesis.problem import Problem
    from .drive import MOTOR_ASSUMPTION, ImpactMachine

    if not isinstance(machine, ImpactMachine):
        raise MechanismError(f"machine must be an ImpactMachine, got {machine!r}")
    stroke = validate.positive("stroke", stroke, "m")
    max_joint_force = validate.positive("max_joint_force", max_joint_force, "N")
    mu = validate.number("min_transmission_deg", min_transmission_deg, "deg")
    if not 0.0 <= mu < 90.0:  # a transmission angle is folded into [0, 90] deg
        raise MechanismError(
            "min_transmission_deg must lie in [0, 90) deg (a transmission angle is at most "
            f"90 deg), got {min_transmission_deg}"
        )
    if motor_power is not None:
        motor_power = validate.positive("motor_power", motor_power, "W")
    if "N" not in machine.inertias:
        raise MechanismError(
            "the machine's inertias give no striker N (its mass enters the blow): e.g. "
            "machines.impact.design.representative_machine('six')"
        )
    masses = dict(MASSES)
    masses.update({"striker": float(machine.inertias["N"][0])})
    p_motor = MOTOR_ASSUMPTION["rated_power_W"] if motor_power is None else float(motor_power)
    energy, work, joints, _, stroke_m, mu_b, pressure_n, walls = _measures(
        *_measure_key(machine, masses, housing)
    )
    prob = Problem(
        machine.linkage,
        variables=dict(VARIABLES if variables is None else variables),
        speed=machine.omega,
        angles=angles,
        slots=SLOTS,
    )
    prob.maximize(energy)
    prob.subject_to(
        (stroke_m == stroke) if exact_stroke else (stroke_m <= stroke),
        mu_b >= deg(min_transmission_deg),
        pressure_n <= deg(90.0 - min_transmission_deg),
        joints <= max_joint_force,
        work <= p_motor * 60.0 / machine.speed_rpm,
        *walls,
    )
    return prob, masses


def synthesize(machine, starts=3, x0=None, **options) -> dict:
    """Solve :func:`impact_problem` (IPOPT, ``starts`` multi-starts, certified); returns a dict:
    the status, the optimum's variables and blow energy, the representative design's values,
    the certification and the checks of the optimum on the exact model (the blow by
    :mod:`.impact` with the anvil where the energy peaks, stroke, angles, peak forces) and
    ``"result"``, the :class:`~mechsynth.synthesis.Result` (not for JSON; the first anchor of
    :func:`pareto_front`). ``x0``: an optional first start ``{variable: value}`` (the others
    are Sobol points)."""
    prob, masses = impact_problem(machine, **options)
    t = time.perf_counter()
    res = prob.solve(starts=starts, progress=False, x0=x0)
    stroke_bound = "== stroke" if options.get("exact_stroke") else "not reached"
    if res.success and not options.get("exact_stroke"):
        c = next(c for c in res.constraints if c.name.startswith("stroke("))
        required, reached = c.bound, c.value  # the certified stroke
        stroke_bound = "active"
        if reached < required * (1.0 - 1e-6):  # a shorter stroke gave more: hold it at the stroke
            prob, masses = impact_problem(machine, **{**options, "exact_stroke": True})
            res = prob.solve(starts=1, progress=False, x0=res.variables)
            stroke_bound = (
                f"inactive at {reached * 1e3:.3f} mm: solved again with the stroke held at "
                f"{required * 1e3:g} mm"
            )
    start = prob.evaluate(machine.linkage)
    out = {
        "result": res,
        "status": res.status,
        "success": bool(res.success),
        "blow_energy_J": float(res.value) if res.success else None,
        "variables": {k: float(v) for k, v in (res.variables or {}).items()},
        "solve_time_s": time.perf_counter() - t,
        "certification": res.report().split("certification", 1)[-1].splitlines()[0].strip(" :()"),
        "stroke_bound": stroke_bound,
        "limits": {
            "stroke_m": options.get("stroke", 0.040),
            "min_transmission_deg": options.get("min_transmission_deg", 40.0),
            "max_joint_force_N": options.get("max_joint_force", 9000.0),
            "speed_rpm": machine.speed_rpm,
            "housing_m": _housing_of(options.get("housing", True)),
        },
        "representative": {
            "blow_energy_J": float(start["blow energy"]),
            "variables": {k: float(machine.linkage.parameters[k]) for k in VARIABLES},
        },
        "report": res.report(),
    }
    if res.success:
        out["check"] = _check(machine, res.design, masses)
        walls = [c for c in res.constraints if "housing" in c.name]
        if walls:
            closest = min(walls, key=lambda c: c.value)
            out["check"]["housing_clearance_m"] = float(closest.value)
            joint, wall = closest.name.split(" >=")[0].split(" from the housing's ")
            out["check"]["housing_closest"] = f"{joint} to the {wall}"
    return out


def _housing_of(housing):
    if housing is True:
        return dict(HOUSING)
    return dict(housing) if housing else None


def pareto_front(
    machine, n=5, starts=1, anchor_starts=3, anchor_x0=None, optimum=None, **options
) -> dict:
    """The Pareto front of the blow energy (maximized) against the peak load across the tool
    axis on the housing (minimized), over :func:`impact_problem`'s feasible set, by the package's
    epsilon-constraint sweep (:func:`mechsynth.synthesis.pareto.pareto_front`): every point a
    certified solve. ``optimum``: :func:`synthesize`'s output with the same options, whose
    result is then the energy's anchor (not solved again). Returns ``front.to_dict()`` plus the
    solve time."""
    from ...synthesis.pareto import pareto_front as sweep

    # the stroke held at the requirement: the loads fall with the stroke, so an upper bound
    # would not be active towards the low-load end of the front
    prob, masses = impact_problem(machine, **{"exact_stroke": True, **options})
    # the problem's own measure objects, so the anchors and points share built programs
    energy = prob.objective
    transverse = _measures(*_measure_key(machine, masses, options.get("housing", True)))[3]
    t = time.perf_counter()
    front = sweep(
        prob,
        energy,
        transverse,
        n=int(n),
        senses=("max", "min"),
        starts=int(starts),
        anchor_starts=int(anchor_starts),
        progress=False,
        anchor_x0=anchor_x0,
        first_anchor=None if optimum is None else optimum["result"],
    )
    d = front.to_dict()
    d["solve_time_s"] = time.perf_counter() - t
    d["n_success"] = int(np.sum(front.success))
    d["n_nondominated"] = int(np.sum(front.nondominated))
    return d


def _stroke_phrase(o):
    h = f"{o['limits']['stroke_m'] * 1e3:g} mm"
    if o["stroke_bound"] == "== stroke":
        return f"stroke == {h}"
    return f"stroke <= {h} (bound {o['stroke_bound']})"


def _housing_phrase(h):
    if not h:
        return ""
    return (
        f", B and K >= {h['boss'] * 1e3:g} mm inside the {(h['x_max'] - h['x_min']) * 1e3:g} x "
        f"{(h['y_max'] - h['y_min']) * 1e3:g} mm housing"
    )


def summary_lines(synth: dict) -> list[str]:
    """The synthesis and the front in a few lines of the study's summary."""
    o = synth["optimum"]
    lim = o["limits"]
    lines = [
        f" synthesis (certified IPOPT, 8 dimensions): maximize the blow energy at "
        f"{lim['speed_rpm']:g} blows/min, {_stroke_phrase(o)}, transmission "
        f">= {lim['min_transmission_deg']:g} deg, joint forces <= {lim['max_joint_force_N']:g} N, "
        f"the motor's rated power{_housing_phrase(lim.get('housing_m'))}: {o['status']} in "
        f"{o['solve_time_s']:.1f} s"
    ]
    if o["success"]:
        c = o["check"]
        lines.append(
            f"   {o['representative']['blow_energy_J']:.2f} J (representative) -> "
            f"{o['blow_energy_J']:.2f} J; checked by the blow model: "
            f"{c['energy_delivered_J']:.2f} J at {c['impact_velocity']:.3f} m/s, stroke "
            f"{c['stroke'] * 1e3:.3f} mm, transmission "
            f"{c['min_transmission_B_deg']:.2f} deg, peak joint force "
            f"{c['peak_joint_force_N']:.0f} "
            f"N, transverse {c['transverse_peak_N']:.0f} N"
            + (
                f", {c['housing_closest']} {c['housing_clearance_m'] * 1e3:.2f} mm"
                if "housing_clearance_m" in c
                else ""
            )
        )
        lines.append(
            "   "
            + ", ".join(
                f"{k} {v * 1e3:.2f} mm" if "angle" not in k else f"{k} {np.degrees(v):.2f} deg"
                for k, v in o["variables"].items()
            )
        )
    p = synth.get("pareto")
    if p is not None:
        pts = [q for q in p["points"] if q["success"]]
        lines.append(
            f" Pareto front (blow energy against the peak transverse housing force): "
            f"{p['n_success']} of {len(p['points'])} points solved, {p['n_nondominated']} "
            f"non-dominated, {p['solve_time_s']:.1f} s"
        )
        for q in sorted(pts, key=lambda q: q["second"]):
            lines.append(f"   transverse {q['second']:8.1f} N  ->  blow {q['first']:.2f} J")
    return lines


def pareto_figure(synth: dict):
    """The front: blow energy against the peak transverse housing force, the representative
    design and the synthesis optimum marked."""
    import matplotlib.pyplot as plt

    from ...plotting import PALETTE

    p = synth["pareto"]
    o = synth["optimum"]
    fig, ax = plt.subplots(figsize=(8, 5), layout="constrained")
    pts = [q for q in p["points"] if q["success"]]
    nd = sorted([q for q in pts if q["nondominated"]], key=lambda q: q["second"])
    ax.plot(
        [q["second"] for q in nd],
        [q["first"] for q in nd],
        "-o",
        color=PALETTE[4],
        ms=5,
        label="non-dominated designs (certified)",
    )
    dom = [q for q in pts if not q["nondominated"]]
    if dom:
        ax.plot(
            [q["second"] for q in dom],
            [q["first"] for q in dom],
            "o",
            mfc="none",
            color="0.5",
            label="dominated",
        )
    if o["success"]:
        ax.plot(
            [o["check"]["transverse_peak_N"]],
            [o["blow_energy_J"]],
            "s",
            ms=9,
            mfc="none",
            color=PALETTE[5],
            label="synthesis optimum (no transverse limit)",
        )
    ax.set_xlabel("peak load across the tool axis on the housing, N")
    ax.set_ylabel("blow energy, J")
    ax.margins(0.1)
    ax.set_title(
        "six-link: blow energy against the transverse housing load "
        f"({p['n_success']} of {len(p['points'])} points solved)",
        fontsize=10,
    )
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return fig


def _check(machine, design, masses):
    from .forces import force_findings

    phi = np.linspace(0.0, 2 * np.pi, 2048, endpoint=False)
    m = machine.replace(
        linkage=design, inertias=inertias_for(design, masses), anvil=None, sense=None
    )
    mo = design.motion(phi, speed=machine.omega)
    mu = np.asarray(mo.transmission_angles["B"])
    e = blow_energy(machine.tool.mass, machine.tool.restitution, machine.drive_inertia(), masses)
    k = int(np.argmax(e.samples(design, mo)))
    from .impact import striker_track

    s, u, _, _ = striker_track(design, "N", phi[k])
    m = m.replace(anvil=float(s), sense=1 if float(u) > 0 else -1)
    b = m.blow()
    f = force_findings(m, n=720)
    return {
        "blow_angle_deg": float(np.degrees(phi[k])),
        "energy_delivered_J": b.energy_delivered,
        "impact_velocity": b.striker_before,
        "stroke": float(np.ptp(mo.sliders["N"].position)),
        "min_transmission_B_deg": float(np.degrees(np.min(np.minimum(mu, np.pi - mu)))),
        "max_pressure_N_deg": float(np.degrees(np.max(mo.pressure_angles["N"]))),
        "peak_joint_force_N": max(p["max_N"] for p in f["peaks"].values()),
        "transverse_peak_N": f["transverse_peak_N"],
    }
