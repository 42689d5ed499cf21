"""Tests of the dwell linkage model and the minimax (Chebyshev) line-fit dwell metrics."""

import cvxpy as cp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mechsynth.kinematics.four_bar import FourBar
from mechsynth.machines.dwell.linkage import DwellSliderCrank
from mechsynth.machines.dwell.metrics import (
    DwellDeviation,
    DwellDuration,
    DwellStroke,
    _hull_width,
    dwell_window,
    dwell_windows,
    minimax_line_fit,
    relative_stroke,
    window_deviation,
)

PHI = np.arange(720) * 2 * np.pi / 720


def _lp_fit(p):
    """Reference: minimax fit by brute-force directions + cvxpy LP polish at the best one."""
    th = np.linspace(0, np.pi, 20001)
    proj = -np.outer(np.sin(th), p[:, 0]) + np.outer(np.cos(th), p[:, 1])
    w = proj.max(1) - proj.min(1)
    t = th[np.argmin(w)]
    # LP for the offset at that direction (minimize the max deviation)
    c, e = cp.Variable(), cp.Variable()
    d = -np.sin(t) * p[:, 0] + np.cos(t) * p[:, 1]
    cp.Problem(cp.Minimize(e), [d - c <= e, c - d <= e]).solve()
    return w.min() / 2, float(e.value)


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 10_000), st.integers(3, 30))
def test_minimax_fit_matches_brute_force(seed, n):
    p = np.random.default_rng(seed).normal(size=(n, 2))
    fit = minimax_line_fit(p)
    brute, lp = _lp_fit(p)
    assert fit.deviation <= brute + 1e-12  # exact optimum is never worse than any direction
    # the width function is Lipschitz with constant = diameter: grid error bound on E
    diam = np.max(np.hypot(*(p[:, None, :] - p[None, :, :]).transpose(2, 0, 1)))
    assert brute - fit.deviation <= diam * (np.pi / 20000) / 4 + 1e-12
    assert lp == pytest.approx(brute, rel=1e-5, abs=1e-7)
    # the compiled kernel used by the dwell sweep agrees with the reference fit
    assert _hull_width(p[:, 0].copy(), p[:, 1].copy()) == pytest.approx(2 * fit.deviation, 1e-12)
    # the line really has that deviation
    d = -np.sin(fit.xi) * p[:, 0] + np.cos(fit.xi) * p[:, 1] - fit.c
    assert np.max(np.abs(d)) == pytest.approx(fit.deviation, rel=1e-12, abs=1e-14)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 10_000), st.integers(3, 400), st.floats(0.05, 6.2))
def test_hull_width_on_convex_arcs(seed, n, span):
    # every point on the hull (an arc of an ellipse, the dwell sweep's usual case): the rotating
    # calipers must agree with the exact fit (scipy's hull, every direction of every edge)
    rng = np.random.default_rng(seed)
    t = np.sort(rng.uniform(0.0, span, n))
    a, b, rot = rng.uniform(0.2, 3.0), rng.uniform(0.01, 3.0), rng.uniform(0, np.pi)
    x0, y0 = a * np.cos(t), b * np.sin(t)
    x = np.cos(rot) * x0 - np.sin(rot) * y0 + rng.normal()
    y = np.sin(rot) * x0 + np.cos(rot) * y0 + rng.normal()
    fit = minimax_line_fit(np.column_stack([x, y]))
    assert _hull_width(x, y) == pytest.approx(2 * fit.deviation, rel=1e-9, abs=1e-13)


def test_collinear_points_zero_deviation():
    t = np.linspace(-1, 2, 9)
    fit = minimax_line_fit(np.column_stack([1 + 2 * t, 3 - t]))
    assert fit.deviation == pytest.approx(0.0, abs=1e-12)
    assert np.tan(fit.xi) == pytest.approx(-0.5)


def test_synthetic_straight_segment_window():
    # a closed curve: straight on samples 100..299 (inclusive), a circle arc elsewhere
    n = 720
    phi = np.arange(n) * 2 * np.pi / n
    x, y = np.cos(phi), np.sin(phi)
    x[100:300] = np.linspace(0.0, 1.0, 200)
    y[100:300] = 5.0 + 0.3 * np.linspace(0.0, 1.0, 200)
    w = dwell_window(phi, x, y, 1e-9)
    assert w.start == 100 and w.count == 200
    assert w.dwell == pytest.approx(199 * 2 * np.pi / n)
    assert w.deviation == pytest.approx(0.0, abs=1e-9)
    assert np.tan(w.xi) == pytest.approx(0.3)


def test_k_zero_is_slider_path():
    # k = 0: C = A is on a circle, no straight section; C at B (k=1, gamma=0) moves on y = 0
    m = DwellSliderCrank(r=0.3, k=1.0, gamma=0.0)
    x, y = m.coupler_curve(PHI)
    w = dwell_window(PHI, x, y, 1e-9)
    assert w.dwell == pytest.approx(2 * np.pi)
    assert w.deviation < 1e-12
    # the slot lies along the path itself: link 5 never moves; across it, it moves by 2r
    assert relative_stroke(x, y, w.xi) == pytest.approx(0.0, abs=1e-12)
    assert relative_stroke(x, y, w.xi + np.pi / 2) == pytest.approx(2 * 0.3, rel=1e-9)


