"""Kinematic measures: values against closed forms, and CasADi derivatives of every smooth
branch against central finite differences of the numpy model."""

import casadi as ca
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth.synthesis.transcription import flatten

W = ms.rpm(600)


# ------------------------------------------------------------------------------ values
def test_centric_slider_crank_closed_forms():
    a, b = 0.05, 0.25  # rod/crank = 5 > 4: peak acceleration at the outer dead centre
    sc = ms.SliderCrank(crank=a, rod=b)
    phi = ms.cycle(7200)
    assert ob.peak_acceleration("slider").evaluate(sc, phi, W) == pytest.approx(
        a * W**2 * (1 + a / b), rel=1e-12
    )
    assert ob.stroke().evaluate(sc) == pytest.approx(2 * a, rel=1e-12)
    assert ob.max_pressure_angle().evaluate(sc, phi) == pytest.approx(np.arcsin(a / b), rel=1e-9)
    assert ob.min_transmission_angle().evaluate(sc, phi) == pytest.approx(
        np.pi / 2 - np.arcsin(a / b), rel=1e-9
    )
    assert ob.time_ratio().evaluate(sc) == pytest.approx(1.0, abs=1e-14)
    assert ob.grashof_margin().evaluate(sc) == pytest.approx(b - a)
    # the crank pin moves on a circle: |v| = a w, |a| = a w^2 at every angle
    assert ob.peak_velocity("A").evaluate(sc, phi, W) == pytest.approx(a * W, rel=1e-12)
    assert ob.peak_acceleration("A").evaluate(sc, phi, W) == pytest.approx(a * W**2, rel=1e-12)


def test_offset_pressure_angle_and_generic_stroke():
    a, b, e = 0.05, 0.2, 0.03
    sc = ms.SliderCrank(crank=a, rod=b, offset=e)
    phi = ms.cycle(8192)  # contains 270 deg, where sin(beta) = (a + e) / b
    assert ob.max_pressure_angle().evaluate(sc, phi) == pytest.approx(np.arcsin((a + e) / b))
    closed = ob.stroke("slider").evaluate(sc)
    assert closed == pytest.approx(np.sqrt((a + b) ** 2 - e**2) - np.sqrt((b - a) ** 2 - e**2))
    # point B's x range over a fine grid: the same stroke without the closed form
    assert ob.stroke("B").evaluate(sc, ms.cycle(200_000)) == pytest.approx(closed, rel=1e-9)
    assert isinstance(ob.stroke("slider").bind(ms.SliderCrank), ob.ScalarMeasure)
    assert isinstance(ob.stroke("B").bind(ms.SliderCrank), ob.Combination)


def test_four_bar_swing_time_ratio_and_peaks():
    fb = ms.FourBar(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2)
    m = fb.motion(ms.cycle(200_000))
    rocker = m.links["rocker"]
    assert ob.swing_angle().evaluate(fb) == pytest.approx(np.ptp(rocker.angle), rel=1e-8)
    assert ob.swing_angle("coupler").evaluate(fb, ms.cycle(200_000)) == pytest.approx(
        np.ptp(m.links["coupler"].angle), rel=1e-9
    )
    assert ob.time_ratio().evaluate(fb) == pytest.approx(fb.time_ratio)
    assert ob.peak_angular_velocity().evaluate(fb, ms.cycle(200_000)) == pytest.approx(
        np.abs(rocker.omega).max()
    )
    assert ob.peak_angular_acceleration().evaluate(fb, ms.cycle(200_000)) == pytest.approx(
        np.abs(rocker.epsilon).max()
    )
    assert ob.grashof_margin().evaluate(fb) == pytest.approx(fb.grashof.margin)


def test_direction_and_errors():
    sc = ms.SliderCrank(crank=0.05, rod=0.2)
    phi = ms.cycle(3600)
    m = sc.motion(phi, speed=W)
    vy = np.abs(m.points["A"].vy).max()
    assert ob.peak_velocity("A", direction=np.pi / 2).evaluate(sc, phi, W) == pytest.approx(vy)
    with pytest.raises(ValueError, match="unknown output 'Z'"):
        ob.peak_velocity("Z").evaluate(sc)
    with pytest.raises(ValueError, match="unknown link"):
        ob.peak_angular_velocity("rocker").evaluate(sc)
    with pytest.raises(ValueError, match="direction"):
        ob.peak_velocity("slider", direction=0.3).evaluate(sc)
    with pytest.raises(ValueError, match="no time ratio"):
        ob.time_ratio().bind(ms.DwellSliderCrank)


def test_measures_compare_into_constraints():
    c = ob.max_pressure_angle() <= ms.deg(30)
    assert c.op == "<=" and c.bound == pytest.approx(np.pi / 6)
    assert c.violation(np.pi / 6 + 0.1) == pytest.approx(0.1)
    combo = 2 * ob.peak_velocity("slider") + 1.0
    sc = ms.SliderCrank(crank=0.05, rod=0.2)
    assert combo.evaluate(sc) == pytest.approx(2 * ob.peak_velocity("slider").evaluate(sc) + 1)


# ------------------------------------------------------------------------------ derivatives
SC_MEASURES = [
    ob.peak_velocity("slider"),
    ob.peak_acceleration("slider"),
    ob.peak_acceleration("B"),
    ob.peak_velocity("A", direction=0.4),
    ob.max_pressure_angle(),
    ob.min_transmission_angle(),
    ob.stroke("slider"),
    ob.stroke("B"),
    ob.time_ratio(),
    ob.grashof_margin(),
    ob.peak_angular_acceleration("rod"),
]
FB_MEASURES = [
    ob.swing_angle("rocker"),
    ob.swing_angle("coupler"),
    ob.time_ratio(),
    ob.min_transmission_angle(),
    ob.max_pressure_angle(),
    ob.peak_angular_velocity("rocker"),
    ob.peak_angular_acceleration("rocker"),
    ob.peak_acceleration("B"),
    ob.grashof_margin(),
]


