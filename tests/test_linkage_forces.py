"""Kinetostatics of general linkages: the power balance to 1e-9 on random designs (six-link with
slider, Stephenson III, cam followers on a rocker's involute and on an eccentric circle, an RRP
on a moving guide and an RPR with a moving pivot), the contact joint's force along its normal,
CasADi forces equal numpy forces."""

import casadi as ca
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from test_kinetostatics import _check_power  # the power balance to 1e-9

import mechsynth as ms
from mechsynth.dynamics import kinetostatics
from mechsynth.dynamics.loads import Gravity, PointForce, Torque, TorsionSpring
from mechsynth.kinematics import Circle, Involute

PHI = ms.cycle(180)


def _masses(draw, bodies):
    return {
        b: (
            draw(st.floats(0.1, 5.0)),
            (draw(st.floats(-0.05, 0.05)), draw(st.floats(-0.02, 0.02))),
            draw(st.floats(0.0, 0.01)),
        )
        for b in bodies
    }


def six_link(rho_deg=57.0):
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
        .attach("K", on=("D", "B"), along=-0.05)
        .rrp("N", ("K", 0.10), guide=((0.12, 0.0), ms.deg(rho_deg)))
    )


def stephenson():
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.0), "F": (0.02, 0.15)})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.09))
        .attach("C", on=("A", "B"), along=0.06, left=0.04)
        .rrr("E", ("C", 0.09), ("F", 0.08))
    )


def five_link():
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


def eccentric_cam(face=None):
    return (
        ms.Linkage(ground={"O": (0, 0)})
        .crank("A", about="O", length=0.01)
        .follower(
            "N",
            on="OA",
            profile=Circle(0.05, (0.01, 0.0)),
            guide=((0.015, 0.0), np.pi / 2),
            roller=None if face is not None else 0.01,
            face=face,
        )
    )


def moving_guides():
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
        .rrp("C", ("A", 0.2), guide=(("D", "B"), 0.3), offset=0.01)
        .rpr("lever", about="B", through="A", offset=0.004)
    )


LINKAGES = {
    "six-link": six_link,
    "stephenson": stephenson,
    "five-link": five_link,
    "cam roller": eccentric_cam,
    "cam flat": lambda: eccentric_cam(face=0.0),
    "moving guides": moving_guides,
}


@pytest.mark.parametrize("name", list(LINKAGES))
@settings(max_examples=12, deadline=None)
@given(data=st.data())
def test_power_balance(name, data):
    lk = LINKAGES[name]()
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
    speed = data.draw(st.sampled_from([ms.rpm(600), -ms.rpm(1500)]))
    res = _check_power(model, lk.motion(PHI, speed=speed, epsilon=data.draw(st.floats(-50, 50))))
    assert np.all(np.isfinite(res.torque))


def test_contact_force_acts_along_the_common_normal():
    """Gravity-free, a massless follower pressed by a force P along its guide: the contact
    carries P / cos(pressure angle) along the normal, the guide the rest."""
    lk = eccentric_cam()
    P = 50.0
    model = lk.force_model({}, [PointForce("N", "N", lambda m: (0.0 * m.phi, -P + 0.0 * m.phi))])
    m = lk.motion(PHI, speed=ms.rpm(100))
    res = kinetostatics(model, m)
    fn, _ = res.normals["N_contact"]
    np.testing.assert_allclose(fn, P / np.cos(m.pressure_angle), rtol=1e-12)
    fx, fy = res.reactions["N_contact"]
    np.testing.assert_allclose(np.arctan2(fy, fx), m.extra["N normal"], atol=1e-12)
    assert np.all(fn > 0)  # pressed together


def test_symbolic_forces_equal_numpy():
    """The force model with CasADi dimensions: the crank torque equals the numpy one."""
    lk = six_link()
    inertias = {"KN": (1.0, (0.05, 0.0), 0.001), "N": (2.0, (0.0, 0.0), 0.0)}
    loads = [Gravity()]
    phi = np.linspace(0.0, 6.0, 9)
    x = ca.SX.sym("x")
    sym = lk(KN=x)
    res = kinetostatics(sym.force_model(inertias, loads), sym.motion(ca.DM(phi), speed=100.0))
    torque = ca.Function("t", [x], [res.torque])(0.1)
    num = kinetostatics(lk.force_model(inertias, loads), lk.motion(phi, speed=100.0)).torque
    np.testing.assert_allclose(np.asarray(torque).ravel(), num, rtol=1e-12, atol=1e-12)


def test_force_model_input_errors():
    lk = six_link()
    with pytest.raises(ValueError, match=r"inertias name unknown links \['crank'\]"):
        lk.force_model({"crank": (1.0, (0, 0), 0.0)})
    with pytest.raises(ValueError, match="inertia of AB"):
        lk.force_model({"AB": 3.0})
    with pytest.raises(ValueError, match="mass of AB must not be negative"):
        lk.force_model({"AB": {"mass": -1.0}})
