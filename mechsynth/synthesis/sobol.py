"""Scrambled Sobol' points for the solvers' start designs, without importing ``scipy.stats``.

``scipy.stats.qmc.Sobol`` is the reference: importing ``scipy.stats`` takes most of a second,
which was most of a certified solve's time in a new interpreter. :func:`sobol` draws the same
points (bit for bit, tested against scipy): Joe and Kuo's direction numbers from the data file
scipy ships, the left linear matrix scramble and digital shift drawn from
``numpy.random.default_rng(seed)`` in scipy's order, 30 bits, Gray-code order with the first
point (the shift) first. Where the data file is not found, scipy draws them.
"""

from __future__ import annotations

import functools
import importlib.util
import os
import zipfile

import numpy as np

__all__ = ["sobol"]

BITS = 30  # scipy's default


def _data_path():
    """scipy's file of direction numbers, or None when it is not where expected."""
    spec = importlib.util.find_spec("scipy")
    for root in (spec.submodule_search_locations or []) if spec else []:
        path = os.path.join(root, "stats", "_sobol_direction_numbers.npz")
        if os.path.isfile(path):
            return path
    return None


def _leading(zf, name, rows, cols=None):
    """The first ``rows`` rows (and ``cols`` columns) of the array ``name`` of the npz archive
    ``zf``, decompressing only the start of it (all of it is 3 MB, some 7 ms a solve)."""
    fmt = np.lib.format
    with zf.open(name) as fh:
        version = fmt.read_magic(fh)
        read_header = {(1, 0): fmt.read_array_header_1_0, (2, 0): fmt.read_array_header_2_0}
        shape, fortran, dtype = read_header[version](fh)
        if len(shape) == 1:
            return np.frombuffer(fh.read(rows * dtype.itemsize), dtype=dtype)
        n, m = shape
        cols = m if cols is None else min(cols, m)
        if not fortran:  # rows one after another
            return np.frombuffer(fh.read(rows * m * dtype.itemsize), dtype=dtype).reshape(rows, m)
        # columns one after another: the first ``cols`` of them
        flat = np.frombuffer(fh.read(cols * n * dtype.itemsize), dtype=dtype)
        return flat.reshape(cols, n).T[:rows]


@functools.lru_cache(maxsize=32)
def _direction_data(d):
    """``(poly, vinit)`` of the first ``d`` dimensions from scipy's data file (``vinit`` up to
    the largest degree among them), or None when the file is not where expected."""
    path = _data_path()
    if path is None:
        return None
    try:
        with zipfile.ZipFile(path) as zf:
            poly = _leading(zf, "poly.npy", d)
            degree = max(int(p).bit_length() - 1 for p in poly)
            vinit = _leading(zf, "vinit.npy", d, max(degree, 1))
    except (KeyError, ValueError, OSError, zipfile.BadZipFile):  # another layout: all of it
        with np.load(path) as f:
            poly, vinit = f["poly"][:d], f["vinit"][:d]
    if len(poly) < d:
        return None
    return poly, vinit


@functools.lru_cache(maxsize=32)
def _directions(d):
    """The ``d x BITS`` direction numbers, column ``j`` scaled by ``2**(BITS - 1 - j)`` (read
    only), or None without the data file."""
    data = _direction_data(d)
    if data is None:
        return None
    poly, vinit = data
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
    v = np.array(v, dtype=np.uint64) << np.arange(BITS - 1, -1, -1, dtype=np.uint64)
    v.flags.writeable = False
    return v


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
    ours = d >= 1 and isinstance(seed, (int, np.integer, type(None)))
    v = _directions(int(d)) if ours else None
    if v is None:
        from scipy.stats import qmc

        return qmc.Sobol(d=d, scramble=True, seed=seed).random(n)
    shift, v = _scramble(v, np.random.default_rng(seed))
    # point i+1 = point i XOR the direction of the lowest zero bit of i (Gray code)
    i = np.arange(max(n - 1, 0), dtype=np.uint64)
    low0 = np.log2((~i & (i + np.uint64(1))).astype(np.float64)).astype(np.int64)
    steps = v[:, low0].T  # (n - 1, d)
    quasi = np.bitwise_xor.accumulate(np.vstack([shift[None, :], steps]), axis=0)
    return (quasi * (1.0 / 2**BITS))[:n]
