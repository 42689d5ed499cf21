"""Batch kinematics of many four-bars and slider-cranks at once, with an optional compiled path.

:func:`four_bar_batch` and :func:`slider_crank_batch` evaluate a batch of ``n`` designs (parameter
arrays of shape ``(n,)``) at ``m`` crank angles and return ``(n, m)`` arrays of the output link's
(rocker's / slider's) position, velocity and acceleration and of the coupler (rod) angle, angular
velocity and acceleration.

Backends
--------
``"numpy"``
    The model itself: :meth:`FourBar.jets` / :meth:`SliderCrank.jets` (built from
    :mod:`~mechsynth.kinematics.blocks`), evaluated in chunks of designs to bound memory.
``"numba"``
    Compiled kernels (``numba.njit(parallel=True)``, no ``fastmath``, so IEEE semantics are
    kept), one loop over designs (``prange``) and crank angles. The kernels are a scalar
    transcription of the same block formulas (crank + RRR dyad; crank + RRP dyad and
    :func:`~mechsynth.kinematics.blocks.link_angle`), with ``cos``/``sin`` of the link angles
    taken as direction cosines instead of from ``arctan2``; the tests check them against the
    numpy model to 1e-12 on random designs. The crank angles' sines and cosines are computed
    once for the whole batch. The number of threads is numba's (``numba.set_num_threads``).
``"auto"`` (default)
    ``"numba"`` when numba can be imported, else ``"numpy"``.

Both backends validate the designs exactly like the mechanism classes (they construct one
:class:`FourBar` / :class:`SliderCrank` with the parameter arrays) and raise the same
``ValueError`` / ``MechanismError``. Designs that come within round-off of a toggle position or
of losing assembly on the angle grid (possible only with ``full_turn=False``, or with a rod
within 1e-9 of ``crank + |offset|``) are not left to the kernels: the numpy model computes them
and raises its ``MechanismError`` (with the crank angle) where they cannot be assembled.

Examples
--------
>>> import numpy as np
>>> from mechsynth.kinematics.compiled import four_bar_batch
>>> res = four_bar_batch(np.array([1.0, 1.1]), 4.3, 3.0, 5.2, np.linspace(0, 2 * np.pi, 360))
>>> res.rocker_angle.shape
(2, 360)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache

import numpy as np

from .four_bar import FourBar
from .slider_crank import SliderCrank

__all__ = [
    "FourBarBatch",
    "SliderCrankBatch",
    "four_bar_batch",
    "slider_crank_batch",
    "numba_available",
]

_BACKENDS = ("auto", "numpy", "numba")
# designs x angles per numpy chunk: keeps the ~50 temporaries of the model in cache-sized blocks
_NUMPY_CHUNK = 1 << 16
_ASSEMBLY_RTOL = 1e-12  # same round-off allowance as kinematics.blocks


@dataclass(frozen=True)
class FourBarBatch:
    """Four-bar kinematics of ``n`` designs at ``m`` crank angles; every array is ``(n, m)``.

    Angles in rad from +x (rocker O2 -> B, coupler A -> B, in (-pi, pi]); ``*_omega`` in rad/s and
    ``*_epsilon`` in rad/s^2 at constant crank speed, or the analogs (rad/rad, rad/rad^2) when no
    speed was given. ``backend`` is the backend that computed them.
    """

    rocker_angle: np.ndarray
    rocker_omega: np.ndarray
    rocker_epsilon: np.ndarray
    coupler_angle: np.ndarray
    coupler_omega: np.ndarray
    coupler_epsilon: np.ndarray
    backend: str


@dataclass(frozen=True)
class SliderCrankBatch:
    """Slider-crank kinematics of ``n`` designs at ``m`` crank angles; every array is ``(n, m)``.

    Slider position (m, the x of B), velocity (m/s) and acceleration (m/s^2) at constant crank
    speed, or the analogs (m/rad, m/rad^2) without a speed; rod angle (rad, A -> B), its angular
    velocity and acceleration likewise. ``backend`` is the backend that computed them.
    """

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    rod_angle: np.ndarray
    rod_omega: np.ndarray
    rod_epsilon: np.ndarray
    backend: str


@cache
def numba_available() -> bool:
    """True when numba can be imported (the compiled backend is then used by default)."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def _backend(backend: str) -> str:
    if backend not in _BACKENDS:
        raise ValueError(f"backend must be one of {_BACKENDS}, got {backend!r}")
    if backend == "auto":
        return "numba" if numba_available() else "numpy"
    if backend == "numba" and not numba_available():
        raise ModuleNotFoundError(
            "backend='numba' needs numba (pip install numba); use backend='numpy' or 'auto'"
        )
    return backend


