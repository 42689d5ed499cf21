"""Validation at the door: every bad argument of the public API is a MechanismError (a
ValueError) naming the parameter, its value and the rule; edge numerics stay exact."""

import math
from fractions import Fraction

import numpy as np
import pytest

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth import validate
from mechsynth.errors import UsageError
from mechsynth.kinematics.compiled import four_bar_batch, slider_crank_batch


@pytest.mark.parametrize(
    "value, match",
    [
        ("0.1", r"crank must be a number \(m\), got '0.1' \(a str\)"),
        (b"0.1", "crank must be a number"),
        (True, r"got True \(a bool\)"),
        (None, "crank must be a number"),
        (1 + 1j, "crank must be a real number .*complex"),
        (np.array([0.1 + 0j]), "complex numbers"),
        (np.array(["a"]), "strings"),
        (np.array([], dtype=float), r"crank is empty \(shape \(0,\)\)"),
        ([[0.1], [0.1, 0.2]], "crank must be a number or an array of numbers"),
        (float("nan"), "crank must be finite, got nan"),
        (-1.0, r"crank must be positive \(a length in m\), got -1.0"),
        (np.array([0.1, -0.2])[:, None], r"got -0.2 \(design index \(1, 0\)\)"),
        (1e300, "at most 1e\\+100 m"),
    ],
)
def test_bad_crank_names_the_parameter_and_value(value, match):
    with pytest.raises(ms.MechanismError, match=match):
        ms.SliderCrank(crank=value, rod=3.0)


def test_good_numbers_of_every_real_kind_pass():
    for v in (1, np.float32(0.5), np.int64(1), Fraction(1, 2), 0.25):
        assert ms.SliderCrank(crank=v, rod=3.0).crank == float(v)
    assert validate.real("x", np.array([Fraction(1, 4)], dtype=object))[0] == 0.25


def test_shapes_that_do_not_broadcast_name_each_parameter():
    with pytest.raises(ms.MechanismError, match=r"crank \(2, 3\), rod \(4, 1\)"):
        ms.SliderCrank(crank=np.full((2, 3), 0.1), rod=np.ones((4, 1)))
    with pytest.raises(ms.MechanismError, match="do not broadcast"):
        ms.FourBar(crank=np.full(2, 1.0), coupler=np.full(3, 4.3), rocker=3.0, ground=5.2)


def test_branch_is_checked_even_when_unhashable():
    with pytest.raises(ms.MechanismError, match="branch must be one of 'open', 'crossed'"):
        ms.FourBar(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2, branch=["open"])


def test_non_finite_angles_refused_by_the_model_and_the_batch_kernels():
    sc = ms.SliderCrank(crank=0.1, rod=0.3)
    with pytest.raises(ms.MechanismError, match=r"crank angles must be finite \(rad\), got nan"):
        sc.motion(np.array([0.0, np.nan]))
    with pytest.raises(ms.MechanismError, match="phi must be finite"):
        four_bar_batch(1.0, 4.3, 3.0, 5.2, np.array([0.0, np.nan]))
    with pytest.raises(ms.MechanismError, match="phi must be finite .*inf"):
        slider_crank_batch(0.1, 0.3, 0.0, np.array([0.0, np.inf]))
    with pytest.raises(ms.MechanismError, match="crank angles must be"):
        sc.motion("0")


def test_stroke_is_exact_at_extreme_rod_to_crank_ratios():
    # the plain difference of the dead-centre positions returns 0.0 here
    assert ms.SliderCrank(crank=0.75, rod=1e16).stroke == pytest.approx(1.5, rel=1e-15)
    for ratio in (1e3, 1e6, 1e9, 1e12):
        sc = ms.SliderCrank(crank=0.75, rod=0.75 * ratio, offset=0.1)
        # series: stroke = 2a (1 + e^2 / (2 b^2) + O(b^-4)) for b >> a, e
        b = 0.75 * ratio
        assert sc.stroke == pytest.approx(1.5 * (1 + 0.01 / (2 * b * b)), rel=1e-14)
        assert 1.0 <= sc.time_ratio < 1 + 1e-6
        outer, inner = sc.dead_centres
        assert math.isfinite(outer) and math.isfinite(inner)