def _branch_values(cls, params, measure, phi, speed):
    """All smooth branches of all atoms of ``measure`` as one flat vector (numpy or CasADi)."""
    mech = cls(**params)
    motion = mech.motion(phi, speed=speed)
    form = flatten(measure, cls)
    parts = []
    for _, atom in form.terms:
        if atom.kind == "peak":
            parts += [atom.sign * b for b in atom.measure.branches(mech, motion)]
        else:
            parts += list(atom.measure.branches(mech))
    if ops_symbolic(parts):
        return ca.vertcat(*[ca.SX(p) if ca.SX(p).numel() > 1 else ca.SX(p) for p in parts])
    return np.concatenate(
        [np.broadcast_to(np.asarray(p, float), np.shape(p)).ravel() for p in parts]
    )


def ops_symbolic(parts):
    return any(isinstance(p, ca.SX) for p in parts)


def _check_jacobian(cls, names, values, fixed, measure, speed):
    phi = ms.cycle(48)
    x = ca.SX.sym("x", len(names))
    sym = _branch_values(
        cls, {**fixed, **{n: x[i] for i, n in enumerate(names)}}, measure, ca.DM(phi), speed
    )
    jac = ca.Function("j", [x], [ca.jacobian(sym, x)])(values).full()
    val = ca.Function("v", [x], [sym])(values).full().ravel()
    num0 = _branch_values(cls, {**fixed, **dict(zip(names, values))}, measure, phi, speed)
    np.testing.assert_allclose(val, num0, rtol=1e-12, atol=1e-12 * np.abs(num0).max())
    fd = np.empty_like(jac)
    for i in range(len(names)):
        h = 1e-6 * max(abs(values[i]), 1e-3)
        up, dn = list(values), list(values)
        up[i] += h
        dn[i] -= h
        fu = _branch_values(cls, {**fixed, **dict(zip(names, up))}, measure, phi, speed)
        fl = _branch_values(cls, {**fixed, **dict(zip(names, dn))}, measure, phi, speed)
        fd[:, i] = (fu - fl) / (2 * h)
    scale = np.abs(fd).max() + 1e-300
    np.testing.assert_allclose(jac, fd, rtol=1e-5, atol=1e-6 * scale)


@pytest.mark.parametrize("measure", SC_MEASURES, ids=lambda m: m.name)
def test_slider_crank_derivatives(measure):
    _check_jacobian(ms.SliderCrank, ["crank", "rod", "offset"], [0.05, 0.21, 0.017], {}, measure, W)


@pytest.mark.parametrize("measure", FB_MEASURES, ids=lambda m: m.name)
def test_four_bar_derivatives(measure):
    names = ["crank", "coupler", "rocker", "ground"]
    _check_jacobian(ms.FourBar, names, [1.0, 4.3, 3.0, 5.2], {}, measure, 2.0)


@settings(max_examples=25, deadline=None)
@given(
    crank=st.floats(0.02, 0.1),
    ratio=st.floats(2.5, 6.0),
    off=st.floats(-0.5, 0.5).filter(lambda v: abs(v) > 1e-3),
)
def test_slider_crank_derivatives_random_designs(crank, ratio, off):
    # (a zero offset puts the kink of |pressure angle| = 0 on grid angles 0 and 180 deg; the
    # kink is never at the peak, so the epigraph does not see it)
    rod = ratio * crank
    offset = off * (rod - crank)
    # the pressure angle is zero where the crank pin is at the guide's height, a kink of its
    # absolute value: a design that puts it on a grid angle has no derivative there
    assume(np.min(np.abs(crank * np.sin(ms.cycle(48)) - offset)) > 1e-6 * crank)
    _check_jacobian(
        ms.SliderCrank,
        ["crank", "rod", "offset"],
        [crank, rod, offset],
        {},
        ob.peak_acceleration("slider") + ob.max_pressure_angle() + ob.stroke(),
        W,
    )


def test_a_bound_signed_peak_is_the_maximum_of_its_magnitude_bit_for_bit():
    """A slider's or a direction's peak, bound to a class, reads ``max(max c, -min c)`` of the
    signed values: the same bits as ``max |c|`` (NaN kept), without a temporary of ``|c|``."""
    sc = ms.SliderCrank(crank=np.array([[0.05], [0.04], [0.03]]), rod=0.2, offset=0.01)
    m = sc.motion(ms.cycle(360), speed=W)
    m.slider.acceleration[1, 7] = np.nan  # a design whose peak is not a number stays so
    for measure, c in (
        (ob.peak_velocity("slider"), m.slider.velocity),
        (ob.peak_acceleration("slider"), m.slider.acceleration),
        (ob.peak_velocity("A", direction=0.3), m.points["A"].along(0.3)[0]),
    ):
        bound = measure.bind(ms.SliderCrank)
        assert type(bound).__name__ == "_SignedPeak"
        got = bound.from_motion(sc, m)
        np.testing.assert_array_equal(got, np.abs(c).max(axis=-1), strict=True)
        np.testing.assert_array_equal(got, measure.from_motion(sc, m), strict=True)
    assert np.isnan(ob.peak_acceleration("slider").bind(ms.SliderCrank).from_motion(sc, m)[1])
