"""The generic 3-D helpers (mechsynth.kinematics.spatial)."""

import numpy as np
import pytest

from mechsynth.kinematics import spatial as sp


def test_cross_dot_norm_against_numpy():
    rng = np.random.default_rng(3)
    a, b = rng.normal(size=(5, 1, 3)), rng.normal(size=(4, 3))
    np.testing.assert_allclose(sp.cross(a, b), np.cross(a, b), rtol=0, atol=1e-15)
    np.testing.assert_allclose(sp.dot(a, b), np.einsum("...i,...i", *np.broadcast_arrays(a, b)))
    np.testing.assert_allclose(sp.norm(a), np.linalg.norm(a, axis=-1))
    np.testing.assert_allclose(sp.norm(sp.unit(a)), 1.0)
    np.testing.assert_allclose(sp.apply(sp.skew(a), b), np.cross(a, b), atol=1e-15)
    with pytest.raises(ValueError, match="zero vector"):
        sp.unit(np.zeros(3))


def test_rotation_is_orthonormal_and_turns_the_right_way():
    rng = np.random.default_rng(4)
    axis = sp.unit(rng.normal(size=(6, 3)))
    angle = rng.uniform(-3, 3, 6)
    R = sp.rotation(axis, angle)
    np.testing.assert_allclose(
        R @ np.swapaxes(R, -1, -2), np.broadcast_to(np.eye(3), R.shape), atol=1e-14
    )
    np.testing.assert_allclose(np.linalg.det(R), 1.0)
    np.testing.assert_allclose(sp.apply(R, axis), axis, atol=1e-14)  # the axis stays
    # a quarter turn about z takes x to y (right-handed)
    np.testing.assert_allclose(sp.apply(sp.rotation(sp.Z, np.pi / 2), sp.X), sp.Y, atol=1e-15)
    # small angles: R v = v + angle axis x v to second order
    h = 1e-6
    v = rng.normal(size=3)
    np.testing.assert_allclose(
        sp.apply(sp.rotation(axis[0], h), v), v + h * np.cross(axis[0], v), atol=1e-11
    )


def test_tilt_and_perpendicular_basis():
    R = sp.tilt(0.01, -0.02)
    z = R[:, 2]
    np.testing.assert_allclose(
        z, sp.apply(sp.rotation(sp.Y, -0.02), sp.apply(sp.rotation(sp.X, 0.01), sp.Z))
    )
    np.testing.assert_allclose(sp.tilt(0.0, 0.0), np.eye(3))
    axes = sp.unit(np.array([[0, 0, 1], [0, 1, 0], [1, 0.2, 0.1], [0.3, 0.95, 0]]))
    t1, t2 = sp.perpendicular_basis(axes)
    for a, b in ((t1, t2), (t1, axes), (t2, axes)):
        np.testing.assert_allclose(sp.dot(a, b), 0.0, atol=1e-15)
    np.testing.assert_allclose(sp.cross(t1, t2), axes, atol=1e-15)  # right-handed


def test_rigid_point_kinematics_and_tracks():
    w, e, r = np.array([0.0, 0.0, 2.0]), np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
    np.testing.assert_allclose(sp.point_velocity(0.0, w, r), [0.0, 2.0, 0.0])
    np.testing.assert_allclose(sp.point_acceleration(0.0, w, e, r), [-4.0, 1.0, 0.0])
    tr = sp.SpatialPointTrack(np.ones((2, 3)), np.ones((2, 3)), np.zeros((2, 3)))
    t = tr.to_time(np.array([2.0, 3.0]), 0.5)
    np.testing.assert_allclose(t.velocity[:, 0], [2.0, 3.0])
    np.testing.assert_allclose(t.acceleration[:, 0], [0.5, 0.5])
    np.testing.assert_allclose(t.speed, np.sqrt(3) * np.array([2.0, 3.0]))
