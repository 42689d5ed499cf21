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

__all__ = ["run", "STAGES"]

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

    lines = _summary(
        o, six, findings, formulas, five, five_formulas, forces, blows, dynamics, synth
    )
    lines.append(f" run time {time.perf_counter() - t0:.1f} s")
    data = {
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
    }
    return StudyResult("impact", "\n".join(lines), data, files, list(ERRATA))


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
    L.append(
        f"   start-up from rest: {reached}, {su['blows']} blows in {su['duration_s']:g} s"
    )
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
            axes[0].plot(
                d,
                f.result.magnitude(j) / 1e3,
                color=PALETTE[(k + 1) % 8],
                ls=LINESTYLES[k % len(LINESTYLES)],
                label=f"joint {j}",
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
        ax.plot(d, cyc["five"].guide, color="k", lw=0.8, label="five-link, involute")
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
