"""Convex minimax synthesis: exact affine maps, LP/SOCP optima against brute force, scipy linprog
and a closed-form balancing result; certification over the continuous crank angle."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import linprog, minimize

import mechsynth as ms
from mechsynth.synthesis import STATUSES
from mechsynth.synthesis.convex import AffineMap, affine_map, minimax_affine, minimax_cycle

OMEGA = ms.rpm(600)
SC = ms.SliderCrank(crank=0.05, rod=0.2, offset=0.02)


def shaking_force(x, phi, m_pin=0.8):
    """Resultant inertia force (N) of a slider-crank with a mass ``m_pin`` at the crank pin,
    a slider mass ``x[1]`` and a counterweight of mass-radius product ``x[0]`` (kg m) opposite
    the crank pin: affine in x, a 2-D vector per crank angle."""
    m = SC.motion(phi, speed=OMEGA)
    a, b = m.points["A"], m.points["B"]
    fx = m_pin * a.ax + x[1] * b.ax + x[0] * OMEGA**2 * np.cos(phi)
    fy = m_pin * a.ay + x[1] * b.ay + x[0] * OMEGA**2 * np.sin(phi)
    return np.stack([fx, fy], axis=-1)


# ------------------------------------------------------------------------------ affine map
def test_affine_map_recovers_the_exact_map():
    rng = np.random.default_rng(1)
    phi = ms.cycle(50)
    A_true = rng.normal(size=(50, 2, 3))
    b_true = rng.normal(size=(50, 2))
    amap = affine_map(lambda x, p: A_true @ x + b_true, x0=[0.3, -2.0, 5.0], angles=phi)
    assert amap.A.shape == (50, 2, 3) and amap.b.shape == (50, 2)
    np.testing.assert_allclose(amap.A, A_true, rtol=0, atol=1e-12)
    np.testing.assert_allclose(amap.b, b_true, rtol=0, atol=1e-11)
    x = np.array([1.0, 2.0, -3.0])
    np.testing.assert_allclose(amap(x), A_true @ x + b_true, atol=1e-11)


def test_affine_map_of_a_mechanism_force_matches_direct_evaluation():
    amap = affine_map(shaking_force, [0.01, 1.0], 90)
    x = np.array([0.037, 1.7])
    np.testing.assert_allclose(amap(x), shaking_force(x, amap.phi), rtol=1e-12, atol=1e-9)


def test_affine_map_rejects_non_affine_and_bad_output():
    with pytest.raises(ValueError, match="not affine in x"):
        affine_map(lambda x, phi: x[0] ** 2 * np.cos(phi), [1.0], 36)
    with pytest.raises(ValueError, match="not affine in x"):
        affine_map(lambda x, phi: np.abs(x[0] - 1.0) * np.cos(phi), [0.0], 36)
    with pytest.raises(ValueError, match="shape"):
        affine_map(lambda x, phi: np.zeros(3), [1.0], 36)
    with pytest.raises(ValueError, match="not finite"):
        affine_map(lambda x, phi: np.full(phi.shape, np.nan), [1.0], 36)
    with pytest.raises(ValueError, match="x0"):
        affine_map(lambda x, phi: phi, [np.inf], 36)


# ------------------------------------------------------------------------------ LP
def _linprog_minimax(A, b, bounds):
    """Reference: min t s.t. -t <= A x + b <= t with scipy's HiGHS."""
    m, n = A.shape
    c = np.r_[np.zeros(n), 1.0]
    A_ub = np.block([[A, -np.ones((m, 1))], [-A, -np.ones((m, 1))]])
    b_ub = np.r_[-b, b]
    res = linprog(c, A_ub=A_ub, b_ub=b_ub, bounds=list(bounds) + [(None, None)], method="highs")
    assert res.status == 0
    return res.x[:n], res.fun


