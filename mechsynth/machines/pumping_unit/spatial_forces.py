"""Kinetostatics of the spatial pumping-unit drive (paper 002), redundant and rational.

Bodies (paper 002's numbers): the crank 1 (shaft and both arms), the pitmans 2 (``"left"``, A-B)
and 3 (``"right"``, A1-B1), the equalizer 4, the beam 5. Pairs and the reactions reported, each
the force and moment **on** the second body **from** the first (paper 002's ``R_ij``):

====== ===== ============================== ===================================================
name   pair  bodies                         kind
====== ===== ============================== ===================================================
R01    O     frame -> crank                 revolute about the shaft + the driving torque
R12    A     crank -> left pitman           revolute (pin axis = shaft) or spherical
R13    A1    crank -> right pitman          revolute or spherical
R24    B     left pitman -> equalizer       revolute (pin axis = equalizer axis) or spherical
R34    B1    right pitman -> equalizer      revolute or spherical
R45    D     equalizer -> beam              spherical
R05    C     frame -> beam                  revolute about the saddle-bearing axis
====== ===== ============================== ===================================================

Each body is in d'Alembert equilibrium (6 equations): gravity ``m g`` (g along -y), inertia
``-m a_S`` at the centre of mass and ``-(J eps + omega x J omega)``, the polished-rod load ``W``
hanging vertically from the horsehead (at the horizontal arm ``A`` from C), the counterbalance on
the crank. 30 equations in all.

* **Rational drive** (``joints="spherical"``): 26 unknowns, rank 26 -- statically determinate. The
  four equations left over are the local mobilities (each pitman spinning about its axis, the
  equalizer spinning about B-B1 and turning in the plane of the pitmans); the loads balance them
  exactly for the ideal unit and to a small ``residual`` with deviations (the kinematics places
  the equalizer by the equilibrium of massless pitmans).
* **Redundant drive** (``joints="revolute"``): 34 unknowns, rank 29 (one local mobility is left:
  the equalizer's idle spin about B-B1), hence **5** self-stress states. They are fixed by the
  pitmans' elasticity: each pitman is a straight elastic bar (axial, torsion, two bendings: the
  6 x 6 cantilever compliance of its section), the beam, equalizer and crank are rigid, and the
  misfits are the relative rotations of the pin axes at A, A1, B, B1 in the rigid reference
  configuration (the rational drive's). The force method (complementary virtual work) closes the
  system: see :mod:`mechsynth.dynamics.spatial_kinetostatics`. The pitmans' own weight and inertia
  are kept in equilibrium but their bending under those loads is left out of the compatibility.

Crank torque: about the shaft, positive in the direction of rotation, the torque the gearbox
applies (as the planar unit's net torque).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from ...dynamics.spatial_kinetostatics import SpatialJoint, cantilever_compliance, solve_spatial
from ...errors import MechanismError
from ...kinematics.mechanism import check_finite
from ...kinematics.spatial import Y, cross, dot, norm, unit
from .spatial_unit import SpatialPumpingUnit, SpatialPumpMotion
from .torque import GRAVITY, Counterbalance, DynamometerCard

__all__ = [
    "Part",
    "body_parts",
    "power_balance",
    "SpatialMasses",
    "SpatialForces",
    "Reaction",
    "spatial_forces",
    "PAIRS",
    "rod_load",
]

#: pair letter -> reaction name
PAIRS = {"O": "R01", "A": "R12", "A1": "R13", "B": "R24", "B1": "R34", "D": "R45", "C": "R05"}


def _nonneg(name, value):
    value = check_finite(name, value)
    if np.any(np.asarray(value) < 0.0):
        raise MechanismError(f"{name} must not be negative, got {value}")
    return value


@dataclass(frozen=True)
class SpatialMasses:
    """Masses (kg) and moments of inertia (kg m^2, about the centre of mass) of the drive.

    Parameters
    ----------
    pitman : mass of each pitman; ``pitman_com`` its centre of mass as a fraction of the length
        from the crank pin; ``pitman_inertia`` about a transverse axis (default ``m l^2 / 12``,
        a slender bar), ``pitman_axial_inertia`` about its own axis.
    equalizer : mass, centre of mass midway between B and B1; ``equalizer_inertia`` transverse
        (default ``m w^2 / 12``), ``equalizer_axial_inertia`` about B-B1.
    beam, beam_com, beam_inertia : the walking beam (and everything rigid with it but the
        horsehead): mass, centre of mass ``(u, v)`` m in the beam frame (origin C, u along the
        horsehead direction, v = n_C x u, "up" when the beam is level), inertia about the
        saddle-bearing axis through its centre of mass.
    head, head_com, head_inertia : the horsehead, the same way (paper 002 keeps beam and head
        apart: G_bal and G_gb).
    crank_inertia : cranks (and the counterweights, unless ``counterweight`` is given) about the
        shaft axis.
    counterweight : total mass of the counterweights; 0 makes the counterbalance a pure moment
        (its weight and inertia forces on the shaft bearing are then left out).
    """

    pitman: float = 0.0
    pitman_com: float = 0.5
    pitman_inertia: float | None = None
    pitman_axial_inertia: float = 0.0
    equalizer: float = 0.0
    equalizer_inertia: float | None = None
    equalizer_axial_inertia: float = 0.0
    beam: float = 0.0
    beam_com: tuple[float, float] = (0.0, 0.0)
    beam_inertia: float = 0.0
    head: float = 0.0
    head_com: tuple[float, float] = (0.0, 0.0)
    head_inertia: float = 0.0
    crank_inertia: float = 0.0
    counterweight: float = 0.0

    def __post_init__(self):
        for name in (
            "pitman",
            "pitman_axial_inertia",
            "equalizer",
            "equalizer_axial_inertia",
            "beam",
            "beam_inertia",
            "head",
            "head_inertia",
            "crank_inertia",
            "counterweight",
        ):
            object.__setattr__(self, name, _nonneg(f"masses.{name}", getattr(self, name)))
        for name in ("pitman_inertia", "equalizer_inertia"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, _nonneg(f"masses.{name}", getattr(self, name)))
        com = check_finite("masses.pitman_com", self.pitman_com)
        if not 0.0 <= com <= 1.0:
            raise MechanismError(
                f"masses.pitman_com must lie in [0, 1] (fraction of the length), got {com}"
            )
        object.__setattr__(self, "pitman_com", com)
        for name in ("beam_com", "head_com"):
            u, v = getattr(self, name)
            object.__setattr__(
                self, name, (check_finite(f"masses.{name}", u), check_finite(f"masses.{name}", v))
            )

    def pitman_transverse(self, length):
        if self.pitman_inertia is not None:
            return self.pitman_inertia
        return self.pitman * np.asarray(length) ** 2 / 12.0

    def equalizer_transverse(self, width):
        if self.equalizer_inertia is not None:
            return self.equalizer_inertia
        return self.equalizer * np.asarray(width) ** 2 / 12.0


class Reaction(NamedTuple):
    """Force (N) and moment (N m) of a pair, arrays (..., 3)."""

    force: Any
    moment: Any

    @property
    def magnitude(self):
        return norm(self.force)


@dataclass(frozen=True)
class SpatialForces:
    """Forces in the spatial drive over the crank angles ``theta``.

    Attributes
    ----------
    theta, omega : crank angles (rad) and speed (rad/s).
    joints : ``"revolute"`` or ``"spherical"``.
    crank_torque : the gearbox torque on the crank, about the shaft, positive in the direction
        of rotation (N m).
    pitman_force : ``{"left", "right"}`` axial force at mid-length, tension positive (N).
    reactions : ``{"R01", "R12", "R13", "R24", "R34", "R45", "R05"}`` -> :class:`Reaction`
        (see the module table; :meth:`pair` takes the pair letter instead).
    elastic : ``{"left", "right"}`` -> ``{"torsion", "bending_A", "bending_B"}`` (N m): each
        pitman's twisting moment about its axis and the bending moments (magnitudes) that the
        pairs apply at its ends; zero in the rational drive.
    elastic_energy : strain energy stored in the pitmans (J).
    load : polished-rod load (N) at every angle.
    residual : load left unbalanced by the local mobilities (N, see
        :mod:`mechsynth.dynamics.spatial_kinetostatics`).
    motion : the :class:`SpatialPumpMotion` used.
    info : rank, nullity (number of self-stress states), masses.
    """

    theta: Any
    omega: Any
    joints: str
    crank_torque: Any
    pitman_force: dict[str, Any]
    reactions: dict[str, Reaction]
    elastic: dict[str, dict[str, Any]]
    elastic_energy: Any
    load: Any
    residual: Any
    motion: SpatialPumpMotion
    info: dict = field(default_factory=dict)

    def pair(self, name: str) -> Reaction:
        """The reaction at pair ``name`` (``"O" "A" "A1" "B" "B1" "D" "C"``)."""
        if name not in PAIRS:
            raise MechanismError(f"unknown pair {name!r}; pairs: {', '.join(PAIRS)}")
        return self.reactions[PAIRS[name]]

    @property
    def split(self):
        """``(F_left - F_right) / mean`` at every angle: the pitmans' load split as a fraction of
        the mean pitman force (0 for equal pitmans)."""
        fl, fr = self.pitman_force["left"], self.pitman_force["right"]
        mean = 0.5 * (fl + fr)
        return (fl - fr) / np.where(mean == 0.0, np.inf, mean)

    @property
    def peak_split(self):
        """Largest ``|F_left - F_right|`` over the cycle divided by the largest mean pitman force
        ``(|F_left| + |F_right|) / 2`` (a fraction; the measure of the tolerance chart). Reduces
        the last axis (the crank angles)."""
        fl, fr = self.pitman_force["left"], self.pitman_force["right"]
        return np.max(np.abs(fl - fr), axis=-1) / np.max(0.5 * (np.abs(fl) + np.abs(fr)), axis=-1)

    def to_dict(self) -> dict[str, Any]:
        """Cycle extremes (one design)."""
        fl, fr = self.pitman_force["left"], self.pitman_force["right"]
        out = {
            "joints": self.joints,
            "peak_crank_torque": float(np.max(np.abs(self.crank_torque))),
            "max_pitman_force_left": float(np.max(fl)),
            "max_pitman_force_right": float(np.max(fr)),
            "max_pitman_difference": float(np.max(np.abs(fl - fr))),
            "peak_split": float(self.peak_split),
            "max_local_split": float(np.max(np.abs(self.split))),
            "max_torsion": float(
                max(np.max(np.abs(self.elastic[s]["torsion"])) for s in ("left", "right"))
            ),
            "max_bending": float(
                max(
                    np.max(self.elastic[s][k])
                    for s in ("left", "right")
                    for k in ("bending_A", "bending_B")
                )
            ),
            "max_elastic_energy": float(np.max(self.elastic_energy)),
            "max_residual": float(np.max(self.residual)),
            "self_stress_states": int(self.info["nullity"]),
        }
        for name, r in self.reactions.items():
            out[f"peak_{name}"] = float(np.max(norm(r.force)))
        return out


def rod_load(unit, motion, theta, load):
    """The polished-rod load (N) at the motion's angles from a number, an array over ``theta``,
    a function of the motion or a :class:`DynamometerCard` (mapped by position and direction)."""
    shape = np.shape(motion.torque_factor)
    if isinstance(load, DynamometerCard):
        w = load.load_on(motion, unit.stroke)
    elif callable(load):
        w = np.asarray(load(motion), dtype=float)
    else:
        w = np.asarray(check_finite("load", load), dtype=float)
    try:
        w = np.broadcast_to(w, shape)
    except ValueError:
        raise MechanismError(
            f"load: shape {np.shape(w)} does not match the crank angles {shape}"
        ) from None
    if not np.all(np.isfinite(w)):
        raise MechanismError("load: not finite at every crank angle")
    return w


def _axisymmetric(j_t, j_a, axis):
    """Inertia tensor (..., 3, 3) of a body symmetric about ``axis``."""
    a = np.asarray(axis)
    j_t = np.asarray(j_t, dtype=float)[..., None, None]
    j_a = np.asarray(j_a, dtype=float)[..., None, None]
    return j_t * np.eye(3) + (j_a - j_t) * (a[..., :, None] * a[..., None, :])


def _body_load(mass, g_vec, com, ref, acc_com, J=None, omega=None, eps=None):
    """Resultant (force, moment about ``ref``) of gravity and d'Alembert inertia of a body."""
    m = np.asarray(mass, dtype=float)[..., None]
    force = m * (g_vec - acc_com)
    moment = cross(com - ref, force)
    if J is not None:
        Jw = np.einsum("...ij,...j->...i", J, omega)
        moment = moment - np.einsum("...ij,...j->...i", J, eps) - cross(omega, Jw)
    return force, moment


