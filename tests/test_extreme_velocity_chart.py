"""Paper 004 (Dzhavadyan): the m0' erratum of eq. (3) and the reference chart over b/a, e/a."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from mechsynth.kinematics.extreme_velocity import (  # noqa: E402
    extreme_velocity,
    velocity_analog,
    velocity_analog_derivative,
)
from mechsynth.studies.extreme_velocity import (  # noqa: E402
    M0_PRIME_ERRATUM,
    TABLE_1,
    m0,
    m0_derivative,
    printed_acceleration_analog,
    printed_m0_derivative,
    reference_chart,
)

PHI = np.linspace(0.05, 2 * np.pi - 0.05, 97)
DESIGNS = [(2.0, 0.0), (2.0, 0.3), (3.0, -0.8), (4.5, 1.2)]


@pytest.mark.parametrize(("i", "e0"), DESIGNS)
def test_m0_prime_printed_without_its_minus_sign(i, e0):
    # Paper 004, eq. (3), p. 1 of the text: m0' = (e0 + sin phi) cos phi / m0 as printed.
    h = 1e-6
    fd = (m0(PHI + h, i, e0) - m0(PHI - h, i, e0)) / (2 * h)
    np.testing.assert_allclose(m0_derivative(PHI, i, e0), fd, atol=1e-8)
    np.testing.assert_allclose(printed_m0_derivative(PHI, i, e0), -fd, atol=1e-8)
    # the printed m0' is wrong wherever (e0 + sin phi) cos phi is not ~0
    big = np.abs((e0 + np.sin(PHI)) * np.cos(PHI)) > 0.1
    assert np.all(np.abs(printed_m0_derivative(PHI, i, e0) - fd)[big] > 0.01)


@pytest.mark.parametrize(("i", "e0"), DESIGNS)
def test_printed_s0_prime_is_right_with_the_corrected_m0_prime(i, e0):
    h = 1e-6
    fd = (velocity_analog(PHI + h, i, e0) - velocity_analog(PHI - h, i, e0)) / (2 * h)
    right = printed_acceleration_analog(PHI, i, e0, m0_derivative(PHI, i, e0))
    wrong = printed_acceleration_analog(PHI, i, e0, printed_m0_derivative(PHI, i, e0))
    np.testing.assert_allclose(right, fd, atol=1e-8)
    np.testing.assert_allclose(right, velocity_analog_derivative(PHI, i, e0), atol=1e-13)
    assert np.max(np.abs(wrong - fd)) > 0.05


def test_polynomial_4_was_built_with_the_correct_sign():
    # Squaring c m0^3 = -[(c^2 - w u) m0^2 +- w^2 c^2]: the correct sign (+) cancels u^8 and u^7
    # and gives the printed degree 6; the printed m0' (-) would leave a degree-8 polynomial.
    P = np.polynomial.Polynomial
    i, e0 = 3.0, 0.7
    u = P([0.0, 1.0])
    w, c2 = e0 + u, 1 - u * u
    m2 = i * i - w * w
    degrees = {}
    for sign in (1.0, -1.0):
        q = (c2 - w * u) * m2 + sign * w * w * c2
        coef = (c2 * m2**3 - q * q).coef
        degrees[sign] = int(np.flatnonzero(np.abs(coef) > 1e-9 * np.abs(coef).max())[-1])
    assert degrees == {1.0: 6, -1.0: 8}
    assert "minus sign" in M0_PRIME_ERRATUM and "(3)" in M0_PRIME_ERRATUM


@pytest.fixture(scope="module")
def chart():
    return reference_chart()


def test_chart_centric_row_is_table_1(chart):
    # Paper 004, Table 1 (e0 = 0): the chart's bottom row passes through every printed S'_v.
    row = chart["offset"][:, 0] == 0.0
    ratios = chart["ratio"][row][0]
    for ratio, _, s_v, _ in TABLE_1:
        k = int(np.argmin(np.abs(ratios - ratio)))
        assert ratios[k] == pytest.approx(ratio, abs=1e-12)
        assert chart["s_max"][row][0][k] == pytest.approx(s_v, abs=1.02e-7)
        # centric: the return stroke's extreme mirrors the working one
        assert chart["s_min"][row][0][k] == pytest.approx(-s_v, abs=1.02e-7)


def test_chart_against_dense_sampling_and_mirror(chart):
    ok = chart["feasible"]
    assert np.all(np.isnan(chart["s_max"][~ok])) and np.all(np.isfinite(chart["s_max"][ok]))
    assert np.all(chart["ratio"][ok] >= 1 + chart["offset"][ok] + 0.05 - 1e-12)
    rng = np.random.default_rng(7)
    idx = rng.choice(np.flatnonzero(ok.ravel()), 40, replace=False)
    i, e0 = chart["ratio"].ravel()[idx], chart["offset"].ravel()[idx]
    grid = np.linspace(0, 2 * np.pi, 20001)
    s = velocity_analog(grid[None, :], i[:, None], e0[:, None])
    # 20001 samples: the sampled extreme is within (pi/20000)^2 |s0''| / 2 of the true one
    np.testing.assert_allclose(chart["s_max"].ravel()[idx], s.max(axis=1), atol=1e-7)
    np.testing.assert_allclose(chart["s_min"].ravel()[idx], s.min(axis=1), atol=1e-7)
    assert np.all(chart["s_max"].ravel()[idx] >= s.max(axis=1) - 1e-13)
    # e < 0 is the mirror image: max and |min| swap (the chart's note)
    ev = extreme_velocity(1.0, i, e0)  # mechsynth offset +e is the paper's -e
    np.testing.assert_allclose(-ev.minimum.value, -chart["s_min"].ravel()[idx], rtol=1e-12)
    np.testing.assert_allclose(ev.maximum.value, chart["s_max"].ravel()[idx], rtol=1e-12)


@pytest.mark.slow
def test_chart_figure_is_clean(chart, tmp_path, monkeypatch):
    from matplotlib.figure import Figure

    from mechsynth.plotting import layout_problems
    from mechsynth.studies.extreme_velocity import _chart_figure

    found = []
    original = Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        found.extend(layout_problems(self))
        kwargs["dpi"] = 40
        return original(self, fname, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", savefig)
    _chart_figure(tmp_path / "chart.png", chart)
    assert found == []
    assert (tmp_path / "chart.png").stat().st_size > 1000
