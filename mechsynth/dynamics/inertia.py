"""Mass properties of links and the kinetic energy they carry.

A :class:`LinkInertia` attaches a mass, a centre of mass and a moment of inertia to a link of a
mechanism's :class:`~mechsynth.kinematics.Motion`: the link's frame has its origin at the point
``base`` (a name in ``motion.points``) and its x axis along the link angle ``link`` (a name in
``motion.links``; ``None`` for a translating link such as a slider, whose frame keeps the x axis
along +x). The centre of mass sits at ``(u, v)`` in that frame.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import MechanismError
from ..kinematics import ops
from ..kinematics.mechanism import check_finite
from ..kinematics.tracks import Motion, PointTrack

__all__ = ["LinkInertia", "com_track", "kinetic_energy", "reduced_inertia"]


def _check_nonnegative(name, value):
    value = check_finite(name, value)
    if not ops.is_symbolic(value):
        import numpy as np

        if np.any(np.asarray(value) < 0.0):
            raise MechanismError(f"{name} must not be negative, got {value}")
    return value


@dataclass(frozen=True)
class LinkInertia:
    """Mass (kg), centre of mass (u, v) in m in the link frame, and moment of inertia (kg m^2)
    about the centre of mass, of the link ``link`` whose frame origin is the point ``base``."""

    link: str | None
    base: str
    mass: float
    com: tuple[float, float] = (0.0, 0.0)
    inertia: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "mass", _check_nonnegative(f"mass of {self.label}", self.mass))
        object.__setattr__(
            self, "inertia", _check_nonnegative(f"inertia of {self.label}", self.inertia)
        )
        u, v = self.com
        object.__setattr__(
            self,
            "com",
            (check_finite(f"com u of {self.label}", u), check_finite(f"com v of {self.label}", v)),
        )

    @property
    def label(self) -> str:
        return self.link if self.link is not None else f"slider at {self.base}"


def com_track(motion: Motion, body: LinkInertia) -> PointTrack:
    """Track (position, velocity, acceleration) of the body's centre of mass."""
    p = motion.points[body.base]
    u, v = body.com
    if body.link is None:
        return PointTrack(p.x + u, p.y + v, p.vx, p.vy, p.ax, p.ay)
    lk = motion.links[body.link]
    c, s = ops.cos(lk.angle), ops.sin(lk.angle)
    ox, oy = u * c - v * s, u * s + v * c
    w, e = lk.omega, lk.epsilon
    return PointTrack(
        p.x + ox,
        p.y + oy,
        p.vx - oy * w,
        p.vy + ox * w,
        p.ax - oy * e - ox * w * w,
        p.ay + ox * e - oy * w * w,
    )


def kinetic_energy(motion: Motion, bodies) -> object:
    """Kinetic energy (J) of the bodies at every angle of ``motion``.

    With an analog motion (no speed) this is half the reduced moment of inertia: ``J(phi) / 2``.
    """
    total = 0.0
    for body in bodies:
        g = com_track(motion, body)
        t = 0.5 * body.mass * (g.vx * g.vx + g.vy * g.vy)
        if body.link is not None:
            w = motion.links[body.link].omega
            t = t + 0.5 * body.inertia * w * w
        total = total + t
    return total


def reduced_inertia(mechanism, bodies, phi):
    """Moment of inertia reduced to the crank, ``J(phi) = sum m v_S^2 + J_S w^2`` per unit crank
    speed (kg m^2), and its derivative ``dJ/dphi``, at crank angles ``phi``.

    The derivative is exact: ``dJ/dphi = 2 sum (m v_S . a_S + J_S w eps)`` with analogs.
    """
    m = mechanism.motion(phi)
    j = 0.0
    dj = 0.0
    for body in bodies:
        g = com_track(m, body)
        j = j + body.mass * (g.vx * g.vx + g.vy * g.vy)
        dj = dj + 2.0 * body.mass * (g.vx * g.ax + g.vy * g.ay)
        if body.link is not None:
            lk = m.links[body.link]
            j = j + body.inertia * lk.omega * lk.omega
            dj = dj + 2.0 * body.inertia * lk.omega * lk.epsilon
    return j, dj
