"""Higher pairs: cam followers against closed forms, the involute profile of paper 001's five-link,
user curves with exact Taylor derivatives, and clear failures."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mechsynth as ms
from mechsynth.errors import MechanismError
from mechsynth.kinematics import Circle, Involute, ParametricCurve, ops

PHI = ms.cycle(360)


def eccentric_cam(e, R, delta, roller=None, face=None, phase=0.0, branch=1, side=1):
    """A circular cam of radius R whose centre is e from the crank pivot O, turning with the
    crank; a translating follower on the vertical guide x = delta."""
    lk = ms.Linkage(ground={"O": (0, 0)}).crank("A", about="O", length=e, phase=phase)
    return lk.follower(
        "N",
        on="OA",
        profile=Circle(R, center=(e, 0.0)),
        guide=((delta, 0.0), np.pi / 2),
        roller=roller,
        face=face,
        branch=branch,
        side=side,
    )


@pytest.mark.parametrize("branch", [1, -1])
@pytest.mark.parametrize("side", [1, -1])
def test_every_follower_variant_equals_its_closed_form(branch, side):
    """Branch -1 rests on the hindmost contact along the guide, side -1 runs the roller inside
    the circle: y = e sin t + branch sqrt((R + side rho)^2 - (delta - e cos t)^2); a flat face
    on branch -1 touches the bottom: y = e sin t - R."""
    e, R, rho, phase = 0.01, 0.05, 0.008, 0.3
    delta = 0.3 * (R - rho - e)
    t = PHI + phase
    u = delta - e * np.cos(t)
    y = e * np.sin(t) + branch * np.sqrt((R + side * rho) ** 2 - u * u)
    m = eccentric_cam(e, R, delta, roller=rho, phase=phase, branch=branch, side=side).motion(PHI)
    np.testing.assert_allclose(m.sliders["N"].position, y, rtol=0, atol=1e-12)
    c = m.points["N_contact"]
    np.testing.assert_allclose(np.hypot(c.x - e * np.cos(t), c.y - e * np.sin(t)), R, atol=1e-13)
    flat = eccentric_cam(e, R, delta, face=0.0, phase=phase, branch=branch).motion(PHI)
    np.testing.assert_allclose(flat.sliders["N"].position, e * np.sin(t) + branch * R, atol=1e-13)


@settings(max_examples=40, deadline=None)
@given(
    st.floats(0.002, 0.03),
    st.floats(0.035, 0.08),
    st.floats(-0.9, 0.9),
    st.floats(0.0, 0.02),
    st.floats(-np.pi, np.pi),
)
def test_roller_follower_on_an_eccentric_circle_equals_the_closed_form(e, R, frac, rho, phase):
    """y = e sin(t) + sqrt((R + rho)^2 - (delta - e cos t)^2), t = phi + phase, and its exact
    first and second derivatives, to 1e-12."""
    delta = frac * (R + rho - e)  # the guide meets the roller's path at every angle
    m = eccentric_cam(e, R, delta, roller=rho, phase=phase).motion(PHI)
    t = PHI + phase
    u = delta - e * np.cos(t)
    w = np.sqrt((R + rho) ** 2 - u * u)
    y = e * np.sin(t) + w
    u1 = e * np.sin(t)
    u2 = e * np.cos(t)
    w1 = -u * u1 / w
    w2 = -(u1 * u1 + u * u2) / w - (u * u1) ** 2 / w**3
    y1, y2 = e * np.cos(t) + w1, -e * np.sin(t) + w2
    s = m.sliders["N"]
    np.testing.assert_allclose(s.position, y, rtol=0, atol=1e-12)
    np.testing.assert_allclose(s.velocity, y1, rtol=0, atol=1e-12)
    np.testing.assert_allclose(s.acceleration, y2, rtol=0, atol=1e-11)
    np.testing.assert_allclose(m.points["N"].x, delta, atol=1e-15)
    # the common normal passes through the cam centre and the roller centre
    n = m.extra["N normal"]
    cx, cy = e * np.cos(t), e * np.sin(t)
    np.testing.assert_allclose(np.cos(n), (delta - cx) / (R + rho), atol=1e-12)
    np.testing.assert_allclose(np.sin(n), (y - cy) / (R + rho), atol=1e-12)
    # pressure angle: between that normal and the guide (+y)
    np.testing.assert_allclose(m.pressure_angle, np.arcsin(np.abs(u) / (R + rho)), atol=1e-12)
    c = m.points["N_contact"]
    np.testing.assert_allclose(np.hypot(c.x - cx, c.y - cy), R, atol=1e-13)


@settings(max_examples=30, deadline=None)
@given(st.floats(0.002, 0.03), st.floats(0.035, 0.08), st.floats(-0.05, 0.05))
def test_flat_faced_follower_on_an_eccentric_circle_is_harmonic(e, R, delta):
    """A flat face perpendicular to the guide: y = e sin(phi) + R exactly (simple harmonic),
    zero pressure angle, wherever the guide passes."""
    m = eccentric_cam(e, R, delta, face=0.0).motion(PHI, speed=ms.rpm(300))
    w = ms.rpm(300)
    s = m.sliders["N"]
    np.testing.assert_allclose(s.position, e * np.sin(PHI) + R, rtol=0, atol=1e-13)
    np.testing.assert_allclose(s.velocity, e * w * np.cos(PHI), rtol=0, atol=1e-12)
    np.testing.assert_allclose(s.acceleration, -e * w * w * np.sin(PHI), rtol=0, atol=1e-10)
    np.testing.assert_allclose(m.pressure_angle, 0.0, atol=1e-15)
    c = m.points["N_contact"]
    np.testing.assert_allclose(c.x, e * np.cos(PHI), atol=1e-13)  # the face touches at the top


def five_link(rb=0.02, pivot=(0.12, 0.05), rho_deg=100.0):
    """Paper 001's five-link: crank O-A, rod AB, rocker DB whose extension is an involute of the
    base circle of radius rb about the rocker pivot D, pushing a roller follower on a guide
    tangent to that base circle (the guide through D offset by rb). The rocker swings over
    115-160 deg; the involute's phase puts the contact near roll angle 2 rad at mid swing."""
    lk = (
        ms.Linkage(ground={"O": (0, 0), "D": pivot})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
    )
    return lk.follower(
        "N",
        on="DB",
        profile=Involute(rb, phase=ms.deg(-62), roll=(0.2, 4.0)),
        guide=("D", ms.deg(rho_deg)),
        offset=rb,
        roller=0.004,
    )


