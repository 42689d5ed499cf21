"""Property tests of the kinematics core over random designs (hypothesis).

Valid designs: loop closure to 1e-10, velocity analogs equal central differences of positions,
acceleration analogs equal central differences of velocity analogs, the two assembly branches are
mirror images, nothing is NaN. Invalid designs raise MechanismError / ValueError naming the
condition with its numbers. CasADi jacobians with respect to the design parameters equal finite
differences of the numpy model.
"""

import casadi as ca
import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from mechsynth.errors import MechanismError
from mechsynth.kinematics import (
    FourBar,
    PointJet,
    SliderCrank,
    crank,
    dyad_rpr,
    dyad_rrp,
    dyad_rrr,
)

PHI = np.linspace(0.0, 2.0 * np.pi, 49)[:-1]
H = 3e-5  # difference step (rad): Richardson truncation ~ H^4, round-off ~ 1e-13 / H
SETTINGS = settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])

length = st.floats(0.05, 3.0)
link = st.floats(0.2, 3.0)  # four-bar links: length ratios up to 15
signed = st.floats(-2.0, 2.0)
angle = st.floats(-np.pi, np.pi)


def _wrap(x):
    return np.angle(np.exp(1j * np.asarray(x)))


def _fd(f, phi):
    """Central difference with one Richardson step: error O(H^4)."""
    d1 = (f(phi + H) - f(phi - H)) / (2.0 * H)
    d2 = (f(phi + 2 * H) - f(phi - 2 * H)) / (4.0 * H)
    return (4.0 * d1 - d2) / 3.0


def _fd_angle(f, phi):
    """``_fd`` for an angle (differences taken modulo 2 pi)."""
    d1 = _wrap(f(phi + H) - f(phi - H)) / (2.0 * H)
    d2 = _wrap(f(phi + 2 * H) - f(phi - 2 * H)) / (4.0 * H)
    return (4.0 * d1 - d2) / 3.0


def _close(fd, exact, scale):
    """Differences agree to 1e-6 of the quantity's size over the cycle (at least 1): ample for
    round-off and truncation, far below any error in a formula."""
    np.testing.assert_allclose(fd, exact, atol=1e-6 * max(scale, 1.0), rtol=0)


def _finite(*arrays):
    for a in arrays:
        assert np.all(np.isfinite(a))


# --------------------------------------------------------------------------- slider-crank
@st.composite
def slider_cranks(draw):
    a = draw(length)
    e = draw(signed) * a
    # rod at least 10 % longer than the full-turn limit crank + |offset|
    b = (a + abs(e)) * draw(st.floats(1.1, 4.0))
    return SliderCrank(a, b, e)


@SETTINGS
@given(slider_cranks())
def test_slider_crank_closure_and_analogs(sc):
    m = sc.motion(PHI)
    A, B = m.points["A"], m.points["B"]
    s = m.slider
    _finite(s.position, s.velocity, s.acceleration, m.links["rod"].angle, m.pressure_angle)
    # loop closure: |AB| = rod, B on the guide y = offset, slider position = x_B
    assert np.max(np.abs(np.hypot(B.x - A.x, B.y - A.y) - sc.rod)) < 1e-10
    assert np.max(np.abs(B.y - sc.offset)) < 1e-12
    np.testing.assert_array_equal(s.position, B.x)

    def pos(phi):
        return sc.motion(phi).slider.position

    def vel(phi):
        return sc.motion(phi).slider.velocity

    def rod_angle(phi):
        return sc.motion(phi).links["rod"].angle

    def rod_omega(phi):
        return sc.motion(phi).links["rod"].omega

    _close(_fd(pos, PHI), s.velocity, np.max(np.abs(s.velocity)))
    _close(_fd(vel, PHI), s.acceleration, np.max(np.abs(s.acceleration)))
    rod = m.links["rod"]
    fd_w = _fd_angle(rod_angle, PHI)
    _close(fd_w, rod.omega, np.max(np.abs(rod.omega)))
    _close(_fd(rod_omega, PHI), rod.epsilon, np.max(np.abs(rod.epsilon)))
    # dead centres: slider velocity analog vanishes there, positions are the extremes
    phis = np.array(sc.dead_centres)
    assert np.max(np.abs(sc.motion(phis).slider.velocity)) < 1e-10 * sc.rod
    assert np.max(s.position) <= sc.dead_centre_positions[0] + 1e-12
    assert np.min(s.position) >= sc.dead_centre_positions[1] - 1e-12


