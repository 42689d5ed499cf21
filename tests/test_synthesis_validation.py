"""Validation of the synthesis engine against closed forms, a brute-force grid search and the
unit-time-ratio crank-rocker relations of Brodell & Soni (1970)."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth.synthesis.problem_file import parse_quantity

SPEED = ms.rpm(600)  # the slider-crank problems are solved at a fixed crank speed of 600 rpm
H = 0.10  # required stroke, m


# ------------------------------------------------------------------------------ centric stroke
def test_centric_stroke_alone_gives_half_stroke_crank():
    # centric slider-crank: stroke = 2 * crank exactly, whatever the rod
    prob = ms.Problem(
        ms.SliderCrank,
        variables={"crank": (0.01, 0.2), "rod": (0.2, 0.6)},
        fixed={"offset": 0.0},
        speed=SPEED,
    )
    prob.minimize(ob.peak_acceleration("slider")).subject_to(ob.stroke("slider") == 0.12)
    res = prob.solve(starts=3)
    assert res.success, res.report()
    assert res.design.crank == pytest.approx(0.06, rel=1e-8)
    # a longer rod lowers the peak acceleration a*w^2*(1 + a/b): the rod goes to its bound
    assert res.design.rod == pytest.approx(0.6, rel=1e-6)
    a, b = 0.06, 0.6
    assert res.value == pytest.approx(a * SPEED**2 * (1 + a / b), rel=1e-8)


def test_stroke_alone_single_variable():
    prob = ms.Problem(
        ms.SliderCrank, variables={"crank": (0.01, 0.2)}, fixed={"rod": 0.4}, speed=None
    )
    prob.minimize(ob.max_pressure_angle()).subject_to(ob.stroke() == H)
    res = prob.solve(starts=2)
    assert res.success, res.report()
    assert res.design.crank == pytest.approx(H / 2, rel=1e-9)
    assert res.constraints[0].value == pytest.approx(H, rel=1e-9)


# ------------------------------------------------------------------------------ brute force
def _crank_for_stroke(rod, offset, stroke):
    """Crank giving ``stroke`` for each (rod, offset), by vectorized bisection on the exact
    stroke sqrt((a+b)^2-e^2) - sqrt((b-a)^2-e^2), which increases with a."""
    lo = np.zeros(np.broadcast(rod, offset).shape)
    hi = np.broadcast_to(np.maximum(rod - np.abs(offset), 0.0), lo.shape).copy()
    for _ in range(80):
        a = 0.5 * (lo + hi)
        outer = np.sqrt(np.maximum((a + rod) ** 2 - offset**2, 0.0))
        s = outer - np.sqrt(np.maximum((rod - a) ** 2 - offset**2, 0.0))
        lo, hi = np.where(s < stroke, a, lo), np.where(s < stroke, hi, a)
    return 0.5 * (lo + hi)


def _peak(values, n):
    """Peak over the last axis with parabolic refinement around the dense maximum."""
    i = np.argmax(values, axis=-1)[..., None]
    y0 = np.take_along_axis(values, (i - 1) % n, -1)[..., 0]
    y1 = np.take_along_axis(values, i, -1)[..., 0]
    y2 = np.take_along_axis(values, (i + 1) % n, -1)[..., 0]
    den = y0 - 2 * y1 + y2
    t = np.where(den < 0, 0.5 * (y0 - y2) / np.where(den < 0, den, -1.0), 0.0)
    return y1 - 0.25 * (y0 - y2) * t


def _brute_force(rod_box, off_box, crank_box, pressure_max, n_angles=4096, n=21, levels=9):
    """Minimize the peak slider acceleration over a (rod, offset) grid, the crank eliminated by
    the stroke; zoom the grid around the best feasible point level by level."""
    phi = ms.cycle(n_angles)
    (r0, r1), (e0, e1) = rod_box, off_box
    best = None
    for _ in range(levels):
        rod, off = np.meshgrid(np.linspace(r0, r1, n), np.linspace(e0, e1, n), indexing="ij")
        rod, off = rod.ravel(), off.ravel()
        crank = _crank_for_stroke(rod, off, H)
        ok = (crank >= crank_box[0]) & (crank <= crank_box[1]) & (rod > crank + np.abs(off))
        rod, off, crank = rod[ok], off[ok], crank[ok]
        sc = ms.SliderCrank(crank=crank[:, None], rod=rod[:, None], offset=off[:, None])
        m = sc.motion(phi, speed=SPEED)
        acc = _peak(np.abs(m.slider.acceleration), n_angles)
        press = _peak(m.pressure_angle, n_angles)
        feas = press <= pressure_max
        k = np.flatnonzero(feas)[np.argmin(acc[feas])]
        best = (acc[k], crank[k], rod[k], off[k])
        dr, de = (r1 - r0) / (n - 1), (e1 - e0) / (n - 1)
        r0, r1 = max(rod_box[0], rod[k] - 2 * dr), min(rod_box[1], rod[k] + 2 * dr)
        e0, e1 = max(off_box[0], off[k] - 2 * de), min(off_box[1], off[k] + 2 * de)
    return best


def _offset_problem():
    prob = ms.Problem(
        ms.SliderCrank,
        variables={"crank": (0.01, 0.2), "rod": (0.05, 0.2), "offset": (-0.1, 0.1)},
        speed=SPEED,
    )
    prob.minimize(ob.peak_acceleration("slider"))
    prob.subject_to(ob.stroke("slider") == H, ob.max_pressure_angle() <= ms.deg(30))
    return prob


@pytest.fixture(scope="module")
def offset_result():
    return _offset_problem().solve(starts=6, seed=1)


def test_offset_slider_crank_matches_brute_force(offset_result):
    res = offset_result
    assert res.success, res.report()
    # the peak acceleration is even in the offset: two mirror optima; search offset >= 0
    value, crank, rod, off = _brute_force((0.05, 0.2), (0.0, 0.1), (0.01, 0.2), ms.deg(30))
    assert res.value == pytest.approx(value, rel=1e-5)
    assert res.design.crank == pytest.approx(crank, rel=1e-4)
    assert res.design.rod == pytest.approx(rod, rel=1e-4)
    assert abs(res.design.offset) == pytest.approx(off, rel=1e-4)
    # the pressure-angle limit is active at the optimum
    assert res.constraints[1].value == pytest.approx(ms.deg(30), rel=1e-7)


def test_offset_slider_crank_certified(offset_result):
    c = offset_result.certification
    assert c.certified and c.starts_converged >= 3
    assert c.spread < 1e-6
    for p in c.peaks:
        assert p.gap <= 1e-9
    # the reported value is the true continuous peak at the design (independent dense check)
    m = offset_result.design.motion(ms.cycle(100_000), speed=SPEED)
    dense = np.abs(m.slider.acceleration).max()
    assert dense <= offset_result.value * (1 + 1e-12)
    assert dense == pytest.approx(offset_result.value, rel=1e-8)


def test_slsqp_and_de_agree_with_ipopt(offset_result):
    prob = _offset_problem()
    slsqp = prob.solve(method="slsqp", starts=4, seed=1)
    assert slsqp.success, slsqp.report()
    assert slsqp.value == pytest.approx(offset_result.value, rel=1e-6)
    de = prob.solve(method="de", seed=3, de_options={"maxiter": 150})
    assert de.success, de.report()
    assert de.value == pytest.approx(offset_result.value, rel=1e-6)
    cross = de.certification.cross_check
    # differential evolution alone gets close; the certified polish gets the rest
    assert cross["method"] == "de" and cross["value"] == pytest.approx(de.value, rel=2e-2)


# ------------------------------------------------------------------------------ four-bar
def test_crank_rocker_unit_time_ratio_optimal_transmission():
    """Crank-rocker, swing psi = 40 deg, time ratio 1, ground 1: maximize the minimum
    transmission angle.

    Reference: R. J. Brodell and A. H. Soni, "Design of the crank-rocker mechanism with unit time
    ratio", J. Mechanisms 5 (1970) 1-4. With unit time ratio the crank and coupler are collinear
    with both rocker limit positions on one line through the crank pivot, so (a crank, b coupler,
    c rocker, d ground)

        a = c sin(psi/2),   a^2 + d^2 = b^2 + c^2,   cos(mu_min) = a d / (b c),

    the extreme transmission angles (at crank angles 0 and 180 deg) being supplementary. Hence
    cos(mu_min) = d sin(psi/2) / sqrt(d^2 - c^2 cos^2(psi/2)), which falls as the rocker
    shortens: the optimum in the box has the rocker at its lower bound and mu_min tends to
    90 deg - psi/2 as c/d -> 0.
    """
    psi, d, c_lo = ms.deg(40), 1.0, 0.3
    prob = ms.Problem(
        ms.FourBar,
        variables={"crank": (0.05, 0.5), "coupler": (0.3, 2.0), "rocker": (c_lo, 1.5)},
        fixed={"ground": d},
    )
    prob.maximize(ob.min_transmission_angle())
    prob.subject_to(ob.swing_angle("rocker") == psi, ob.time_ratio() == 1.0)
    res = prob.solve(starts=6)
    assert res.success, res.report()
    # IPOPT's iterations are deterministic (seeded Sobol starts): 111 over the 6 starts (16-20
    # each). A peak's constraint repeated in the unused refinement slots and an uncapped
    # barrier parameter took 345 (28-83 each); the bound leaves room for rounding differences
    # between platforms, not for either of those.
    assert res.certification.total_iterations <= 150, res.certification.iterations
    c = c_lo
    a = c * np.sin(psi / 2)
    b = np.sqrt(d**2 - c**2 * np.cos(psi / 2) ** 2)
    mu = np.arccos(a * d / (b * c))
    assert res.design.rocker == pytest.approx(c, rel=1e-7)
    assert res.design.crank == pytest.approx(a, rel=1e-7)
    assert res.design.coupler == pytest.approx(b, rel=1e-7)
    assert res.value == pytest.approx(mu, rel=1e-8)
    assert res.value < np.pi / 2 - psi / 2
    # the design itself: swing, time ratio and transmission angle by independent analysis
    fb = res.design
    assert fb.swing_angle == pytest.approx(psi, rel=1e-8)
    assert fb.time_ratio == pytest.approx(1.0, abs=1e-8)
    mu_t = fb.motion(ms.cycle(20_000)).transmission_angle
    assert np.minimum(mu_t, np.pi - mu_t).min() == pytest.approx(mu, rel=1e-7)


# ------------------------------------------------------------------------------ failures
def test_unreachable_stroke_is_infeasible_and_named():
    prob = ms.Problem(
        ms.SliderCrank,
        variables={"crank": (0.01, 0.1), "rod": (0.3, 0.5), "offset": (-0.05, 0.05)},
        speed=SPEED,
    )
    prob.minimize(ob.peak_acceleration("slider")).subject_to(ob.stroke("slider") >= 0.5)
    res = prob.solve(starts=3)
    assert not res.success
    assert res.status == "infeasible"
    assert [c.name for c in res.violated] == ["stroke(slider) >= 0.5"]
    assert "stroke(slider) >= 0.5" in res.message
    assert "VIOLATED" in res.report()


def test_conflicting_constraints_are_infeasible():
    # a stroke of 0.1 m needs crank + |offset| >= 0.05 m, so with a rod <= 0.2 m the pressure
    # angle is at least asin(0.05 / 0.2) = 14.5 deg > 10 deg
    prob = ms.Problem(
        ms.SliderCrank,
        variables={"crank": (0.01, 0.2), "rod": (0.05, 0.2), "offset": (-0.1, 0.1)},
        speed=SPEED,
    )
    prob.minimize(ob.peak_acceleration("slider"))
    prob.subject_to(ob.stroke("slider") == H, ob.max_pressure_angle() <= ms.deg(10))
    res = prob.solve(starts=3)
    assert not res.success
    assert res.status == "infeasible"
    assert res.violated
    assert all(c.name in res.message for c in res.violated)


def test_no_valid_start_is_reported():
    # rod always shorter than the crank: no design in the box can turn
    prob = ms.Problem(
        ms.SliderCrank, variables={"crank": (0.3, 0.4), "rod": (0.1, 0.2)}, fixed={"offset": 0.0}
    )
    prob.minimize(ob.peak_velocity("slider"))
    res = prob.solve(starts=2)
    assert not res.success and res.status == "solver_failed"
    assert res.design is None and "no valid start" in res.message


def test_result_reports_solver_iterations():
    import mechsynth as ms
    from mechsynth import objectives as ob

    prob = ms.Problem(ms.SliderCrank, {"crank": (0.02, 0.1), "rod": (0.2, 0.5)}, {"offset": 0.0})
    prob.minimize(ob.peak_acceleration("slider"))
    prob.subject_to(ob.stroke("slider") == 0.1)
    res = prob.solve(starts=2, progress=False)
    c = res.certification
    assert len(c.iterations) == c.starts_run == 2 and all(i > 0 for i in c.iterations)
    assert c.total_iterations == sum(c.iterations) + c.refinement_iterations
    assert c.to_dict()["iterations"] == list(c.iterations)
    assert "solver iterations" in res.report()


def test_an_angle_in_degrees_typed_as_radians_is_refused_with_the_reading_meant():
    """30 (degrees meant) was taken as 30 rad: a pressure-angle limit no design can miss."""
    prob = ms.Problem(
        ms.SliderCrank, variables={"crank": (0.01, 0.2), "rod": (0.05, 0.2), "offset": (0, 0.1)}
    )
    with pytest.raises(ms.MechanismError, match=r"30 rad is more than a turn .* ms.deg\(30\)"):
        prob.subject_to(ob.max_pressure_angle() <= 30)
    prob.subject_to(ob.max_pressure_angle() <= ms.deg(30))  # radians: taken
    with pytest.raises(ms.MechanismError, match=r"'N_guide_angle': bounds 40 rad .*40 deg"):
        ms.Problem(ms.six_link(), variables={"N_guide_angle": (40, 70)})


@pytest.mark.parametrize(
    "call",
    [
        lambda: ms.path_generation(
            np.array([[0, 0], [0.1, 0.05], [0.2, 0.0]]), min_transmission=30
        ),
        lambda: ms.function_generation(
            "log10(x)", (1, 10), input_range=1.0, output_range=1.0, min_transmission=40
        ),
        lambda: parse_quantity("120", "--min-transmission", "rad"),
        lambda: parse_quantity(45.0, "guide", "rad"),
    ],
    ids=["path_generation", "function_generation", "cli-text", "file-number"],
)
def test_angles_beyond_a_turn_are_refused_with_the_degree_reading(call):
    with pytest.raises(ms.MechanismError, match=r"rad is more than a turn .* deg\)"):
        call()


def test_angles_with_a_unit_or_within_a_turn_are_taken():
    assert parse_quantity("120 deg", "a", "rad") == pytest.approx(np.deg2rad(120))
    assert parse_quantity("0.5", "a", "rad") == 0.5
    assert parse_quantity("700", "a", "m") == 700.0  # lengths are not angles
