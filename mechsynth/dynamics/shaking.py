"""Shaking force and shaking moment: what the moving links of a machine do to its frame.

The shaking force is minus the sum of the inertia forces' opposites, ``F_sh = -sum m_i a_Si``, and
the shaking moment about a point P of the frame is ``M_sh = -sum [(r_Si - P) x m_i a_Si + J_i
eps_i]`` (N, N m, counter-clockwise positive): the d'Alembert inertia loads of the moving bodies,
all of which the frame must take.

Two independent computations are provided. :func:`shaking` takes them from the kinematics and
the mass properties alone. :func:`frame_load` takes them from a kinetostatic solution: the frame
receives the opposite of every ground-joint reaction, of every applied load (those are reacted by
the frame: a die, a spring's anchor; the drive's stator takes the opposite of the balancing
torque) -- and the part of this due to gravity, the moving bodies' weight and its moment, is taken
off (the foundation, not the frame's vibration, carries it). By the bodies' equilibrium the two
are equal at every crank angle; the tests check it to round-off.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..kinematics import ops
from ..kinematics.tracks import Motion
from .inertia import com_track
from .kinetostatics import FRAME, Contact, ForceModel, ForceResult, Prismatic, Revolute

__all__ = ["FrameLoad", "shaking", "frame_load"]


@dataclass(frozen=True)
class FrameLoad:
    """A force and a moment on the frame over the crank angles ``phi``.

    Attributes
    ----------
    phi : crank angles (rad).
    fx, fy : force components (N).
    moment : moment about ``about`` (N m, counter-clockwise positive).
    about : the point (m) the moment is taken about.
    """

    phi: Any
    fx: Any
    fy: Any
    moment: Any
    about: tuple = (0.0, 0.0)

    @property
    def magnitude(self):
        """``|F|`` (N) at every angle."""
        return ops.hypot(self.fx, self.fy)

    def peak(self) -> tuple[float, float]:
        """(largest ``|F|`` in N, the crank angle in rad where it occurs)."""
        f = np.asarray(self.magnitude, dtype=float)
        i = int(np.argmax(f))
        return float(f[i]), float(np.asarray(self.phi)[i])

    def peak_moment(self) -> tuple[float, float]:
        """(largest ``|M|`` in N m, the crank angle in rad where it occurs)."""
        m = np.abs(np.asarray(self.moment, dtype=float))
        i = int(np.argmax(m))
        return float(m[i]), float(np.asarray(self.phi)[i])


def _moment(fx, fy, x, y, about):
    return (x - about[0]) * fy - (y - about[1]) * fx


def shaking(model: ForceModel, motion: Motion, about=(0.0, 0.0)) -> FrameLoad:
    """Shaking force and moment (about ``about``, m) of the bodies of ``model`` from their
    kinematics: ``-sum m a_S`` and ``-sum [(r_S - P) x m a_S + J eps]``. ``motion`` must be a time
    motion (with a speed)."""
    fx = fy = mz = 0.0
    for body in model.bodies.values():
        s = com_track(motion, body)
        ix, iy = -body.mass * s.ax, -body.mass * s.ay
        fx, fy = fx + ix, fy + iy
        mz = mz + _moment(ix, iy, s.x, s.y, about)
        if body.link is not None:
            mz = mz - body.inertia * motion.links[body.link].epsilon
    shape = np.shape(motion.phi)
    return FrameLoad(
        motion.phi, *(np.broadcast_to(v, shape) + 0.0 for v in (fx, fy, mz)), tuple(about)
    )


def frame_load(
    model: ForceModel, motion: Motion, result: ForceResult, about=(0.0, 0.0)
) -> FrameLoad:
    """The frame's dynamic load from a kinetostatic ``result`` of ``model`` on ``motion``.

    The frame receives minus the ground-joint reactions (with the pair moments of sliding pairs),
    minus every applied load (reacted by the frame) and minus the balancing torque (or driving
    force), less the bodies' weight; equal to :func:`shaking` by the bodies' equilibrium."""
    fx = fy = mz = 0.0
    for j in model.joints:
        if FRAME not in (j.on, j.by):
            continue
        sign = 1.0 if j.by == FRAME else -1.0  # the force on the moving body from the frame
        rx, ry = result.reactions[j.name]
        p = motion.points[j.point]
        fx, fy = fx + sign * rx, fy + sign * ry
        mz = mz + sign * _moment(rx, ry, p.x, p.y, about)
        if isinstance(j, Prismatic):
            mz = mz + sign * result.normals[j.name][1]
        elif not isinstance(j, (Revolute, Contact)):
            raise TypeError(f"unknown joint type {type(j).__name__}")
    for load in model.loads:
        for w in load.contributions(motion, model.bodies):
            fx, fy = fx + w.fx, fy + w.fy
            mz = mz + _moment(w.fx, w.fy, w.x, w.y, about) + w.tz
    if model.drive is None:
        mz = mz + result.torque
    else:
        d = model.drive.direction
        th = motion.links[d].angle if isinstance(d, str) else d
        p = motion.points[model.drive.point]
        ux, uy = ops.cos(th) * result.torque, ops.sin(th) * result.torque
        fx, fy = fx + ux, fy + uy
        mz = mz + _moment(ux, uy, p.x, p.y, about)
    # what the moving bodies receive from the frame, the loads and the drive balances their
    # inertia loads: the frame's dynamic load is its opposite
    shape = np.shape(motion.phi)
    return FrameLoad(
        motion.phi, *(np.broadcast_to(-v, shape) + 0.0 for v in (fx, fy, mz)), tuple(about)
    )