def test_stable_stroke_agrees_with_the_difference_where_that_is_accurate():
    a = np.linspace(0.05, 0.1, 7)[:, None]
    sc = ms.SliderCrank(crank=a, rod=0.3, offset=0.02)
    outer, inner = sc.dead_centre_positions
    plain = np.sqrt((0.3 + a) ** 2 - 0.02**2) - np.sqrt((0.3 - a) ** 2 - 0.02**2)
    np.testing.assert_allclose(sc.stroke, plain, rtol=1e-13)
    np.testing.assert_allclose(outer - inner, plain, rtol=1e-13)
    # and against a dense motion
    m = ms.SliderCrank(crank=0.07, rod=0.24, offset=0.01).motion(ms.cycle(200_000))
    span = m.slider.position.max() - m.slider.position.min()
    assert ms.SliderCrank(crank=0.07, rod=0.24, offset=0.01).stroke == pytest.approx(span, 1e-9)


def test_motion_too_large_is_refused_before_allocation():
    cranks = np.full((10**6, 1), 0.1)
    with pytest.raises(ms.MechanismError, match=r"would need about .*iB of memory \(limit 4 GiB\)"):
        ms.SliderCrank(crank=cranks, rod=0.3).motion(ms.cycle(3600))
    with pytest.raises(ms.MechanismError, match="would need about"):
        slider_crank_batch(np.full(10**6, 0.1), 0.3, 0.0, ms.cycle(3600))


def test_structural_requests_fail_when_the_problem_is_built():
    prob = ms.Problem(
        ms.FourBar,
        variables={"crank": (0.1, 0.3), "coupler": (2, 3), "rocker": (2, 3)},
        fixed={"ground": 3.0},
    )
    with pytest.raises(UsageError, match="objective cannot be evaluated.*unknown output 'slider'"):
        prob.minimize(ob.peak_acceleration("slider"))
    with pytest.raises(ms.MechanismError, match="constraint .*unknown output 'Q'"):
        prob.subject_to(ob.peak_velocity("Q") <= 1.0)
    with pytest.raises(ms.MechanismError, match=r"takes the mechanism class \(ms.SliderCrank\)"):
        ms.Problem(ms.SliderCrank(crank=0.1, rod=0.3), variables={"crank": (0.01, 0.1)})


def test_unknown_joint_lists_the_joints():
    from mechsynth.dynamics import kinetostatics, slider_crank_model

    sc = ms.SliderCrank(crank=0.1, rod=0.3)
    res = kinetostatics(slider_crank_model(), sc.motion(ms.cycle(8), speed=10.0))
    with pytest.raises(ms.MechanismError, match="no joint 'R99'.*the joints: "):
        res.magnitude("R99")


@pytest.mark.parametrize(
    "value, lo, hi, match",
    [
        (True, 1, None, "whole number, got True"),
        (2.5, 1, None, "whole number, got 2.5"),
        ("3", 1, None, "whole number"),
        (None, 1, None, "whole number"),
        (0, 1, 10, "between 1 and 10, got 0"),
        (11, 1, 10, "between 1 and 10, got 11"),
        (-1, 0, None, "at least 0"),
    ],
)
def test_integer_rules(value, lo, hi, match):
    with pytest.raises(ms.MechanismError, match=match):
        validate.integer("n", value, lo, hi)
    assert validate.integer("n", 4.0, 1, 10) == 4
    assert validate.integer("n", np.int32(4), 1, 10) == 4


def test_extreme_velocity_up_to_its_stated_ratio_and_a_clear_error_beyond():
    for ratio in (1e3, 1e6):
        sc = ms.SliderCrank(crank=1.0, rod=ratio, offset=0.3)
        ev = sc.extreme_velocity()
        v = sc.motion(ms.cycle(200_000)).slider.velocity
        assert ev.maximum.value == pytest.approx(v.max(), rel=1e-9)
        assert ev.minimum.value == pytest.approx(v.min(), rel=1e-9)
    with pytest.raises(ms.MechanismError, match="rod/crank 1e\\+07 is above 1e\\+06"):
        ms.SliderCrank(crank=1.0, rod=1e7).extreme_velocity()
