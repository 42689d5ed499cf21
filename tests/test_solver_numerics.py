"""The solvers' own numerics, in place of heavy scipy modules: scipy's scrambled Sobol' start
points drawn without scipy.stats, and the certifier's line search without scipy.optimize."""

import warnings

import numpy as np
import pytest
from scipy.stats import qmc

from mechsynth.synthesis.sobol import sobol


@pytest.mark.parametrize("d", [*range(1, 13), 21])
@pytest.mark.parametrize("seed", [0, 1, 42, 2**31 + 7, np.int64(3), None])
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


def test_the_leading_rows_of_an_archived_array(tmp_path):
    # scipy's file holds a 1-D and a Fortran-ordered array; the reader takes C order as well
    import zipfile

    from mechsynth.synthesis.sobol import _leading

    a = np.arange(7 * 5, dtype=np.int64).reshape(7, 5) * 3 - 40
    np.savez_compressed(tmp_path / "x.npz", c=a, f=np.asfortranarray(a), v=a[:, 0])
    with zipfile.ZipFile(tmp_path / "x.npz") as zf:
        for rows in (1, 3, 7):
            assert np.array_equal(_leading(zf, "c.npy", rows), a[:rows])
            assert np.array_equal(_leading(zf, "f.npy", rows), a[:rows])
            assert np.array_equal(_leading(zf, "f.npy", rows, 2), a[:rows, :2])
            assert np.array_equal(_leading(zf, "v.npy", rows), a[:rows, 0])


def test_balance_of_a_power_of_two():
    # every dyadic interval of length 1/n holds one point per coordinate
    pts = sobol(4, 64, 0)
    for j in range(4):
        assert sorted(np.floor(pts[:, j] * 64).astype(int)) == list(range(64))


def test_the_certifiers_line_search_is_scipys_step_for_step():
    """certify._local_min in place of scipy's bounded minimize_scalar: the same minimum, bit for
    bit, on random smooth functions and brackets (wide and down to 1e-6 rad), and the same
    point when the evaluation budget ends the search."""
    from scipy.optimize import minimize_scalar

    from mechsynth.synthesis.certify import _local_min

    rng = np.random.default_rng(1)
    for _ in range(400):
        c = rng.uniform(-1, 1, 4)
        a = np.float64(rng.uniform(-3, 0))
        b = a + 10.0 ** rng.uniform(-6, 0.5)

        def f(t, c=c):
            return np.cos(3 * t + c[0]) * c[1] + c[2] * t * t + 0.3 * np.sin(7 * t) * c[3]

        x, fx = _local_min(f, a, b, xatol=1e-11)
        ref = minimize_scalar(f, bounds=(a, b), method="bounded", options={"xatol": 1e-11})
        assert x == ref.x and fx == ref.fun

    def rough(t):
        return np.sign(t - 0.3) * abs(t - 0.3) ** 0.5 + np.sin(50 * t)

    for budget in (2, 5, 8, 30):  # the last one ends on the tolerance
        x, fx = _local_min(rough, 0.0, 1.0, xatol=1e-30, maxfun=budget)
        ref = minimize_scalar(
            rough, bounds=(0.0, 1.0), method="bounded", options={"xatol": 1e-30, "maxiter": budget}
        )
        assert ref.nfev == min(budget, 13) and x == ref.x and fx == ref.fun
