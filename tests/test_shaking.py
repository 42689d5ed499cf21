"""Shaking force and moment of any force model: from the kinematics (-sum m a_S, ...) and from the
kinetostatic ground reactions, loads and drive less the weight -- equal to round-off for revolute,
sliding and cam pairs, a crank or a driving slider, about any point."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mechsynth as ms
from mechsynth.dynamics import LinkInertia, kinetostatics, slider_crank_model
from mechsynth.dynamics.loads import Gravity, PointForce, Torque, TorsionSpring
from mechsynth.dynamics.shaking import frame_load, shaking
from mechsynth.kinematics import Involute

PHI = ms.cycle(120)


def _masses(draw, bodies):
    return {
        b: (
            draw(st.floats(0.1, 5.0)),
            (draw(st.floats(-0.05, 0.05)), draw(st.floats(-0.02, 0.02))),
            draw(st.floats(0.0, 0.01)),
        )
        for b in bodies
    }


def five_link():  # a crank-rocker driving a cam follower (a Contact pair) on an involute
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
        .follower(
            "N",
            on="DB",
            profile=Involute(0.02, phase=ms.deg(-62), roll=(0.2, 4.0)),
            guide=("D", ms.deg(100)),
            offset=0.02,
            roller=0.004,
        )
    )


def six_link():  # crank, rocker, slider on a fixed guide (a Prismatic pair with the frame)
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
        .attach("K", on=("D", "B"), along=-0.05)
        .rrp("N", ("K", 0.10), guide=((0.12, 0.0), ms.deg(57)))
    )


def cylinder():  # a driving slider (DrivingForce) pushing a rocker and a slider
    return (
        ms.Linkage(ground={"D": (0.2, 0.1)})
        .slider("A", guide=((0.0, 0.0), 0.3), travel=(0.0, 0.1))
        .rrr("B", ("A", 0.2), ("D", 0.1))
        .attach("K", on=("D", "B"), along=-0.04)
        .rrp("N", ("K", 0.12), guide=("D", ms.deg(100)))
    )


def _agree(model, m, about):
    res = kinetostatics(model, m)
    a, b = shaking(model, m, about), frame_load(model, m, res, about)
    scale = max(np.max(np.abs(a.fx)), np.max(np.abs(a.fy)), np.max(np.abs(a.moment)), 1.0)
    for u, v in ((a.fx, b.fx), (a.fy, b.fy), (a.moment, b.moment)):
        np.testing.assert_allclose(u, v, atol=1e-10 * scale)
    return a


@pytest.mark.parametrize("make", [five_link, six_link, cylinder], ids=["cam", "slider", "cyl"])
@settings(max_examples=8, deadline=None)
@given(data=st.data())
def test_two_computations_agree(make, data):
    lk = make()
    inertias = _masses(data.draw, lk.links)
    last = lk.links[-1]
    f = data.draw(st.floats(-200.0, 200.0))
    loads = [
        Gravity(tilt=data.draw(st.floats(-3.0, 3.0))),
        PointForce(last, lk.default_output, lambda m: (f + 5.0 * m.phi, -f)),
        Torque(lk.links[1], lambda m: 2.0 * np.cos(m.phi)),
        TorsionSpring(lk.links[1], lk.links[1], 1.0, 3.0, 0.5),
    ]
    model = lk.force_model(inertias, loads)
    grid = PHI if make is not cylinder else lk.input_grid(60)
    speed = data.draw(st.sampled_from([0.5, -2.0])) if make is cylinder else ms.rpm(600)
    m = lk.motion(grid, speed=speed, epsilon=data.draw(st.floats(-50, 50)))
    about = (data.draw(st.floats(-0.3, 0.3)), data.draw(st.floats(-0.3, 0.3)))
    a = _agree(model, m, about)
    assert np.all(np.isfinite(a.magnitude))


def test_slider_crank_shaking_by_hand_and_about_another_point():
    # slider-crank with a massive slider only: F = -m a_B along x, M_P = (y_B - y_P) m a_B
    sc = ms.SliderCrank(crank=0.07, rod=0.24, offset=0.01)
    model = slider_crank_model(slider_body=LinkInertia(None, "B", 3.0), loads=[Gravity()])
    m = sc.motion(PHI, speed=ms.rpm(600))
    p = (0.1, -0.2)
    a = _agree(model, m, p)
    by, ax = m.points["B"].y, m.points["B"].ax
    np.testing.assert_allclose(a.fx, -3.0 * ax, rtol=1e-12)
    np.testing.assert_allclose(a.fy, 0.0, atol=1e-9)
    np.testing.assert_allclose(a.moment, (by - p[1]) * 3.0 * ax, rtol=1e-12)
    # the moment about another point differs by the force's moment arm
    o = shaking(model, m)
    np.testing.assert_allclose(o.moment - a.moment, p[0] * a.fy - p[1] * a.fx, atol=1e-9)
    peak, at = a.peak()
    assert peak == pytest.approx(np.max(np.abs(3.0 * ax))) and at in PHI