def _designs(phi, **params):
    """Parameters as float arrays broadcast to ``(n,)`` and the angles as a float ``(m,)`` array."""
    phi = np.asarray(phi, dtype=float)
    if phi.ndim != 1:
        raise ValueError(f"phi must be a 1-D array of crank angles, got shape {phi.shape}")
    arrays = {k: np.asarray(v, dtype=float) for k, v in params.items()}
    for k, v in arrays.items():
        if v.ndim > 1:
            raise ValueError(f"{k} must be a scalar or a 1-D array of designs, got shape {v.shape}")
    shape = np.broadcast_shapes(*(v.shape for v in arrays.values()), (1,))
    return phi, {k: np.ascontiguousarray(np.broadcast_to(v, shape)) for k, v in arrays.items()}


def _speed(speed):
    if speed is None:
        return 1.0
    w = float(speed)
    if not math.isfinite(w):
        raise ValueError(f"speed must be finite, got {speed!r}")
    return w


# ------------------------------------------------------------------------------- four-bar
def four_bar_batch(
    crank,
    coupler,
    rocker,
    ground,
    phi,
    branch="open",
    full_turn=True,
    speed=None,
    backend="auto",
    out=None,
) -> FourBarBatch:
    """Rocker and coupler kinematics of a batch of four-bars over crank angles ``phi``.

    Parameters
    ----------
    crank, coupler, rocker, ground : link lengths (m), scalars or 1-D arrays of ``n`` designs.
    phi : 1-D array of ``m`` crank angles (rad).
    branch : ``"open"`` or ``"crossed"`` (see :class:`FourBar`), one for the batch.
    full_turn : as in :class:`FourBar`: designs whose crank cannot turn fully raise.
    speed : constant crank speed (rad/s); None gives the analogs.
    backend : ``"auto"``, ``"numpy"`` or ``"numba"`` (see the module docstring).
    out : optional float64 C-contiguous array of shape ``(6, n, m)`` to write into (reuse it
        across calls to save the allocation, which costs as much as the compiled kernel).

    Returns
    -------
    FourBarBatch of ``(n, m)`` arrays (views into ``out`` when given), in the order rocker angle,
    omega, epsilon, coupler angle, omega, epsilon.
    """
    backend = _backend(backend)
    phi, p = _designs(phi, crank=crank, coupler=coupler, rocker=rocker, ground=ground)
    fb = FourBar(**p, branch=branch, full_turn=full_turn)  # validation, with its messages

    def model(rows):
        part = FourBar(
            **{k: v[rows, None] for k, v in p.items()}, branch=branch, full_turn=full_turn
        )
        _, _, cpl, rck = part.jets(phi)
        return (*rck, *cpl)

    out = _output(out, p["crank"].size, phi.size)
    if backend == "numpy":
        _numpy_chunks(model, out)
    else:
        cphi, sphi = np.cos(phi), np.sin(phi)
        a, b, c, d = p["crank"], p["coupler"], p["rocker"], p["ground"]
        _kernels()[0](a, b, c, d, cphi, sphi, float(fb.sigma), out)
        # |AO2|^2 over the grid lies between its values at the largest and smallest cos(phi);
        # designs whose |AO2| comes near |coupler - rocker| or coupler + rocker (toggle, or no
        # assembly) are recomputed by the numpy model, which raises for them if it must.
        rho2_min = a * a + d * d - 2.0 * a * d * cphi.max(initial=-1.0)
        rho2_max = a * a + d * d - 2.0 * a * d * cphi.min(initial=1.0)
        near = (rho2_min <= (b - c) ** 2 * (1 + 1e-9)) | (rho2_max >= (b + c) ** 2 * (1 - 1e-9))
        _numpy_rows(model, np.flatnonzero(near), out)
    return _scaled(FourBarBatch, out, speed, backend)


