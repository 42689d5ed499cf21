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

from ...dynamics.inertia import com_track
from ...dynamics.kinetostatics import applied_power, kinetic_energy_rate, kinetostatics
from ...dynamics.loads import Gravity
from ...dynamics.reduced import G
from ...kinematics import ops
from .drive import ImpactMachine

__all__ = [
    "CycleForces",
    "cycle_forces",
    "six_link_forces",
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
        model = machine.linkage.force_model(machine.inertias)
        hx = 0.0
        hy = 0.0
        for j in model.joints:
            if j.by == "frame":
                fx, fy = result.reactions[j.name]
                hx, hy = hx - np.asarray(fx), hy - np.asarray(fy)
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


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


def six_link_forces(mech, motion, inertias, tilt=0.0, g=G):
    """Closed-form kinetostatics of the six-link (dyad by dyad: the striker and the rod K-N, then
    the rod A-B and the rocker, then the crank), written with ``ops`` so that it serves numpy
    and CasADi alike; the same equilibrium as :func:`mechsynth.dynamics.kinetostatics` (tested
    to 1e-9), a fraction of its symbolic size.

    Returns ``{joint: (fx, fy)}`` for ``"O", "A", "B", "D", "K", "N"`` (the force on the joint's
    ``on`` body as the general model names it, up to sign), ``"guide"`` (the guide's normal force
    on the striker along the guide's left normal, N) and ``"housing"`` (the mechanism's total
    force on the housing, ``(fx, fy)``)."""
    model = mech.force_model(inertias)
    b = model.bodies
    gx, gy = g * ops.sin(tilt), -g * ops.cos(tilt)

    def load(name):
        body = b[name]
        c = com_track(motion, body)
        fx = body.mass * (gx - c.ax)
        fy = body.mass * (gy - c.ay)
        mz = 0.0 if body.link is None else -body.inertia * motion.links[body.link].epsilon
        return c, fx, fy, mz

    pts = motion.points
    rho = mech.parameters["N_guide_angle"]
    ux, uy = ops.cos(rho), ops.sin(rho)
    nx, ny = -uy, ux
    # striker N and rod K-N
    _, fnx, fny, _ = load("N")
    ckn, fkx, fky, mkn = load("KN")
    k, n = pts["K"], pts["N"]
    dx, dy = n.x - k.x, n.y - k.y
    pu = -(fnx * ux + fny * uy)
    num = -pu * _cross(dx, dy, ux, uy) + _cross(ckn.x - k.x, ckn.y - k.y, fkx, fky) + mkn
    pn = num / _cross(dx, dy, nx, ny)
    px, py = pu * ux + pn * nx, pu * uy + pn * ny  # on the striker from the rod at N
    q = -(pn + fnx * nx + fny * ny)
    rx, ry = px - fkx, py - fky  # on the rod K-N from the rocker at K
    # rod A-B and rocker D-B
    cdb, fdx, fdy, mdb = load("DB")
    cab, fax, fay, mab = load("AB")
    a, bb, d = pts["A"], pts["B"], pts["D"]
    ex, ey = bb.x - d.x, bb.y - d.y
    hx, hy = bb.x - a.x, bb.y - a.y
    r1 = _cross(k.x - d.x, k.y - d.y, rx, ry) - _cross(cdb.x - d.x, cdb.y - d.y, fdx, fdy) - mdb
    r2 = _cross(cab.x - a.x, cab.y - a.y, fax, fay) + mab
    det = _cross(ex, ey, hx, hy)
    sx = (r1 * hx - r2 * ex) / det
    sy = (r1 * hy - r2 * ey) / det
    tx, ty = rx - sx - fdx, ry - sy - fdy  # on the rocker from the frame at D
    ux_, uy_ = sx - fax, sy - fay  # on the rod A-B from the crank at A
    _, fox, foy, _ = load("OA")
    vx, vy = ux_ - fox, uy_ - foy  # on the crank from the frame at O
    return {
        "O": (vx, vy),
        "A": (ux_, uy_),
        "B": (sx, sy),
        "D": (tx, ty),
        "K": (rx, ry),
        "N": (px, py),
        "guide": q,
        "housing": (-(vx + tx + q * nx), -(vy + ty + q * ny)),
    }