def test_involute_profile_pushes_along_its_guide_without_side_force():
    """The involute's normal is tangent to its base circle: on a guide tangent to it the pressure
    angle is zero and the follower moves exactly rb times the rocker's rotation."""
    lk = five_link()
    m = lk.motion(PHI, speed=ms.rpm(600))
    np.testing.assert_allclose(m.pressure_angle, 0.0, atol=1e-12)
    rocker = m.links["DB"]
    np.testing.assert_allclose(m.sliders["N"].velocity, -0.02 * rocker.omega, rtol=0, atol=1e-12)
    np.testing.assert_allclose(
        m.sliders["N"].acceleration, -0.02 * rocker.epsilon, rtol=0, atol=1e-9
    )
    s = m.sliders["N"].position
    swing = np.ptp(np.unwrap(rocker.angle))
    np.testing.assert_allclose(np.ptp(s), 0.02 * swing, rtol=1e-12)


def test_involute_closed_form_matches_taylor_derivatives():
    p = {"base_radius": 0.02, "center_u": 0.01, "center_v": -0.02, "phase": 0.3}
    inv = Involute(0.02, center=(0.01, -0.02), phase=0.3)

    def fn(t, rb, u, v, ph):
        a = t + ph
        return u + rb * (ops.cos(a) + t * ops.sin(a)), v + rb * (ops.sin(a) - t * ops.cos(a))

    user = ParametricCurve(fn, params={"rb": 0.02, "u": 0.01, "v": -0.02, "ph": 0.3})
    sigma = np.linspace(0.1, 3.0, 50)
    exact = inv.jet(sigma, p)
    taylor = user.jet(sigma, {"rb": 0.02, "u": 0.01, "v": -0.02, "ph": 0.3})
    for a, b in zip(exact, taylor):
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-15)
    circ = Circle(0.05, (0.01, 0.02)).jet(
        sigma, {"radius": 0.05, "center_u": 0.01, "center_v": 0.02}
    )
    user_c = ParametricCurve(
        lambda t, r: (0.01 + r * np.cos(t), 0.02 + r * np.sin(t)), params={"r": 0.05}
    ).jet(sigma, {"r": 0.05})
    for a, b in zip(circ, user_c):
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-15)