# ------------------------------------------------------------------------------- slider-crank
def slider_crank_batch(
    crank, rod, offset, phi, speed=None, backend="auto", out=None
) -> SliderCrankBatch:
    """Slider and rod kinematics of a batch of offset slider-cranks over crank angles ``phi``.

    Parameters
    ----------
    crank, rod, offset : crank and rod lengths (m) and guide offset (m), scalars or 1-D arrays
        of ``n`` designs (see :class:`SliderCrank`; the crank must turn fully).
    phi : 1-D array of ``m`` crank angles (rad).
    speed : constant crank speed (rad/s); None gives the analogs.
    backend : ``"auto"``, ``"numpy"`` or ``"numba"``.
    out : optional float64 C-contiguous ``(6, n, m)`` array to write into (see
        :func:`four_bar_batch`).

    Returns
    -------
    SliderCrankBatch of ``(n, m)`` arrays (views into ``out`` when given).
    """
    backend = _backend(backend)
    phi, p = _designs(phi, crank=crank, rod=rod, offset=offset)
    SliderCrank(**p)  # validation, with its messages

    def model(rows):
        _, _, s, rod_jet = SliderCrank(**{k: v[rows, None] for k, v in p.items()}).jets(phi)
        return (*s, *rod_jet)

    out = _output(out, p["crank"].size, phi.size)
    if backend == "numpy":
        _numpy_chunks(model, out)
    else:
        a, b, e = p["crank"], p["rod"], p["offset"]
        _kernels()[1](a, b, e, np.cos(phi), np.sin(phi), out)
        # rods within round-off of crank + |offset| (near a toggle) go to the numpy model
        _numpy_rows(model, np.flatnonzero(b * b - (a + np.abs(e)) ** 2 <= 1e-9 * b * b), out)
    return _scaled(SliderCrankBatch, out, speed, backend)


def _output(out, n, m):
    if out is None:
        return np.empty((6, n, m))
    if not (
        isinstance(out, np.ndarray)
        and out.shape == (6, n, m)
        and out.dtype == np.float64
        and out.flags.c_contiguous
        and out.flags.writeable
    ):
        raise ValueError(
            f"out must be a writeable C-contiguous float64 array of shape {(6, n, m)}, got "
            f"{getattr(out, 'shape', None)} {getattr(out, 'dtype', type(out).__name__)}"
        )
    return out


