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
