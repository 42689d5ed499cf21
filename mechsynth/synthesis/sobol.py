"""Scrambled Sobol' points for the solvers' start designs, without importing ``scipy.stats``.

``scipy.stats.qmc.Sobol`` is the reference: importing ``scipy.stats`` takes most of a second,
which was most of a certified solve's time in a new interpreter. :func:`sobol` draws the same
points (bit for bit, tested against scipy): Joe and Kuo's direction numbers from the data file
scipy ships, the left linear matrix scramble and digital shift drawn from
``numpy.random.default_rng(seed)`` in scipy's order, 30 bits, Gray-code order with the first
point (the shift) first. Where the data file is not found, scipy draws them.
"""

from __future__ import annotations

import importlib.util
import os

import numpy as np

__all__ = ["sobol"]

BITS = 30  # scipy's default


def _direction_data():
    """``(poly, vinit)`` from scipy's data file, or None when it is not where expected."""
    spec = importlib.util.find_spec("scipy")
    for root in (spec.submodule_search_locations or []) if spec else []:
        path = os.path.join(root, "stats", "_sobol_direction_numbers.npz")
        if os.path.isfile(path):
            with np.load(path) as f:
                return f["poly"], f["vinit"]
    return None


def _directions(d, poly, vinit):
    """The ``d x BITS`` direction numbers, column ``j`` scaled by ``2**(BITS - 1 - j)``."""
    v = [[1] * BITS]
    for k in range(1, d):
        p = int(poly[k])
        m = p.bit_length() - 1
        row = [int(x) for x in vinit[k, :m]] + [0] * (BITS - m)
        for j in range(m, BITS):  # Bratley and Fox's recurrence
            new = row[j - m]
            for i in range(m):
                if (p >> (m - 1 - i)) & 1:
                    new ^= row[j - i - 1] << (i + 1)
            row[j] = new
        v.append(row)
    return np.array(v, dtype=np.uint64) << np.arange(BITS - 1, -1, -1, dtype=np.uint64)


def _scramble(v, rng):
    """Digital shift and left linear matrix scramble of ``v`` (uint64, ``d x BITS``), the random
    bits drawn as scipy draws them."""
    d = v.shape[0]
    shift = rng.integers(2, size=(d, BITS), dtype=np.uint32).astype(np.uint64)
    shift = shift @ (np.uint64(1) << np.arange(BITS, dtype=np.uint64))
    ltm = np.tril(rng.integers(2, size=(d, BITS, BITS), dtype=np.uint32)).astype(np.int64)
    ltm[:, np.arange(BITS), np.arange(BITS)] = 1
    # bit b of each direction number; column k' of ltm's row p multiplies bit BITS-1-k'
    bits = ((v[:, :, None] >> np.arange(BITS - 1, -1, -1, dtype=np.uint64)) & 1).astype(np.int64)
    parity = np.einsum("dpk,djk->djp", ltm, bits) & 1  # output bit BITS-1-p
    scrambled = parity.astype(np.uint64) @ (
        np.uint64(1) << np.arange(BITS - 1, -1, -1, dtype=np.uint64)
    )
    return shift, scrambled


def sobol(d: int, n: int, seed=None) -> np.ndarray:
    """``n`` scrambled Sobol' points in ``[0, 1)^d`` (``n x d``), equal to
    ``scipy.stats.qmc.Sobol(d, scramble=True, seed=seed).random(n)``; ``seed`` an int, None or a
    ``numpy.random.Generator`` (then scipy's draws are matched only for an int or None)."""
    data = _direction_data()
    if data is None or not isinstance(seed, (int, np.integer, type(None))):
        from scipy.stats import qmc

        return qmc.Sobol(d=d, scramble=True, seed=seed).random(n)
    v = _directions(d, *data)
    shift, v = _scramble(v, np.random.default_rng(seed))
    # point i+1 = point i XOR the direction of the lowest zero bit of i (Gray code)
    i = np.arange(max(n - 1, 0), dtype=np.uint64)
    low0 = np.log2((~i & (i + np.uint64(1))).astype(np.float64)).astype(np.int64)
    steps = v[:, low0].T  # (n - 1, d)
    quasi = np.bitwise_xor.accumulate(np.vstack([shift[None, :], steps]), axis=0)
    return (quasi * (1.0 / 2**BITS))[:n]
