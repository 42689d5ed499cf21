"""Kinetostatics: power balance on random designs, closed-form checks, bad models."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mechsynth as ms
from mechsynth.dynamics.inertia import LinkInertia
from mechsynth.dynamics.kinetostatics import (
    ForceModel,
    Revolute,
    applied_power,
    four_bar_model,
    kinetic_energy_rate,
    kinetostatics,
    slider_crank_model,
)
from mechsynth.dynamics.loads import Gravity, PointForce, Torque, TorsionSpring

PHI = ms.cycle(72)


def _check_power(model, motion):
    res = kinetostatics(model, motion)
    lhs = res.torque * motion.omega
    rhs = kinetic_energy_rate(model, motion) - applied_power(model, motion)
    scale = np.max(np.abs(rhs)) + np.max(np.abs(lhs)) + 1e-300
    assert np.max(np.abs(lhs - rhs)) <= 1e-9 * scale
    return res


pos = st.floats(0.1, 5.0)


@settings(max_examples=30, deadline=None)
@given(
    st.floats(0.05, 0.2),
    st.floats(2.2, 5.0),
    st.floats(-0.5, 0.5),
    pos,
    pos,
    pos,
    st.floats(-0.05, 0.05),
    st.floats(0.0, 0.5),
    st.floats(-300.0, 300.0),
    st.floats(-3.0, 3.0),
)
def test_power_balance_slider_crank(a, ratio, off, m1, m2, m3, u1, j, f, tilt):
    sc = ms.SliderCrank(crank=a, rod=ratio * a, offset=off * a)
    model = slider_crank_model(
        LinkInertia("crank", "O", m1, (u1, 0.01), j),
        LinkInertia("rod", "A", m2, (0.4 * ratio * a, 0.02), j),
        LinkInertia(None, "B", m3, (0.03, -0.01)),
        loads=[
            Gravity(tilt=tilt),
            PointForce("slider", "B", lambda m: (f + 10 * m.points["B"].vx, 0.0 * f)),
            Torque("rod", lambda m: 2.0 * np.cos(m.phi)),
        ],
    )
    _check_power(model, sc.motion(PHI, speed=-31.4))


@settings(max_examples=30, deadline=None)
@given(pos, pos, pos, st.floats(0.0, 0.3), st.floats(-50.0, 50.0), st.floats(0.0, 5.0))
def test_power_balance_four_bar(m1, m2, m3, j, f, k):
    fb = ms.FourBar(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2)
    model = four_bar_model(
        LinkInertia("crank", "O1", m1, (0.3, 0.0), j),
        LinkInertia("coupler", "A", m2, (2.0, 0.5), j),
        LinkInertia("rocker", "O2", m3, (1.5, -0.2), j),
        loads=[
            Gravity(),
            PointForce("coupler", "A", lambda m: (f, -f)),
            TorsionSpring("rocker", "rocker", 1.0, k, 2.0),
        ],
    )
    _check_power(model, fb.motion(PHI, speed=10.0))


def test_static_slider_crank_closed_form():
    # massless slider-crank with a force P on the slider: T = -P * dx_B/dphi (virtual work)
    sc = ms.SliderCrank(crank=0.1, rod=0.3)
    P = 1000.0
    model = slider_crank_model(loads=[PointForce("slider", "B", lambda m: (-P, 0.0))])
    m = sc.motion(PHI, speed=1.0)
    res = kinetostatics(model, m)
    np.testing.assert_allclose(res.torque, P * m.points["B"].vx, atol=1e-9)
    # rod is a two-force member: R21 along the rod
    fx, fy = res.reactions["R21"]
    ang = m.links["rod"].angle
    np.testing.assert_allclose(fx * np.sin(ang) - fy * np.cos(ang), 0.0, atol=1e-8)


def test_unknown_count_checked():
    with pytest.raises(ValueError, match="unknowns"):
        ForceModel({"crank": LinkInertia("crank", "O", 1.0)}, (), (), "crank")
    with pytest.raises(ValueError, match="unknown body"):
        ForceModel(
            {"crank": LinkInertia("crank", "O", 1.0)},
            (Revolute("R10", "crank", "nothing", "O"),),
            (),
            "crank",
        )


def test_casadi_geometry_slider_crank():
    ca = pytest.importorskip("casadi")
    a = ca.SX.sym("a")
    phi = ms.cycle(12)

    def torque(crank):
        sc = ms.SliderCrank(crank=crank, rod=0.3)
        model = slider_crank_model(
            LinkInertia("crank", "O", 2.0, (0.01, 0.0), 0.01),
            LinkInertia("rod", "A", 1.5, (0.1, 0.0), 0.02),
            LinkInertia(None, "B", 3.0),
            loads=[Gravity(), PointForce("slider", "B", lambda m: (-200.0, 0.0))],
        )
        return kinetostatics(model, sc.motion(phi, speed=20.0)).torque

    f = ca.Function("f", [a], [torque(a), ca.jacobian(torque(a), a)])
    val, jac = (np.asarray(v).ravel() for v in f(0.08))
    np.testing.assert_allclose(val, torque(0.08), rtol=1e-10, atol=1e-9)
    h = 1e-6
    np.testing.assert_allclose(
        jac, (torque(0.08 + h) - torque(0.08 - h)) / (2 * h), rtol=1e-5, atol=1e-4
    )


def _block_case(pattern_dense, k, rng):
    """A random k x k block with the given constant entries (a dict), the others random."""
    A = rng.normal(size=(k, k)) + 3.0 * np.eye(k)
    pattern = []
    for i in range(k):
        for j in range(k):
            if (i, j) in pattern_dense:
                A[i, j] = pattern_dense[i, j]
                if A[i, j] != 0.0:
                    pattern.append((i, j, float(A[i, j])))
            else:
                pattern.append((i, j, None))
    return A, tuple(pattern)


@pytest.mark.parametrize(
    "constants",
    [
        {},  # no constant pivot: casadi.solve (QR beyond 3 x 3)
        # a revolute dyad's force rows: unit entries, and the zeros between them
        {
            (0, 0): 1.0,
            (0, 1): 0.0,
            (0, 2): -1.0,
            (0, 3): 0.0,
            (1, 0): 0.0,
            (1, 1): 1.0,
            (1, 2): 0.0,
            (1, 3): -1.0,
        },
        # a near-zero constant is no pivot
        {(0, 0): 1e-17},
    ],
)
def test_block_elimination_equals_a_dense_solve(constants):
    """Each block of the symbolic kinetostatics is an elimination written once (constant pivots
    first, ``casadi.solve`` for the rest); over random entries it equals numpy's solve."""
    from mechsynth.dynamics.kinetostatics import _block_function

    rng = np.random.default_rng(7)
    for k in (2, 5, 6):
        A, pattern = _block_case({kv: v for kv, v in constants.items() if max(kv) < k}, k, rng)
        b = rng.normal(size=k)
        fn = _block_function(pattern, k)
        inputs = [A[i, j] for i, j, v in pattern if v is None] + list(b)
        got = np.asarray(fn(inputs), dtype=float).ravel()
        np.testing.assert_allclose(got, np.linalg.solve(A, b), rtol=1e-10, atol=1e-12)


