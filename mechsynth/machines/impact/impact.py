"""The blow: Newton's impact law between the striker -- the whole machine reduced to the
striker's line of action -- and the tool, the impulse reduced to the crank through the
mechanism's Jacobian, and the joint impulses.

Model (see docs/impact.md)
--------------------------
The striker's drive is rigid: in the six-link the striker N is pinned to the rod K-N, in the
five-link it is held in a yoke on both sides of the profile, in the base machine it *is* the
rocker. So at the blow the striker cannot leave its drive: the impulse of the tool on it passes
through every joint to the crank, and the machine meets the tool with the mass it has along the
striker's line, ``m_eff = J(phi_b) / u(phi_b)^2`` (``J`` the reduced moment of inertia at the
crank, flywheel and motor included; ``u = ds/dphi`` the striker's velocity analog, m/rad). The
structure changes for the instant of the blow only: the tool (mass ``m_t``, at rest on the rock)
and the machine form a two-body collision with Newton's coefficient of restitution ``e``;
afterwards the tool carries its momentum into the rock (the energy delivered) and the machine
goes on as a one-degree-of-freedom mechanism from the jumped crank speed. The tool absorbs what
it receives: its kinetic energy goes into the rock, and the operator's feed force brings it back
to the anvil, at rest, before the next blow. (A rigid, infinitely heavy anvil is not offered: it
would stop a rigid drive dead, ``omega^+ = -e omega^-``.)

With ``v = u omega^-`` (striker speed before the blow, towards the tool):

* ``v^+ = v (m_eff - e m_t) / (m_eff + m_t)``, ``v_t = v m_eff (1 + e) / (m_eff + m_t)``,
  impulse ``P = m_t v_t`` (N s), energy delivered ``m_t v_t^2 / 2``, dissipated
  ``(1 - e^2) mu v^2 / 2`` with ``mu = m_eff m_t / (m_eff + m_t)``;
* the crank: ``J (omega^+ - omega^-) = -u P``, so ``omega^+ = v^+ / u``.

``e = 1`` conserves the kinetic energy, ``e = 0`` is plastic (striker and tool move together).
The joint impulses follow from the impulsive d'Alembert equilibrium: the kinetostatics of the
linkage with every body's velocity jump ``u_body Delta omega`` in place of its acceleration
(``motion(phi_b, speed=0, epsilon=Delta omega)``) and the tool's impulse as the load; the
crank's balancing "torque" is then the impulse the motor would have to give, zero up to
rounding because the drive's inertia is in the crank's body (a check).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ... import validate
from ...dynamics.inertia import LinkInertia, reduced_inertia
from ...dynamics.kinetostatics import kinetostatics
from ...dynamics.loads import PointForce
from ...errors import MechanismError

__all__ = ["Tool", "newton_impact", "Blow", "striker_track", "blow_angle", "blow"]


@dataclass(frozen=True)
class Tool:
    """The tool the striker hits.

    Parameters
    ----------
    mass : kg, the tool (chisel, bit) at rest against the rock, which absorbs the energy the
        tool receives.
    restitution : Newton's coefficient of restitution ``e`` in [0, 1].
    """

    mass: float = 1.5
    restitution: float = 0.5

    def __post_init__(self):
        e = validate.number("restitution e", self.restitution)
        if not 0.0 <= e <= 1.0:
            raise MechanismError(f"restitution e must lie in [0, 1], got {self.restitution}")
        object.__setattr__(self, "restitution", e)
        m = validate.number("tool mass", self.mass, "kg")
        if m <= 0.0:
            raise MechanismError(f"tool mass must be a positive finite mass in kg, got {self.mass}")
        object.__setattr__(self, "mass", m)


def newton_impact(m_eff, v, tool: Tool) -> dict:
    """Newton's law for the striker (effective mass ``m_eff`` kg, speed ``v`` m/s towards the
    tool) hitting ``tool`` at rest. Arrays broadcast.

    Returns a dict of ``v_after`` (striker, m/s), ``tool_velocity`` (m/s; 0 for an absorbing
    tool), ``impulse`` (N s, on the tool), ``energy_before`` (the striker side's kinetic energy
    along its line, J), ``energy_delivered`` (to the tool and the rock, J), ``energy_lost``
    (dissipated in the collision, J).
    """
    if not isinstance(tool, Tool):
        raise MechanismError(f"tool must be a Tool, got {tool!r}")
    m_eff = np.asarray(validate.positive("effective mass m_eff", m_eff, "kg"), dtype=float)
    v = np.asarray(validate.real("striker speed v", v, "m/s"), dtype=float)
    validate.broadcast(m_eff=m_eff, v=v)
    e = tool.restitution
    before = 0.5 * m_eff * v * v
    mt = tool.mass
    after = v * (m_eff - e * mt) / (m_eff + mt)
    vt = v * m_eff * (1.0 + e) / (m_eff + mt)
    impulse = mt * vt
    delivered = 0.5 * mt * vt * vt
    lost = before - 0.5 * m_eff * after * after - delivered
    return {
        "v_after": after,
        "tool_velocity": vt,
        "impulse": impulse,
        "energy_before": before,
        "energy_delivered": delivered,
        "energy_lost": lost,
    }


def _striker_link(linkage, striker):
    """The body whose rotation about a ground pivot carries a striker that is not a slider."""
    for g in linkage.groups:
        if g.key == striker and hasattr(g, "frame"):
            return g.frame.body
    raise MechanismError(f"striker {striker!r} is neither a slider nor a point attached to a link")


def striker_track(linkage, striker, phi):
    """The striker's coordinate along its line of action and its analogs at crank angles
    ``phi``: ``(s, u, u')`` (m, m/rad, m/rad^2) and the unit direction ``(cx, cy)`` of
    increasing ``s``. A slider moves along its guide; a point on a rocker (the base machine)
    along its circle, ``s`` its arc length from the rocker's angle 0."""
    m = linkage.motion(phi)
    if striker in m.sliders:
        t = m.sliders[striker]
        ang = np.asarray(m.links[striker].angle) + 0.0 * np.asarray(t.position)
        return t.position, t.velocity, t.acceleration, (np.cos(ang), np.sin(ang))
    p = m.points[striker]
    link = m.links[_striker_link(linkage, striker)]
    d = None
    for name, q in m.points.items():
        if np.allclose(q.vx, 0.0) and np.allclose(q.vy, 0.0):
            if np.allclose(np.hypot(p.x - q.x, p.y - q.y).std(), 0.0, atol=1e-12) and name != "O":
                d = q
    if d is None:
        raise MechanismError(f"striker {striker!r}: its link turns about no ground pivot")
    radius = np.hypot(p.x - d.x, p.y - d.y)
    s = radius * np.unwrap(np.atleast_1d(np.asarray(link.angle))).reshape(np.shape(link.angle))
    u = radius * link.omega
    du = radius * link.epsilon
    ang = np.arctan2(p.y - d.y, p.x - d.x) + np.pi / 2
    return s, u, du, (np.cos(ang), np.sin(ang))


def blow_angle(linkage, striker, anvil, sense=1, n=720):
    """The crank angle (rad, in [0, 2 pi)) where the striker reaches the anvil position
    ``anvil`` (m, its coordinate of :func:`striker_track`) moving with ``sense`` (+1: towards
    increasing coordinate), refined by Newton steps. Raises MechanismError if the anvil lies
    outside the stroke."""
    if sense not in (1, -1):
        raise MechanismError(f"sense must be +1 or -1, got {sense}")
    phi = np.linspace(0.0, 2 * np.pi, int(n) + 1)
    s, u, _, _ = striker_track(linkage, striker, phi)
    f = np.asarray(s) - anvil
    idx = [
        i
        for i in np.flatnonzero(np.sign(f[:-1]) != np.sign(f[1:]))
        if sense * (f[i + 1] - f[i]) > 0
    ]
    if not idx:
        raise MechanismError(
            f"the anvil at {anvil:.6g} m lies outside the striker's stroke "
            f"[{np.min(s):.6g}, {np.max(s):.6g}] m (or is never passed with sense {sense:+d})"
        )
    i = idx[0]
    x = phi[i] - f[i] * (phi[i + 1] - phi[i]) / (f[i + 1] - f[i])
    for _ in range(30):
        si, ui, _, _ = striker_track(linkage, striker, x)
        step = float((si - anvil) / ui)
        x -= step
        if abs(step) < 1e-15:
            break
    return float(np.mod(x, 2 * np.pi))


@dataclass(frozen=True)
class Blow:
    """One blow at crank angle ``phi`` (rad).

    Attributes: crank speeds ``omega_before``, ``omega_after`` (rad/s); the striker's speed
    towards the tool before and after (m/s); ``tool_velocity`` (m/s); ``effective_mass`` (kg,
    the machine along the striker's line) and ``inertia`` (kg m^2, reduced, drive included);
    ``impulse`` (N s, on the tool); ``energy_delivered``, ``energy_lost`` (J); the machine's
    kinetic energy before and after (J); ``joint_impulses`` ``{joint: (x, y)}`` (N s, on the
    joint's ``on`` body); ``crank_impulse`` (N m s: what the motor would have to supply; zero
    up to rounding, a check); ``direction`` (unit vector of the blow)."""

    phi: float
    omega_before: float
    omega_after: float
    striker_before: float
    striker_after: float
    tool_velocity: float
    effective_mass: float
    inertia: float
    impulse: float
    energy_delivered: float
    energy_lost: float
    machine_energy_before: float
    machine_energy_after: float
    joint_impulses: dict = field(default_factory=dict)
    crank_impulse: float = 0.0
    direction: tuple = (0.0, 0.0)

    def as_dict(self) -> dict:
        d = {k: getattr(self, k) for k in self.__dataclass_fields__ if k != "joint_impulses"}
        d["direction"] = [float(x) for x in self.direction]
        d["joint_impulses"] = {
            j: {"x": float(x), "y": float(y), "magnitude": float(np.hypot(x, y))}
            for j, (x, y) in self.joint_impulses.items()
        }
        return d


def _bodies(linkage, inertias, drive_inertia):
    """LinkInertia of every body; the drive's inertia (kg m^2 at the crank) added to the
    crank's."""
    model = linkage.force_model(inertias)
    bodies = dict(model.bodies)
    crank = model.driver
    c = bodies[crank]
    bodies[crank] = LinkInertia(c.link, c.base, c.mass, c.com, c.inertia + float(drive_inertia))
    return model, bodies


def blow(linkage, inertias, phi, omega, tool: Tool, *, striker="N", sense=1, drive_inertia=0.0):
    """The blow at crank angle ``phi`` (rad) and crank speed ``omega`` (rad/s) just before it.

    Parameters
    ----------
    linkage : the machine (:func:`~.model.six_link`, :func:`~.model.five_link`,
        :func:`~.model.crank_rocker`).
    inertias : the bodies' mass properties, as :meth:`Linkage.force_model` takes them.
    tool : :class:`Tool`.
    striker : the striking point (a slider, or ``"K"`` on the base machine's rocker).
    sense : +1 if the blow acts along increasing striker coordinate.
    drive_inertia : motor rotor, gear and flywheel referred to the crank (kg m^2).

    Raises
    ------
    MechanismError
        if the striker does not move towards the tool, or if the rebound would turn the crank
        backwards (``omega^+ <= 0``: the rigid-drive model no longer holds).
    """
    omega = validate.number("crank speed before the blow (omega)", omega, "rad/s")
    if omega <= 0:
        raise MechanismError(f"crank speed before the blow must be positive, got {omega}")
    if not math.isfinite(float(drive_inertia)) or float(drive_inertia) < 0:
        raise MechanismError(f"drive_inertia must be a non-negative inertia, got {drive_inertia}")
    model, bodies = _bodies(linkage, inertias, drive_inertia)
    j, _ = reduced_inertia(linkage, list(bodies.values()), phi)
    j = float(j)
    _, u, _, (cx, cy) = striker_track(linkage, striker, phi)
    u = float(u)
    if sense * u <= 0:
        raise MechanismError(
            f"at crank angle {np.degrees(phi):.6g} deg the striker moves away from the tool "
            f"(velocity analog {u:.6g} m/rad, sense {sense:+d})"
        )
    m_eff = j / (u * u)
    v = abs(u) * omega
    r = newton_impact(m_eff, v, tool)
    w_after = float(r["v_after"]) / abs(u)
    if w_after <= 0:
        raise MechanismError(
            f"the rebound turns the crank backwards (omega {omega:.6g} -> {w_after:.6g} rad/s): "
            f"effective mass {m_eff:.6g} kg against a tool of {tool.mass} kg with e = "
            f"{tool.restitution}; the rigid-drive blow does not apply"
        )
    dw = w_after - omega
    p = float(r["impulse"])
    # impulsive kinetostatics: velocity jumps in place of accelerations, the tool's impulse as load
    fx, fy = -sense * p * float(cx), -sense * p * float(cy)
    body = striker if striker in model.bodies else _striker_link(linkage, striker)
    load = PointForce(body, striker, lambda m: (fx + 0.0 * m.phi, fy + 0.0 * m.phi), "tool")
    fmodel = model.replace_loads([load])
    for name, b in bodies.items():
        fmodel = fmodel.with_body(name, b)
    res = kinetostatics(fmodel, linkage.motion(np.array([phi]), speed=0.0, epsilon=dw))
    impulses = {k: (float(x[0]), float(y[0])) for k, (x, y) in res.reactions.items()}
    return Blow(
        phi=float(phi),
        omega_before=omega,
        omega_after=w_after,
        striker_before=v,
        striker_after=float(r["v_after"]),
        tool_velocity=float(r["tool_velocity"]),
        effective_mass=m_eff,
        inertia=j,
        impulse=p,
        energy_delivered=float(r["energy_delivered"]),
        energy_lost=float(r["energy_lost"]),
        machine_energy_before=0.5 * j * omega * omega,
        machine_energy_after=0.5 * j * w_after * w_after,
        joint_impulses=impulses,
        crank_impulse=float(np.asarray(res.torque).ravel()[0]),
        direction=(sense * float(cx), sense * float(cy)),
    )
