"""Forces in the impact machines over the cycle: kinetostatics with the links' inertia, gravity
at the machine's tilt, and the blow's impulses; the load on the housing, its component across
the tool's axis (the transverse vibration the six-link and five-link exist to remove), the
guide's normal force, the power balance, and paper 001's force findings.

Conventions: reactions as :func:`mechsynth.dynamics.kinetostatics` gives them (the force on a
joint's ``on`` body from its ``by`` body, N); the housing receives minus the frame joints'
reactions. The *tool axis* is the blow's direction (the guide for a slider; for the base
machine, the striker's velocity at the blow); the *transverse housing force* is the component of
the mechanism's total force on the housing perpendicular to it.
"""

from __future__ import annotations

import numpy as np

from ...dynamics.kinetostatics import FRAME, applied_power, kinetic_energy_rate, kinetostatics
from ...dynamics.loads import Gravity
from .drive import ImpactMachine

__all__ = [
    "CycleForces",
    "cycle_forces",
    "housing_load",
    "power_balance",
    "force_findings",
    "dead_centres",
]


class CycleForces:
    """Kinetostatics of an :class:`~.drive.ImpactMachine` over crank angles ``phi``.

    Attributes: ``phi`` (rad), ``omega``, ``epsilon`` (crank speed and acceleration, rad/s,
    rad/s^2, scalars or per angle), ``result`` (the
    :class:`~mechsynth.dynamics.kinetostatics.ForceResult`), ``housing`` (``(fx, fy)``, the
    mechanism's force on the housing, N), ``axis`` (unit vector of the tool axis),
    ``transverse`` and ``axial`` (its components across and along the tool axis, N), ``guide``
    (the guide's normal force on the striker, N; None for the base machine), ``motion``.
    """

    def __init__(self, machine, phi, omega, epsilon, result, motion, axis):
        self.machine, self.phi, self.omega, self.epsilon = machine, phi, omega, epsilon
        self.result, self.motion, self.axis = result, motion, axis
        hx, hy = housing_load(machine.linkage.force_model(machine.inertias), result)
        self.housing = (np.broadcast_to(hx, np.shape(phi)), np.broadcast_to(hy, np.shape(phi)))
        ax, ay = axis
        self.axial = self.housing[0] * ax + self.housing[1] * ay
        self.transverse = -self.housing[0] * ay + self.housing[1] * ax
        name = f"{machine.striker}_guide"
        self.guide = np.asarray(result.normals[name][0]) if name in result.normals else None

    def peak(self, joint):
        return self.result.peak(joint)

    def joints(self):
        return list(self.result.reactions)


def housing_load(model, result):
    """The mechanism's total force ``(fx, fy)`` (N) on the housing: minus the reactions of the
    joints with the frame (numbers or CasADi expressions, as ``result`` holds them)."""
    hx = hy = 0.0
    for j in model.joints:
        if j.by == FRAME:
            fx, fy = result.reactions[j.name]
            hx, hy = hx - fx, hy - fy
    return hx, hy


def _axis(machine: ImpactMachine):
    b = machine.blow()
    return b.direction


def cycle_forces(machine: ImpactMachine, phi, omega=None, epsilon=0.0, gravity=True) -> CycleForces:
    """Joint reactions, the driving torque and the housing's load of ``machine`` at crank angles
    ``phi`` (rad) and crank speed ``omega`` (rad/s; default nominal; an array per angle, e.g. a
    steady state's, with ``epsilon`` its angular acceleration), with the links' inertia and
    gravity at the machine's tilt (``gravity=False`` leaves it out). The motor's rotor and the
    flywheel are not in the linkage: the driving torque is the crankshaft's."""
    omega = machine.omega if omega is None else omega
    loads = [Gravity(tilt=machine.tilt)] if gravity else []
    model = machine.linkage.force_model(machine.inertias, loads)
    motion = machine.linkage.motion(phi, speed=omega, epsilon=epsilon)
    res = kinetostatics(model, motion)
    return CycleForces(machine, phi, omega, epsilon, res, motion, _axis(machine))


def power_balance(machine: ImpactMachine, phi, omega=None, epsilon=0.0):
    """``T_b omega + P_applied - dT/dt`` (W) at every angle: zero for a correct force analysis
    (the balancing torque's power plus the loads' power is the rate of the kinetic energy).
    Returns ``(residual, scale)``, ``scale`` the largest of the three powers."""
    f = cycle_forces(machine, phi, omega, epsilon)
    model = machine.linkage.force_model(machine.inertias, [Gravity(tilt=machine.tilt)])
    w = np.asarray(f.motion.links["OA"].omega)
    pt = np.asarray(f.result.torque) * w
    pa = np.asarray(applied_power(model, f.motion))
    dt = np.asarray(kinetic_energy_rate(model, f.motion))
    scale = max(np.max(np.abs(pt)), np.max(np.abs(pa)), np.max(np.abs(dt)))
    return pt + pa - dt, scale


def dead_centres(linkage, n=1440):
    """Crank angles (rad) where crank and rod line up (the rocker's extreme positions)."""
    phi = np.linspace(0.0, 2 * np.pi, int(n) + 1)
    m = linkage.motion(phi)
    a, b, o = m.points["A"], m.points["B"], m.points["O"]
    cross = (a.x - o.x) * (b.y - a.y) - (a.y - o.y) * (b.x - a.x)
    i = np.flatnonzero(np.sign(cross[:-1]) != np.sign(cross[1:]))
    return phi[i] - cross[i] * (phi[i + 1] - phi[i]) / (cross[i + 1] - cross[i])


def force_findings(machine: ImpactMachine, n=720) -> dict:
    """Paper 001's force findings checked on ``machine`` at its nominal speed.

    * the joint forces peak when the links line up: the angle of each four-bar joint's peak
      against the nearest dead centre (crank and rod in line);
    * the force between the rocker and the striker's drive (the joint K, or the cam contact) is
      much smaller than the crank-rocker joint forces: the ratio of the peaks;
    * the involute puts no side load on the guide: the guide's normal force without gravity.
    """
    phi = np.linspace(0.0, 2 * np.pi, int(n), endpoint=False)
    f = cycle_forces(machine, phi)
    dc = dead_centres(machine.linkage)
    out = {"dead_centres_deg": np.degrees(dc).tolist(), "peaks": {}}
    for j in ("O", "A", "B", "D"):
        peak, at = f.peak(j)
        gap = np.min(np.abs(np.angle(np.exp(1j * (at - dc))))) if dc.size else np.nan
        out["peaks"][j] = {
            "max_N": peak,
            "at_deg": float(np.degrees(at)),
            "from_dead_centre_deg": float(np.degrees(gap)),
        }
    four_bar = max(out["peaks"][j]["max_N"] for j in ("A", "B", "D"))
    link = "K" if "K" in f.result.reactions and "KN" in machine.inertias else None
    contact = f"{machine.striker}_contact"
    if contact in f.result.reactions:
        link = contact
    if link is not None:
        out["rocker_striker_joint"] = link
        out["rocker_striker_peak_N"] = f.peak(link)[0]
        out["rocker_striker_ratio"] = f.peak(link)[0] / four_bar
    if f.guide is not None:
        g0 = cycle_forces(machine, phi, gravity=False)
        out["guide_peak_N"] = float(np.max(np.abs(f.guide)))
        out["guide_peak_without_gravity_N"] = float(np.max(np.abs(g0.guide)))
    out["transverse_peak_N"] = float(np.max(np.abs(f.transverse)))
    out["axial_peak_N"] = float(np.max(np.abs(f.axial)))
    return out