class Part(NamedTuple):
    """A mass of a body: its centre's track (..., 3) and, for a rotating body, its inertia
    tensor about that centre (..., 3, 3) with the body's angular velocity and acceleration."""

    mass: Any
    position: Any
    velocity: Any
    acceleration: Any
    J: Any = None
    omega: Any = None
    epsilon: Any = None


def body_parts(unit, motion, masses: SpatialMasses, counterbalance=None, gravity=GRAVITY):
    """``{body: [Part, ...]}``: the masses of the crank (rotary inertia; point counterweights
    if ``masses.counterweight``), the pitmans, the equalizer and the beam (beam and horsehead)
    with their tracks, from the ``motion`` (time derivatives)."""
    P, K = motion.points, motion.links
    pos = {k: v.position for k, v in P.items()}
    L = unit.lengths
    zero = 0.0 * pos["N"]
    lk = K["crank"]
    J1 = np.asarray(masses.crank_inertia, dtype=float)[..., None, None] * (
        lk.axis[..., :, None] * lk.axis[..., None, :]
    )
    parts = {"crank": [Part(0.0, pos["N"], zero, zero, J1, lk.omega, lk.epsilon)]}
    if counterbalance is not None and masses.counterweight > 0.0:
        rs, _ = unit.axes()
        M, tau = counterbalance.moment, counterbalance.phase
        phi = unit.sense * (np.asarray(motion.theta) - tau) + np.pi / 2.0
        radius = M / (masses.counterweight * gravity)
        rel = radius * (
            np.cos(phi)[..., None] * rs[..., :, 0] + np.sin(phi)[..., None] * rs[..., :, 1]
        )
        parts["crank"].append(
            Part(
                masses.counterweight,
                pos["N"] + rel,
                cross(lk.omega, rel),
                cross(lk.epsilon, rel) + cross(lk.omega, cross(lk.omega, rel)),
            )
        )
    for side, a, b in (("left", "A", "B"), ("right", "A1", "B1")):
        body = f"pitman_{side}"
        lk = K[body]
        r = masses.pitman_com * (pos[b] - pos[a])
        J = _axisymmetric(masses.pitman_transverse(L[body]), masses.pitman_axial_inertia, lk.axis)
        parts[body] = [
            Part(
                masses.pitman,
                pos[a] + r,
                P[a].velocity + cross(lk.omega, r),
                P[a].acceleration + cross(lk.epsilon, r) + cross(lk.omega, cross(lk.omega, r)),
                J,
                lk.omega,
                lk.epsilon,
            )
        ]
    lk = K["equalizer"]
    J = _axisymmetric(
        masses.equalizer_transverse(unit.equalizer_width), masses.equalizer_axial_inertia, lk.axis
    )
    parts["equalizer"] = [
        Part(
            masses.equalizer,
            0.5 * (pos["B"] + pos["B1"]),
            0.5 * (P["B"].velocity + P["B1"].velocity),
            0.5 * (P["B"].acceleration + P["B1"].acceleration),
            J,
            lk.omega,
            lk.epsilon,
        )
    ]
    lk = K["beam"]
    head = (pos["E"] - pos["C"]) / np.asarray(unit.front_arm, dtype=float)[..., None]
    up = cross(lk.axis, head)
    parts["beam"] = []
    for mass, (cu, cv), inertia in (
        (masses.beam, masses.beam_com, masses.beam_inertia),
        (masses.head, masses.head_com, masses.head_inertia),
    ):
        r = cu * head + cv * up
        J = np.asarray(inertia, dtype=float)[..., None, None] * (
            lk.axis[..., :, None] * lk.axis[..., None, :]
        )
        parts["beam"].append(
            Part(
                mass,
                pos["C"] + r,
                cross(lk.omega, r),
                cross(lk.epsilon, r) + cross(lk.omega, cross(lk.omega, r)),
                J,
                lk.omega,
                lk.epsilon,
            )
        )
    return parts


