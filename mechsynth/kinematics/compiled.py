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
    kept), one loop over designs (``prange``) and crank angles, built from the model itself:
    the chain functions :func:`~mechsynth.kinematics.four_bar.four_bar_chain` and
    :func:`~mechsynth.kinematics.slider_crank.slider_crank_chain` and the blocks they call
    (:func:`~mechsynth.kinematics.blocks.crank_pin`, ``dyad_rrr``, ``dyad_rrp``, ``link_angle``)
    are compiled from their own code with ``ops`` rebound to the scalar
    :mod:`~mechsynth.kinematics.scalar_ops`. There is no second copy of the formulas; the tests
    check the kernels against the numpy model to 1e-12 on random designs. The crank angles'
    sines and cosines are computed once for the whole batch (and remembered for the last grid).
    Batches of fewer than :data:`PARALLEL_MIN` designs x angles run on the calling thread
    (waking the thread pool costs more than it gains on them); larger ones on numba's threads
    (``numba.set_num_threads``). The compiled code is cached on disk, keyed on the model's
    bytecode, so an edited model is recompiled (about 15 s, once; announced in one line).
``"auto"`` (default)
    ``"numba"`` when numba can be imported, else ``"numpy"``.

Both backends validate the designs exactly like the mechanism classes, in a few vectorized
passes over the designs (O(designs), not designs x angles); when a check fails they construct
the :class:`FourBar` / :class:`SliderCrank` with the parameter arrays, which raises the same
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

import contextlib
import dataclasses
import hashlib
import math
import sys
import threading
import types
from dataclasses import dataclass
from functools import cache

import numpy as np

from .. import validate
from ..errors import MechanismError
from . import ops
from .four_bar import FourBar, four_bar_chain
from .slider_crank import SliderCrank, slider_crank_chain
from .tracks import LinkTrack, Motion, SliderTrack