@settings(max_examples=30, deadline=None)
@given(
    st.lists(st.floats(-3, 3), min_size=3, max_size=3),
    st.floats(0.2, 4.0),
)
def test_lp_1d_matches_brute_force_and_linprog(coef, amp):
    phi = ms.cycle(120)
    # y = x cos(phi) + coef . (1, cos 2phi, sin 3phi) + amp sin(phi)
    A = np.cos(phi)[:, None]
    b = coef[0] + coef[1] * np.cos(2 * phi) + coef[2] * np.sin(3 * phi) + amp * np.sin(phi)
    res = minimax_affine(A, b, angles=phi, bounds=[(-5.0, 5.0)], names=["x"])
    assert res.status == "optimal" and res.success and res.status in STATUSES
    xs = np.linspace(-5, 5, 20001)
    peaks = np.max(np.abs(np.outer(xs, A[:, 0]) + b), axis=1)
    assert res.value <= peaks.min() + 1e-9 * max(1.0, peaks.min())
    assert res.value >= peaks.min() - (xs[1] - xs[0]) * 1.0  # |A| <= 1: grid step bounds the gap
    x_ref, t_ref = _linprog_minimax(A, b, [(-5.0, 5.0)])
    assert res.value == pytest.approx(t_ref, rel=1e-7, abs=1e-9)
    assert np.max(np.abs(A @ res.x + b)) == pytest.approx(res.value, rel=1e-12)
    assert res.active.size >= 1
    assert np.all(np.abs(A[res.active] @ res.x + b[res.active]) >= res.value * (1 - 1e-6))


def test_lp_two_variables_matches_linprog_with_constraints():
    rng = np.random.default_rng(7)
    phi = ms.cycle(400)
    A = np.stack([np.cos(phi), np.sin(2 * phi) + 0.3], axis=-1) * 150.0
    b = 400.0 * np.cos(phi + 0.4) + 90.0 * np.cos(3 * phi) + rng.normal(size=phi.size)
    A_ub, b_ub = np.array([[1.0, 1.0]]), np.array([1.5])
    res = minimax_affine(A, b, angles=phi, bounds=[(0, None), (0, None)], A_ub=A_ub, b_ub=b_ub)
    # reference with the extra inequality
    m, n = A.shape
    c = np.r_[np.zeros(n), 1.0]
    Aub = np.block([[A, -np.ones((m, 1))], [-A, -np.ones((m, 1))], [A_ub, np.zeros((1, 1))]])
    ref = linprog(c, A_ub=Aub, b_ub=np.r_[-b, b, b_ub], bounds=[(0, None)] * 2 + [(None, None)])
    assert res.success
    assert res.value == pytest.approx(ref.fun, rel=1e-7)
    assert res.x.sum() <= 1.5 + 1e-9 and np.all(res.x >= 0.0)


def test_signed_max_norm():
    phi = ms.cycle(360)
    # max_phi (x cos phi + 2 - x) over x in [0, 3]: the peak is max(2, 2 - 2x)... = 2 at x >= 0
    A = (np.cos(phi) - 1.0)[:, None]
    res = minimax_affine(A, 2.0 + 0 * phi, norm="max", bounds=[(0.0, 3.0)])
    assert res.success and res.value == pytest.approx(2.0, abs=1e-8)


# ------------------------------------------------------------------------------ SOCP
def test_socp_half_balance_of_the_primary_force():
    """Closed form: a primary inertia force m r w^2 (cos phi, 0) balanced by a counterweight u
    opposite the crank leaves w^2 ((m r - u) cos phi, -u sin phi); its peak magnitude
    w^2 max(|m r - u|, u) is least at u = m r / 2 (half balance), value m r w^2 / 2."""
    mr = 0.06

    def force(x, phi):
        return OMEGA**2 * np.stack([(mr - x[0]) * np.cos(phi), -x[0] * np.sin(phi)], axis=-1)

    res = minimax_cycle(force, [0.0], 48, norm="euclidean", bounds=[(0.0, None)], names=["u"])
    assert res.success
    assert res.variables["u"] == pytest.approx(mr / 2, rel=1e-6)
    assert res.value == pytest.approx(mr * OMEGA**2 / 2, rel=1e-7)