def power_balance(forces: SpatialForces, counterbalance=None, gravity=GRAVITY) -> dict[str, Any]:
    """The energy balance of a force result, term by term (W, arrays over the angles).

    ``drive`` (crank torque x speed) + ``counterbalance`` + ``gravity`` + ``rod`` (the
    polished-rod load) + ``pair_moments`` (the power of the pairs' reaction moments on the
    relative angular velocities of the rigid motion: the strain-energy rate of the elastically
    closed redundant drive) + ``unbalanced`` (of the loads a local mobility leaves unbalanced)
    = ``kinetic`` (dT/dt). ``error`` is the difference, which vanishes for a correct solution.
    """
    m = forces.motion
    masses = forces.info["masses"]
    unit = forces.info["unit"]
    g = np.array([0.0, -gravity, 0.0])
    kinetic = gravity_power = 0.0
    for items in body_parts(unit, m, masses, counterbalance, gravity).values():
        for part in items:
            kinetic = kinetic + part.mass * dot(part.velocity, part.acceleration)
            gravity_power = gravity_power + part.mass * dot(g, part.velocity)
            if part.J is not None:
                Je = np.einsum("...ij,...j->...i", part.J, part.epsilon)
                kinetic = kinetic + dot(part.omega, Je)
    K, P = m.links, m.points
    omega = {k: K[k].omega for k in ("crank", "pitman_left", "pitman_right", "equalizer", "beam")}
    omega["frame"] = 0.0 * omega["crank"]
    velocity = {
        "crank": 0.0 * P["N"].velocity,
        "pitman_left": P["A"].velocity,
        "pitman_right": P["A1"].velocity,
        "equalizer": P["D"].velocity,
        "beam": 0.0 * P["C"].velocity,
    }
    speed = np.asarray(forces.omega)
    cb = 0.0
    if counterbalance is not None and not masses.counterweight > 0.0:
        cb = counterbalance.torque(forces.theta) * speed
    pairs = {
        "R12": ("pitman_left", "crank"),
        "R13": ("pitman_right", "crank"),
        "R24": ("equalizer", "pitman_left"),
        "R34": ("equalizer", "pitman_right"),
        "R45": ("beam", "equalizer"),
        "R05": ("beam", "frame"),
    }
    pair_moments = sum(
        dot(forces.reactions[n].moment, omega[a] - omega[b]) for n, (a, b) in pairs.items()
    )
    unbalanced = sum(
        dot(f, velocity[b]) + dot(t, omega[b]) for b, (f, t) in forces.info["unbalanced"].items()
    )
    out = {
        "drive": forces.crank_torque * speed,
        "counterbalance": cb + 0.0 * speed,
        "gravity": gravity_power,
        "rod": -forces.load * m.polished_rod.velocity,
        "pair_moments": pair_moments,
        "unbalanced": unbalanced,
        "kinetic": kinetic,
    }
    out["error"] = (
        out["drive"]
        + out["counterbalance"]
        + out["gravity"]
        + out["rod"]
        + out["pair_moments"]
        - out["unbalanced"]
        - out["kinetic"]
    )
    return out


