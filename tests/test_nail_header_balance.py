"""AB4115 nail header (paper 003, first part): shaking force and moment, counterweights, the
trade-off with the joint reactions, and the slider mass over several nail sizes."""

from dataclasses import replace

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from mechsynth.dynamics.kinetostatics import (  # noqa: E402
    applied_power,
    kinetic_energy_rate,
    kinetostatics,
)
from mechsynth.dynamics.shaking import frame_load, shaking  # noqa: E402
from mechsynth.errors import MechanismError  # noqa: E402
from mechsynth.machines.nail_header import NailHeader  # noqa: E402
from mechsynth.machines.nail_header.balance import (  # noqa: E402
    CW_MASS,
    CW_MAX_RADIUS,
    balance_counterweight,
    balance_front,
    balance_maps,
    counterweighted_model,
    peak_reaction,
    peak_shaking,
)
from mechsynth.machines.nail_header.load_cases import nail_case, robust_slider_mass  # noqa: E402
from mechsynth.units import cycle  # noqa: E402

PHI = -cycle(360)


def _both(nh, model):
    m = nh.motion(PHI, speed=nh.omega)
    res = kinetostatics(model, m)
    return shaking(model, m), frame_load(model, m, res), m, res


def _agree(a, b, force_scale):
    assert np.max(np.abs(a.fx - b.fx)) <= 1e-12 * force_scale
    assert np.max(np.abs(a.fy - b.fy)) <= 1e-12 * force_scale
    assert np.max(np.abs(a.moment - b.moment)) <= 1e-12 * force_scale


@pytest.mark.parametrize("m3", [15.0, 50.0])
@pytest.mark.parametrize("gravity", [True, False])
def test_shaking_equals_the_frame_load_from_the_ground_reactions(m3, gravity):
    # Two independent computations: -sum m a_S from the kinematics, and the frame's load from
    # the kinetostatic ground reactions (R10, R30 with its pair moment, R50), the upsetting
    # force, the spring and the drive's reaction, less the weight.
    nh = NailHeader(m3=m3)
    a, b, _, _ = _both(nh, nh.force_model(gravity))
    _agree(a, b, 6e4)
    assert a.peak()[0] > 5e3  # a real load, not two zeros


@settings(max_examples=15, deadline=None)
@given(
    st.floats(1.0, 120.0),
    st.floats(-3.0, 3.0),
    st.floats(-3.0, 3.0),
    st.floats(1.0, 40.0),
    st.sampled_from([1, -1]),
)
def test_shaking_equals_frame_load_with_any_counterweight(m3, cx, cy, mc, sense):
    nh = NailHeader(m3=m3, spring_sense=sense)
    a, b, m, res = _both(nh, counterweighted_model(nh, mc, (cx, cy)))
    _agree(a, b, 1e5)
    # and the counterweighted model passes the power balance
    model = counterweighted_model(nh, mc, (cx, cy))
    keep = np.abs(np.sin(PHI)) > 1e-3  # the upsetting force jumps at the dead centre
    rhs = (kinetic_energy_rate(model, m) - applied_power(model, m))[keep]
    lhs = (res.torque * m.omega)[keep]
    assert np.max(np.abs(lhs - rhs)) <= 1e-9 * np.max(np.abs(rhs))


def test_shaking_force_is_minus_the_inertia_of_the_moving_links():
    # By hand for the slider alone: its inertia force -m3 a_B along x, no moment about O.
    nh = NailHeader(m1=0.0, m2=0.0, m5=0.0, j_s1=0.0, j_s2=0.0, j_s5=0.0)
    model = nh.force_model()
    m = nh.motion(PHI, speed=nh.omega)
    sh = shaking(model, m)
    np.testing.assert_allclose(sh.fx, -nh.m3 * m.points["B"].ax, atol=1e-9)
    np.testing.assert_allclose(sh.fy, 0.0, atol=1e-12)
    np.testing.assert_allclose(sh.moment, 0.0, atol=1e-9)


@pytest.fixture(scope="module")
def maps():
    return balance_maps(NailHeader(), PHI)


def test_affine_maps_equal_direct_solves(maps):
    rng = np.random.default_rng(3)
    for _ in range(3):
        x = np.array([rng.uniform(5, 150), rng.uniform(-2, 2), rng.uniform(-2, 2)])
        nh = NailHeader(m3=x[0])
        model = counterweighted_model(nh, CW_MASS, x[1:])
        m = nh.motion(PHI, speed=nh.omega)
        res = kinetostatics(model, m)
        sh = shaking(model, m)
        np.testing.assert_allclose(maps.shaking(x), np.stack([sh.fx, sh.fy], -1), atol=1e-7)
        for j in ("R10", "R21", "R32"):
            np.testing.assert_allclose(maps.reactions[j](x), np.stack(res.reactions[j], -1),
                                       atol=1e-7)
        # the shaking moment about O depends on neither the slider mass nor the counterweight
        np.testing.assert_allclose(sh.moment, maps.moment, atol=1e-9)
    assert maps.affine_deviation < 1e-6