def _numpy_chunks(model, out):
    """The numpy model over all designs, in chunks of about ``_NUMPY_CHUNK`` evaluations."""
    n, m = out.shape[1:]
    step = max(1, _NUMPY_CHUNK // max(m, 1))
    for i in range(0, n, step):
        rows = slice(i, i + step)
        for j, x in enumerate(model(rows)):
            out[j, rows] = x


def _numpy_rows(model, rows, out):
    """Overwrite the given designs' rows with the numpy model's results."""
    if rows.size:
        for j, x in enumerate(model(rows)):
            out[j, rows] = x


def _scaled(cls, out, speed, backend):
    w = _speed(speed)
    if w != 1.0:
        out[[1, 4]] *= w
        out[[2, 5]] *= w * w
    return cls(*out, backend=backend)


# ------------------------------------------------------------------------------- kernels
# atan on [-tan(pi/8)-ish, 0.66]: the rational approximation of Cephes' atan (S. L. Moshier),
# accurate to a few units in the last place over the reduced range.
_P = (
    -8.750608600031904122785e-1,
    -1.615753718733365076637e1,
    -7.500855792314704667340e1,
    -1.228866684490136173410e2,
    -6.485021904942025371773e1,
)
_Q = (
    2.485846490142306297962e1,
    1.650270098316988542046e2,
    4.328810604912902668951e2,
    4.853903996359136964868e2,
    1.945506571482613964425e2,
)
_MOREBITS = 6.123233995736765886130e-17  # pi/2 - float(pi/2)


@cache
def _kernels():
    """Compile (once per process; cached on disk) the four-bar and slider-crank kernels.

    ``error_model="numpy"`` makes a division by zero give inf/nan instead of raising (the
    designs that could reach one are sent to the numpy model beforehand), which lets LLVM
    vectorize the angle loop. ``atan2`` is written out branch-free (the libm call would not
    vectorize); it agrees with ``numpy.arctan2`` to 2 ulp, away from the signed zeros.
    """
    import numba

    p0, p1, p2, p3, p4 = _P
    q0, q1, q2, q3, q4 = _Q
    more = _MOREBITS
    pio4, pio2, pi = math.pi / 4, math.pi / 2, math.pi
    jit = numba.njit(error_model="numpy", cache=True, inline="always")
    jit_par = numba.njit(error_model="numpy", cache=True, parallel=True)

    @jit
    def atan2(y, x):
        ax, ay = abs(x), abs(y)
        swap = ay > ax
        big = ay if swap else ax
        small = ax if swap else ay
        r = small / (big if big > 0.0 else 1.0)  # in [0, 1]
        red = r > 0.66
        u = (r - 1.0 if red else r) / (r + 1.0 if red else 1.0)
        z = u * u
        p = (((p0 * z + p1) * z + p2) * z + p3) * z + p4
        q = ((((z + q0) * z + q1) * z + q2) * z + q3) * z + q4
        a = u + u * (z * p / q)
        a = (pio4 + (a + 0.5 * more)) if red else a
        a = (pio2 - a + more) if swap else a
        a = (pi - a + 2.0 * more) if x < 0.0 else a
        return -a if y < 0.0 else a

    @jit_par
    def four_bar_kernel(a_, b_, c_, d_, cphi, sphi, sigma, out):
        n, m = a_.shape[0], cphi.shape[0]
        for i in numba.prange(n):
            a, l1, l2, d = a_[i], b_[i], c_[i], d_[i]
            for j in range(m):
                cp, sp = cphi[j], sphi[j]
                # crank pin A (its analogs are (-a sp, a cp) and -A)
                ax, ay = a * cp, a * sp
                # RRR dyad A-B-O2 (blocks.dyad_rrr with p1 = A, p2 = O2 fixed)
                dx, dy = d - ax, -ay
                dd = dx * dx + dy * dy
                frac = (l1 * l1 - l2 * l2 + dd) / (2.0 * dd)
                h2 = l1 * l1 / dd - frac * frac
                h = sigma * math.sqrt(h2 if h2 > 0.0 else 0.0)
                cx = ax + frac * dx - h * dy
                cy = ay + frac * dy + h * dx
                u1x, u1y = cx - ax, cy - ay  # coupler A -> B
                u2x, u2y = cx - d, cy  # rocker O2 -> B
                c1, s1 = u1x / l1, u1y / l1
                c2, s2 = u2x / l2, u2y / l2
                sin21 = s2 * c1 - c2 * s1
                rx, ry = a * sp, -a * cp  # O2' - A'
                w1 = (rx * c2 + ry * s2) / (l1 * sin21)
                w2 = (rx * c1 + ry * s1) / (l2 * sin21)
                rx2 = ax + l1 * w1 * w1 * c1 - l2 * w2 * w2 * c2
                ry2 = ay + l1 * w1 * w1 * s1 - l2 * w2 * w2 * s2
                out[0, i, j] = atan2(u2y, u2x)
                out[1, i, j] = w2
                out[2, i, j] = (rx2 * c1 + ry2 * s1) / (l2 * sin21)
                out[3, i, j] = atan2(u1y, u1x)
                out[4, i, j] = w1
                out[5, i, j] = (rx2 * c2 + ry2 * s2) / (l1 * sin21)

    @jit_par
    def slider_crank_kernel(a_, b_, e_, cphi, sphi, out):
        n, m = a_.shape[0], cphi.shape[0]
        for i in numba.prange(n):
            a, b, e = a_[i], b_[i], e_[i]
            for j in range(m):
                cp, sp = cphi[j], sphi[j]
                ax, ay = a * cp, a * sp
                adx, ady = -a * sp, a * cp
                addx, addy = -ax, -ay
                # RRP dyad on the guide y = e, direction +x, branch +1 (blocks.dyad_rrp)
                hgt = ay - e
                w2 = b * b - hgt * hgt
                w = math.sqrt(w2)
                w_1 = -hgt * ady / w
                w_2 = -(ady * ady + hgt * addy) / w - (hgt * ady) ** 2 / (w * w2)
                s0, s1, s2 = ax + w, adx + w_1, addx + w_2
                # rod angle A -> B (blocks.link_angle)
                ux, uy = s0 - ax, e - ay
                dux, duy = s1 - adx, -ady
                ddux, dduy = s2 - addx, -addy
                r2 = ux * ux + uy * uy
                cross1 = ux * duy - uy * dux
                out[0, i, j] = s0
                out[1, i, j] = s1
                out[2, i, j] = s2
                out[3, i, j] = atan2(uy, ux)
                out[4, i, j] = cross1 / r2
                out[5, i, j] = (ux * dduy - uy * ddux) / r2 - cross1 * 2.0 * (
                    ux * dux + uy * duy
                ) / (r2 * r2)

    return four_bar_kernel, slider_crank_kernel, atan2