# --------------------------------------------------------------------------- four-bar
@st.composite
def four_bars(draw):
    """Any assemblable four-bar (all Grashof kinds), as (design, crank angles where it closes)."""
    a, b, c, d = (draw(link) for _ in range(4))
    branch = draw(st.sampled_from(["open", "crossed"]))
    longest = max(a, b, c, d)
    assume(a + b + c + d - 2 * longest > 0.05 * longest)
    fb = FourBar(a, b, c, d, branch=branch, full_turn=False)
    # keep the angles where the transmission angle mu (between coupler and rocker) stays away
    # from 0 and pi: near a toggle the analogs and their derivatives blow up
    rho2 = (d - a * np.cos(PHI)) ** 2 + (a * np.sin(PHI)) ** 2
    cos_mu = (b * b + c * c - rho2) / (2 * b * c)
    ok = np.abs(cos_mu) < np.cos(np.deg2rad(15.0))
    assume(ok.sum() >= 3)
    return fb, PHI[ok]


@SETTINGS
@given(four_bars())
def test_four_bar_closure_analogs_and_branches(case):
    fb, phi = case
    m = fb.motion(phi)
    A, B, O2 = m.points["A"], m.points["B"], m.points["O2"]
    cpl, rck = m.links["coupler"], m.links["rocker"]
    _finite(B.x, B.y, B.vx, B.ax, cpl.omega, cpl.epsilon, rck.omega, rck.epsilon)
    # loop closure O1A + AB = O1O2 + O2B, with the link angles
    res_x = fb.crank * np.cos(phi) + fb.coupler * np.cos(cpl.angle)
    res_x -= fb.ground + fb.rocker * np.cos(rck.angle)
    res_y = fb.crank * np.sin(phi) + fb.coupler * np.sin(cpl.angle) - fb.rocker * np.sin(rck.angle)
    assert np.max(np.hypot(res_x, res_y)) < 1e-10
    assert np.max(np.abs(np.hypot(B.x - A.x, B.y - A.y) - fb.coupler)) < 1e-10
    assert np.max(np.abs(np.hypot(B.x - O2.x, B.y - O2.y) - fb.rocker)) < 1e-10

    def angles(p):
        mm = fb.motion(p)
        return np.stack([mm.links["coupler"].angle, mm.links["rocker"].angle])

    def omegas(p):
        mm = fb.motion(p)
        return np.stack([mm.links["coupler"].omega, mm.links["rocker"].omega, mm.points["B"].vx])

    w = np.stack([cpl.omega, rck.omega])
    e = np.stack([cpl.epsilon, rck.epsilon, B.ax])
    fd_w = _fd_angle(angles, phi)
    _close(fd_w, w, np.max(np.abs(w)))
    _close(_fd(omegas, phi), e, np.max(np.abs(e)))

    # branches: the other assembly is B mirrored in the line A -> O2, and "open" is to its left
    other = fb.replace(branch="crossed" if fb.branch == "open" else "open").motion(phi)
    B2 = other.points["B"]
    ux, uy = O2.x - A.x, O2.y - A.y
    side = ux * (B.y - A.y) - uy * (B.x - A.x)
    assert np.all(np.sign(side) == (1 if fb.branch == "open" else -1))
    # midpoint on the line A-O2 and chord perpendicular to it
    mx, my = (B.x + B2.x) / 2 - A.x, (B.y + B2.y) / 2 - A.y
    assert np.max(np.abs(ux * my - uy * mx)) < 1e-9
    assert np.max(np.abs(ux * (B.x - B2.x) + uy * (B.y - B2.y))) < 1e-9


@st.composite
def full_turn_four_bars(draw):
    """Crank-rockers and double-cranks (the crank turns fully), built to satisfy
    ``short + long_side < b + c`` and ``long_side - short > |b - c|`` with a margin."""
    b, c = draw(st.floats(0.3, 3.0)), draw(st.floats(0.3, 3.0))
    long_side = draw(st.floats(0.3, 3.0))
    upper = min(b + c - long_side, long_side - abs(b - c))
    assume(upper > 0.05)
    short = draw(st.floats(0.05, 0.9)) * upper
    a, d = (short, long_side) if draw(st.booleans()) else (long_side, short)
    return FourBar(a, b, c, d, branch=draw(st.sampled_from(["open", "crossed"])))