def _rod_direction(n_c):
    """The horizontal unit vector in the beam's plane pointing to the well: the arm of the
    vertical polished-rod load about the saddle bearing is ``A`` times it."""
    return unit(cross(Y, n_c))


def _pitman_frame(axis, shaft, splay):
    """The pitman's section axes (x along the pitman, z across it nearest the shaft, y = z x x)
    as the columns of a rotation matrix, and the axis of its pin holes: parallel to the shaft in
    the ideal drive, where the pitman leans by ``splay`` = (its axis . shaft) when the crank
    spacing and the equalizer width differ, and turning with the pitman in the plane of its axis
    and the shaft otherwise."""
    across = unit(shaft - dot(shaft, axis)[..., None] * axis)
    ey = cross(across, axis)
    splay = np.asarray(splay, dtype=float)[..., None]
    holes = splay * axis + np.sqrt(1.0 - splay**2) * across
    return np.stack([axis, ey, across], axis=-1), holes


def spatial_forces(
    unit: SpatialPumpingUnit,
    theta,
    speed,
    load=0.0,
    counterbalance: Counterbalance | None = None,
    masses: SpatialMasses | None = None,
    epsilon=0.0,
    gravity=GRAVITY,
    pin_play=0.0,
) -> SpatialForces:
    """Reactions in every pair, the pitman forces and moments and the crank torque.

    Parameters
    ----------
    unit : the :class:`SpatialPumpingUnit` (its ``joints`` select the redundant or the
        rational drive).
    theta : crank angles (rad, from 12 o'clock in the direction of rotation).
    speed : crank speed (rad/s, > 0), a number or an array over ``theta``.
    load : polished-rod load (N, downward): a number, an array over ``theta``, a function of the
        :class:`SpatialPumpMotion`, or a :class:`DynamometerCard`.
    counterbalance : :class:`Counterbalance` (moment ``M`` in N m, phase ``tau``): the crank
        counterweights' gravity torque ``M sin(theta - tau)`` in the direction of rotation, as in
        the planar unit; with ``masses.counterweight`` it is the weight of those point masses.
    masses : :class:`SpatialMasses` (default: massless links).
    epsilon : crank angular acceleration (rad/s^2).
    gravity : g (m/s^2) along -y.
    pin_play : the angle (rad) a pin can tilt freely in its hole at A, A1, B, B1 (wear
        clearance: diametral clearance / bearing length), for the redundant drive. Each pair's
        misfit rotation is shortened by it (a dead zone: a pin inside its play carries no
        moment, beyond it the rest of the misfit strains the pitmans); ``info["misfit_angle"]``
        gives the misfit (rad) of each pair, the play that frees it.

    Returns
    -------
    SpatialForces
    """
    if not isinstance(unit, SpatialPumpingUnit):
        raise MechanismError(f"unit must be a SpatialPumpingUnit, got {type(unit).__name__}")
    if speed is None:
        raise MechanismError("forces need the crank speed (rad/s); e.g. speed=ms.spm(6)")
    speed = check_finite("speed", speed)
    if np.any(np.asarray(speed) <= 0.0):
        raise MechanismError(
            f"speed must be positive (rad/s in the direction of rotation), got {speed}"
        )
    if counterbalance is not None and not isinstance(counterbalance, Counterbalance):
        raise MechanismError("counterbalance must be a Counterbalance(moment, phase) or None")
    masses = SpatialMasses() if masses is None else masses
    if not isinstance(masses, SpatialMasses):
        raise MechanismError("masses must be a SpatialMasses")
    g = check_finite("gravity", gravity)
    play = float(check_finite("pin_play", pin_play))
    if play < 0.0:
        raise MechanismError(f"pin_play must be >= 0 rad (clearance / bearing length), got {play}")
    theta = np.asarray(theta, dtype=float)
    m = unit.motion(theta, speed=speed, epsilon=epsilon)
    w = rod_load(unit, m, theta, load)
    P, K = m.points, m.links
    pos = {k: v.position for k, v in P.items()}
    shape = np.shape(m.torque_factor)
    g_vec = np.array([0.0, -g, 0.0])
    L = unit.lengths
    s = unit.sense

    parts = body_parts(unit, m, masses, counterbalance, g)
    loads = {}
    for body, items in parts.items():
        ref = {
            "crank": pos["N"],
            "pitman_left": pos["A"],
            "pitman_right": pos["A1"],
            "equalizer": pos["D"],
            "beam": pos["C"],
        }[body]
        f_tot = np.zeros(shape + (3,))
        m_tot = np.zeros(shape + (3,))
        for part in items:
            fb, mb = _body_load(
                part.mass,
                g_vec,
                part.position,
                ref,
                part.acceleration,
                part.J,
                part.omega,
                part.epsilon,
            )
            f_tot, m_tot = f_tot + fb, m_tot + mb
        loads[body] = (f_tot, m_tot)
    n_o, n_c = K["crank"].axis, K["beam"].axis
    C = pos["C"]
    if counterbalance is not None and not masses.counterweight > 0.0:
        # the counterweights as a pure moment: M sin(theta - tau) in the direction of rotation
        M, tau = counterbalance.moment, counterbalance.phase
        f_c, m_c = loads["crank"]
        loads["crank"] = (f_c, m_c + (M * np.sin(theta - tau))[..., None] * (s * n_o))
    # the polished-rod load hangs from the horsehead at the horizontal arm A from C
    arm = np.asarray(unit.front_arm, dtype=float)[..., None] * _rod_direction(n_c)
    f_rod = -w[..., None] * Y
    f_b, m_b = loads["beam"]
    loads["beam"] = (f_b + f_rod, m_b + cross(arm, f_rod))

    kind = unit.joints
    joints = (
        SpatialJoint("R01", "crank", "frame", "driven"),
        SpatialJoint("R12", "pitman_left", "crank", kind),
        SpatialJoint("R13", "pitman_right", "crank", kind),
        SpatialJoint("R24", "equalizer", "pitman_left", kind),
        SpatialJoint("R34", "equalizer", "pitman_right", kind),
        SpatialJoint("R45", "beam", "equalizer", "spherical"),
        SpatialJoint("R05", "beam", "frame", "revolute"),
    )
    e_axis = K["equalizer"].axis
    points = {
        "R01": pos["N"],
        "R12": pos["A"],
        "R13": pos["A1"],
        "R24": pos["B"],
        "R34": pos["B1"],
        "R45": pos["D"],
        "R05": C,
    }
    axes = {"R01": n_o, "R12": n_o, "R13": n_o, "R24": e_axis, "R34": e_axis, "R05": n_c}
    refs = {
        "crank": pos["N"],
        "pitman_left": pos["A"],
        "pitman_right": pos["A1"],
        "equalizer": pos["D"],
        "beam": C,
    }
    frames = {}
    for side, body in (("left", "pitman_left"), ("right", "pitman_right")):
        # the ideal lean of the pitman along the shaft: (B_z - A_z) / l in the ideal drive
        lean = (unit.crank_spacing - unit.equalizer_width) / 2.0 / L[body]
        frames[side] = _pitman_frame(K[body].axis, n_o, lean if side == "left" else -lean)
    compliance = misfit = None
    misfit_angle = {}
    if kind == "revolute":
        compliance, misfit = {}, {}
        for side, jb, ja in (("left", "R24", "R12"), ("right", "R34", "R13")):
            R, h = frames[side]
            c_loc = cantilever_compliance(L[f"pitman_{side}"], unit.pitman_section)
            T = np.zeros(np.shape(R)[:-2] + (6, 6))
            T[..., :3, :3] = R
            T[..., 3:, 3:] = R
            c_glob = T @ c_loc[..., :, :] @ np.swapaxes(T, -1, -2)
            compliance[jb] = (f"pitman_{side}", c_glob)
            zero = np.zeros(shape + (3,))
            misfit[ja] = (zero, cross(n_o, h))  # crank pin (by) -> pitman hole (on)
            misfit[jb] = (zero, cross(h, e_axis))  # pitman hole (by) -> equalizer pin (on)
            # the tilt (rad) of each pin in its hole that the rigid motion asks for: a
            # diametral clearance of (bearing length x this angle) lets the pair take it freely
            for j in (ja, jb):
                rot = misfit[j][1]
                size = norm(rot)
                misfit_angle[j] = size
                if play > 0.0:
                    keep = np.maximum(size - play, 0.0) / np.where(size > 0.0, size, 1.0)
                    misfit[j] = (zero, rot * keep[..., None])
    length = float(np.max(np.asarray(unit.rear_arm)))
    sol = solve_spatial(
        ["crank", "pitman_left", "pitman_right", "equalizer", "beam"],
        refs,
        joints,
        points,
        axes,
        loads,
        compliance=compliance,
        misfit=misfit,
        length=length,
    )
    reactions = {j.name: Reaction(sol.force[j.name], sol.moment[j.name]) for j in joints}
    torque = s * sol.torque["R01"]
    pitman, elastic = {}, {}
    for side, ja, jb, body in (
        ("left", "R12", "R24", "pitman_left"),
        ("right", "R13", "R34", "pitman_right"),
    ):
        ax = K[body].axis
        n_a = -dot(sol.force[ja], ax)
        n_b = -dot(sol.force[jb], ax)  # the force on the pitman at B is -R24
        pitman[side] = 0.5 * (n_a + n_b)
        m_a = sol.moment[ja]
        m_b = -sol.moment[jb]
        t_a, t_b = dot(m_a, ax), dot(m_b, ax)
        elastic[side] = {
            "torsion": 0.5 * (t_b - t_a),
            "bending_A": norm(m_a - t_a[..., None] * ax),
            "bending_B": norm(m_b - t_b[..., None] * ax),
        }
    return SpatialForces(
        theta=theta,
        omega=m.omega,
        joints=kind,
        crank_torque=torque,
        pitman_force=pitman,
        reactions=reactions,
        elastic=elastic,
        elastic_energy=sol.elastic_energy,
        load=w,
        residual=sol.residual,
        motion=m,
        info={
            "misfit_angle": misfit_angle,
            "rank": sol.rank,
            "nullity": sol.nullity,
            "masses": masses,
            "unbalanced": sol.unbalanced,
            "unit": unit,
        },
    )