def test_counterweight_minimax_is_optimal_and_costs_r10(maps):
    res = balance_counterweight(maps, 15.0)
    assert res.success and res.x[0] == 15.0
    base = peak_shaking(maps, [15.0, 0.0, 0.0])
    assert res.value < 0.5 * base  # 7.26 kN -> 3.34 kN
    assert res.value == pytest.approx(peak_shaking(maps, res.x), rel=1e-9)
    # independent check: no counterweight moment on a polar grid around it does better
    c = np.hypot(res.x[1], res.x[2])
    assert c <= CW_MASS * CW_MAX_RADIUS * (1 + 1e-9)
    rr, aa = np.meshgrid(np.linspace(0.0, 2.0, 41), np.deg2rad(np.arange(0.0, 360.0, 3.0)))
    X = np.stack([np.full(rr.size, 15.0), (rr * np.cos(aa)).ravel(), (rr * np.sin(aa)).ravel()])
    y = np.einsum("mdn,nk->kmd", maps.shaking.A, X) + maps.shaking.b
    grid = np.max(np.linalg.norm(y, axis=-1), axis=1)
    assert grid.min() >= res.value * (1 - 1e-6)
    assert grid[0] == pytest.approx(peak_shaking(maps, X[:, 0]), rel=1e-12)
    # it sits opposite A (the slider moves on the line through O and the outer dead centre)
    assert abs(np.rad2deg(np.arctan2(res.x[2], res.x[1]))) == pytest.approx(180.0, abs=0.5)
    # the price: the crank bearing R10 grows; R21 and R32 do not change
    before = {j: peak_reaction(maps, [15.0, 0, 0], (j,)) for j in ("R10", "R21", "R32")}
    after = {j: peak_reaction(maps, res.x, (j,)) for j in ("R10", "R21", "R32")}
    assert after["R10"] > before["R10"] + 1e3
    assert after["R21"] == pytest.approx(before["R21"], rel=1e-9)
    assert after["R32"] == pytest.approx(before["R32"], rel=1e-9)


def test_trade_off_front_is_monotone_and_respects_its_limits(maps):
    front = balance_front(maps, n=4)
    assert all(r["status"] == "optimal" for r in front)
    for r in front:
        assert r["reaction"] <= r["reaction_limit"] * (1 + 1e-6)
    shakes = [r["shaking"] for r in front]
    assert all(a > b for a, b in zip(shakes, shakes[1:]))
    # the low-reaction end is the slider-mass optimum of the train (68.4 kg, 27.9 kN)
    assert front[0]["m3"] == pytest.approx(68.37, abs=0.05)
    assert front[0]["reaction"] == pytest.approx(27933, rel=2e-3)
    # the blow goes into the bearings or into the frame: their peaks add up to the blow's
    # 52.35 kN (plus the weights) all along the front
    for r in front:
        assert 52.3e3 < r["shaking"] + r["reaction"] < 52.8e3


def test_nail_cases_scale_the_blow_with_d_squared():
    base = NailHeader()
    assert nail_case(3.0) == base
    at0 = np.array([0.0])
    blows = {d: float(nail_case(d).upsetting(nail_case(d).motion(at0, speed=base.omega))[0])
             for d in (2.0, 3.0)}
    assert blows[2.0] / blows[3.0] == pytest.approx((2.0 / 3.0) ** 2, rel=1e-12)
    with pytest.raises(MechanismError, match="nail diameter"):
        nail_case(-1.0)


def test_robust_slider_mass_over_nail_sizes():
    r = robust_slider_mass((2.0, 3.0), phi=-cycle(360))
    small, big = r["cases"]
    for c in r["cases"]:
        assert c["own_mass"] == pytest.approx(c["check_mass"], abs=1e-4)
        assert c["certified"]
    assert r["robust"]["certified"] and r["compromise"]["certified"]
    # the worst peak is the largest nail's: the robust mass is its own optimum
    assert r["robust"]["mass"] == pytest.approx(big["own_mass"], abs=1e-4)
    assert r["robust"]["mass"] == pytest.approx(r["robust"]["check_mass"], abs=1e-4)
    assert small["peak_at_robust"] > small["peak_at_15kg"] > small["own_peak"]
    # the compromise equalizes the ratios to the own optima, between the two own masses
    com = r["compromise"]
    assert small["own_mass"] < com["mass"] < big["own_mass"]
    ratios = [c["peak_at_compromise"] / c["own_peak"] for c in r["cases"]]
    assert max(ratios) == pytest.approx(com["value"], rel=1e-6)
    assert ratios[0] == pytest.approx(ratios[1], rel=1e-4)
    assert com["value"] < max(c["peak_at_15kg"] / c["own_peak"] for c in r["cases"])


def test_counterweight_mass_must_be_positive():
    with pytest.raises(MechanismError, match="counterweight mass"):
        counterweighted_model(NailHeader(), 0.0, (0.1, 0.0))
    with pytest.raises(MechanismError, match="without its own counterweight"):
        balance_maps(replace(NailHeader(), counterweight=1.0), PHI)
