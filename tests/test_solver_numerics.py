"""The solvers' own numerics, in place of heavy scipy modules: scipy's scrambled Sobol' start
points drawn without scipy.stats, and the certifier's line search without scipy.optimize."""

import warnings

import numpy as np
import pytest
from scipy.stats import qmc

from mechsynth.synthesis.sobol import sobol


@pytest.mark.parametrize("d", [1, 2, 3, 5, 8, 12, 21])
@pytest.mark.parametrize("seed", [0, 1, 42, 2**31 + 7, None])
def test_points_equal_scipys_bit_for_bit(d, seed):
    for n in (1, 2, 16, 64, 100, 1024):
        ours = sobol(d, n, seed)
        if seed is None:  # unseeded: no two draws alike; check the shape and the range
            assert ours.shape == (n, d) and np.all((ours >= 0) & (ours < 1))
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # scipy warns for n not a power of 2
            ref = qmc.Sobol(d=d, scramble=True, seed=seed).random(n)
        assert ours.dtype == ref.dtype and np.array_equal(ours, ref)


def test_a_generator_seed_is_handed_to_scipy():
    a = sobol(3, 8, np.random.default_rng(5))
    b = qmc.Sobol(d=3, scramble=True, seed=np.random.default_rng(5)).random(8)
    assert np.array_equal(a, b)


def test_balance_of_a_power_of_two():
    # every dyadic interval of length 1/n holds one point per coordinate
    pts = sobol(4, 64, 0)
    for j in range(4):
        assert sorted(np.floor(pts[:, j] * 64).astype(int)) == list(range(64))


def test_the_certifiers_line_search_finds_scipys_minima():
    """certify._local_min (Brent's method, in place of scipy's bounded minimize_scalar): the
    same minima on random smooth functions, interior ones to 1e-12 in the value and the
    angle's tolerance, those at an end of the bracket within sqrt(eps) |x| of it."""
    from scipy.optimize import minimize_scalar

    from mechsynth.synthesis.certify import _local_min

    rng = np.random.default_rng(1)
    interior = 0
    for _ in range(300):
        c = rng.uniform(-1, 1, 4)
        a = rng.uniform(-3, 0)
        b = a + rng.uniform(0.01, 3)

        def f(t, c=c):
            return np.cos(3 * t + c[0]) * c[1] + c[2] * t * t + 0.3 * np.sin(7 * t) * c[3]

        x, fx = _local_min(f, a, b, xatol=1e-11)
        ref = minimize_scalar(f, bounds=(a, b), method="bounded", options={"xatol": 1e-11})
        assert a <= x <= b and fx == f(x)
        edge = 2e-8 * max(1.0, abs(x)) * 3
        if min(x - a, b - x) > edge and min(ref.x - a, b - ref.x) > edge:
            interior += 1
            assert abs(fx - ref.fun) <= 1e-12 * max(1.0, abs(fx))
            assert abs(x - ref.x) <= 1e-6
        else:  # a minimum at an end: both stop within their tolerance of it
            assert abs(fx - ref.fun) <= 1e-6 * max(1.0, abs(fx))
    assert interior > 150
