"""Paper 001: percussive machines of variable structure -- the six-link and five-link impact
mechanisms against the base crank-rocker, driven by an induction motor, with the blow.

The representative machine (every number an assumption: the paper prints none) is described in
:mod:`mechsynth.machines.impact.design` (``SOURCES``). What is computed: the six-link for rho =
57, 90 and 123 deg (the paper's curves of V_N against V_K and of a_N against a_K^t), its findings
at the special position, the printed formulas (1)-(12), (20)-(21) against the exact model (the
errata); the five-link with its involute against a circular arc (side load on the guide); the
forces over the cycle and the load across the tool axis on the housing against the base
crank-rocker; the blow (Newton's law, the crank's speed jump, the joint impulses); the motor-
driven machine: steady state (solve_ivp and the paper's energy stepping), start-up from rest,
speed fluctuation and the flywheel for a required one; the synthesis and the Pareto front of
impact energy against the peak transverse housing force.
"""

from __future__ import annotations

import csv
import time

import numpy as np

from ..fileio import atomic
from ..machines.impact.design import MASSES, SOURCES, representative_machine
from ..machines.impact.drive import (
    MOTOR_ASSUMPTION,
    motor_for,
    size_flywheel,
    start_up,
    steady_state,
)
from ..machines.impact.forces import cycle_forces, force_findings
from ..machines.impact.impact import Tool
from ..machines.impact.model import guide_offset_from_D
from ..machines.impact.paper001 import ERRATA, check_five_link, check_six_link, rho_finding
from ..options import Option, takes_options
from ..progress import Stages
from ..report import StudyResult
from ..units import deg, rpm, to_rpm
from .coverage import Coverage, Item

__all__ = ["run", "STAGES", "COVERAGE"]

#: the extra rod's lengths (m) and the guide angles (deg) of the conclusions 3-4 charts
EXTRA_RODS = (0.05, 0.055, 0.06, 0.065, 0.07, 0.075, 0.08, 0.085, 0.09)
SUPPORT_RHOS = tuple(float(r) for r in range(50, 131, 5))
#: the rocker's width for its profile (Fig. 13), m
ROCKER_WIDTH = 0.010

STAGES = (
    "six-link kinematics and the paper's formulas",
    "five-link and forces",
    "the blow",
    "motor-driven dynamics",
    "synthesis and Pareto front",
    "figures, tables, animation",
)


@takes_options(
    Option("angles", 720, "crank positions per turn", minimum=36, maximum=100_000),
    Option(
        "rho_deg",
        (57.0, 90.0, 123.0),
        "guide angles rho of the six-link",
        unit="deg",
        minimum=10.0,
        maximum=170.0,
    ),
    Option(
        "speed_rpm",
        2000.0,
        "crank speed = blows per minute",
        unit="rpm",
        minimum=0.0,
        exclusive=True,
    ),
    Option("striker_mass", 3.0, "striker mass", unit="kg", minimum=0.0, exclusive=True),
    Option("tool_mass", 1.0, "tool (chisel) mass", unit="kg", minimum=0.0, exclusive=True),
    Option("restitution", 0.5, "coefficient of restitution striker-tool", minimum=0.0, maximum=1.0),
    Option("flywheel", 0.01, "flywheel on the crankshaft", unit="kg m^2", minimum=0.0),
    Option("psi_deg", 0.0, "machine tilt to the horizontal", unit="deg"),
    Option("gamma_deg", 0.0, "mechanism tilt in the housing", unit="deg"),
    Option(
        "delta",
        0.05,
        "required speed fluctuation for the flywheel sizing",
        minimum=0.0,
        exclusive=True,
        maximum=1.0,
    ),
    Option(
        "startup_s",
        0.6,
        "duration of the start-up from rest",
        unit="s",
        minimum=0.0,
        exclusive=True,
        maximum=10.0,
    ),
    Option("synthesis", True, "run the synthesis and the Pareto front"),
    Option(
        "pareto_points",
        5,
        "points of the Pareto front of blow energy against transverse housing force "
        "(0: skip; each point is a certified solve, some 20 s each)",
        minimum=0,
        maximum=40,
    ),
    owner="study 'impact'",
)
def run(
    out=None,
    angles=720,
    rho_deg=(57.0, 90.0, 123.0),
    speed_rpm=2000.0,
    striker_mass=3.0,
    tool_mass=1.0,
    restitution=0.5,
    flywheel=0.01,
    psi_deg=0.0,
    gamma_deg=0.0,
    delta=0.05,
    startup_s=0.6,
    synthesis=False,
    pareto_points=5,
):
    """Run the study (options as declared; SI unless a unit is named)."""
    stages = STAGES if synthesis else tuple(s for s in STAGES if not s.startswith("synthesis"))
    if out is None:
        stages = stages[:-1]
    if int(pareto_points) == 1:
        raise ValueError("study 'impact': option pareto_points must be 0 (skip) or at least 2")
    o = dict(
        angles=int(angles),
        rho_deg=tuple(float(r) for r in rho_deg),
        speed_rpm=float(speed_rpm),
        striker_mass=float(striker_mass),
        tool_mass=float(tool_mass),
        restitution=float(restitution),
        flywheel=float(flywheel),
        psi=deg(float(psi_deg)),
        gamma=deg(float(gamma_deg)),
        delta=float(delta),
        startup_s=float(startup_s),
        synthesis=bool(synthesis),
        pareto_points=int(pareto_points),
    )
    with Stages("impact", stages) as st:
        return _run(out, o, st)


def _machine(kind, o, rho=90.0):
    masses = dict(MASSES)
    masses["striker"] = o["striker_mass"]
    from ..machines.impact.design import inertias_for

    m = representative_machine(
        kind,
        rho,
        tool=Tool(o["tool_mass"], o["restitution"]),
        flywheel=o["flywheel"],
        psi=o["psi"],
        gamma=o["gamma"],
        speed_rpm=o["speed_rpm"],
    )
    return m.replace(inertias=inertias_for(m.linkage, masses))


def _xy(p, i=0):
    return [float(np.ravel(p.x)[i]), float(np.ravel(p.y)[i])]


