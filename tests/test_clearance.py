"""Clearance and interference measures: each against a brute-force evaluation that shares no
code with it, and as an active constraint of a certified solve with a closed-form optimum."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth import objectives as ob

PHI = ms.cycle(2000)


def _dense_segment_distance(p, a, b, k=4001):
    """Distance from points p (2, n) to segments a-b (2, n) by sampling the segments."""
    t = np.linspace(0.0, 1.0, k)[:, None, None]
    pts = a[None] + t * (b - a)[None]
    return np.min(np.hypot(*(pts - p[None]).transpose(1, 0, 2)), axis=0)


def test_point_to_circle_is_the_distance_minus_the_radius():
    sc = ms.SliderCrank(crank=0.1, rod=0.35)
    m = sc.motion(PHI)
    c = ob.clearance("B", circle=("O", "crank")).from_motion(sc, m)
    # B runs on the guide through O: nearest at x = rod - crank, the crank circle's radius 0.1
    assert float(c) == pytest.approx(0.35 - 0.1 - 0.1, abs=1e-12)
    fixed = ob.clearance("B", circle=((0.5, 0.0), 0.02)).from_motion(sc, m)
    assert float(fixed) == pytest.approx(np.min(np.abs(m.points["B"].x - 0.5)) - 0.02, abs=1e-12)


def test_line_through_a_point_clears_a_circle():
    fb = ms.FourBar(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2)
    m = fb.motion(PHI, coupler_points={"P": (2.0, 1.0)})
    c = ob.clearance("P", circle=("O2", 0.5), direction=np.pi / 2).from_motion(fb, m)
    # the vertical line through P against the circle about O2 = (5.2, 0)
    assert float(c) == pytest.approx(np.min(np.abs(m.points["P"].x - 5.2)) - 0.5, abs=1e-12)


def test_point_to_moving_link_against_sampled_segments():
    fb = ms.FourBar(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2)
    m = fb.motion(PHI, coupler_points={"P": (2.0, 1.5)})
    got = ob.clearance("P", segment=("O2", "B")).per_angle(fb, m)
    pt = lambda n: np.array([m.points[n].x, m.points[n].y])  # noqa: E731
    want = _dense_segment_distance(pt("P"), pt("O2"), pt("B"))
    np.testing.assert_allclose(got, want, atol=3.0 / 4000)  # the sampling's resolution


def test_links_that_cross_give_a_negative_separation():
    # the coupler point's arm P-A crosses the rocker O2-B during part of the turn
    fb = ms.FourBar(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2)
    m = fb.motion(PHI, coupler_points={"P": (4.0, -1.0)})
    sep = ob.link_separation(("A", "P"), ("O2", "B")).per_angle(fb, m)
    pt = lambda n: np.array([m.points[n].x, m.points[n].y])  # noqa: E731
    a, p, o2, b = pt("A"), pt("P"), pt("O2"), pt("B")

    def cross(u, v, w):
        return (v[0] - u[0]) * (w[1] - u[1]) - (v[1] - u[1]) * (w[0] - u[0])

    crossing = (cross(a, p, o2) * cross(a, p, b) < 0) & (cross(o2, b, a) * cross(o2, b, p) < 0)
    assert crossing.any() and (~crossing).any()  # the case has both
    assert np.all(sep[crossing] <= 0) and np.all(sep[~crossing] >= 0)
    apart = np.minimum.reduce(
        [
            _dense_segment_distance(a, o2, b),
            _dense_segment_distance(p, o2, b),
            _dense_segment_distance(o2, a, p),
            _dense_segment_distance(b, a, p),
        ]
    )
    np.testing.assert_allclose(np.abs(sep), apart, atol=6.0 / 4000)


def test_a_certified_solve_holds_the_clearance_it_is_given():
    """Shortest rod whose slider B stays 50 mm clear of the crank circle: rod = 2 crank + 0.05
    (B's nearest approach to O is rod - crank), reached with the constraint active."""
    prob = ms.Problem(
        ms.SliderCrank, variables={"rod": (0.2, 1.0)}, fixed={"crank": 0.1, "offset": 0.0}
    )
    prob.minimize(ob.grashof_margin())  # = rod - crank: pushes the rod down to the clearance
    prob.subject_to(ob.clearance("B", circle=("O", "crank")) >= 0.05)
    res = prob.solve(starts=2, progress=False)
    assert res.success, res.report()
    assert res.variables["rod"] == pytest.approx(0.25, rel=1e-6)
    assert res.constraints[0].value == pytest.approx(0.05, abs=1e-7)


def test_bad_arguments_are_named():
    with pytest.raises(ms.MechanismError, match="give one obstacle"):
        ob.clearance("B")
    with pytest.raises(ms.MechanismError, match="radius must be >= 0"):
        ob.clearance("B", circle=("O", -1.0))
    with pytest.raises(ms.MechanismError, match="is an end of the segment"):
        ob.clearance("B", segment=("A", "B"))
    with pytest.raises(ms.MechanismError, match="share a point"):
        ob.link_separation(("A", "B"), ("B", "O2"))
    sc = ms.SliderCrank(crank=0.1, rod=0.35)
    with pytest.raises(ms.MechanismError, match="unknown point 'Z'"):
        ob.clearance("Z", circle=("O", 0.1)).from_motion(sc, sc.motion(PHI))
    with pytest.raises(ms.MechanismError, match="not a parameter of the design"):
        ob.clearance("B", circle=("O", "nope")).from_motion(sc, sc.motion(PHI))


def test_the_measure_stays_callable_after_a_machine_imports_its_module():
    # a submodule named like the lazy public name would replace it on the package (ob.clearance
    # became the module once the impact machine's synthesis was imported)
    import mechsynth.machines.impact.synthesis  # noqa: F401
    import mechsynth.machines.pumping_unit.measures  # noqa: F401

    assert callable(ob.clearance) and callable(ob.link_separation)