def test_s5_stationary_over_dwell_and_derivatives():
    m = DwellSliderCrank(r=0.3, k=1.2, gamma=np.deg2rad(20))
    x, y = m.coupler_curve(PHI)
    w = dwell_window(PHI, x, y, 0.002)
    assert w.deviation <= 0.002 and w.dwell > np.deg2rad(60)
    mo = m.replace(xi=w.xi).motion(PHI, speed=3.0)
    s5 = mo.sliders["5"].position
    idx = (w.start + np.arange(w.count)) % PHI.size
    assert np.ptp(s5[idx]) <= 2 * w.deviation + 1e-12
    assert np.ptp(s5) / 1.0 == pytest.approx(relative_stroke(x, y, w.xi))
    # analogs vs finite differences
    h = 1e-6
    j = m.replace(xi=w.xi).output_jet(PHI)
    jp, jm = (m.replace(xi=w.xi).output_jet(PHI + s) for s in (h, -h))
    np.testing.assert_allclose(j.d1, (jp.value - jm.value) / (2 * h), atol=1e-7)
    np.testing.assert_allclose(j.d2, (jp.d1 - jm.d1) / (2 * h), atol=1e-7)
    np.testing.assert_allclose(mo.sliders["5"].velocity, 3.0 * j.d1)
    np.testing.assert_allclose(mo.sliders["5"].acceleration, 9.0 * j.d2)


def test_gamma_sign_convention():
    m = DwellSliderCrank(r=0.2, k=0.5, gamma=np.deg2rad(30))
    c = m.coupler_jet(np.array([0.0]))
    # at phi = 0 the rod lies along +x: gamma > 0 puts C above it
    assert c.y[0] == pytest.approx(0.5 * np.sin(np.deg2rad(30)))


def test_bad_input():
    with pytest.raises(ValueError, match="r = l_OA"):
        DwellSliderCrank(r=1.2, k=1.0)
    with pytest.raises(ValueError, match="xi"):
        DwellSliderCrank(r=0.2, k=1.0).output_jet(PHI)
    with pytest.raises(ValueError, match="tolerance"):
        dwell_window(PHI, np.cos(PHI), np.sin(PHI), 0.0)


def test_measures_batch():
    m = DwellSliderCrank(r=np.array([[0.3], [0.25]]), k=1.2, gamma=np.deg2rad(20))
    mo = m.motion(PHI)
    dur = DwellDuration(0.002).from_motion(m, mo)
    single = DwellDuration(0.002).evaluate(DwellSliderCrank(0.25, 1.2, np.deg2rad(20)), PHI)
    assert dur.shape == (2,) and dur[1] == pytest.approx(single)
    assert DwellStroke(0.002).from_motion(m, mo).shape == (2,)
    m1 = DwellSliderCrank(0.25, 1.2, 0.3)
    e = DwellDeviation(PHI[30], np.pi / 4).evaluate(m1, PHI)
    x, y = m1.coupler_curve(PHI)
    assert e == pytest.approx(window_deviation(x, y, 30, 30 + 91).deviation, rel=1e-12)


def test_hoeken_straight_line_linkage():
    # Hoeken straight-line four-bar (K. Hoecken, Werkstattstechnik 1926), proportions crank :
    # coupler : rocker : ground = 1 : 2.5 : 2.5 : 2, tracing point on the coupler extended to
    # 2 x coupler from the crank pin. Published characteristic: the point runs on an approximate
    # straight line over about half the crank turn (~180 deg), e.g. Mechanical Design Handbook,
    # "Design Hoeken's linkage" (2025), Fig. 1. Reproduced here with a band half-width of 0.5 % of
    # the crank (computed E = 0.0049 over 209 deg); a band half as wide holds less than 180 deg.
    fb = FourBar(crank=1.0, coupler=2.5, rocker=2.5, ground=2.0)
    p = fb.motion(PHI, coupler_points={"P": (5.0, 0.0)}).points["P"]
    x, y = np.asarray(p.x), np.asarray(p.y)
    assert dwell_window(PHI, x, y, 0.005).dwell >= np.pi
    assert dwell_window(PHI, x, y, 0.0025).dwell < np.pi


def test_batch_matches_single():
    r = np.array([0.2, 0.3, 0.35])[:, None]
    x, y = DwellSliderCrank(r=r, k=1.2, gamma=np.deg2rad(25)).coupler_curve(PHI)
    b = dwell_windows(PHI, x, y, 0.002)
    for i in range(3):
        w = dwell_window(PHI, x[i], y[i], 0.002)
        assert b["dwell"][i] == w.dwell and b["phi_L"][i] == w.phi_L
        assert b["deviation"][i] == pytest.approx(w.deviation) and b["deviation"][i] <= 0.002


def test_casadi_model_matches_numpy():
    import casadi as ca

    p = ca.SX.sym("p", 3)
    ph = ca.SX.sym("phi")
    j = DwellSliderCrank(p[0], p[1], p[2], xi=0.2).output_jet(ph)
    f = ca.Function("s5", [p, ph], [j.value, j.d1, j.d2])
    num = DwellSliderCrank(0.3, 1.2, 0.35, xi=0.2).output_jet(PHI[::40])
    for i, phi in enumerate(PHI[::40]):
        got = [float(v) for v in f([0.3, 1.2, 0.35], phi)]
        np.testing.assert_allclose(got, [num.value[i], num.d1[i], num.d2[i]], atol=1e-12)
