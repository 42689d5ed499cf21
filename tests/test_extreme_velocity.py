"""Paper 004 (Dzhavadyan): extreme slider velocities of the offset slider-crank."""

import json

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

import mechsynth as ms
from mechsynth.cli import main
from mechsynth.kinematics.extreme_velocity import (
    extreme_velocity,
    polynomial_coefficients,
    printed_coefficients,
    stroke_crank_angle,
    velocity_analog,
    velocity_analog_derivative,
)
from mechsynth.studies.extreme_velocity import TABLE_1, run
from mechsynth.units import dms

ARCMIN = np.deg2rad(1.0 / 60.0)
ARCSEC = np.deg2rad(1.0 / 3600.0)
#: S'_v agrees with the print to one unit of its 7th decimal (largest: 1.011e-7 at b/a = 2.00)
S_V_TOL = 1.02e-7
MISPRINTED_ANGLE_ROWS = {5.25}  # printed 79°31'14"; s0 there is 1.0180004, not the printed S'_v


def _numeric(sc, sign):
    """(angle, value) of the max (sign=+1) or min (sign=-1) of dx_B/dphi, dense + bounded search."""
    grid = np.linspace(0, 2 * np.pi, 4001)
    v = sc.motion(grid).slider.velocity
    k = int(np.argmax(sign * v))

    def f(p):
        return -sign * float(sc.motion(np.array(p)).slider.velocity)

    res = minimize_scalar(
        f, bounds=(grid[k - 1], grid[k + 1]), method="bounded", options={"xatol": 1e-12}
    )
    return np.mod(res.x, 2 * np.pi), -sign * res.fun


@pytest.mark.parametrize(("ratio", "angle", "s_v", "lambda_s"), TABLE_1)
def test_table_1_row(ratio, angle, s_v, lambda_s):
    # Source: Dzhavadyan, paper 004, Table 1 (e0 = 0, a = 1); S'_v to one unit of the 7th
    # decimal (1.02e-7), phi0 to 20 arc-seconds (the misprinted row apart).
    ev = ms.SliderCrank(crank=1.0, rod=ratio).extreme_velocity()
    assert -ev.minimum.value == pytest.approx(s_v, abs=S_V_TOL)
    assert ev.maximum.value == pytest.approx(s_v, abs=S_V_TOL)  # centric: symmetric extremes
    deviation = abs(ev.minimum.angle - dms(*angle))
    if ratio in MISPRINTED_ANGLE_ROWS:
        # Misprint: the printed angle is inconsistent with the printed S'_v itself.
        assert deviation > 3 * ARCMIN
        assert abs(velocity_analog(dms(*angle), ratio, 0.0) - s_v) > 3e-7
        assert velocity_analog(ev.minimum.angle, ratio, 0.0) == pytest.approx(s_v, abs=1e-7)
    else:
        assert deviation < 20 * ARCSEC
    assert ev.maximum.angle == pytest.approx(2 * np.pi - ev.minimum.angle, abs=1e-12)
    # lambda_s by (6) with phi_u = pi and S_u = 2 (centric); published column differs (errata).
    assert ev.minimum.lambda_s == pytest.approx(s_v * np.pi / 2, abs=2e-6)


def test_lambda_s_erratum_two():
    # Seeds README: lambda = 2.00 gives 1.7643, not the printed 1.7751.
    ev = ms.SliderCrank(crank=1.0, rod=2.0).extreme_velocity()
    assert ev.minimum.lambda_s == pytest.approx(1.7643, abs=5e-5)
    assert abs(ev.minimum.lambda_s - 1.7751467) > 0.01


@pytest.mark.parametrize(
    ("a", "b", "e"),
    [(1.0, 2.0, 0.3), (0.1, 0.35, -0.05), (1.0, 3.0, 1.5), (2.0, 9.0, -4.0), (1.0, 1.3, 0.2)],
)
def test_offset_extremes_match_numeric_search(a, b, e):
    sc = ms.SliderCrank(crank=a, rod=b, offset=e)
    ev = sc.extreme_velocity()
    for ext, sign in ((ev.maximum, 1.0), (ev.minimum, -1.0)):
        angle, value = _numeric(sc, sign)
        assert ext.value == pytest.approx(value, rel=1e-10, abs=1e-12 * a)
        assert abs(np.angle(np.exp(1j * (ext.angle - angle)))) < 1e-5
        # The acceleration analog vanishes there.
        acc = sc.motion(np.array(ext.angle)).slider.acceleration
        assert abs(acc) < 1e-8 * a


def test_batch_equals_single_designs():
    rng = np.random.default_rng(4)
    a = rng.uniform(0.5, 1.5, 20)
    e = rng.uniform(-1.0, 1.0, 20)
    b = a + np.abs(e) + rng.uniform(0.2, 4.0, 20)
    batch = extreme_velocity(a, b, e)
    for k in range(20):
        one = ms.SliderCrank(a[k], b[k], e[k]).extreme_velocity()
        assert batch.maximum.value[k] == pytest.approx(one.maximum.value, rel=1e-13)
        assert batch.minimum.angle[k] == pytest.approx(one.minimum.angle, abs=1e-12)