def _six_entry(m, phi, w):
    lk = m.linkage
    p = lk.parameters
    mo = lk.motion(phi, speed=w)
    m0 = lk.motion(np.array([0.0]))
    f = cycle_forces(m, phi, w)
    mu = np.asarray(mo.transmission_angles["B"])
    rho = float(p["N_guide_angle"])
    h_o = float(p["N_guide_offset"])
    guide_point = [-h_o * np.sin(rho), h_o * np.cos(rho)]  # foot of O's perpendicular
    design = {
        "O": [0.0, 0.0],
        "D": [float(p["D_x"]), float(p["D_y"])],
        "OA": float(p["OA"]),
        "AB": float(p["AB"]),
        "DB": float(p["DB"]),
        "DK": float(np.hypot(p["K_along"], p["K_left"])),
        "K_along": float(p["K_along"]),
        "K_left": float(p["K_left"]),
        "KN": float(p["KN"]),
        "guide_point": [float(v) for v in guide_point],
        "guide_angle_deg": float(np.degrees(rho)),
        "guide_offset_from_D": float(guide_offset_from_D(lk)),
        "speed_rpm": float(to_rpm(w)),
    }
    return (
        {
            "rho_deg": float(np.degrees(rho)),
            "design": design,
            "points_at_0": {k: _xy(m0.points[k]) for k in ("A", "B", "K", "N")},
            "stroke": float(np.ptp(mo.sliders["N"].position)),
            "peak_velocity": float(np.max(np.abs(mo.sliders["N"].velocity))),
            "peak_acceleration": float(np.max(np.abs(mo.sliders["N"].acceleration))),
            "peak_guide_force": float(np.max(np.abs(f.guide))),
            "max_pressure_angle_deg": float(np.degrees(np.max(mo.pressure_angles["N"]))),
            "min_transmission_angle_B_deg": float(np.degrees(np.min(np.minimum(mu, np.pi - mu)))),
        },
        mo,
        f,
    )


def _run(out, o, stages):
    t0 = time.perf_counter()
    w = rpm(o["speed_rpm"])
    phi = np.linspace(0.0, 2 * np.pi, o["angles"], endpoint=False)

    # 1. six-link at each rho: kinematics, the paper's formulas, findings at the special position
    stages.next(STAGES[0])
    six, motions, six_forces, findings, formulas = [], {}, {}, [], {}
    for rho in o["rho_deg"]:
        m = _machine("six", o, rho)
        entry, mo, f = _six_entry(m, phi, w)
        six.append(entry)
        motions[rho], six_forces[rho] = mo, f
        findings.append(rho_finding(m.linkage, w))
        formulas[f"{rho:g}"] = check_six_link(m.linkage, phi, w)

    # 2. five-link (involute and arc) and the forces against the base machine
    stages.next(STAGES[1])
    machines = {k: _machine(k, o) for k in ("six", "five", "arc", "base")}
    five = {}
    for k in ("five", "arc"):
        mo = machines[k].linkage.motion(phi, speed=w)
        f = cycle_forces(machines[k], phi, w)
        five[k] = {
            "profile": "involute" if k == "five" else "circular arc",
            "stroke": float(np.ptp(mo.sliders["N"].position)),
            "peak_velocity": float(np.max(np.abs(mo.sliders["N"].velocity))),
            "peak_acceleration": float(np.max(np.abs(mo.sliders["N"].acceleration))),
            "peak_guide_force": float(np.max(np.abs(f.guide))),
            "max_pressure_angle_deg": float(np.degrees(np.max(mo.pressure_angle))),
            "base_radius": float(
                machines[k].linkage.parameters.get("N_profile_base_radius", np.nan)
            ),
        }
    five_formulas = check_five_link(machines["five"].linkage, phi, w)
    forces = {k: force_findings(m, n=o["angles"]) for k, m in machines.items()}
    cyc = {k: cycle_forces(m, phi, w) for k, m in machines.items()}

    fnd = _findings(machines, o)

    # 3. the blow at the nominal speed
    stages.next(STAGES[2])
    blows = {k: m.blow().as_dict() for k, m in machines.items()}

    # 4. the motor-driven six-link at rho = 90 deg
    stages.next(STAGES[3])
    head = machines["six"]
    motor = motor_for(head)
    head = head.replace(gear_ratio=motor.gear_ratio)
    ivp = steady_state(head, motor)
    step = steady_state(head, motor, method="stepping")
    su = start_up(head, motor, duration=o["startup_s"])
    j_fly, fly_state = size_flywheel(head, o["delta"], motor)
    e_blow = ivp.blow.energy_delivered + ivp.blow.energy_lost
    dynamics = {
        "motor": {
            **MOTOR_ASSUMPTION,
            "gear_ratio": float(motor.gear_ratio),
            "critical_slip": float(motor.critical_slip),
            "breakdown_torque_Nm": float(motor.breakdown_torque),
        },
        "steady_state": ivp.summary(),
        "stepping": step.summary(),
        "stepping_vs_ivp_max_rel": float(np.max(np.abs(step.omega / ivp.omega - 1.0))),
        "quartic_positive_roots": sorted({int(c) for c in step.positive_roots}),
        "start_up": {
            "duration_s": o["startup_s"],
            "blows": int(su.blows.shape[0]),
            "time_to_95pct_s": su.time_to(0.95, ivp.omega_mean),
            "first_blow_energy_J": float(su.blows[0, 3]) if su.blows.size else None,
        },
        "flywheel": {
            "delta_target": o["delta"],
            "flywheel_kgm2": j_fly,
            "delta": fly_state.delta,
            "energy_delivered_J": fly_state.blow.energy_delivered,
            "energy_method_kgm2": float(
                e_blow / (o["delta"] * ivp.omega_mean**2) - head.drive_inertia() + head.flywheel
            ),
            "current_flywheel_kgm2": o["flywheel"],
            "current_delta": ivp.delta,
        },
    }

    synth = None
    if o["synthesis"]:
        stages.next(STAGES[4])
        from ..machines.impact.synthesis import pareto_front, synthesize

        optimum = synthesize(head)
        synth = {"optimum": optimum, "pareto": None}
        if o["pareto_points"] >= 2:  # the synthesis is the front's energy anchor
            synth["pareto"] = pareto_front(head, o["pareto_points"], optimum=optimum)
        del optimum["result"]  # the Result object: not for the JSON

    files = []
    if out is not None:
        stages.next(STAGES[-1])
        files = _write(out, o, phi, w, six, motions, six_forces, machines, cyc, ivp, su, synth)
        files += _write_findings(out, o, phi, cyc, fnd)

    lines = _summary(
        o, six, findings, formulas, five, five_formulas, forces, blows, dynamics, synth
    )
    lines.extend(_findings_lines(fnd))
    lines.append(f" run time {time.perf_counter() - t0:.1f} s")
    # the run succeeded unless the synthesis (when asked for) failed or no front point solved
    success = synth is None or bool(synth["optimum"]["success"]) and (
        synth["pareto"] is None or any(q["success"] for q in synth["pareto"]["points"])
    )
    data = {
        "success": bool(success),
        "representative": {
            "sources": SOURCES,
            "masses": {k: v for k, v in MASSES.items()},
            "striker_mass": o["striker_mass"],
            "tool_mass": o["tool_mass"],
            "restitution": o["restitution"],
            "speed_rpm": o["speed_rpm"],
        },
        "six_link": six,
        "special_position": findings,
        "paper_formulas": {"six_link": formulas, "five_link": five_formulas},
        "five_link": five,
        "forces": forces,
        "blow": blows,
        "dynamics": dynamics,
        "synthesis": synth,
        "findings": _findings_data(fnd),
    }
    result = StudyResult("impact", "\n".join(lines), data, files, list(ERRATA))
    return COVERAGE.attach(result, out)