__all__ = [
    "FourBarBatch",
    "SliderCrankBatch",
    "four_bar_batch",
    "slider_crank_batch",
    "numba_available",
    "announce_compilation",
    "PARALLEL_MIN",
    "BatchWorkspace",
    "batch_motion",
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


#: each batch class's array fields in the kernels' output order (for :func:`_scaled`)
_FIELDS = {
    cls: tuple(f.name for f in dataclasses.fields(cls) if f.name != "backend")
    for cls in (FourBarBatch, SliderCrankBatch)
}


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
        raise MechanismError(f"backend must be one of {_BACKENDS}, got {backend!r}")
    if backend == "auto":
        return "numba" if numba_available() else "numpy"
    if backend == "numba" and not numba_available():
        raise ModuleNotFoundError(
            "backend='numba' needs numba (pip install numba); use backend='numpy' or 'auto'"
        )
    return backend


def _designs(phi, **params):
    """Parameters as float arrays broadcast to ``(n,)`` and the angles as a float ``(m,)`` array."""
    phi = np.asarray(validate.angles(phi, "phi"), dtype=float)
    if phi.ndim != 1:
        raise MechanismError(f"phi must be a 1-D array of crank angles, got shape {phi.shape}")
    values = params.values()
    if all(type(v) is float or type(v) is int for v in values):  # one design: no broadcasting
        return phi, {k: np.array([v], dtype=float) for k, v in params.items()}
    arrays = {k: np.asarray(validate.real(k, v), dtype=float) for k, v in params.items()}
    n = 1
    for k, v in arrays.items():
        if v.ndim > 1:
            raise MechanismError(
                f"{k} must be a scalar or a 1-D array of designs, got shape {v.shape}"
            )
        if v.ndim == 1 and v.size != 1:
            if n != 1 and v.size != n:
                sizes = {k: x.shape for k, x in arrays.items()}
                raise MechanismError(f"the parameter arrays do not broadcast together: {sizes}")
            n = v.size
    validate.check_size(f"a batch of {n} designs x {phi.size} crank angles", 6.0 * n * phi.size)
    return phi, {
        k: np.ascontiguousarray(v) if v.size == n and v.ndim == 1 else np.full(n, v.item())
        for k, v in arrays.items()
    }


def _valid_lengths(*lengths) -> bool:
    """True when every entry of the ``(n,)`` arrays is finite and positive: one pass over the
    designs (O(n)); the mechanism class is built (for its exact message) only when not."""
    if len(lengths[0]) == 1:
        return all(math.isfinite(x[0]) and x[0] > 0.0 for x in lengths)
    return all(bool(np.all(x > 0.0)) and bool(np.all(x < np.inf)) for x in lengths)


# Designs x angles below which a batch runs on one thread: waking numba's thread pool costs
# more than it gains on small batches (measured in benchmarks/bench_small_calls.py: on a
# shared two-core machine threads did not gain up to 10,000 designs x 360 angles).
PARALLEL_MIN = 1 << 22


def _speed(speed):
    if speed is None:
        return 1.0
    if type(speed) is float and math.isfinite(speed):
        return speed
    from .. import validate

    return validate.number("speed", speed, "rad/s")


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
    _check_four_bars(p, branch, full_turn)
    sigma = 1.0 if branch == "open" else -1.0

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
        cphi, sphi = ops.cos_sin(phi)
        a, b, c, d = p["crank"], p["coupler"], p["rocker"], p["ground"]
        _kernel("four_bar", a.size * phi.size)(a, b, c, d, cphi, sphi, sigma, out)
        # designs near a toggle or an assembly limit: the numpy model (see _four_bar_near)
        cmax, cmin = cphi.max(initial=-1.0), cphi.min(initial=1.0)
        _numpy_rows(model, _rows(_four_bar_near, p, cmax, cmin), out)
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
    _check_slider_cranks(p)

    def model(rows):
        _, _, s, rod_jet = SliderCrank(**{k: v[rows, None] for k, v in p.items()}).jets(phi)
        return (*s, *rod_jet)

    out = _output(out, p["crank"].size, phi.size)
    if backend == "numpy":
        _numpy_chunks(model, out)
    else:
        a, b, e = p["crank"], p["rod"], p["offset"]
        cphi, sphi = ops.cos_sin(phi)
        _kernel("slider_crank", a.size * phi.size)(a, b, e, cphi, sphi, out)
        _numpy_rows(model, _rows(_slider_crank_near, p), out)
    return _scaled(SliderCrankBatch, out, speed, backend)


def _four_bar_near(a, b, c, d, cmax, cmin):
    """True for four-bars to recompute with the numpy model: |AO2|^2 over the grid lies between
    its values at the largest and smallest cos(phi) (``cmax``, ``cmin``); designs whose |AO2|
    comes near |coupler - rocker| or coupler + rocker (toggle, or no assembly) are recomputed by
    the numpy model, which raises for them if it must."""
    rho2_min = a * a + d * d - 2.0 * a * d * cmax
    rho2_max = a * a + d * d - 2.0 * a * d * cmin
    return (rho2_min <= (b - c) ** 2 * (1 + 1e-9)) | (rho2_max >= (b + c) ** 2 * (1 - 1e-9))


def _slider_crank_near(a, b, e):
    """True for slider-cranks to recompute with the numpy model: rods within round-off of
    crank + |offset| (near a toggle)."""
    return b * b - (a + abs(e)) ** 2 <= 1e-9 * b * b


def _rows(near, p, *grid):
    """The designs (indices) for which ``near(*parameters, *grid)`` holds. One design is tested
    on numbers: numpy's cost per call would be most of a one-design batch's time."""
    if len(p["crank"]) == 1:
        return _ONE if near(*(float(v[0]) for v in p.values()), *grid) else _NONE
    return np.flatnonzero(near(*p.values(), *grid))


_ONE, _NONE = np.zeros(1, dtype=np.intp), np.zeros(0, dtype=np.intp)


def _check_four_bars(p, branch, full_turn):
    """The checks of :class:`FourBar` over the ``(n,)`` parameter arrays in a few vectorized
    passes; the class itself is built (it raises with its message) only if one fails."""
    a, b, c, d = p["crank"], p["coupler"], p["rocker"], p["ground"]
    ok = branch in ("open", "crossed") and _valid_lengths(a, b, c, d)
    if ok and len(a) == 1:  # one design: the same tests on numbers (finite, checked above)
        a, b, c, d = float(a[0]), float(b[0]), float(c[0]), float(d[0])
        if full_turn:
            ok = a + d < b + c and abs(d - a) > abs(b - c)
        else:
            ok = 2 * max(a, b, c, d) < a + b + c + d
    elif ok and full_turn:
        ok = bool(np.all(a + d < b + c)) and bool(np.all(np.abs(d - a) > np.abs(b - c)))
    elif ok:
        longest = np.maximum(np.maximum(a, b), np.maximum(c, d))
        ok = bool(np.all(2 * longest < a + b + c + d))
    if not ok:
        FourBar(**p, branch=branch, full_turn=full_turn)  # raises, naming the condition


def _check_slider_cranks(p):
    """The checks of :class:`SliderCrank` over the ``(n,)`` arrays (as :func:`_check_four_bars`)."""
    a, b, e = p["crank"], p["rod"], p["offset"]
    if len(a) == 1:  # one design: the same tests on numbers
        a, b, e = float(a[0]), float(b[0]), float(e[0])
        ok = 0.0 < a < math.inf and 0.0 < b < math.inf and abs(e) < math.inf and b > a + abs(e)
    else:
        ok = _valid_lengths(a, b) and bool(np.all(np.abs(e) < np.inf))
        ok = ok and bool(np.all(b > a + np.abs(e)))
    if not ok:
        SliderCrank(**p)  # raises, naming the condition


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
        raise MechanismError(
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
        w2 = w * w
        for r, f in ((1, w), (4, w), (2, w2), (5, w2)):  # in place: fancy indexing copies
            out[r] *= f
    # ``cls(*out, backend=backend)`` without the frozen dataclass's ``__init__`` (one
    # ``object.__setattr__`` per field: for one design a good part of the call)
    res = object.__new__(cls)
    res.__dict__.update(zip(_FIELDS[cls], out))
    res.__dict__["backend"] = backend
    return res


# ------------------------------------------------------------------------------- kernels
def _twin(fn, namespace, jit):
    """``fn``'s own code, compiled, with the global names in ``namespace`` rebound."""
    g = dict(fn.__globals__)
    g.update(namespace)
    twin = types.FunctionType(fn.__code__, g, fn.__name__, fn.__defaults__, fn.__closure__)
    twin.__kwdefaults__ = fn.__kwdefaults__
    twin.__doc__ = fn.__doc__
    return jit(twin)


def code_digest(h, code) -> None:
    """Feed ``code`` (bytecode, names, constants, nested code) into the hash ``h``, the same
    in every process: ``marshal.dumps`` of a code object is not (it flags objects by their
    reference counts), which made every new process compile a new kernel."""
    h.update(code.co_code)
    h.update(repr((code.co_names, code.co_varnames, code.co_freevars)).encode())
    for c in code.co_consts:
        if isinstance(c, types.CodeType):
            code_digest(h, c)
        elif isinstance(c, frozenset):  # its order follows the strings' per-process hashes
            h.update(repr(sorted(map(repr, c))).encode())
        else:
            h.update(repr(c).encode())


def _stamp(functions) -> int:
    """A 60-bit digest of the functions' code (bytecode, constants, names)."""
    h = hashlib.sha256()
    for fn in functions:
        code_digest(h, getattr(fn, "py_func", fn).__code__)
    return int(h.hexdigest()[:15], 16)


# The compiled chains and rows live in module globals (set by _kernels): numba keys its on-disk
# cache on the bytecode and the *closure* of a function, so the kernels close over nothing but
# the model's stamp, and a changed model is recompiled instead of loaded stale from the cache.
_FB_CHAIN = _SC_CHAIN = _FB_ROW = _SC_ROW = None


@cache
def _kernels():
    """Compile (once per process, cached on disk) the four-bar and slider-crank kernels.

    The model's chain functions (:func:`four_bar_chain`, :func:`slider_crank_chain`) and the
    blocks they call are compiled from their own code, with ``ops`` rebound to
    :mod:`~mechsynth.kinematics.scalar_ops` and the assembly checks to its no-raise stand-ins:
    there is no second copy of the formulas. ``error_model="numpy"`` makes a division by zero
    give inf/nan instead of raising (the designs that could reach one are sent to the numpy
    model beforehand), which lets LLVM vectorize the loop over crank angles.
    """
    global _FB_CHAIN, _SC_CHAIN, _FB_ROW, _SC_ROW
    import numba

    from . import blocks, scalar_ops

    jit = numba.njit(error_model="numpy", inline="always")
    jit_cached = numba.njit(error_model="numpy", cache=True)
    jit_par = numba.njit(error_model="numpy", parallel=True, cache=True)
    ns = {
        "ops": scalar_ops,
        "_check_nonnegative": scalar_ops.check_nonnegative,
        "_check_toggle": scalar_ops.check_toggle,
        "_failed": scalar_ops.failed,
    }
    # the blocks' own functions (the dyads without their numpy warning guard)
    model = [
        getattr(f, "__wrapped__", f)
        for f in (
            blocks._root,
            blocks.link_angle,
            blocks.crank_pin,
            blocks.rrr_apart,
            blocks.dyad_rrr,
            blocks._rrp_slide,
            blocks.dyad_rrp,
        )
    ]
    for fn in model:
        ns[fn.__name__] = _twin(fn, ns, jit)
    _FB_CHAIN = _twin(four_bar_chain, ns, jit)
    _SC_CHAIN = _twin(slider_crank_chain, ns, jit)
    model += [four_bar_chain, slider_crank_chain]
    model += [v for v in vars(scalar_ops).values() if hasattr(v, "py_func")]
    stamp = _stamp(model)

    # One design's row of angles per call: the chain is inlined into this serial loop (which
    # LLVM vectorizes); the parallel loop over designs only calls it.
    @jit_cached
    def four_bar_row(a, b, c, d, cphi, sphi, sigma, out, i):
        for j in range(cphi.shape[0]):
            _, _, cpl, rck = _FB_CHAIN(cphi[j], sphi[j], a, b, c, d, sigma)
            out[0, i, j], out[1, i, j], out[2, i, j] = rck
            out[3, i, j], out[4, i, j], out[5, i, j] = cpl
        return stamp

    @jit_cached
    def slider_crank_row(a, b, e, cphi, sphi, out, i):
        for j in range(cphi.shape[0]):
            _, _, x, rod = _SC_CHAIN(cphi[j], sphi[j], a, b, e)
            out[0, i, j], out[1, i, j], out[2, i, j] = x
            out[3, i, j], out[4, i, j], out[5, i, j] = rod
        return stamp

    _FB_ROW, _SC_ROW = four_bar_row, slider_crank_row

    @jit_par
    def four_bar_kernel(a, b, c, d, cphi, sphi, sigma, out):
        for i in numba.prange(a.shape[0]):
            _FB_ROW(a[i], b[i], c[i], d[i], cphi, sphi, sigma, out, i)
        return stamp

    @jit_par
    def slider_crank_kernel(a, b, e, cphi, sphi, out):
        for i in numba.prange(a.shape[0]):
            _SC_ROW(a[i], b[i], e[i], cphi, sphi, out, i)
        return stamp

    # the same loops on the calling thread, for batches too small to gain from threads
    @jit_cached
    def four_bar_serial(a, b, c, d, cphi, sphi, sigma, out):
        for i in range(a.shape[0]):
            _FB_ROW(a[i], b[i], c[i], d[i], cphi, sphi, sigma, out, i)
        return stamp

    @jit_cached
    def slider_crank_serial(a, b, e, cphi, sphi, out):
        for i in range(a.shape[0]):
            _SC_ROW(a[i], b[i], e[i], cphi, sphi, out, i)
        return stamp

    kernels = {
        ("four_bar", False): four_bar_serial,
        ("four_bar", True): four_bar_kernel,
        ("slider_crank", False): slider_crank_serial,
        ("slider_crank", True): slider_crank_kernel,
        "atan2": scalar_ops.arctan2,
    }
    # compile (or load from the disk cache) now, on one design at one angle: a compilation
    # (seconds, once per model version) is announced in one line; a cache load is silent
    one, grid, buf = np.ones(1), np.ones(1), np.empty((6, 1, 1))
    dispatchers = [k for key, k in kernels.items() if key != "atan2"]
    what = "the four-bar and slider-crank batch kernels"
    with announce_compilation(what, dispatchers=dispatchers):
        for key, kern in kernels.items():
            if key == "atan2":
                continue
            if key[0] == "four_bar":
                kern(one, 4 * one, 3 * one, 5 * one, grid, 0 * grid, 1.0, buf)
            else:
                kern(one, 3 * one, 0 * one, grid, 0 * grid, buf)
    return kernels


def _kernel(kind: str, evaluations: int):
    """The compiled kernel of ``kind`` for a batch of ``evaluations`` designs x angles: on
    numba's threads when the batch is large enough to gain (:data:`PARALLEL_MIN`), else serial."""
    return _kernels()[kind, evaluations >= PARALLEL_MIN]


@contextlib.contextmanager
def _interrupt_after():
    """Hold a Ctrl-C that lands in one of LLVM's callbacks during a compilation (Python would
    print it as an ignored exception with its traceback, and the compilation would go on) and
    raise it when the block ends."""
    held = []
    previous = sys.unraisablehook

    def hook(unraisable):
        if isinstance(unraisable.exc_value, KeyboardInterrupt):
            held.append(unraisable.exc_value)
        else:
            previous(unraisable)

    sys.unraisablehook = hook
    try:
        yield
    finally:
        sys.unraisablehook = previous
    if held:
        raise KeyboardInterrupt


def cached_on_disk(dispatchers) -> bool | None:
    """True when every numba dispatcher of ``dispatchers`` has a valid entry in its disk cache
    (the next call loads it; numba's index is stale-checked against the source), False when
    one must compile, None when that cannot be told (numba's cache internals changed)."""
    try:
        return all(bool(d._cache._cache_file._load_index()) for d in dispatchers)
    except Exception:  # a private API: no verdict rather than a failure
        return None


@contextlib.contextmanager
def announce_compilation(what: str, after: float = 3.0, dispatchers=()):
    """Print one line to stderr if the block compiles: at once when ``dispatchers`` (numba
    dispatchers the block calls) are not all in the disk cache, never when they are, else if
    the block takes longer than ``after`` seconds; at most once per process and ``what``. A
    slow load from the disk cache on a busy machine is not announced as a compilation. A
    Ctrl-C during the block interrupts it (when it ends, if it lands inside LLVM)."""
    cached = cached_on_disk(dispatchers) if dispatchers else None
    if what in _ANNOUNCED or cached:
        with _interrupt_after():
            yield
        return
    _ANNOUNCED.add(what)
    timer = threading.Timer(
        0.0 if cached is False else after,
        lambda: print(
            f"mechsynth: compiling {what} (once; cached on disk for later runs) ...",
            file=sys.stderr,
            flush=True,
        ),
    )
    timer.daemon = True
    timer.start()
    try:
        with _interrupt_after():
            yield
    finally:
        timer.cancel()


_ANNOUNCED: set[str] = set()


# ------------------------------------------------------------------------------- batch motion
class BatchWorkspace:
    """Reused buffers for :func:`batch_motion`: one ``(8, n, m)`` block (the kernel's six
    outputs and the pressure and transmission angles; a linkage kernel's ``(rows, n, m)``),
    grown when a larger batch asks, never shrunk, so a sweep streaming blocks through it
    allocates its kinematics once."""

    def __init__(self):
        self._buf = np.empty(0)

    def block(self, n: int, m: int, rows: int = 8) -> np.ndarray:
        size = rows * n * m
        if self._buf.size < size:
            self._buf = np.empty(size)
        return self._buf[:size].reshape(rows, n, m)


def _slider_crank_pressure(motion, res, extra):
    """A slider-crank's pressure angle, ``arcsin(|offset - y_A| / rod) = |rod angle|``."""
    return np.abs(res.rod_angle, out=extra[0])


def _slider_crank_transmission(motion, res, extra):
    """A slider-crank's raw transmission angle, the complement of its pressure angle."""
    return np.subtract(np.pi / 2, motion.pressure_angle, out=extra[1])


def _four_bar_transmission(motion, res, extra):
    """A four-bar's raw transmission angle in [0, pi] (``extra[0]`` as scratch)."""
    np.subtract(res.coupler_angle, res.rocker_angle, out=extra[1])
    np.abs(extra[1], out=extra[1])
    np.subtract(2.0 * np.pi, extra[1], out=extra[0])
    return np.minimum(extra[1], extra[0], out=extra[1])


def _four_bar_pressure(motion, res, extra):
    """A four-bar's pressure angle, ``|pi/2 - transmission angle|``."""
    np.subtract(np.pi / 2, motion.raw_transmission_angle, out=extra[0])
    return np.abs(extra[0], out=extra[0])


_ANGLES = {
    SliderCrank: (_slider_crank_pressure, _slider_crank_transmission),
    FourBar: (_four_bar_pressure, _four_bar_transmission),
}


class _OnRead:
    """A field of :class:`_BatchMotion` computed from the kernel's outputs when first read
    (and stored like any field when set, e.g. by ``dataclasses.replace``)."""

    def __set_name__(self, owner, name):
        self.key = "_" + name
        self.which = ("pressure_angle", "raw_transmission_angle").index(name)

    def __get__(self, motion, owner=None):
        if motion is None:
            return self
        d = motion.__dict__
        if self.key not in d:
            kind, res, extra = d["_kernel_outputs"]
            d[self.key] = _ANGLES[kind][self.which](motion, res, extra)
        return d[self.key]

    def __set__(self, motion, value):
        if value is not _PENDING:
            motion.__dict__[self.key] = value


_PENDING = object()  # a _BatchMotion's angle not computed yet


def _fields_of(res, start, stop):
    """The arrays of a batch result's fields ``start`` ... ``stop - 1`` in the kernels' order."""
    return [res.__dict__[f] for f in _FIELDS[type(res)][start:stop]]


class _AtSpeed:
    """A rate of a :func:`batch_motion` track (a velocity or an acceleration), computed by the
    kernel as the crank-angle analog and multiplied in place by the crank speed's ``power``
    the first time it is read: a chart pays only for the rates its measures read."""

    def __init__(self, power):
        self.power = power

    def __set_name__(self, owner, name):
        self.key = "_" + name

    def __get__(self, track, owner=None):
        if track is None:
            return self
        d = track.__dict__
        value = d[self.key]
        if self.key in d["_pending"]:
            d["_pending"].discard(self.key)
            w = d["_speed"]
            value *= w if self.power == 1 else w * w  # a view into the block: scaled there
        return value

    def __set__(self, track, value):
        d = track.__dict__
        d[self.key] = value
        d.setdefault("_pending", set()).discard(self.key)  # a value given: taken as it is


class _LinkAtSpeed(LinkTrack):
    """A :class:`LinkTrack` of :func:`batch_motion` whose rates are scaled on first read
    (:class:`_AtSpeed`); pickled and copied as a plain :class:`LinkTrack`."""

    omega = _AtSpeed(1)
    epsilon = _AtSpeed(2)

    def __reduce__(self):
        return LinkTrack, (self.angle, self.omega, self.epsilon)


class _SliderAtSpeed(SliderTrack):
    """A :class:`SliderTrack` of :func:`batch_motion` whose rates are scaled on first read."""

    velocity = _AtSpeed(1)
    acceleration = _AtSpeed(2)

    def __reduce__(self):
        return SliderTrack, (self.position, self.velocity, self.acceleration)


def _at_speed(cls, first, rate, rate2, speed):
    """A track of ``cls`` whose analogs ``rate``, ``rate2`` are scaled by ``speed`` on first
    read (none when ``speed`` is 1)."""
    track = cls(first, rate, rate2)
    if speed != 1.0:
        d = track.__dict__
        d["_speed"] = speed
        d["_pending"] = {"_" + f.name for f in dataclasses.fields(cls)[1:]}
    return track


class _BatchMotion(Motion):
    """The motion :func:`batch_motion` returns: a :class:`Motion` whose pressure and raw
    transmission angles are computed from the kernel's outputs the first time one of them is
    read, each on its own. A chart whose measures do not read them does not pay for them (a
    slider-crank chart's two passes over a chunk's block, an eighth of its time; the
    pressure angle alone, one). Pickled and copied as a plain :class:`Motion`."""

    pressure_angle = _OnRead()
    raw_transmission_angle = _OnRead()

    def __reduce__(self):
        return Motion, tuple(getattr(self, f.name) for f in dataclasses.fields(Motion))


def batch_motion(mechanism, phi, speed=None, workspace: BatchWorkspace | None = None):
    """The motion of a batch of numeric :class:`SliderCrank` or :class:`FourBar` designs (each
    parameter a number or an ``(n,)`` / ``(n, 1)`` array) on the compiled kernels, or None when
    this mechanism or backend has none (the caller then uses ``mechanism.motion``).

    The :class:`~mechsynth.kinematics.tracks.Motion` holds what the kernels compute -- the
    slider (``sliders["B"]``) or the rocker, the rod or coupler, the crank, the pressure and
    transmission angles -- as ``(n, m)`` views into ``workspace``'s block (valid until its next
    use); it has no point tracks (a measure that asks for one raises ``KeyError`` or
    ``ValueError`` and the caller falls back to the model). The pressure and transmission
    angles are computed, and each velocity and acceleration multiplied by the crank speed, the
    first time it is read (in the block, so read them before its next use): a chart pays for
    what its measures read.
    Values agree with the model to 1e-12 (``tests/test_charts.py``).
    """
    from .tracks import LinkTrack

    kind = type(mechanism)
    if kind not in (SliderCrank, FourBar) or not numba_available():
        return None
    params = {}
    for name in kind.parameters:
        v = getattr(mechanism, name)
        if ops.is_symbolic(v):
            return None
        a = np.asarray(v, dtype=float)
        params[name] = a.reshape(-1) if a.ndim else a
    phi = np.asarray(phi, dtype=float)
    if phi.ndim != 1:
        return None
    n = max(int(np.size(v)) for v in params.values())
    ws = workspace if workspace is not None else BatchWorkspace()
    block = ws.block(n, phi.size)
    out, extra = block[:6], block[6:]
    # the kernels give the analogs; each rate is scaled by the crank speed when first read
    omega = _speed(speed)
    if kind is SliderCrank:
        res = slider_crank_batch(*params.values(), phi, out=out)
        links = {"rod": _at_speed(_LinkAtSpeed, *_fields_of(res, 3, 6), omega)}
        sliders = {"B": _at_speed(_SliderAtSpeed, *_fields_of(res, 0, 3), omega)}
    else:
        res = four_bar_batch(
            *params.values(), phi, branch=mechanism.branch, full_turn=mechanism.full_turn,
            out=out,
        )  # fmt: skip
        links = {
            "coupler": _at_speed(_LinkAtSpeed, *_fields_of(res, 3, 6), omega),
            "rocker": _at_speed(_LinkAtSpeed, *_fields_of(res, 0, 3), omega),
        }
        sliders = {}
    shape = (n, phi.size)
    links["crank"] = LinkTrack(
        np.broadcast_to(phi, shape), np.broadcast_to(omega, shape), np.broadcast_to(0.0, shape)
    )
    motion = _BatchMotion(
        phi=phi,
        omega=omega,
        epsilon=0.0,
        points={},
        links=links,
        pressure_angle=_PENDING,
        sliders=sliders,
        raw_transmission_angle=_PENDING,
    )
    motion.__dict__["_kernel_outputs"] = (kind, res, extra)
    return motion