@SETTINGS
@given(full_turn_four_bars())
def test_full_turn_four_bar_is_smooth_over_the_whole_turn(fb):
    m = fb.motion(PHI)
    rck = m.links["rocker"]
    _finite(rck.angle, rck.omega, rck.epsilon, m.transmission_angle, m.pressure_angle)
    # net rocker rotation over one crank turn: 0 for a crank-rocker, 2 pi for a double-crank
    fine = np.linspace(0.0, 2.0 * np.pi, 721)
    turned = np.unwrap(fb.motion(fine).links["rocker"].angle)
    expected = 2.0 * np.pi if fb.grashof.kind == "double-crank" else 0.0
    assert abs(turned[-1] - turned[0] - expected) < 1e-9
    assert np.all((m.raw_transmission_angle >= 0) & (m.raw_transmission_angle <= np.pi))
    assert np.all((m.transmission_angle >= 0) & (m.transmission_angle <= np.pi / 2))


# --------------------------------------------------------------------------- dyads, any guide
def _moving_point(r, x0, y0):
    return lambda phi: crank(phi, r, x0, y0)


@SETTINGS
@given(length, signed, signed, angle, signed, st.floats(1.05, 4.0), st.sampled_from([1, -1]))
def test_rrp_dyad_any_guide_angle(r, x0, y0, gamma, g_off, factor, branch):
    """RRP with an arbitrary guide direction: B on the guide at ``length`` from the crank pin."""
    gx, gy = -g_off * np.sin(gamma), g_off * np.cos(gamma)  # guide through this point
    p_of = _moving_point(r, x0, y0)
    p = p_of(PHI)
    height = np.abs((p.x - gx) * -np.sin(gamma) + (p.y - gy) * np.cos(gamma))
    link = factor * np.max(height) + 1e-3
    b, s, th = dyad_rrp(p, link, gx, gy, gamma, branch=branch, phi=PHI)
    _finite(*b, *s, *th)
    assert np.max(np.abs(np.hypot(b.x - p.x, b.y - p.y) - link)) < 1e-10
    assert np.max(np.abs(-(b.x - gx) * np.sin(gamma) + (b.y - gy) * np.cos(gamma))) < 1e-10
    # the two branches are symmetric about the foot of p on the guide
    _, s_other, _ = dyad_rrp(p, link, gx, gy, gamma, branch=-branch, phi=PHI)
    foot = (p.x - gx) * np.cos(gamma) + (p.y - gy) * np.sin(gamma)
    np.testing.assert_allclose((s.value + s_other.value) / 2, foot, atol=1e-12)
    assert np.all(branch * (s.value - foot) >= 0)

    def s_jet(phi):
        return dyad_rrp(p_of(phi), link, gx, gy, gamma, branch=branch, phi=phi)[1]

    _close(_fd(lambda q: s_jet(q).value, PHI), s.d1, np.max(np.abs(s.d1)))
    _close(_fd(lambda q: s_jet(q).d1, PHI), s.d2, np.max(np.abs(s.d2)))
    fd_th = _fd_angle(lambda q: dyad_rrp(p_of(q), link, gx, gy, gamma, branch=branch)[2].value, PHI)
    _close(fd_th, th.d1, np.max(np.abs(th.d1)))


@SETTINGS
@given(length, st.floats(1.1, 5.0), angle, st.floats(-0.9, 0.9), st.sampled_from([1, -1]))
def test_rpr_dyad_slotted_lever(r, dist_factor, pivot_dir, off_factor, branch):
    """RPR: pin = pivot + s u + offset n for the lever angle; analogs are finite differences."""
    dist = r * dist_factor  # pivot outside the crank circle so the slider never meets it
    px, py = dist * np.cos(pivot_dir), dist * np.sin(pivot_dir)
    offset = off_factor * (dist - r)
    p = crank(PHI, r)
    th, s = dyad_rpr(p, px, py, offset, branch=branch, phi=PHI)
    _finite(*th, *s)
    c, sn = np.cos(th.value), np.sin(th.value)
    assert np.max(np.abs(px + s.value * c - offset * sn - p.x)) < 1e-10
    assert np.max(np.abs(py + s.value * sn + offset * c - p.y)) < 1e-10
    assert np.all(branch * s.value > 0)

    def jets(phi):
        return dyad_rpr(crank(phi, r), px, py, offset, branch=branch)

    fd_th = _fd_angle(lambda q: jets(q)[0].value, PHI)
    _close(fd_th, th.d1, np.max(np.abs(th.d1)))
    _close(_fd(lambda q: jets(q)[0].d1, PHI), th.d2, np.max(np.abs(th.d2)))
    _close(_fd(lambda q: jets(q)[1].value, PHI), s.d1, np.max(np.abs(s.d1)))
    _close(_fd(lambda q: jets(q)[1].d1, PHI), s.d2, np.max(np.abs(s.d2)))