def planar_torque(
    unit: SpatialPumpingUnit,
    theta,
    speed,
    load=0.0,
    counterbalance: Counterbalance | None = None,
    masses: SpatialMasses | None = None,
    epsilon=0.0,
    gravity=GRAVITY,
):
    """The crank torque (N m, in the direction of rotation) of the **planar** unit
    ``unit.planar`` with the same masses, by the planar kinetostatics of
    :mod:`mechsynth.dynamics.kinetostatics`: both pitmans as one planar pitman of twice the mass
    and inertia, the beam and horsehead as one beam, the equalizer as a point mass at its bearing
    (it does not turn in the ideal drive). The reference the ideal spatial drive must reproduce
    -- exactly when the pitmans are parallel; leaning pitmans (crank spacing and equalizer width
    unequal) turn about the shaft with a slightly smaller moment of inertia than a planar one.
    """
    from ...dynamics.inertia import LinkInertia
    from ...dynamics.kinetostatics import FRAME, ForceModel, Revolute, kinetostatics
    from ...dynamics.loads import Gravity, PointForce, Torque

    masses = SpatialMasses() if masses is None else masses
    if masses.counterweight > 0.0:
        raise MechanismError("planar_torque: give the counterweights as crank_inertia and a moment")
    pu = unit.planar
    theta = np.asarray(theta, dtype=float)
    m = pu.motion(theta, speed=speed, epsilon=epsilon)
    pitman = float(np.asarray(pu.pitman))
    # beam + horsehead + equalizer (a point mass at the rear-arm end) as one body
    rear = -1.0 if pu.unit_class == "conventional" else 1.0
    parts = [
        (masses.beam, masses.beam_com, masses.beam_inertia),
        (masses.head, masses.head_com, masses.head_inertia),
        (masses.equalizer, (rear * float(pu.rear_arm), 0.0), 0.0),
    ]
    mass = sum(p[0] for p in parts)
    if mass > 0.0:
        cu = sum(p[0] * p[1][0] for p in parts) / mass
        cv = sum(p[0] * p[1][1] for p in parts) / mass
    else:
        cu = cv = 0.0
    inertia = sum(p[2] + p[0] * ((p[1][0] - cu) ** 2 + (p[1][1] - cv) ** 2) for p in parts)
    bodies = {
        "crank": LinkInertia("crank", "O1", 0.0, inertia=masses.crank_inertia),
        "pitman": LinkInertia(
            "pitman",
            "A",
            2.0 * masses.pitman,
            com=(masses.pitman_com * pitman, 0.0),
            inertia=2.0 * float(np.asarray(masses.pitman_transverse(unit.lengths["pitman_left"]))),
        ),
        "beam": LinkInertia("beam", "O2", mass, com=(cu, cv), inertia=inertia),
    }
    joints = (
        Revolute("R10", "crank", FRAME, "O1"),
        Revolute("R21", "pitman", "crank", "A"),
        Revolute("R32", "beam", "pitman", "B"),
        Revolute("R30", "beam", FRAME, "O2"),
    )
    w = rod_load(pu, m, theta, load)
    loads = [Gravity(gravity), PointForce("beam", "PR", lambda mm: (0.0 * w, -w))]
    if counterbalance is not None:
        M, tau = counterbalance.moment, counterbalance.phase
        loads.append(Torque("crank", lambda mm: pu.sense * M * np.sin(theta - tau)))
    res = kinetostatics(ForceModel(bodies, joints, tuple(loads), "crank"), m)
    return pu.sense * np.asarray(res.torque)