def test_symbolic_forces_with_a_guide_equal_the_numeric_ones_and_their_differences():
    """A slider-crank with offset, gravity and a load: the symbolic solve (dimensions as
    CasADi symbols) equals the numeric one to 1e-10 at every angle, and its exact derivative
    in the crank equals central differences."""
    import casadi as ca

    phi = ms.cycle(36)
    model = slider_crank_model(
        LinkInertia("crank", "O", 2.0, (0.01, 0.0), 0.01),
        LinkInertia("rod", "A", 1.5, (0.1, 0.02), 0.02),
        LinkInertia(None, "B", 3.0),
        loads=[Gravity(), PointForce("slider", "B", lambda m: (-200.0, 0.0))],
    )

    def forces(crank, offset):
        sc = ms.SliderCrank(crank=crank, rod=0.3, offset=offset)
        res = kinetostatics(model, sc.motion(phi, speed=20.0, epsilon=5.0))
        out = [res.torque] + [
            res.reactions[j][k] for j in ("R10", "R21", "R32", "R30") for k in (0, 1)
        ]
        return out

    x = ca.SX.sym("x", 2)
    sym = forces(x[0], x[1])
    fn = ca.Function("f", [x], [ca.horzcat(*sym)])
    jac = ca.Function("j", [x], [ca.jacobian(ca.vec(ca.horzcat(*sym)), x)])
    x0 = (0.08, 0.03)
    want = np.column_stack([np.broadcast_to(v, phi.shape) for v in forces(*x0)])
    got = np.asarray(fn(x0))
    assert np.max(np.abs(got - want)) <= 1e-10 * np.max(np.abs(want))
    h = 1e-6
    fd = (
        np.column_stack([np.broadcast_to(v, phi.shape) for v in forces(x0[0] + h, x0[1])])
        - np.column_stack([np.broadcast_to(v, phi.shape) for v in forces(x0[0] - h, x0[1])])
    ) / (2 * h)
    exact = np.asarray(jac(x0))[:, 0].reshape(fd.shape, order="F")
    np.testing.assert_allclose(exact, fd, rtol=1e-5, atol=1e-5 * np.max(np.abs(fd)))