# --------------------------------------------------------------------------- invalid designs
def _num(x):
    return f"{x:.6g}"


@SETTINGS
@given(length, signed, st.floats(0.1, 1.0))
def test_slider_crank_that_cannot_turn_raises(a, e, frac):
    reach = a + abs(e)
    rod = frac * reach
    with pytest.raises(MechanismError) as err:
        SliderCrank(a, rod, e)
    msg = str(err.value)
    assert "cannot make a full turn" in msg
    assert _num(rod) in msg and _num(reach) in msg


@SETTINGS
@given(length, length, length, length)
def test_four_bar_that_cannot_turn_raises(a, b, c, d):
    assume(not (a + d < b + c and abs(d - a) > abs(b - c)))
    with pytest.raises(MechanismError) as err:
        FourBar(a, b, c, d)
    msg = str(err.value)
    assert "the crank cannot make a full turn" in msg
    if a + d >= b + c:
        assert _num(a + d) in msg and _num(b + c) in msg
    else:
        assert _num(abs(d - a)) in msg and _num(abs(b - c)) in msg


@SETTINGS
@given(length, length, length, st.floats(1.0, 3.0))
def test_four_bar_that_cannot_close_raises(a, b, c, factor):
    d = factor * (a + b + c)  # ground at least as long as the other three together
    with pytest.raises(MechanismError) as err:
        FourBar(a, b, c, d, full_turn=False)
    msg = str(err.value)
    assert "cannot be assembled" in msg
    assert _num(d) in msg and _num(a + b + c) in msg


@SETTINGS
@given(four_bars())
def test_four_bar_outside_its_range_raises_at_the_angle(case):
    fb, _ = case
    a, b, c, d = fb.crank, fb.coupler, fb.rocker, fb.ground
    phi = np.linspace(0, 2 * np.pi, 721)
    rho = np.hypot(d - a * np.cos(phi), a * np.sin(phi))
    bad = (rho < abs(b - c) * (1 - 1e-6)) | (rho > (b + c) * (1 + 1e-6))
    inside = (rho > abs(b - c) + 1e-6 * (b + c)) & (rho < (b + c) * (1 - 1e-6))
    if bad.any():
        with pytest.raises(MechanismError, match=r"RRR dyad: .* at crank angle .* deg"):
            fb.motion(phi)
    # the assemblable angles alone are fine (away from the toggle positions, where the velocity
    # analogs are infinite)
    m = fb.motion(phi[inside])
    _finite(m.links["rocker"].omega, m.links["rocker"].epsilon)


bad_value = st.sampled_from([0.0, -1.0, -1e-9, np.nan, np.inf, -np.inf])


@SETTINGS
@given(st.sampled_from(["crank", "coupler", "rocker", "ground"]), bad_value)
def test_four_bar_bad_length_names_parameter(name, value):
    args = dict(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2)
    args[name] = value
    with pytest.raises(
        ValueError, match=rf"^{name} must be (positive \(a length in m\)|finite), got"
    ):
        FourBar(**args)


@SETTINGS
@given(st.sampled_from(["crank", "rod", "offset"]), bad_value)
def test_slider_crank_bad_value_names_parameter(name, value):
    args = dict(crank=0.07, rod=0.24, offset=0.01)
    args[name] = value
    # any finite offset (also <= 0) is a valid guide position
    assume(not (name == "offset" and np.isfinite(value)))
    with pytest.raises(
        ValueError, match=rf"^{name} must be (positive \(a length in m\)|finite), got"
    ):
        SliderCrank(**args)


def test_bad_entry_in_a_batch_names_its_index():
    with pytest.raises(ValueError, match=r"rocker must be positive .* got -2.0 \(design index"):
        FourBar(1.0, 4.3, np.array([3.0, -2.0, 3.0]), 5.2)
    with pytest.raises(MechanismError, match=r"design index \(1,\)"):
        SliderCrank(np.array([0.05, 0.3]), 0.24)