def test_polynomial_vanishes_at_the_numeric_extrema():
    # The derived polynomial has sin(phi0) as a root for every extremum, and the printed one
    # does not (for e0 != 0): this is the erratum in eq. (4).
    for i, e0 in [(2.0, 0.3), (3.0, -0.8), (5.0, 2.0)]:
        sc = ms.SliderCrank(1.0, i, -e0)
        for sign in (1.0, -1.0):
            angle, _ = _numeric(sc, sign)
            u = np.sin(angle)
            derived = np.polyval(polynomial_coefficients(i, e0), u)
            printed = np.polyval(printed_coefficients(i, e0), u)
            scale = np.polyval(np.abs(polynomial_coefficients(i, e0)), 1.0)
            assert abs(derived) < 1e-8 * scale
            assert abs(printed) > 1e-3 * scale


def test_polynomial_is_the_squared_extremum_condition():
    # Rebuild the polynomial independently: c^2 m^6 - P^2 with P from the derivative (3).
    P = np.polynomial.Polynomial
    for i, e0 in [(2.0, 0.0), (3.0, 0.7), (4.5, -1.2)]:
        u = P([0.0, 1.0])
        w = e0 + u
        m2 = i * i - w * w
        c2 = 1 - u * u
        q = c2 * m2 - w * u * m2 + w * w * c2
        built = c2 * m2**3 - q * q
        coef = built.coef[::-1]  # highest power first, degree 6 after cancellation
        coef = coef[np.argmax(np.abs(coef) > 1e-12 * np.abs(coef).max()) :]
        assert coef.size == 7
        np.testing.assert_allclose(-coef, polynomial_coefficients(i, e0), rtol=1e-12, atol=1e-9)


def test_centric_polynomial_reduces_to_the_printed_cubic():
    # Paper 004: for e0 = 0, sin^6 - i^2 sin^4 - i^4 sin^2 + i^4 = 0 (times 1 - i^2).
    i = 2.7
    expected = (1 - i * i) * np.array([1, 0, -(i**2), 0, -(i**4), 0, i**4])
    np.testing.assert_allclose(polynomial_coefficients(i, 0.0), expected, rtol=1e-14)
    np.testing.assert_allclose(printed_coefficients(i, 0.0), expected, rtol=1e-14)


def test_acceleration_analog_formula_matches_finite_differences():
    phi = np.linspace(0.1, 6.2, 50)
    h = 1e-6
    for i, e0 in [(2.0, 0.3), (4.0, -1.0)]:
        fd = (velocity_analog(phi + h, i, e0) - velocity_analog(phi - h, i, e0)) / (2 * h)
        np.testing.assert_allclose(velocity_analog_derivative(phi, i, e0), fd, atol=1e-8)
        # and the paper's s0 is -(dx_B/dphi)/a with offset = -e
        sc = ms.SliderCrank(1.0, i, -e0)
        np.testing.assert_allclose(
            -sc.motion(phi).slider.velocity, velocity_analog(phi, i, e0), atol=1e-14
        )


def test_stroke_crank_angle_formula_7_matches_dead_centres():
    for a, b, e in [(1.0, 3.0, 0.5), (1.0, 3.0, -0.5), (0.2, 0.5, 0.1), (1.0, 4.0, 0.0)]:
        sc = ms.SliderCrank(a, b, e)
        longer = max(sc.crank_spans)
        assert stroke_crank_angle(a, b, e) == pytest.approx(longer, abs=1e-12)


@pytest.mark.slow
def test_study_rows_and_errata(tmp_path):
    result = run(out=tmp_path)
    assert len(result.data["rows"]) == len(TABLE_1)
    assert all(abs(r["S_v_deviation"]) < 1e-6 for r in result.data["rows"])
    assert 2.0 in result.data["lambda_s_errata_rows"]
    assert any("5.25" in e and "phi0" in e for e in result.errata)
    assert any("p3" in e for e in result.errata)
    assert any("eq. (3)" in e and "minus sign" in e for e in result.errata)
    assert result.data["reference_chart"]["feasible_points"] > 5000
    names = ("table1.csv", "offset_check.csv", "velocity_analogs.png")
    for name in names + ("extreme_velocity_chart.png", "extreme_velocity_chart.csv"):
        assert (tmp_path / name).stat().st_size > 500
    assert all(o["derived_vs_numeric"] < 1e-12 for o in result.data["offset_check"])
    # the paper's chart as an alignment chart too, its reading error measured against the model
    for extreme in ("max", "min"):
        assert (tmp_path / f"nomogram_extreme_velocity_{extreme}.pdf").stat().st_size > 5000
        assert result.data["nomograms"][extreme]["max_error"] < 0.01
    assert "Nomogram of the maximum velocity analog" in result.summary


def test_study_cli_json(capsys):
    assert main(["study", "run", "extreme-velocity", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert [r["lambda"] for r in data["rows"]] == [row[0] for row in TABLE_1]
    assert data["errata"]
    assert any("eq. (3)" in e and "minus sign" in e for e in data["errata"])
    assert data["reference_chart"]["feasible_points"] > 5000
    assert data["coverage"]["study"] == "extreme-velocity"
