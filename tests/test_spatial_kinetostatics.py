"""The generic spatial kinetostatics with redundant pairs closed by compliance (force method)."""

import numpy as np
import pytest

from mechsynth.dynamics.spatial_kinetostatics import (
    BeamSection,
    SpatialJoint,
    cantilever_compliance,
    solve_spatial,
)

SEC = BeamSection(E=2.1e11, G=8.1e10, area=4e-3, J_y=2e-6, J_z=1.2e-6, J_p=3e-6)


def test_cantilever_compliance_is_the_inverse_of_the_beam_element_stiffness():
    """Against the end block of the standard 12 x 12 Euler-Bernoulli space-frame element
    (Przemieniecki): the compliance of a bar clamped at one end is its inverse."""
    L = 2.7
    E, G, A, Iy, Iz, J = SEC.E, SEC.G, SEC.area, SEC.J_y, SEC.J_z, SEC.J_p
    K = np.zeros((6, 6))
    K[0, 0] = E * A / L
    K[3, 3] = G * J / L
    K[1, 1], K[1, 5], K[5, 1], K[5, 5] = (
        12 * E * Iz / L**3, -6 * E * Iz / L**2, -6 * E * Iz / L**2, 4 * E * Iz / L,
    )  # fmt: skip
    K[2, 2], K[2, 4], K[4, 2], K[4, 4] = (
        12 * E * Iy / L**3, 6 * E * Iy / L**2, 6 * E * Iy / L**2, 4 * E * Iy / L,
    )  # fmt: skip
    C = cantilever_compliance(L, SEC)
    np.testing.assert_allclose(C @ K, np.eye(6), atol=1e-12)
    np.testing.assert_allclose(C, C.T)
    assert np.all(np.linalg.eigvalsh(C) > 0)
    # broadcast over designs
    assert cantilever_compliance(np.array([[1.0], [2.0]]), SEC).shape == (2, 1, 6, 6)


def _two_cantilevers(a, load=0.0, misfit=0.0):
    """A hub welded to two bars of length a clamped at x = 0 and x = 2a: a beam clamped at both
    ends, loaded at its middle (and/or with a kink ``misfit`` rad about z at the left weld)."""
    x = np.array([1.0, 0.0, 0.0])
    z = np.array([0.0, 0.0, 1.0])
    joints = (
        SpatialJoint("J1", "bar1", "frame", "driven"),
        SpatialJoint("J2", "bar2", "frame", "driven"),
        SpatialJoint("J3", "hub", "bar1", "driven"),
        SpatialJoint("J4", "hub", "bar2", "driven"),
    )
    pts = {"J1": 0 * x, "J2": 2 * a * x, "J3": a * x, "J4": a * x}
    refs = {"bar1": 0 * x, "bar2": 2 * a * x, "hub": a * x}
    c_loc = cantilever_compliance(a, SEC)
    R2 = np.column_stack([-x, [0.0, -1.0, 0.0], z])  # bar2 points back along -x
    T2 = np.zeros((6, 6))
    T2[:3, :3] = T2[3:, 3:] = R2
    comp = {"J3": ("bar1", c_loc), "J4": ("bar2", T2 @ c_loc @ T2.T)}
    loads = {"hub": (np.array([0.0, -load, 0.0]), np.zeros(3))}
    return solve_spatial(
        ["bar1", "bar2", "hub"],
        refs,
        joints,
        pts,
        {k: z for k in pts},
        loads,
        compliance=comp,
        misfit={"J3": (np.zeros(3), misfit * z)},
        length=a,
    )


def test_clamped_clamped_beam_with_a_central_load():
    a, P = 1.5, 1000.0
    sol = _two_cantilevers(a, load=P)
    assert sol.nullity == 6 and sol.rank == 18
    for j in ("J1", "J2"):
        np.testing.assert_allclose(sol.force[j], [0.0, P / 2, 0.0], atol=1e-9)
        # the clamping moment of a beam of length L = 2a: P L / 8
        np.testing.assert_allclose(abs(sol.moment[j][2]), P * 2 * a / 8, rtol=1e-12)
    np.testing.assert_allclose(abs(sol.moment["J3"][2]), P * 2 * a / 8, rtol=1e-12)
    assert np.max(sol.residual) < 1e-9


def test_a_kink_closed_by_bending():
    """A kink gamma at the middle of a clamped-clamped beam: by compatibility the moment is
    E J gamma / (2 a) all along, and no shear."""
    a, gamma = 1.5, 1e-3
    sol = _two_cantilevers(a, misfit=gamma)
    np.testing.assert_allclose(
        abs(sol.moment["J3"][2]), SEC.E * SEC.J_z * gamma / (2 * a), rtol=1e-10
    )
    np.testing.assert_allclose(sol.force["J3"], 0.0, atol=1e-8)
    # the strain energy is the work of that moment on half the kink
    np.testing.assert_allclose(
        sol.elastic_energy, 0.5 * abs(sol.moment["J3"][2]) * gamma, rtol=1e-10
    )


def test_determinate_and_indeterminate_models():
    z = np.array([0.0, 0.0, 1.0])
    x = np.array([1.0, 0.0, 0.0])
    # a bar welded to the frame: determinate, no compliance needed
    sol = solve_spatial(
        ["bar"], {"bar": 0 * x}, (SpatialJoint("J", "bar", "frame", "driven"),), {"J": 0 * x},
        {"J": z}, {"bar": (np.array([0.0, -10.0, 0.0]), np.array([0.0, 0.0, -10.0]))},
    )  # fmt: skip
    assert sol.nullity == 0
    np.testing.assert_allclose(sol.force["J"], [0.0, 10.0, 0.0])
    np.testing.assert_allclose(sol.torque["J"], 10.0)
    # held at both ends by revolutes: redundant, and without compliance that is an error
    joints = (
        SpatialJoint("J1", "bar", "frame", "revolute"),
        SpatialJoint("J2", "bar", "frame", "revolute"),
    )
    with pytest.raises(ValueError, match="statically indeterminate"):
        solve_spatial(
            ["bar"], {"bar": 0 * x}, joints, {"J1": 0 * x, "J2": x}, {"J1": z, "J2": z},
            {"bar": (np.zeros(3), np.zeros(3))},
        )  # fmt: skip
    with pytest.raises(ValueError, match="kind must be one of"):
        SpatialJoint("J", "a", "b", "prismatic")
    with pytest.raises(ValueError, match="to itself"):
        SpatialJoint("J", "a", "a", "revolute")