def test_rrp_point_too_far_from_guide_raises():
    p = crank(PHI, 1.0)
    with pytest.raises(MechanismError, match="farther from the guide than the link length"):
        dyad_rrp(p, 0.5, 0.0, 0.0, 0.3, phi=PHI)


# --------------------------------------------------------------------------- CasADi jacobians
def _symbolic(fn, names):
    x = ca.SX.sym("x", len(names))
    phi = ca.SX.sym("phi")
    out = fn(phi, *(x[i] for i in range(len(names))))
    return ca.Function("f", [phi, x], [out, ca.jacobian(out, x)])


def _slider_outputs(phi, a, b, e):
    s = SliderCrank(a, b, e).motion(phi).slider
    return ca.vertcat(s.position, s.velocity, s.acceleration)


def _rocker_outputs(phi, a, b, c, d, branch="open"):
    r = FourBar(a, b, c, d, branch=branch).motion(phi).links["rocker"]
    return ca.vertcat(r.angle, r.omega, r.epsilon)


_F_SLIDER = _symbolic(_slider_outputs, ["crank", "rod", "offset"])
_F_ROCKER = {
    br: _symbolic(lambda p, *x, br=br: _rocker_outputs(p, *x, branch=br), "abcd")
    for br in ("open", "crossed")
}


def _check_jacobian(f, numeric, phi, x0):
    val, jac = (np.array(v) for v in f(phi, x0))
    np.testing.assert_allclose(val.ravel(), numeric(phi, x0), rtol=1e-12, atol=1e-12)
    h = 1e-6
    for j in range(x0.size):
        xp, xm = x0.copy(), x0.copy()
        xp[j] += h * max(1.0, abs(x0[j]))
        xm[j] -= h * max(1.0, abs(x0[j]))
        fd = (numeric(phi, xp) - numeric(phi, xm)) / (xp[j] - xm[j])
        np.testing.assert_allclose(jac[:, j], fd, atol=1e-6 * max(1.0, np.max(np.abs(fd))))


@settings(max_examples=25, deadline=None)
@given(slider_cranks(), angle)
def test_casadi_slider_jacobian_equals_finite_differences(sc, phi):
    def numeric(p, x):
        s = SliderCrank(*x).motion(p).slider
        return np.array([s.position, s.velocity, s.acceleration], dtype=float)

    _check_jacobian(_F_SLIDER, numeric, phi, np.array([sc.crank, sc.rod, sc.offset]))


@settings(max_examples=25, deadline=None)
@given(full_turn_four_bars(), angle)
def test_casadi_rocker_jacobian_equals_finite_differences(fb, phi):
    def numeric(p, x):
        r = FourBar(*x, branch=fb.branch).motion(p).links["rocker"]
        return np.array([r.angle, r.omega, r.epsilon], dtype=float)

    x0 = np.array([fb.crank, fb.coupler, fb.rocker, fb.ground])
    # the rocker angle is continuous in the parameters away from the +-pi cut of arctan2
    assume(np.pi - abs(numeric(phi, x0)[0]) > 1e-3)
    _check_jacobian(_F_ROCKER[fb.branch], numeric, phi, x0)


def test_dyad_rrr_symbolic_matches_numeric():
    x = ca.SX.sym("x", 2)
    p1 = crank(0.7, 1.0)
    p2 = PointJet.fixed(x[0], 0.0 * x[0])
    c, _, _ = dyad_rrr(p1, p2, x[1], 3.0)
    f = ca.Function("f", [x], [ca.vertcat(c.x, c.y, c.ddx)])
    num, _, _ = dyad_rrr(p1, PointJet.fixed(5.0, 0.0), 4.0, 3.0)
    np.testing.assert_allclose(np.array(f([5.0, 4.0])).ravel(), [num.x, num.y, num.ddx], rtol=1e-13)


def test_toggle_positions_raise_instead_of_nan():
    # change-point parallelogram: all four links in line at phi = 0 (0/0 in the RRR dyad)
    with pytest.raises(MechanismError, match=r"RRR dyad: links in line .* at crank angle 0 deg"):
        FourBar(1.0, 2.0, 1.0, 2.0, full_turn=False).motion(np.array([0.0, 0.5]))
    # crank pin at the link's length from the guide: the link stands perpendicular to it
    p = crank(np.pi / 2, 1.0)
    with pytest.raises(MechanismError, match=r"RRP dyad: link perpendicular .* at crank angle 90"):
        dyad_rrp(p, 1.0, phi=np.pi / 2)
