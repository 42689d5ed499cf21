"""Points, unit vectors and rotations in 3-D, vectorized over crank angles and designs.

A 3-D vector is a numpy array whose **last axis has length 3** (x, y, z); any leading axes
(designs, crank angles) broadcast, exactly like the planar models' parameters and angles. A
rotation is an array of shape ``(..., 3, 3)``. Everything here is plain numpy: the spatial models
that use it close their loops by Newton's method, which is not a CasADi expression, so there is
no symbolic path to serve (the planar models keep theirs through :mod:`mechsynth.kinematics.ops`).

Rigid-body kinematics in the form of Bour's formula: a vector ``r`` fixed in a body turning with
angular velocity ``omega`` and acceleration ``eps`` changes as ``dr/dt = omega x r`` and
``d2r/dt2 = eps x r + omega x (omega x r)``; :func:`point_velocity` and
:func:`point_acceleration` apply it to a point of the body.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import MechanismError

__all__ = [
    "X",
    "Y",
    "Z",
    "vec",
    "dot",
    "cross",
    "norm",
    "unit",
    "skew",
    "rotation",
    "tilt",
    "apply",
    "perpendicular_basis",
    "point_velocity",
    "point_acceleration",
    "SpatialPointTrack",
    "SpatialLinkTrack",
]

X = np.array([1.0, 0.0, 0.0])
Y = np.array([0.0, 1.0, 0.0])
Z = np.array([0.0, 0.0, 1.0])


def vec(x, y, z) -> np.ndarray:
    """A vector (..., 3) from broadcast components."""
    x, y, z = np.broadcast_arrays(*(np.asarray(c, dtype=float) for c in (x, y, z)))
    return np.stack([x, y, z], axis=-1)


def dot(a, b) -> np.ndarray:
    """Scalar product over the last axis."""
    return np.sum(np.asarray(a) * np.asarray(b), axis=-1)


def cross(a, b) -> np.ndarray:
    """Vector product over the last axis (broadcast)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out


def norm(a) -> np.ndarray:
    """Length of the vectors (last axis)."""
    return np.sqrt(dot(a, a))


def unit(a) -> np.ndarray:
    """The vectors scaled to length 1 (ValueError for a zero vector)."""
    a = np.asarray(a, dtype=float)
    n = norm(a)
    if np.any(n == 0.0):
        raise MechanismError("unit: zero vector has no direction")
    return a / n[..., None]


def skew(a) -> np.ndarray:
    """The matrix ``[a]x`` (..., 3, 3) with ``[a]x @ b = a x b``."""
    a = np.asarray(a, dtype=float)
    out = np.zeros(a.shape[:-1] + (3, 3))
    x, y, w = a[..., 0], a[..., 1], a[..., 2]
    out[..., 0, 1], out[..., 0, 2] = -w, y
    out[..., 1, 0], out[..., 1, 2] = w, -x
    out[..., 2, 0], out[..., 2, 1] = -y, x
    return out


def rotation(axis, angle) -> np.ndarray:
    """Rotation matrices (..., 3, 3) by ``angle`` (rad, right-handed) about the unit ``axis``
    (Rodrigues' formula)."""
    k = np.asarray(axis, dtype=float)
    angle = np.asarray(angle, dtype=float)
    K = skew(k)
    s, c = np.sin(angle)[..., None, None], np.cos(angle)[..., None, None]
    return np.eye(3) + s * K + (1.0 - c) * (K @ K)


def tilt(about_x, about_y) -> np.ndarray:
    """The rotation that tilts the z axis by ``about_x`` (rad, about x) and then by ``about_y``
    (about y): ``R_y(about_y) @ R_x(about_x)``. Used for axes misaligned from their nominal z
    direction; both angles zero give the identity."""
    return rotation(Y, about_y) @ rotation(X, about_x)


def apply(R, v) -> np.ndarray:
    """``R @ v`` for stacks of matrices (..., 3, 3) and vectors (..., 3)."""
    return np.einsum("...ij,...j->...i", np.asarray(R, dtype=float), np.asarray(v, dtype=float))


def perpendicular_basis(axis):
    """Two unit vectors ``(t1, t2)`` perpendicular to the unit ``axis`` and to each other, with
    ``(t1, t2, axis)`` right-handed: ``t1 = unit(Y x axis)``, or ``unit(X x axis)`` where the
    axis is within about 25 deg of y."""
    a = np.asarray(axis, dtype=float)
    near_y = np.abs(a[..., 1:2]) > 0.9
    ref = np.where(near_y, X, Y)
    t1 = unit(cross(ref, a))
    t2 = cross(a, t1)
    return t1, t2


def point_velocity(v_ref, omega, r) -> np.ndarray:
    """Velocity of the body point at ``r`` from a body point of velocity ``v_ref``:
    ``v_ref + omega x r`` (Bour)."""
    return np.asarray(v_ref, dtype=float) + cross(omega, r)


def point_acceleration(a_ref, omega, eps, r) -> np.ndarray:
    """Acceleration of the body point at ``r``: ``a_ref + eps x r + omega x (omega x r)``."""
    return np.asarray(a_ref, dtype=float) + cross(eps, r) + cross(omega, cross(omega, r))


@dataclass(frozen=True)
class SpatialPointTrack:
    """A point over the cycle: ``position`` (m), ``velocity`` (m/s) and ``acceleration`` (m/s^2),
    each an array (..., 3). Analogs (m/rad, m/rad^2) for a motion asked without a crank speed.

    Unlike the planar :class:`~mechsynth.kinematics.PointTrack`, ``velocity`` is the vector;
    its magnitude is :attr:`speed`.
    """

    position: Any
    velocity: Any
    acceleration: Any

    @property
    def x(self):
        return self.position[..., 0]

    @property
    def y(self):
        return self.position[..., 1]

    @property
    def z(self):
        return self.position[..., 2]

    @property
    def speed(self):
        """Magnitude of the velocity."""
        return norm(self.velocity)

    def to_time(self, omega, epsilon) -> SpatialPointTrack:
        """Time derivatives from analogs for crank speed ``omega`` and acceleration ``epsilon``
        (numbers or arrays over the leading axes)."""
        w = np.asarray(omega, dtype=float)[..., None]
        e = np.asarray(epsilon, dtype=float)[..., None]
        return SpatialPointTrack(
            self.position, self.velocity * w, self.acceleration * w * w + self.velocity * e
        )


@dataclass(frozen=True)
class SpatialLinkTrack:
    """A body's angular velocity ``omega`` (rad/s) and acceleration ``epsilon`` (rad/s^2) as
    vectors (..., 3), and the unit vector ``axis`` that the body carries along (a link's
    direction, a rotation axis). Analogs (rad/rad, rad/rad^2) without a crank speed."""

    omega: Any
    epsilon: Any
    axis: Any

    def to_time(self, omega, epsilon) -> SpatialLinkTrack:
        w = np.asarray(omega, dtype=float)[..., None]
        e = np.asarray(epsilon, dtype=float)[..., None]
        return SpatialLinkTrack(self.omega * w, self.epsilon * w * w + self.omega * e, self.axis)