def _summary(o, six, findings, formulas, five, five_formulas, forces, blows, dynamics, synth):
    L = ["Paper 001: percussive machines of variable structure (six-link, five-link)"]
    L.append(f" {SOURCES}")
    L.append(
        " six-link   rho deg  stroke mm  peak V_N m/s  peak a_N m/s^2  guide N  "
        "V_N/V_K at the special position (paper)"
    )
    for e, f in zip(six, findings):
        r = max(f["ratio"])
        L.append(
            f"            {e['rho_deg']:7.1f}  {e['stroke'] * 1e3:9.2f}  {e['peak_velocity']:12.3f}"
            f"  {e['peak_acceleration']:14.0f}  {e['peak_guide_force']:7.1f}  {r:.4f} "
            f"(paper: V_N {f['paper']} V_K: {'holds' if f['holds'] else 'refuted'})"
        )
    L.append(" printed six-link formulas (largest deviation over the cycle, relative):")
    first = formulas[next(iter(formulas))]
    for k, row in enumerate(first):
        devs = [formulas[r][k]["printed_deviation"] for r in formulas]
        L.append(
            f"   {row['formula']:5s} {row['quantity']:24s} printed {max(devs):9.3g}  "
            f"corrected {max(formulas[r][k]['corrected_deviation'] for r in formulas):9.3g}"
        )
    for row in five_formulas:
        L.append(
            f"   {row['formula']:5s} {row['quantity'][:24]:24s} printed "
            f"{row['printed_deviation']:9.3g}  corrected {row['corrected_deviation']:9.3g}"
        )
    for v in five.values():
        L.append(
            f" five-link ({v['profile']}): stroke {v['stroke'] * 1e3:.2f} mm, peak guide side "
            f"force {v['peak_guide_force']:.3g} N, max pressure angle "
            f"{v['max_pressure_angle_deg']:.3g} deg"
        )
    L.append(
        " forces at the nominal speed: peak across the tool axis on the housing / peak "
        "joint force (A, B, D) / rocker-striker joint vs four-bar:"
    )
    names = {
        "six": "six-link",
        "five": "five-link involute",
        "arc": "five-link arc",
        "base": "base crank-rocker",
    }
    for k, f in forces.items():
        ratio = f.get("rocker_striker_ratio")
        peaks = ", ".join(
            f"{j} {f['peaks'][j]['max_N']:.0f} N at {f['peaks'][j]['at_deg']:.1f} deg"
            for j in ("A", "B", "D")
        )
        L.append(
            f"   {names[k]:20s} transverse {f['transverse_peak_N']:7.1f} N; {peaks}"
            + (f"; rocker-striker {ratio:.2f} of the four-bar's" if ratio else "")
        )
    dc = ", ".join(f"{d:.1f}" for d in forces["six"]["dead_centres_deg"])
    L.append(
        f"   dead centres (crank and rod in line) at {dc} deg: the joint forces peak "
        f"{forces['six']['peaks']['A']['from_dead_centre_deg']:.1f} deg from one"
    )
    L.append(" blow at the nominal speed (machine along the striker's line against the tool):")
    for k, b in blows.items():
        L.append(
            f"   {names[k]:20s} v {b['striker_before']:.3f} m/s, m_eff "
            f"{b['effective_mass']:.2f} kg, energy to the tool {b['energy_delivered']:.2f} J"
            f", lost {b['energy_lost']:.2f} J, crank {to_rpm(b['omega_before']):.0f} -> "
            f"{to_rpm(b['omega_after']):.0f} rpm"
        )
    d = dynamics
    s = d["steady_state"]
    L.append(f" motor: {MOTOR_ASSUMPTION['note']}; gear ratio {d['motor']['gear_ratio']:.4f}")
    L.append(
        f" steady state (six-link, rho 90): {s['blows_per_minute']:.1f} blows/min, speed "
        f"{s['min_rpm']:.1f}-{s['max_rpm']:.1f} rpm, delta {s['delta']:.4f}, impact velocity "
        f"{s['impact_velocity']:.3f} m/s, {s['energy_delivered']:.2f} J per blow, "
        f"{s['power_delivered_W']:.0f} W to the tool, motor {s['motor_power_W']:.0f} W"
    )
    L.append(
        f"   energy stepping (quartic) against solve_ivp: largest relative speed difference "
        f"{d['stepping_vs_ivp_max_rel']:.2e}; positive real roots per step "
        f"{d['quartic_positive_roots']}"
    )
    su = d["start_up"]
    reached = (
        f"95 % of the steady speed after {su['time_to_95pct_s']:.3f} s"
        if su["time_to_95pct_s"] is not None
        else f"95 % of the steady speed not reached within {su['duration_s']:g} s"
    )
    L.append(f"   start-up from rest: {reached}, {su['blows']} blows in {su['duration_s']:g} s")
    fw = d["flywheel"]
    L.append(
        f"   flywheel for delta = {fw['delta_target']:g}: {fw['flywheel_kgm2']:.4f} kg m^2 "
        f"(simulated; energy-method estimate {fw['energy_method_kgm2']:.4f}), blow "
        f"{fw['energy_delivered_J']:.2f} J"
    )
    if synth is not None:
        from ..machines.impact.synthesis import summary_lines

        L.extend(summary_lines(synth))
    return L