def test_user_curve_cam_equals_the_built_in_circle():
    """An eccentric circle written as a user's curve gives the same follower motion."""
    built_in = eccentric_cam(0.01, 0.05, 0.02, roller=0.008).motion(PHI)
    user = (
        ms.Linkage(ground={"O": (0, 0)})
        .crank("A", about="O", length=0.01)
        .follower(
            "N",
            on="OA",
            profile=ParametricCurve(
                lambda t, e, r: (e + r * ops.cos(t), r * ops.sin(t)),
                params={"e": 0.01, "r": 0.05},
                closed=True,
            ),
            guide=((0.02, 0.0), np.pi / 2),
            roller=0.008,
        )
    )
    m = user.motion(PHI)
    for f in ("position", "velocity", "acceleration"):
        np.testing.assert_allclose(
            getattr(m.sliders["N"], f), getattr(built_in.sliders["N"], f), atol=1e-12
        )
    assert {"N_profile_e", "N_profile_r", "N_roller"} <= set(user.parameters)


def test_follower_failures_are_clear():
    cam = eccentric_cam(0.01, 0.05, 0.0, roller=0.005)
    with pytest.raises(MechanismError, match=r"higher pair N .*misses the profile .*crank angle"):
        cam(N_guide_x=0.2).motion(PHI)
    lk = five_link()
    with pytest.raises(MechanismError, match="higher pair N"):
        lk(N_profile_phase=ms.deg(100)).motion(PHI)
    with pytest.raises(ValueError, match="roll angles must start above 0"):
        Involute(0.02, roll=(0.0, 2.0))
    with pytest.raises(ValueError, match="N_roller must not be negative"):
        cam(N_roller=-0.001)
    with pytest.raises(ValueError, match="must return \\(x, y\\)"):
        ParametricCurve(lambda t: t).jet(0.5, {})
    with pytest.raises(TypeError, match="not supported in a curve function"):
        ParametricCurve(lambda t: (np.maximum(t, 0.0), t)).jet(np.array([0.5]), {})
    margins = five_link().assembly_margins(PHI)
    assert set(margins) == {"B", "N:start", "N:end", "N:contact"}
    assert np.min(margins["N:start"]) > 0 and np.min(margins["N:end"]) > 0


def test_cam_contact_derivatives_by_casadi_equal_differences():
    """The same contact search (sampling, bracket, Newton) in CasADi: the derivatives of the
    follower's acceleration, pressure angle and profile margin with respect to the profile's,
    the guide's and the rocker's dimensions equal central differences of the numpy model."""
    import casadi as ca

    lk = five_link()(N_guide_offset=0.021)  # off the base circle's tangent: pressure angle > 0
    names = ["N_profile_base_radius", "N_profile_phase", "N_guide_angle", "N_roller", "DB"]
    x = ca.SX.sym("x", len(names))
    phi = np.linspace(0.1, 6.0, 7)
    m = lk(**{n: x[i] for i, n in enumerate(names)}).motion(ca.DM(phi), speed=100.0)
    out = ca.vertcat(
        m.sliders["N"].acceleration, m.pressure_angles["N"], m.extra["assembly margins"]["N:start"]
    )
    x0 = np.array([lk.parameters[n] for n in names])
    J = np.asarray(ca.Function("j", [x], [ca.jacobian(out, x)])(x0))

    def f(v):
        mm = lk(**dict(zip(names, v))).motion(phi, speed=100.0)
        return np.concatenate(
            [
                mm.sliders["N"].acceleration,
                mm.pressure_angles["N"],
                mm.extra["assembly margins"]["N:start"],
            ]
        )

    assert np.min(f(x0)[7:14]) > 1e-3
    for i in range(len(names)):
        e = np.zeros(len(names))
        e[i] = 1e-7
        fd = (f(x0 + e) - f(x0 - e)) / 2e-7
        np.testing.assert_allclose(J[:, i], fd, rtol=1e-5, atol=1e-6 * np.max(np.abs(fd)) + 1e-9)


def test_certified_cam_design():
    """An eccentric circular cam with a roller: the smallest peak pressure angle for a 30 mm
    stroke, optimized over the eccentricity (the circle's centre on the crank) and the cam
    radius, certified: the stroke of a cam turning about a point of its follower's line is twice
    its eccentricity, and the pressure angle's peak is asin(e / (R + roller)) (closed form)."""
    from mechsynth import objectives as ob

    cam = eccentric_cam(0.01, 0.05, 0.0, roller=0.01)
    prob = ms.Problem(
        cam, variables={"N_profile_center_u": (0.005, 0.03), "N_profile_radius": (0.03, 0.08)}
    )
    prob.minimize(ob.max_pressure_angle("N")).subject_to(ob.stroke("N") == 0.03)
    res = prob.solve(starts=1)
    assert res.status == "optimal"
    e = res.variables["N_profile_center_u"]
    assert e == pytest.approx(0.015, rel=1e-6)  # stroke 2 e with the guide through the pivot
    R = res.variables["N_profile_radius"] + 0.01
    assert res.value == pytest.approx(np.arcsin(e / R), rel=1e-6)