def test_socp_two_variables_matches_brute_force_and_local_search():
    amap = affine_map(shaking_force, [0.01, 1.0], 180)
    bounds = [(0.0, 0.2), (0.5, 2.0)]
    res = minimax_affine(amap, norm="euclidean", bounds=bounds, names=["u", "m_slider"])
    assert res.success and res.kind == "SOCP"

    def peak(x):
        return np.max(np.linalg.norm(amap(x), axis=-1))

    U, M = np.meshgrid(np.linspace(0, 0.2, 201), np.linspace(0.5, 2.0, 151), indexing="ij")
    X = np.stack([U.ravel(), M.ravel()], axis=-1)
    vals = np.max(np.linalg.norm(np.einsum("mdn,kn->kmd", amap.A, X) + amap.b, axis=-1), axis=1)
    i = int(np.argmin(vals))
    assert res.value <= vals[i] * (1 + 1e-9)
    polished = minimize(
        peak,
        X[i],
        method="Nelder-Mead",
        bounds=bounds,
        options=dict(xatol=1e-12, fatol=1e-12, maxiter=4000),
    )
    assert res.value == pytest.approx(min(polished.fun, vals[i]), rel=1e-5)
    assert peak(res.x) == pytest.approx(res.value, rel=1e-12)
    # the slider mass sits at its lower bound: every kilogram adds inertia force
    assert res.variables["m_slider"] == pytest.approx(0.5, abs=1e-7)


def test_minimax_cycle_certifies_the_continuous_peak():
    bounds = [(0.0, 0.2), (0.5, 2.0)]
    coarse = minimax_cycle(shaking_force, [0.01, 1.0], 24, norm="euclidean", bounds=bounds)
    assert coarse.success and coarse.extra["certified"]
    assert coarse.extra["rounds"] >= 1  # 24 angles miss the peak
    fine = minimax_affine(
        affine_map(shaking_force, coarse.x, 20000), norm="euclidean", bounds=bounds
    )
    assert coarse.value == pytest.approx(fine.value, rel=1e-6)
    # the certified peak is the true peak at the reported design
    dense = np.max(np.linalg.norm(shaking_force(coarse.x, ms.cycle(20000)), axis=-1))
    assert dense <= coarse.value * (1 + 1e-9)


# ------------------------------------------------------------------------------ failures
def test_infeasible_and_unbounded_are_reported():
    phi = ms.cycle(36)
    A = np.cos(phi)[:, None]
    b = np.sin(phi)
    res = minimax_affine(A, b, bounds=[(0.0, 1.0)], A_eq=[[1.0]], b_eq=[2.0])
    assert not res.success and res.status == "infeasible" and res.x is None
    assert "infeasible" in res.message and np.isnan(res.value)
    # cos takes both signs, so max_phi (x cos phi + sin phi) is bounded below without bounds
    assert minimax_affine(A, b, norm="max").success
    # a constant direction is not: the signed peak decreases without limit
    res = minimax_affine(np.ones((4, 1)), np.zeros(4), norm="max")
    assert not res.success and res.status == "solver_failed" and "unbounded" in res.message


def test_bad_input_raises_value_error():
    A, b = np.ones((4, 1)), np.zeros(4)
    with pytest.raises(ValueError, match="norm"):
        minimax_affine(A, b, norm="l1")
    with pytest.raises(ValueError, match="euclidean"):
        minimax_affine(A, b, norm="euclidean")
    with pytest.raises(ValueError, match="bounds"):
        minimax_affine(A, b, bounds=[(1.0, 0.0)])
    with pytest.raises(ValueError, match="shape"):
        AffineMap(np.ones((4, 2)), np.ones(3))


def test_report_dict_and_plot():
    res = minimax_cycle(
        shaking_force,
        [0.01, 1.0],
        72,
        norm="euclidean",
        bounds=[(0.0, 0.2), (0.5, 2.0)],
        names=["u", "m_slider"],
    )
    text = res.report()
    assert "optimal" in text and "u =" in text and "m_slider" in text
    d = res.to_dict()
    assert d["status"] == "optimal" and set(d["variables"]) == {"u", "m_slider"}
    fig = res.plot(label="shaking force", unit="N")
    assert len(fig.axes[0].lines) >= 2


def test_affine_map_only_evaluates_forward_of_x0():
    """A model that rejects negative masses is never called with one when x0 >= 0."""
    seen = []

    def force(x, phi):
        if np.any(x < 0):
            raise ValueError(f"mass must be >= 0, got {x}")
        seen.append(x.copy())
        return x[0] * np.cos(phi) + x[1] * np.sin(phi)

    amap = affine_map(force, [0.0, 0.0], 12)
    assert len(seen) == 1 + 2 + 3 and amap.A.shape == (12, 2)