def _write(out, o, phi, w, six, motions, six_forces, machines, cyc, ivp, su, synth):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..plotting import LINESTYLES, PALETTE, crank_axis, style
    from ..plotting import save as save_figure

    files = []

    def save(fig, name):
        files.append(save_figure(fig, out / name, dpi=110))

    d = np.degrees(phi)
    rhos = list(motions)
    with style():
        fig, axes = plt.subplots(2, 1, figsize=(9, 7.5), sharex=True)
        for k, rho in enumerate(rhos):
            mo = motions[rho]
            kw = dict(color=PALETTE[4 + k % 3], ls=LINESTYLES[k % len(LINESTYLES)])
            axes[0].plot(d, mo.sliders["N"].velocity, label=f"V_N, rho = {rho:g} deg", **kw)
            axes[1].plot(
                d, mo.sliders["N"].acceleration / 1e3, label=f"a_N, rho = {rho:g} deg", **kw
            )
        mo = motions[rhos[0]]
        lk = machines["six"].linkage
        arm = float(np.hypot(lk.parameters["K_along"], lk.parameters["K_left"]))
        axes[0].plot(d, mo.links["DB"].omega * arm, color="k", lw=0.8, label="V_K (rocker point K)")
        axes[1].plot(
            d, mo.links["DB"].epsilon * arm / 1e3, color="k", lw=0.8, label="a_K^t (rocker point K)"
        )
        axes[0].set_ylabel("velocity along the guide, m/s")
        axes[1].set_ylabel("acceleration, km/s^2")
        axes[0].set_title(
            f"six-link at {o['speed_rpm']:g} rpm: the striker N against the rocker "
            "point K (paper 001, Figs. 10 and 12)",
            fontsize=9,
        )
        for ax in axes:
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
        crank_axis(axes[1])
        save(fig, "impact_kinematics.png")

        fig, axes = plt.subplots(2, 1, figsize=(9, 7.5), sharex=True)
        f = cyc["six"]
        for k, j in enumerate(("O", "A", "B", "D", "K", "N")):
            # the crank carries O's force to A almost unchanged: O wide and pale under A
            wide = j == "O"
            axes[0].plot(
                d,
                f.result.magnitude(j) / 1e3,
                color=PALETTE[(k + 1) % 8],
                ls=LINESTYLES[k % len(LINESTYLES)],
                lw=4.0 if wide else 1.5,
                alpha=0.45 if wide else 1.0,
                label=f"joint {j}" + (" (under A)" if wide else ""),
            )
        axes[0].set_ylabel("joint force, kN")
        axes[0].set_title(
            f"six-link (rho 90 deg) at {o['speed_rpm']:g} rpm: joint forces", fontsize=9
        )
        names = {"base": "base crank-rocker", "six": "six-link", "five": "five-link involute"}
        for k, key in enumerate(("base", "six", "five")):
            axes[1].plot(
                d,
                cyc[key].transverse,
                color=PALETTE[4 + k],
                ls=LINESTYLES[k % len(LINESTYLES)],
                label=names[key],
            )
        axes[1].set_ylabel("force across the tool axis, N")
        axes[1].set_title("the mechanism's load on the housing across the tool axis", fontsize=9)
        for ax in axes:
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
        crank_axis(axes[1])
        save(fig, "impact_forces.png")

        fig, ax = plt.subplots(figsize=(9, 4.5))
        for k, rho in enumerate(rhos):
            ax.plot(
                d,
                six_forces[rho].guide,
                color=PALETTE[4 + k % 3],
                ls=LINESTYLES[k % len(LINESTYLES)],
                label=f"six-link, rho = {rho:g} deg",
            )
        ax.plot(
            d,
            cyc["arc"].guide,
            color=PALETTE[1],
            ls=LINESTYLES[3 % len(LINESTYLES)],
            label="five-link, circular arc",
        )
        # the involute's side load is zero all turn: a wide band on the zero line, named so
        ax.plot(
            d, cyc["five"].guide, color="k", lw=3.5, alpha=0.35, label="five-link, involute (0)"
        )
        ax.set_ylabel("guide's normal force on the striker, N")
        ax.set_title(f"side load on the striker's guide at {o['speed_rpm']:g} rpm", fontsize=9)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
        crank_axis(ax)
        save(fig, "impact_guide.png")

        fig, axes = plt.subplots(2, 1, figsize=(9, 7))
        axes[0].plot(su.t, to_rpm(su.omega), color=PALETTE[4])
        if su.blows.size:
            axes[0].plot(
                su.blows[:, 0],
                to_rpm(su.blows[:, 2]),
                "v",
                color=PALETTE[6],
                ms=4,
                label="after each blow",
            )
            axes[0].legend(loc="lower right")
        axes[0].set_xlabel("time from switching on, s")
        axes[0].set_ylabel("crank speed, rpm")
        axes[0].set_title(
            "six-link (rho 90 deg): start-up from rest with the assumed motor", fontsize=9
        )
        dd = np.degrees(ivp.phi - ivp.phi[0])
        axes[1].plot(dd, to_rpm(ivp.omega), color=PALETTE[5])
        axes[1].set_xlim(0, 360)
        axes[1].set_xticks(np.arange(0, 361, 45))
        axes[1].set_xlabel("crank angle after the blow, deg")
        axes[1].set_ylabel("crank speed, rpm")
        axes[1].set_title(
            f"steady state: {ivp.blows_per_minute:.0f} blows/min, delta {ivp.delta:.3f}", fontsize=9
        )
        save(fig, "impact_speed.png")

        if synth is not None and synth["pareto"] is not None:
            from ..machines.impact.synthesis import pareto_figure

            fig = pareto_figure(synth)
            save(fig, "impact_pareto.png")

    anim = machines["six"].linkage.animate(frames=36, speed=w, dpi=60)
    files.append(anim.save(out / "impact_six_link.gif"))

    p = out / "impact_six_link.csv"
    with atomic(p, "w", newline="") as fh:
        wr = csv.writer(fh)
        head = ["crank angle [deg]", "V_K [m/s]", "a_K^t [m/s^2]"]
        for rho in rhos:
            head += [
                f"V_N rho {rho:g} [m/s]",
                f"a_N rho {rho:g} [m/s^2]",
                f"guide force rho {rho:g} [N]",
            ]
        wr.writerow(head)
        mo0 = motions[rhos[0]]
        lk = machines["six"].linkage
        arm = float(np.hypot(lk.parameters["K_along"], lk.parameters["K_left"]))
        for i, a in enumerate(d):
            row = [
                a,
                float(mo0.links["DB"].omega[i] * arm),
                float(mo0.links["DB"].epsilon[i] * arm),
            ]
            for rho in rhos:
                mo = motions[rho]
                row += [
                    float(mo.sliders["N"].velocity[i]),
                    float(mo.sliders["N"].acceleration[i]),
                    float(six_forces[rho].guide[i]),
                ]
            wr.writerow(row)
    files.append(p)

    p = out / "impact_forces.csv"
    with atomic(p, "w", newline="") as fh:
        wr = csv.writer(fh)
        joints = list(cyc["six"].result.reactions)
        wr.writerow(
            ["crank angle [deg]"]
            + [f"six-link |{j}| [N]" for j in joints]
            + [f"{k} transverse [N]" for k in cyc]
            + ["six-link torque [N m]"]
        )
        for i, a in enumerate(d):
            wr.writerow(
                [a]
                + [float(cyc["six"].result.magnitude(j)[i]) for j in joints]
                + [float(cyc[k].transverse[i]) for k in cyc]
                + [float(cyc["six"].result.torque[i])]
            )
    files.append(p)

    p = out / "impact_steady_state.csv"
    with atomic(p, "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(["crank angle [deg]", "crank speed [rpm]", "motor torque at the crank [N m]"])
        for a, ww, tq in zip(np.degrees(ivp.phi), to_rpm(ivp.omega), ivp.motor_torque):
            wr.writerow([float(a), float(ww), float(tq)])
    files.append(p)
    return files


def _findings(machines, o):
    """Paper 001's arguments on the study's machines (machines.impact.findings)."""
    from ..machines.impact import findings as F

    rhos = np.radians(o["rho_deg"])
    return {
        "extra_rod": F.extra_rod_effect(machines["six"], EXTRA_RODS, rhos, n=o["angles"] // 2),
        "support": F.support_position_effect(
            machines["six"], np.radians(SUPPORT_RHOS), n=o["angles"] // 2
        ),
        "profile": F.rocker_profile(machines["five"], ROCKER_WIDTH),
        "reduced": F.reduced_terms(machines["five"], n=o["angles"]),
        "gravity": F.gravity_assist(machines["five"]),
        "pairs": F.pair_force_findings(machines["five"], n=o["angles"]),
        "circular": {k: F.circular_links(machines[k]) for k in ("six", "five")},
    }


def _findings_data(f):
    e, s, p = f["extra_rod"], f["support"], f["profile"]
    return {
        "extra_rod": {
            "lengths_m": e["lengths"].tolist(),
            "rows": {
                str(r): {k: v.tolist() for k, v in row.items()} for r, row in e["rows"].items()
            },
            "verdict": {str(r): v for r, v in e["verdict"].items()},
            "unassembled": {str(r): v for r, v in e["unassembled"].items()},
        },
        "support_position": {
            k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in s.items()
        },
        "rocker_profile": {
            "width_m": p["width"],
            "base_radius_m": p["base_radius"],
            "max_rel_difference": p["max_rel_difference"],
            **{k: {"radius_range_m": p[k]["radius_range"]} for k in ("outer", "axis", "inner")},
        },
        "reduced_peaks": {
            "inertia_kgm2": {k: float(np.max(v)) for k, v in f["reduced"]["inertia"].items()},
            "gravity_Nm": {k: float(np.max(np.abs(v))) for k, v in f["reduced"]["gravity"].items()},
        },
        "gravity_assist": f["gravity"],
        "pair_forces": f["pairs"],
        "circular_links": f["circular"],
    }


def _findings_lines(f):
    e, s, p, g, q = (f[k] for k in ("extra_rod", "support", "profile", "gravity", "pairs"))
    L = [" paper 001's arguments (six-link: extra rod and support; five-link: profile, dynamics):"]
    word = {1: "rises", -1: "falls", 0: "flat/not monotone"}
    for r, v in e["verdict"].items():
        t, row = v["trends"], e["rows"][r]
        ok = np.isfinite(row["stroke"])
        gf, sp, st = (row[k][ok] for k in ("peak_guide_force", "peak_velocity", "stroke"))
        L.append(
            f"   K-N {e['lengths'][0] * 1e3:.0f} -> {e['lengths'][-1] * 1e3:.0f} mm at rho {r:g} "
            f"deg: guide force {word[t['peak_guide_force']]} ({gf[0]:.0f} -> {gf[-1]:.0f} N), "
            f"peak speed {word[t['peak_velocity']]} ({sp[0]:.3f} -> {sp[-1]:.3f} m/s), stroke "
            f"{word[t['stroke']]} ({st[0] * 1e3:.1f} -> {st[-1] * 1e3:.1f} mm)"
        )
    v = e["verdict"].values()
    falls = all(x["guide_force_falls"] for x in v)
    rises = [r for r, x in e["verdict"].items() if x["speed_rises"] and x["stroke_rises"]]
    L.append(
        "   conclusion 4 (a longer rod: less guide force, more speed and stroke): guide force "
        f"{'falls at every rho' if falls else 'does not always fall'}; speed and stroke rise at "
        f"rho {', '.join(f'{r:g}' for r in rises) or 'none'} deg of "
        f"{', '.join(f'{r:g}' for r in e['verdict'])}"
    )
    L.append(
        f"   conclusion 3 (support position, rho {SUPPORT_RHOS[0]:g}-{SUPPORT_RHOS[-1]:g} deg): "
        f"least guide force {s['least_guide_force_N']:.0f} N at rho "
        f"{s['least_guide_force_rho_deg']:g} deg; stroke {s['stroke_range'][0] * 1e3:.1f}-"
        f"{s['stroke_range'][1] * 1e3:.1f} mm, peak speed {s['speed_range'][0]:.2f}-"
        f"{s['speed_range'][1]:.2f} m/s"
    )
    L.append(
        f"   rocker profile {p['width'] * 1e3:g} mm wide (Fig. 13): outer, axis and inner "
        f"surfaces are involutes of the {p['base_radius'] * 1e3:g} mm base circle (measured radii "
        f"of curvature equal the involute's to {p['max_rel_difference']:.1e})"
    )
    L.append(
        f"   gravity (Figs. 17-18, tool down): the links' gravity moments drive the crank over the "
        f"{g['assist_arc_deg']:.1f} deg before the blow (from {g['assist_from_deg']:.1f} to "
        f"{g['blow_deg']:.1f} deg), {g['work_over_arc_J']:.2f} J (the paper's 60 deg is in an "
        "origin of crank angle the text does not give)"
    )
    a = q["along_links"]
    L.append(
        f"   joint loads along the links (conclusion 9): A {a['A']['cos_at_peak']:.5f}, B "
        f"{a['B']['cos_at_peak']:.5f} along the rod (cos at the peak); D "
        f"{a['D']['mean_cos_weighted']:.2f} along the rocker (force-weighted mean cos)"
    )
    tdc = ", ".join(f"{t:+.2f}" for t in q["torque_at_dead_centres_Nm"])
    tb = q["torque_before_blow_Nm"]
    L.append(
        f"   driving moment (Fig. 26): {tdc} N m at the rocker's extremes (of "
        f"{q['torque_range_Nm'][0]:.1f}..{q['torque_range_Nm'][1]:.1f} N m), "
        f"{tb[0]:.1f}..{tb[1]:.1f} N m over the 20 deg before the blow (the machine's forces "
        f"drive the crank there over {q['assist_before_blow_fraction']:.0%} of it); "
        "rocker-striker force "
        f"{q['rocker_striker_ratio']:.2f} of the four-bar's"
    )
    c = f["circular"]["five"]
    L.append(
        f"   circular links (Figs. 5, 7): the same motion (a disc in a bore is a revolute pair); "
        f"nesting needs a rocker of {c['rocker_needed'] * 1e3:.0f} mm (8 mm shafts, 3 mm walls),"
        f" this one is {c['rocker'] * 1e3:.0f} mm: {'feasible' if c['feasible'] else 'not'}"
        " embodied so"
    )
    return L


def _write_findings(out, o, phi, cyc, f):
    """Figures and tables of the findings: extra rod and support (conclusions 3-4), the
    five-link's forces (Figs. 25-26), reduced inertias and gravity moments (Figs. 17-18), the
    rocker's profile (Fig. 13)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..plotting import LINESTYLES, PALETTE, crank_axis, style
    from ..plotting import save as save_figure

    files = []
    d = np.degrees(phi)
    e, s = f["extra_rod"], f["support"]
    names = {"OA": "crank (with the flywheel)", "AB": "rod", "DB": "rocker", "N": "striker"}
    with style():
        fig, axes = plt.subplots(2, 2, figsize=(11, 7.5))
        mm = e["lengths"] * 1e3
        for k, (r, row) in enumerate(e["rows"].items()):
            kw = dict(color=PALETTE[4 + k % 3], ls=LINESTYLES[k % len(LINESTYLES)], marker="o")
            axes[0, 0].plot(mm, row["stroke"] * 1e3, ms=3, label=f"rho {r:g} deg", **kw)
            axes[0, 1].plot(mm, row["peak_guide_force"], ms=3, label=f"rho {r:g} deg", **kw)
        axes[0, 0].set_xlabel("extra rod K-N, mm")
        axes[0, 0].set_ylabel("striker stroke, mm")
        axes[0, 1].set_xlabel("extra rod K-N, mm")
        axes[0, 1].set_ylabel("guide's peak side force, N")
        axes[0, 1].set_yscale("log")
        axes[0, 0].set_title("conclusion 4: the extra rod's length", fontsize=9)
        axes[1, 0].plot(s["rho_deg"], s["stroke"] * 1e3, "o-", color=PALETTE[4], ms=3)
        ax2 = axes[1, 0].twinx()
        ax2.plot(s["rho_deg"], s["peak_velocity"], "s--", color=PALETTE[6], ms=3)
        ax2.set_ylabel("peak striker speed, m/s (dashed)")
        axes[1, 0].set_ylabel("striker stroke, mm (solid)")
        axes[1, 0].set_xlabel("guide angle rho (support position), deg")
        axes[1, 0].set_title("conclusion 3: the support position", fontsize=9)
        axes[1, 1].plot(s["rho_deg"], s["peak_guide_force"], "o-", color=PALETTE[5], ms=3)
        axes[1, 1].set_yscale("log")
        axes[1, 1].set_xlabel("guide angle rho (support position), deg")
        axes[1, 1].set_ylabel("guide's peak side force, N")
        for ax in axes[0]:
            ax.legend(fontsize=8)
        fig.suptitle(
            f"six-link at {o['speed_rpm']:g} rpm: extra rod and support position", fontsize=10
        )
        files.append(save_figure(fig, out / "impact_extra_rod.png", dpi=110))

        fig, axes = plt.subplots(2, 1, figsize=(9, 7.5), sharex=True)
        fv = cyc["five"]
        for k, j in enumerate(("O", "A", "B", "D")):
            axes[0].plot(
                d,
                fv.result.magnitude(j) / 1e3,
                color=PALETTE[(k + 1) % 8],
                ls=LINESTYLES[k % len(LINESTYLES)],
                label=f"joint {j}",
            )
        axes[0].set_ylabel("joint force, kN")
        axes[0].set_title(
            f"five-link (involute) at {o['speed_rpm']:g} rpm: joint forces (paper's Fig. 25)",
            fontsize=9,
        )
        axes[1].plot(
            d,
            np.asarray(fv.result.torque) * np.ones(d.shape),
            color="k",
            lw=1,
            label="driving moment at the crank, N m",
        )
        axes[1].plot(
            d,
            fv.result.magnitude("N_contact") / 100.0,
            color=PALETTE[6],
            ls="--",
            label="rocker-striker force / 100, N",
        )
        axes[1].set_ylabel("N m;  N / 100")
        axes[1].set_title("driving moment and rocker-striker force (paper's Fig. 26)", fontsize=9)
        for ax in axes:
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
        crank_axis(axes[1])
        files.append(save_figure(fig, out / "impact_five_link_forces.png", dpi=110))

        red = f["reduced"]
        rd = np.degrees(red["phi"])
        fig, axes = plt.subplots(2, 1, figsize=(9, 7.5), sharex=True)
        for k, (b, j) in enumerate(red["inertia"].items()):
            kw = dict(color=PALETTE[(k + 1) % 8], ls=LINESTYLES[k % len(LINESTYLES)])
            axes[0].plot(rd, j * 1e3, label=names.get(b, b), **kw)
            axes[1].plot(rd, red["gravity"][b], label=names.get(b, b), **kw)
        axes[1].plot(rd, red["gravity_total"], color="k", lw=2.6, label="sum")
        g = f["gravity"]
        axes[1].axvspan(g["blow_deg"] - g["assist_arc_deg"], g["blow_deg"], color="0.9")
        axes[1].axvline(g["blow_deg"], color="0.4", ls=":", lw=1)
        axes[0].set_yscale("log")
        axes[0].set_ylabel("reduced inertia, 10^-3 kg m^2")
        axes[1].set_ylabel("reduced gravity moment, N m")
        axes[0].set_title("five-link: per-link reduced inertias (paper's Fig. 18)", fontsize=9)
        axes[1].set_title(
            "reduced gravity moments, tool down (Fig. 17); shaded: gravity drives the crank "
            "up to the blow (dotted)",
            fontsize=9,
        )
        for ax in axes:
            ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
        crank_axis(axes[1])
        files.append(save_figure(fig, out / "impact_reduced.png", dpi=110))

        p = f["profile"]
        fig, ax = plt.subplots(figsize=(9, 5))
        for k, name in enumerate(("outer", "axis", "inner")):
            x, y = p["curves"][name]
            ax.plot(
                x * 1e3,
                y * 1e3,
                color=PALETTE[4 + k],
                ls=LINESTYLES[k],
                label=f"{name} (radius {p[name]['radius_range'][0] * 1e3:.1f}-"
                f"{p[name]['radius_range'][1] * 1e3:.1f} mm)",
            )
        t = np.linspace(0, 2 * np.pi, 181)
        rb = p["base_radius"]
        ax.plot(
            rb * 1e3 * np.cos(t), rb * 1e3 * np.sin(t), color="0.6", lw=0.8, label="base circle"
        )
        ax.set_aspect("equal")
        ax.set_xlabel("along the rocker D-B, mm")
        ax.set_ylabel("across the rocker, mm")
        ax.set_title(
            f"rocker profile {p['width'] * 1e3:g} mm wide (paper's Fig. 13): involutes, radii "
            f"equal to {p['max_rel_difference']:.0e}",
            fontsize=9,
        )
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
        files.append(save_figure(fig, out / "impact_rocker_profile.png", dpi=110))

    path = out / "impact_five_link_forces.csv"
    fv = cyc["five"]
    joints = ("O", "A", "B", "D", "N_contact", "N_guide")
    red = f["reduced"]
    same = red["phi"].size == phi.size
    with atomic(path, "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(
            ["crank angle [deg]"]
            + [f"|{j}| [N]" for j in joints]
            + ["driving moment [N m]"]
            + ([f"J {b} [kg m^2]" for b in red["inertia"]] if same else [])
            + ([f"M_G {b} [N m]" for b in red["gravity"]] if same else [])
        )
        torque = np.asarray(fv.result.torque) * np.ones(d.shape)
        mags = {j: fv.result.magnitude(j) for j in joints}
        for i, a in enumerate(d):
            row = [a] + [float(mags[j][i]) for j in joints] + [float(torque[i])]
            if same:
                row += [float(v[i]) for v in red["inertia"].values()]
                row += [float(v[i]) for v in red["gravity"].values()]
            wr.writerow(row)
    files.append(path)
    path = out / "impact_extra_rod.csv"
    with atomic(path, "w", newline="") as fh:
        wr = csv.writer(fh)
        wr.writerow(
            [
                "study",
                "rho [deg]",
                "K-N [m]",
                "stroke [m]",
                "peak V_N [m/s]",
                "impact speed [m/s]",
                "peak guide force [N]",
            ]
        )
        for r, row in e["rows"].items():
            for i, kn in enumerate(e["lengths"]):
                wr.writerow(
                    [
                        "extra rod",
                        r,
                        kn,
                        row["stroke"][i],
                        row["peak_velocity"][i],
                        row["impact_velocity"][i],
                        row["peak_guide_force"][i],
                    ]
                )
        kn = float(cyc["six"].machine.linkage.parameters["KN"])
        for i, r in enumerate(s["rho_deg"]):
            wr.writerow(
                [
                    "support position",
                    r,
                    kn,
                    s["stroke"][i],
                    s["peak_velocity"][i],
                    s["impact_velocity"][i],
                    s["peak_guide_force"][i],
                ]
            )
    files.append(path)
    return files


def _t(name):
    file, _, test = name.partition("::")
    return f"tests/test_impact_{file}.py::{test}"


_MODEL = _t("model::test_printed_six_link_formulas")
_FIVE = _t("model::test_printed_five_link_formulas")
_FIND = "findings::"

COVERAGE = Coverage(
    "Paper 001 (Takyrbashev): percussive machines of variable structure",
    "impact",
    (
        Item(
            "dimensions",
            "data",
            "the machine's dimensions, masses and motor",
            "not reproducible",
            "machines.impact.design.representative_machine",
            note="the paper prints none: a representative 15-20 J breaker (design.SOURCES)",
        ),
        Item(
            "Fig. 1",
            "figure",
            "the six-link scheme: extra rod K-N, striker N on a guide at rho",
            "reproduced",
            "machines.impact.model.six_link",
            (_t("model::test_six_link_stroke_and_special_position"),),
            "the figure is missing from the text; built from its description, animated "
            "(impact_six_link.gif)",
        ),
        Item(
            "Fig. 2",
            "finding",
            "at the special position rho = 90 deg gives V_N = V_K",
            "reproduced",
            "machines.impact.paper001.rho_finding",
            (_t("model::test_rho_findings_at_the_special_position"),),
            "exact for any rod (K moves along the guide there)",
        ),
        Item(
            "Figs. 3-4",
            "finding",
            "rho > 90 deg gives V_N < V_K, rho < 90 deg V_N > V_K",
            "reproduced",
            "machines.impact.paper001.rho_finding",
            (_t("model::test_rho_findings_at_the_special_position"),),
            "for the striker behind K with the rod leaning by more than |90 deg - rho|/2 "
            "(the representative machine: 1.024 at 57 deg, 0.653 at 123 deg); reversed ahead",
        ),
        Item(
            "Figs. 3-4, dashed",
            "finding",
            "the extra rod's length changes the striker's speed",
            "reproduced",
            "machines.impact.findings.extra_rod_effect",
            (_t(_FIND + "test_extra_rod_length_conclusion_4"),),
            "K-N 50-90 mm: peak speed -15 % at rho 57 deg, +11 % at 123 deg, none at 90 deg "
            "(impact_extra_rod.png)",
        ),
        Item(
            "eq. (1)",
            "equation",
            "the extra rod's angle eta",
            "erratum",
            "machines.impact.paper001.check_six_link",
            (_MODEL,),
            "sin(phi3 + rho) must be sin(phi3 - rho); as printed the arcsin leaves [-1, 1]",
        ),
        Item(
            "eqs. (2)-(3), (5)-(7)",
            "equation",
            "velocity and acceleration plans: V_KN, U41, a_KN^t, a_N",
            "reproduced",
            "machines.impact.paper001.check_six_link",
            (_MODEL,),
            "exact as printed for the striker behind K; ahead of K signs change",
        ),
        Item(
            "eq. (4)",
            "equation",
            "the striker's speed V_N",
            "erratum",
            "machines.impact.paper001.check_six_link",
            (_MODEL,),
            "the opposite sign of the exact value for the assembly where (3), (5)-(7) hold",
        ),
        Item(
            "Figs. 10, 12",
            "figure",
            "V_N, a_N against V_K, a_K^t for rho = 57, 90, 123 deg",
            "not reproducible",
            "impact_kinematics.png",
            note="the figures are missing from the text; redrawn from the tested formulas",
        ),
        Item(
            "Figs. 5, 7",
            "figure",
            "circular-link (eccentric) embodiments have the lever schemes' kinematics",
            "reproduced",
            "machines.impact.findings.circular_links",
            (_t(_FIND + "test_circular_links_nest_only_with_a_long_rocker"),),
            "a disc in a bore is a revolute pair about its centre: the same motion by "
            "construction; nesting needs a rocker D-B >= OA + AB + walls (98 mm with 8 mm "
            "shafts, 3 mm walls): the representative 36 mm rocker cannot be so embodied",
        ),
        Item(
            "Fig. 6",
            "figure",
            "the five-link: the rocker's curved extension pushes the striker",
            "reproduced",
            "machines.impact.model.five_link",
            (_t("model::test_five_link_involute_moves_striker_by_base_radius"),),
            "the figure is missing from the text; an involute of a circle about D, guide tangent",
        ),
        Item(
            "Fig. 13",
            "figure",
            "the rocker's profile for a given width: outer surface, axis, inner surface",
            "reproduced",
            "machines.impact.findings.rocker_profile",
            (_t(_FIND + "test_rocker_profile_radii_are_the_involute"),),
            "built from the motion for a 10 mm width (impact_rocker_profile.png)",
        ),
        Item(
            "finding: profile radii",
            "finding",
            "the constructed profile's radii of curvature equal the involute's",
            "reproduced",
            "machines.impact.findings.rocker_profile",
            (_t(_FIND + "test_rocker_profile_radii_are_the_involute"),),
            "to 2e-5 (finite differences); the surfaces are involutes of the same base circle",
        ),
        Item(
            "conclusion 5",
            "finding",
            "an involute profile passes the force only along the striker's motion",
            "reproduced",
            "machines.impact.forces.force_findings",
            (_t("forces::test_involute_puts_no_side_load_on_the_guide_the_arc_does"),),
            "1e-12 N side load without gravity; 211 N with the circular arc",
        ),
        Item(
            "eq. (8)",
            "equation",
            "L_DP from the contact geometry",
            "erratum",
            "machines.impact.paper001.check_five_link",
            (_FIVE,),
            "the left side is L_DP (printed L_EB)",
        ),
        Item(
            "eq. (9)",
            "equation",
            "the striker's speed from the contact point's",
            "erratum",
            "machines.impact.paper001.check_five_link",
            (_FIVE,),
            "V_P sin(phi3R) = omega3 R_EB, not V_P cos(phi3R)",
        ),
        Item(
            "eq. (10)",
            "equation",
            "the striker's acceleration",
            "erratum",
            "machines.impact.paper001.check_five_link",
            (_FIVE,),
            "not the projection of the contact point's: a_N = eps3 R_EB",
        ),
        Item(
            "eqs. (11)-(12)",
            "equation",
            "the striker's reduced gravity moment and the reduced inertia",
            "reproduced",
            "machines.impact.findings.reduced_terms",
            (
                _t("drive::test_paper_eq12_and_eq11_on_the_five_link"),
                _t(_FIND + "test_reduced_terms_sum_to_the_machine_model_and_eq_11"),
            ),
        ),
        Item(
            "Figs. 17-18",
            "figure",
            "per-link reduced gravity moments and inertias over the crank angle",
            "not reproducible",
            "impact_reduced.png",
            note="the figures are missing from the text; every body's curves computed "
            "(findings.reduced_terms, tested) and drawn",
        ),
        Item(
            "finding: gravity",
            "finding",
            "from 60 deg of crank angle to the blow gravity turns the crank forward",
            "reproduced",
            "machines.impact.findings.gravity_assist",
            (_t(_FIND + "test_gravity_assists_the_crank_before_the_blow"),),
            "with the tool down, over the 86.4 deg before the blow (0.56 J); the paper's "
            "origin of the crank angle is in a missing figure",
        ),
        Item(
            "eq. (13)",
            "equation",
            "the equation of motion in energy form with Kloss's motor",
            "reproduced",
            "machines.impact.drive.steady_state",
            (_t("drive::test_stepping_against_solve_ivp"),),
            "stepping against solve_ivp to 1e-7",
        ),
        Item(
            "eqs. (14)-(18)",
            "equation",
            "the stepping's quartic in omega_i",
            "erratum",
            "dynamics.equation_of_motion.quartic_coefficients",
            (
                "tests/test_equation_of_motion.py::test_quartic_coefficients_match_symbolic_"
                "derivation",
                _t("drive::test_stepping_against_solve_ivp"),
            ),
            "(14) the sign of 2A/dphi, (16) the squared slip, (17)-(18) the factor a^2/2: "
            "derived; one positive real root per step (the paper's claim) holds",
        ),
        Item(
            "eqs. (19)-(21)",
            "equation",
            "the striker's equilibrium: F43, F45",
            "reproduced",
            "machines.impact.paper001",
            (_t("forces::test_paper_eq20_eq21_on_the_involute_five_link"),),
            "(20) is the rocker's force on the striker (the text says the reverse)",
        ),
        Item(
            "eqs. (22)-(28)",
            "equation",
            "the rocker's joint forces from its moment equations",
            "not reproducible",
            "dynamics.kinetostatics",
            note="they refer to figures missing from the text; the joint forces come from the "
            "general kinetostatics, power-balanced (test_impact_forces.py::test_power_balance)",
        ),
        Item(
            "Figs. 25-26",
            "figure",
            "the five-link's joint forces, driving moment and rocker-striker force",
            "not reproducible",
            "impact_five_link_forces.png, impact_five_link_forces.csv",
            note="the figures are missing from the text; drawn and exported from the kinetostatics",
        ),
        Item(
            "finding: alignment",
            "finding",
            "the joint forces peak when the links line up",
            "refuted",
            "machines.impact.forces.force_findings",
            (_t("forces::test_findings_reported"),),
            "they peak about 16 deg before a dead centre, where the rocker's acceleration "
            "peaks: near, not at, the alignment",
        ),
        Item(
            "finding: F34",
            "finding",
            "the rocker-striker force is many times smaller than the four-bar's joint forces",
            "refuted",
            "machines.impact.findings.pair_force_findings",
            (_t(_FIND + "test_pair_force_findings"), _t("forces::test_findings_reported")),
            "0.42 of the four-bar's peak with a 3 kg striker: smaller, not many times",
        ),
        Item(
            "finding: M_D",
            "finding",
            "pair, inertia and gravity forces assist the driving moment at the rocker's "
            "extreme and pre-impact positions",
            "refuted",
            "machines.impact.findings.pair_force_findings",
            (_t(_FIND + "test_pair_force_findings"),),
            "the driving moment is about 0 (< 0.2 N m) at the extremes and positive (2-17 N m) "
            "over the 20 deg before the blow: the striker is being accelerated",
        ),
        Item(
            "conclusion 9",
            "finding",
            "the joints' main loads are normal forces along the links",
            "reproduced",
            "machines.impact.findings.pair_force_findings",
            (_t(_FIND + "test_pair_force_findings"),),
            "at A and B along the rod (cos > 0.9999 at the peaks); the rocker's pivot D is "
            "not loaded along the rocker (mean cos 0.80)",
        ),
        Item(
            "conclusion 3",
            "finding",
            "the support position (rho) lowers the guide force and changes speed and stroke",
            "reproduced",
            "machines.impact.findings.support_position_effect",
            (_t(_FIND + "test_support_position_conclusion_3"),),
            "least guide force 135 N at rho = 90 deg; stroke 15.7-44.9 mm, speed 2.49-4.80 m/s "
            "over rho 50-130 deg",
        ),
        Item(
            "conclusion 4, guide",
            "finding",
            "a longer extra rod lowers the force between striker and guide",
            "reproduced",
            "machines.impact.findings.extra_rod_effect",
            (_t(_FIND + "test_extra_rod_length_conclusion_4"),),
            "at every rho (57, 90, 123 deg) over K-N 50-90 mm",
        ),
        Item(
            "conclusion 4, speed",
            "finding",
            "a longer extra rod raises the striker's speed and stroke",
            "refuted",
            "machines.impact.findings.extra_rod_effect",
            (_t(_FIND + "test_extra_rod_length_conclusion_4"),),
            "holds for rho > 90 deg only; at 90 deg neither changes, below 90 both fall",
        ),
        Item(
            "conclusions 1-2",
            "finding",
            "the new schemes reduce the transverse load of the percussive machine",
            "reproduced",
            "machines.impact.forces.force_findings",
            (_t("forces::test_transverse_housing_load_against_the_base_machine"),),
            "about 1,040 N (base) to 180 N (six-link) and 270 N (five-link) across the tool",
        ),
        Item(
            "the blow",
            "data",
            "the blow and the change of structure (the paper has no impact model)",
            "added",
            "machines.impact.impact.blow",
            (_t("blow::test_newton_law_bookkeeping"),),
        ),
        Item(
            "synthesis",
            "recommendation",
            "the dimensions for the blow energy (the paper's 'synthesis of the parameters')",
            "added",
            "machines.impact.synthesis.synthesize",
            (_t("synthesis::test_certified_synthesis"),),
        ),
    ),
)
