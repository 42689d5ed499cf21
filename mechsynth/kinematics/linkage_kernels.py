"""Compiled kernels for general linkages, generated from the model itself.

A :class:`~mechsynth.kinematics.linkage.Linkage` is solved by Python code that walks its groups
and calls the blocks (:mod:`~mechsynth.kinematics.linkage_groups`,
:mod:`~mechsynth.kinematics.blocks`). For a big batch of designs this module turns that very
solve into one compiled function:

1. the linkage's strict solve is traced once on CasADi symbols -- the input (crank angle or
   driving slider's displacement) and every parameter -- which records its arithmetic as a
   straight-line list of instructions (the same trace an optimizer differentiates; the
   symbolic "hold" of groups that cannot close is off, so the trace is the numeric model's:
   NaN where a group cannot close, inf at a toggle);
2. the instructions become straight-line code (:func:`_program`) with the parameter-only part
   hoisted out of the loop over inputs and sines and cosines resolved without libm, written
   out by one of two code generators of the same trace:

   * **C** (:func:`_c_source`): one function over a range of designs and every input, compiled
     by the machine's C compiler (``-O2``, vectorized for this processor, fused multiply-adds;
     no ``-ffast-math``: see :data:`C_FLAGS`) into a shared library loaded with ctypes. A
     six-bar compiles in 0.2-0.6 s of the compiler's CPU time (1-2 s wall on a busy
     machine), and a later process loads it in milliseconds, without numba;
   * **numba** (:func:`_source`): a numba function of one design, its transcendental functions
     those of :mod:`~mechsynth.kinematics.scalar_ops` (as the four-bar and slider-crank
     kernels), compiled with numba's disk cache (a six-bar in 6-8 s of CPU, most of it numba's
     typing and LLVM; a later process loads it in some 0.05 s after numba's own start, 0.5-2 s
     once per process);

   which one: :func:`kernel_backend` -- ``$MECHSYNTH_KERNELS`` = ``c``, ``numba`` or ``auto``
   (the default: C when a compiler is found -- ``$MECHSYNTH_CC``, else ``cc`` or ``gcc`` on
   the PATH -- else numba; neither: no kernels, the model serves). Both give every output
   within 1e-12 of the model (the tests run on both);
3. the source is written to the cache directory (:func:`cache_dir`) under the digest of its
   text (the C library under the digest of its text, compiler, flags and processor, with the
   digest of its bytes beside it: a damaged library is built again), and recorded under the
   structure's key so that a later process finds it without tracing.
   ``linkage_kernel(..., wait=False)`` builds it in a background thread while the caller goes
   on with the model (a few milliseconds to return).

The loop is compiled with fused multiply-adds as its only value-changing optimization (numba's
fast-math flag ``contract``: see :data:`_FASTMATH`; ``-ffp-contract=fast`` for C); the finite
test is a sum of the outputs, ``t - t``.

The kernel computes every output of :meth:`Linkage.motion` -- each point's, link's and slider's
jet, each group's pressure and transmission angles and assembly margin, the followers' extra
quantities -- into one ``(outputs, designs, inputs)`` block, and two numbers per design that
say whether the model must look at it: whether every output was finite, and the smallest
assembly margin. Only the structure matters (which groups, branches and parameter names); the
values are the kernel's inputs. Tests check the kernels against ``Linkage.motion`` to 1e-12.
A kernel of the points alone (``outputs="points"``) writes the points' jets and the same two
numbers per design (its margins reduced, not stored): :func:`linkage_batch` makes a motion of
the points' tracks of it.

Linkages with a cam follower get no kernel (None), nor do those whose trace holds an operation
the generator does not know; the callers then use the model. (A follower's contact is found by a
fixed number of Newton steps from sampled profile points: paper 001's five-link traces to about
3,400 lines, which numba took 93 s to compile -- more than the model needs for any chart.)
"""

from __future__ import annotations

import contextlib
import ctypes
import dataclasses
import functools
import hashlib
import importlib.util
import math
import os
import sys
import tempfile
import threading
from dataclasses import dataclass
from operator import itemgetter
from pathlib import Path

import numpy as np

from ..errors import MechanismError
from . import ops
from .linkage_groups import _State
from .mechanism import MAX_SPEED, speed_pair
from .ops import cos_sin
from .tracks import (
    Jet,
    LinkTrack,
    Motion,
    PointJet,
    PointTrack,
    SliderTrack,
    _Links,
    _Points,
    _Sliders,
)

__all__ = [
    "LinkageKernel",
    "linkage_kernel",
    "kernel_pending",
    "is_compiled",
    "cache_dir",
    "linkage_batch",
    "kernel_backend",
    "c_compiler",
    "held_kernel",
]

# casadi operation -> Python expression over the inputs {0}, {1} (scalar_ops as ``so``)
_FORMS = {
    "OP_ADD": "{0} + {1}",
    "OP_SUB": "{0} - {1}",
    "OP_MUL": "{0} * {1}",
    "OP_DIV": "{0} / {1}",
    "OP_NEG": "-{0}",
    "OP_SQ": "{0} * {0}",
    "OP_TWICE": "{0} + {0}",
    "OP_INV": "1.0 / {0}",
    "OP_SQRT": "so.sqrt({0})",
    "OP_SIN": "so.sin({0})",
    "OP_COS": "so.cos({0})",
    "OP_TAN": "so.tan({0})",
    # arcsin and arccos through the branch-free arctan2 (NaN outside [-1, 1] as theirs)
    "OP_ASIN": "so.arctan2({0}, so.sqrt(1.0 - {0} * {0}))",
    "OP_ACOS": "so.arctan2(so.sqrt(1.0 - {0} * {0}), {0})",
    "OP_ATAN": "math.atan({0})",
    "OP_ATAN2": "so.arctan2({0}, {1})",
    "OP_FABS": "so.fabs({0})",
    "OP_FMIN": "so.fmin({0}, {1})",
    "OP_FMAX": "so.fmax({0}, {1})",
    "OP_HYPOT": "so.hypot({0}, {1})",
    "OP_EXP": "math.exp({0})",
    "OP_LOG": "math.log({0})",
    "OP_POW": "{0} ** {1}",
    "OP_CONSTPOW": "{0} ** {1}",
    "OP_FLOOR": "math.floor({0})",
    "OP_CEIL": "math.ceil({0})",
    "OP_FMOD": "math.fmod({0}, {1})",
    "OP_SIGN": "(1.0 if {0} > 0.0 else (-1.0 if {0} < 0.0 else 0.0))",
    "OP_COPYSIGN": "math.copysign({0}, {1})",
    "OP_LT": "(1.0 if {0} < {1} else 0.0)",
    "OP_LE": "(1.0 if {0} <= {1} else 0.0)",
    "OP_EQ": "(1.0 if {0} == {1} else 0.0)",
    "OP_NE": "(1.0 if {0} != {1} else 0.0)",
    "OP_NOT": "(1.0 if {0} == 0.0 else 0.0)",
    "OP_AND": "(1.0 if {0} != 0.0 and {1} != 0.0 else 0.0)",
    "OP_OR": "(1.0 if {0} != 0.0 or {1} != 0.0 else 0.0)",
    "OP_IF_ELSE_ZERO": "({1} if {0} != 0.0 else 0.0)",
}


def cache_dir() -> Path:
    """Where generated kernels are kept: ``$MECHSYNTH_CACHE_DIR``, else the user's cache
    directory (``$XDG_CACHE_HOME`` or ``~/.cache``) ``/mechsynth``, else a temporary one."""
    env = os.environ.get("MECHSYNTH_CACHE_DIR")
    if env:
        base = Path(env)
    else:
        base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "mechsynth"
    for d in (base / "linkage_kernels", Path(tempfile.gettempdir()) / "mechsynth_kernels"):
        try:
            d.mkdir(parents=True, exist_ok=True)
            if os.access(d, os.W_OK):
                return d
        except OSError:
            continue
    raise OSError("no writable directory for mechsynth's compiled linkage kernels")


@dataclass(frozen=True)
class LinkageKernel:
    """A compiled linkage structure.

    Attributes
    ----------
    names : the parameters, in the order of the kernel's parameter matrix's columns.
    layout : ``(kind, key, offset, size)`` per output of the solve: ``kind`` one of
        ``"points"`` (6 rows: x, y and their first and second analogs), ``"links"``,
        ``"sliders"`` (3 rows: value and analogs), ``"pressure"``, ``"transmission"``,
        ``"margins"``, ``"extra"`` (1 row).
    outputs : the number of rows.
    source : the generated source (Python for numba, C for the C compiler).
    serial, parallel : numba's dispatchers of the loop over designs on the calling thread and
        on numba's threads; for C, the loaded function (``kernel(n, m, lo, hi, ...)``) and None.
    backend : ``"c"`` or ``"numba"`` (:func:`kernel_backend`).
    kinds : ``"all"`` (every output of the motion) or ``"points"`` (the points' jets alone:
        pylinkage's kinematics, a path's; the flags as the full kernel's).
    once : the rows the kernel writes in the first column alone (``out[r, :, 0]``): those
        that do not vary with the input, in a kernel of the points alone (its ground points';
        a reader broadcasts them along the inputs, as :func:`linkage_batch` does); () for a
        kernel of every output, which writes every row whole.
    """

    names: tuple
    layout: tuple
    outputs: int
    source: str
    serial: object
    parallel: object
    backend: str = "numba"
    kinds: str = "all"
    once: tuple = ()

    def __call__(
        self, params: np.ndarray, phi: np.ndarray, out=None, flags=None, threads=None, speed=None
    ):
        """Evaluate ``params`` (``(n, len(names))``) at the inputs ``phi`` (``(m,)``) into
        ``out`` (``(outputs, n, m)``) and ``flags`` (``(n, 2)``: per design 0 where every
        output is finite (else NaN) and its smallest assembly margin). ``threads`` None: the
        cores' threads (numba's, or two or more threads of the C loop) for batches of at least
        :data:`~mechsynth.kinematics.compiled.PARALLEL_MIN` evaluations. ``speed``:
        ``(omega, epsilon)`` of the input, which the analog rows are turned into time
        derivatives with (None: the analogs)."""
        if self.backend == "c":
            return _run_c(self, params, phi, out, flags, threads, speed)
        from .compiled import PARALLEL_MIN

        params = np.require(params, float, ["C", "W"])  # one array type per compiled kernel
        n, m = params.shape[0], phi.shape[0]
        if out is None:
            out = np.empty((self.outputs, n, m))
        if flags is None:
            flags = np.empty((n, 2))
        parallel = (n * m >= PARALLEL_MIN) if threads is None else bool(threads)
        if not (type(phi) is np.ndarray and phi.dtype == np.float64 and phi.flags.c_contiguous
                and phi.flags.writeable):  # fmt: skip
            phi = np.array(phi, dtype=float)  # one array type per kernel: writable, contiguous
        c, s = cos_sin(phi)  # the last grid's, remembered (the kernel only reads them)
        w, e = (1.0, 0.0) if speed is None else (float(speed[0]), float(speed[1]))
        if parallel:
            from .compiled import announce_compilation

            with announce_compilation(
                "a linkage kernel's threaded loop", dispatchers=[self.parallel]
            ):
                self.parallel(params, phi, c, s, w, e, out, flags)
        else:
            self.serial(params, phi, c, s, w, e, out, flags)
        return out, flags


_F64 = np.dtype(np.float64)


@functools.cache
def _parallel_min() -> int:
    from .compiled import PARALLEL_MIN

    return PARALLEL_MIN


def _run_c(kernel, params, phi, out, flags, threads, speed):
    """:meth:`LinkageKernel.__call__` on the C loop: its arrays passed by address (``out`` and
    ``flags`` through contiguous copies when they are not writable C-ordered doubles of their
    shape), the designs split over the cores' threads for large batches (ctypes releases
    Python's lock during the call; each design's rows are its own: the same result)."""
    if not (type(params) is np.ndarray and params.dtype is _F64 and params.flags.c_contiguous):
        params = np.ascontiguousarray(params, dtype=float)
    if not (type(phi) is np.ndarray and phi.dtype is _F64 and phi.flags.c_contiguous):
        phi = np.ascontiguousarray(phi, dtype=float)
    n, m = params.shape[0], phi.shape[0]
    if params.shape[1:] != (len(kernel.names),) or phi.ndim != 1:
        raise ValueError(
            f"params of shape {params.shape} and inputs of shape {phi.shape}: expected "
            f"(n, {len(kernel.names)}) and (m,)"
        )
    shape = (kernel.outputs, n, m)
    o = out
    if not (type(o) is np.ndarray and o.dtype is _F64 and o.shape == shape
            and o.flags.c_contiguous and o.flags.writeable):  # fmt: skip
        o = np.empty(shape)
    fl = flags
    if not (type(fl) is np.ndarray and fl.dtype is _F64 and fl.shape == (n, 2)
            and fl.flags.c_contiguous and fl.flags.writeable):  # fmt: skip
        fl = np.empty((n, 2))
    c, s = cos_sin(phi)  # the last grid's, remembered (the kernel only reads them)
    w, e = (1.0, 0.0) if speed is None else (float(speed[0]), float(speed[1]))
    grid = _GRID_ADDRESSES[0]  # numpy's ctypes.data costs microseconds: the grid's remembered
    if grid is None or grid[0] is not phi or grid[1] is not c or grid[2] is not s:
        grid = _GRID_ADDRESSES[0] = (phi, c, s, *(_address(a) for a in (phi, c, s)))
    args = (
        params.shape[1], _address(params), *grid[3:], w, e, _address(o), _address(fl),
    )  # fmt: skip
    fn = kernel.serial
    parallel = (n * m >= _parallel_min()) if threads is None else bool(threads)
    workers = min(n, os.cpu_count() or 1) if parallel else 1
    if workers > 1:
        cuts = [n * k // workers for k in range(workers + 1)]
        jobs = [_pool().submit(fn, n, m, lo, hi, *args) for lo, hi in zip(cuts, cuts[1:])]
        for job in jobs:
            job.result()
    else:
        fn(n, m, 0, n, *args)
    if out is None:
        out = o
    elif o is not out:
        out[...] = o
    if flags is None:
        flags = fl
    elif fl is not flags:
        flags[...] = fl
    return out, flags


def _address(a) -> int:
    """The address of ``a``'s data (0 when it has none)."""
    if a.flags.writeable and a.size:
        return _ADDRESS_OF(_DOUBLE.from_buffer(a))  # a third of numpy's ctypes.data's time
    return a.ctypes.data if a.size else 0


#: the last grid's (inputs, cosines, sines) and their addresses
_GRID_ADDRESSES: list = [None]
_DOUBLE, _ADDRESS_OF = ctypes.c_double, ctypes.addressof


@functools.cache
def _pool():
    """The threads the C loop's designs are split over (one per core)."""
    from concurrent.futures import ThreadPoolExecutor

    return ThreadPoolExecutor(os.cpu_count() or 1, thread_name_prefix="mechsynth kernel")


# -------------------------------------------------------------------------------- the trace
def _trace(linkage, outputs: str = "all"):
    """``(casadi Function (input, parameters) -> outputs, parameter names, layout)``; with
    ``outputs="points"`` the points' jets alone (the rest of the solve drops out of the
    trace), and after the rows of the layout the groups' assembly margins, which the kernel
    reduces into its flags without storing them (:func:`_checks`): a design that cannot be
    assembled is told from a toggle as on the full kernel."""
    import casadi as ca

    names = tuple(linkage.parameters)
    p = ca.SX.sym("p", len(names))
    x = ca.SX.sym("x")
    sym = linkage.with_parameters(**{k: p[i] for i, k in enumerate(names)})
    st = sym._solve(x, strict=True, hold=False)
    rows, layout = [], []

    def put(kind, key, values):
        layout.append((kind, key, len(rows), len(values)))
        rows.extend(ca.SX(v) for v in values)

    for kind in ("points", "links", "sliders"):
        for key, jet in getattr(st, kind).items():
            if kind == "points" or outputs == "all":
                put(kind, key, tuple(jet))
    for kind in ("pressure", "transmission", "margins", "extra") if outputs == "all" else ():
        for key, value in getattr(st, kind).items():
            put(kind, key, (value,))
    if outputs != "all":  # the margins, for the flags alone: outside the layout
        rows.extend(ca.SX(v) for v in st.margins.values())
    f = ca.Function("linkage", [x, p], [ca.vertcat(*rows)])
    return f, names, tuple(layout)


def _stamp() -> str:
    """A digest of what the generated code calls: scalar_ops' code and numba's version."""
    import numba

    from . import scalar_ops
    from .compiled import code_digest

    h = hashlib.sha256(numba.__version__.encode())
    for name, v in sorted(vars(scalar_ops).items()):
        fn = getattr(v, "py_func", None)
        if fn is not None:
            h.update(name.encode())
            code_digest(h, fn.__code__)
    return h.hexdigest()[:16]


def _checks(layout, writes) -> set:
    """The rows of the traced function past its ``layout``'s: assembly margins the kernel
    reduces into its flags (the smallest margin) without storing them or testing them finite
    (the kernel of the points alone, :func:`_trace`)."""
    stored = sum(size for *_, size in layout)
    return {r for r, _ in writes if r >= stored}


#: the generated source's note of the rows written once per design (their numbers follow)
_ONCE = "rows written once per design, in the first column:"


def _once_rows(source: str) -> tuple:
    """The rows a kernel's ``source`` writes in the first column alone (the kernel of the
    points alone: its rows that do not vary with the input, the ground points' -- a third to
    two fifths of a six-bar's rows, whose stores were that share of the kernel's time), from
    the note the generators leave in it; () for a kernel of every output."""
    at = source.find(_ONCE)
    if at < 0:
        return ()
    line = source[at + len(_ONCE) : source.index("\n", at)]
    return tuple(int(r) for r in line.replace("*/", " ").split())


def _orders(layout) -> dict:
    """``{row: (order, row of the first derivative)}`` of the analog rows (order 1 or 2) of the
    points', links' and sliders' jets."""
    out = {}
    for kind, _, off, _size in layout:
        if kind == "points":
            out.update({off + 2: (1, None), off + 3: (1, None)})
            out.update({off + 4: (2, off + 2), off + 5: (2, off + 3)})
        elif kind in ("links", "sliders"):
            out.update({off + 1: (1, None), off + 2: (2, off + 1)})
    return out


#: LLVM's fast-math flags of a kernel's row: fused multiply-adds (``contract``) alone, 1.3 x
#: faster per evaluation on a Watt II, every output within 5e-15 of the model's (relative to its
#: size). Not ``reassoc``, ``nsz``, ``nnan`` or ``ninf``: NaN and inf mark the designs the model
#: must judge, and reassociation cancels ``x + (-x)`` whatever x is (with ``arcp``, ``nsz`` and
#: ``reassoc`` together a NaN did not reach the finite test: failed designs read as good); the
#: sign of a zero picks ``arctan2``'s branch at pi.
_FASTMATH = ("contract",)


@dataclass(frozen=True)
class _Dialect:
    """How one code generator writes the trace's operations: the expression of each casadi
    operation over its inputs ``{0}``, ``{1}``, the calls of ``sqrt``/``cos``/``sin``, a
    parameter's read (``{0}`` its column) and the non-finite constants."""

    forms: dict
    calls: dict
    param: str
    nan: str
    inf: str


_PYTHON = _Dialect(
    _FORMS, {k: f"so.{k}" for k in ("sqrt", "cos", "sin")}, "p[i, {0}]", "math.nan", "math.inf"
)


def _program(f, dialect: _Dialect):
    """The traced function ``f`` as straight-line code in ``dialect``: ``(hoisted, body,
    writes, varies)`` -- ``(name, expression)`` pairs of the parameter-only part and of the
    part that depends on the input ``x`` (its cosine ``cx`` and sine ``sx`` given), the
    ``(row, name)`` of each output and ``{name: depends on the input}``.

    Sines and cosines are resolved before they reach libm (whose scalar calls would keep the
    loop over inputs from being vectorized): of the input, from its cosines and sines computed
    once per grid; of an ``arctan2(y, x)``, ``(x, y) / hypot``; of sums, differences,
    negations and doublings, by the angle-addition formulas; of parameters alone, once per
    design outside the loop. Any other argument calls libm. Where a rewrite differs from the
    model beyond round-off (at ``hypot == 0``) it gives NaN, which sends the design to the
    model.
    """
    import casadi as ca

    opname = {getattr(ca, k): k for k in dir(ca) if k.startswith("OP_")}
    call = dialect.calls
    hoisted, body, writes = [], [], []
    var = {}  # casadi work slot -> current SSA name
    node = {}  # SSA name -> (operation, argument names)
    varies = {"cx": True, "sx": True}  # SSA name -> depends on the input
    trig = {}  # SSA name -> (its cosine's name, its sine's name)

    def emit(name, line, dep):
        (body if dep else hoisted).append((name, line))
        varies[name] = dep

    def cos_sin(z):
        if z in trig:
            return trig[z]
        op, args = node[z]
        c, s = f"c_{z}", f"s_{z}"
        if not varies[z]:
            emit(c, f"{call['cos']}({z})", False)
            emit(s, f"{call['sin']}({z})", False)
        elif op == "OP_INPUT":
            c, s = "cx", "sx"
        elif op == "OP_ATAN2":
            y, x = args
            emit(f"r_{z}", f"{call['sqrt']}({x} * {x} + {y} * {y})", True)
            emit(c, f"{x} / r_{z}", True)
            emit(s, f"{y} / r_{z}", True)
        elif op in ("OP_ADD", "OP_SUB"):
            (ca_, sa), (cb, sb) = cos_sin(args[0]), cos_sin(args[1])
            sign = "-" if op == "OP_ADD" else "+"
            emit(c, f"{ca_} * {cb} {sign} {sa} * {sb}", True)
            emit(s, f"{sa} * {cb} {'+' if op == 'OP_ADD' else '-'} {ca_} * {sb}", True)
        elif op == "OP_NEG":
            ca_, sa = cos_sin(args[0])
            c = ca_
            emit(s, f"-{sa}", True)
        elif op == "OP_TWICE":
            ca_, sa = cos_sin(args[0])
            emit(c, f"{ca_} * {ca_} - {sa} * {sa}", True)
            emit(s, f"2.0 * {sa} * {ca_}", True)
        else:
            emit(c, f"{call['cos']}({z})", True)
            emit(s, f"{call['sin']}({z})", True)
        trig[z] = (c, s)
        return c, s

    for k in range(f.n_instructions()):
        op = opname.get(f.instruction_id(k), str(f.instruction_id(k)))
        ins, outs = f.instruction_input(k), f.instruction_output(k)
        name = f"v{k}"
        args = ()
        if op == "OP_INPUT":
            line = "x" if ins[0] == 0 else dialect.param.format(ins[1])
            dep = ins[0] == 0
        elif op == "OP_CONST":
            c = float(f.instruction_constant(k))
            if math.isfinite(c):
                line = repr(c)
            else:
                line = dialect.nan if c != c else ("-" if c < 0 else "") + dialect.inf
            dep = False
        elif op == "OP_OUTPUT":
            writes.append((outs[1], var[ins[0]]))
            continue
        elif op in ("OP_COS", "OP_SIN"):
            arg = var[ins[0]]
            line = cos_sin(arg)[op == "OP_SIN"]
            dep = varies[arg]
        elif op in dialect.forms:
            args = tuple(var[i] for i in ins)
            line = dialect.forms[op].format(*args)
            dep = any(varies[a] for a in args)
        else:
            raise NotImplementedError(f"casadi operation {op}")
        emit(name, line, dep)
        node[name] = (op, args)
        var[outs[0]] = name
    return hoisted, body, writes, varies


def _source(f, layout, stamp, once: bool = False) -> str:
    """The numba source of the traced function ``f`` (one design, a loop over inputs; the
    straight-line code of :func:`_program`). The analogs are written as time derivatives at the
    input's speed ``w`` and acceleration ``e`` (``d/dt = w d``, ``d2/dt2 = w^2 d2 + e d``); the
    finite test is on the analogs. ``once``: the rows that do not vary with the input are
    written in the first column alone (:func:`_once_rows`).
    """
    hoisted, body, writes, varies = _program(f, _PYTHON)
    hoisted = [f"{name} = {line}" for name, line in hoisted]
    body = [f"{name} = {line}" for name, line in body]
    ind = " " * 8
    lines = [
        '"""A linkage kernel generated by mechsynth (do not edit: regenerated when stale)."""',
        "import math",
        "",
        "import numba",
        "import numpy as np",
        "",
        "from mechsynth.kinematics import scalar_ops as so",
        "",
        f"STAMP = {stamp!r}",
        "",
        "",
        "@@finite@@",
        '@numba.njit(error_model="numpy", cache=True, nogil=True, fastmath={'
        + ", ".join(map(repr, _FASTMATH))
        + "})",  # a set written in one order: the same text, the same cached module
        "def row(p, phi, cphi, sphi, w, e, out, flags, i):",
        *("    " + s for s in hoisted),
        "    w2 = w * w",
        "    check = np.empty((2, phi.shape[0]))",
        "    for j in range(phi.shape[0]):",
        ind + "x = phi[j]",
        ind + "cx = cphi[j]",
        ind + "sx = sphi[j]",
        *(ind + s for s in body),
    ]
    # per input, not accumulated: a running sum or minimum would keep the loop from being
    # vectorized (floating-point reductions are not reordered without fastmath)
    # finite test: one sum of the outputs, then ``t - t`` (NaN where one is NaN or inf; a sum
    # that overflows sends a finite design to the model, the safe side), in functions compiled
    # without fast-math flags (a sum of an output and its negation must stay NaN)
    finite, fixed, least = ["fixed"], [], ["math.inf"]
    once_rows, once_lines = [], []
    orders = _orders(layout)
    checks = _checks(layout, writes)
    margins = {off for kind, _, off, _ in layout if kind == "margins"} | checks
    raw = dict(writes)
    for r, name in sorted(writes):
        if r in margins:
            least = [f"min({least[0]}, {name})"]
        if r in checks:
            continue
        order, first = orders.get(r, (0, None))
        value = (name, f"w * {name}", f"w2 * {name} + e * {raw.get(first)}")[order]
        if once and not varies[name]:
            once_rows.append(r)
            once_lines.append(ind + f"out[{r}, i, 0] = {value}")
        else:
            lines.append(ind + f"out[{r}, i, j] = {value}")
        (finite if varies[name] else fixed).append(name)
    if once_rows:
        at = lines.index("    w2 = w * w") + 1
        lines[at:at] = ["    if phi.shape[0] > 0:", *once_lines]
        lines.insert(lines.index("@@finite@@"), f"# {_ONCE} {' '.join(map(str, once_rows))}")
    fixed = fixed or ["0.0"]
    lines.insert(lines.index("    w2 = w * w"), f"    fixed = finite_fixed({', '.join(fixed)})")
    at = lines.index("@@finite@@")
    lines[at : at + 1] = [
        text
        for fn, names in (("finite_fixed", fixed), ("finite_varying", finite))
        for args in ([f"a{k}" for k in range(len(names))],)
        for text in (
            '@numba.njit(error_model="numpy", cache=True, nogil=True)',
            f"def {fn}({', '.join(args)}):",
            f"    t = {' + '.join(args)}",
            "    return t - t",
            "",
            "",
        )
    ]
    lines += [
        ind + f"check[0, j] = finite_varying({', '.join(finite)})",
        ind + f"check[1, j] = {least[0]}",
        "    flags[i, 0] = check[0].sum()",
        "    flags[i, 1] = check[1].min() if phi.shape[0] else math.inf",
        "",
        "",
        '@numba.njit(error_model="numpy", cache=True, nogil=True)',
        "def serial(p, phi, cphi, sphi, w, e, out, flags):",
        "    for i in range(p.shape[0]):",
        "        row(p, phi, cphi, sphi, w, e, out, flags, i)",
        "",
        "",
        '@numba.njit(error_model="numpy", cache=True, parallel=True)',
        "def parallel(p, phi, cphi, sphi, w, e, out, flags):",
        "    for i in numba.prange(p.shape[0]):",
        "        row(p, phi, cphi, sphi, w, e, out, flags, i)",
        "",
    ]
    return "\n".join(lines)


# -------------------------------------------------------------------------------- the C kernel
#: the C generator's expressions of the casadi operations (those of :data:`_FORMS`, with
#: scalar_ops' meanings: ``fmin``/``fmax`` as its comparisons, ``arctan2`` its branch-free
#: rational form ``ms_atan2`` below)
_C_FORMS = {
    **{k: v for k, v in _FORMS.items() if "so." not in v and "math." not in v and "if" not in v},
    "OP_SQRT": "sqrt({0})",
    "OP_SIN": "sin({0})",
    "OP_COS": "cos({0})",
    "OP_TAN": "tan({0})",
    "OP_ASIN": "ms_atan2({0}, sqrt(1.0 - {0} * {0}))",
    "OP_ACOS": "ms_atan2(sqrt(1.0 - {0} * {0}), {0})",
    "OP_ATAN": "atan({0})",
    "OP_ATAN2": "ms_atan2({0}, {1})",
    "OP_FABS": "fabs({0})",
    "OP_FMIN": "({0} <= {1} ? {0} : {1})",
    "OP_FMAX": "({0} >= {1} ? {0} : {1})",
    "OP_HYPOT": "sqrt({0} * {0} + {1} * {1})",
    "OP_EXP": "exp({0})",
    "OP_LOG": "log({0})",
    "OP_POW": "pow({0}, {1})",
    "OP_CONSTPOW": "pow({0}, {1})",
    "OP_FLOOR": "floor({0})",
    "OP_CEIL": "ceil({0})",
    "OP_FMOD": "fmod({0}, {1})",
    "OP_SIGN": "({0} > 0.0 ? 1.0 : ({0} < 0.0 ? -1.0 : 0.0))",
    "OP_COPYSIGN": "copysign({0}, {1})",
    "OP_LT": "({0} < {1} ? 1.0 : 0.0)",
    "OP_LE": "({0} <= {1} ? 1.0 : 0.0)",
    "OP_EQ": "({0} == {1} ? 1.0 : 0.0)",
    "OP_NE": "({0} != {1} ? 1.0 : 0.0)",
    "OP_NOT": "({0} == 0.0 ? 1.0 : 0.0)",
    "OP_AND": "({0} != 0.0 && {1} != 0.0 ? 1.0 : 0.0)",
    "OP_OR": "({0} != 0.0 || {1} != 0.0 ? 1.0 : 0.0)",
    "OP_IF_ELSE_ZERO": "({0} != 0.0 ? {1} : 0.0)",
}
assert set(_C_FORMS) == set(_FORMS)

_C = _Dialect(_C_FORMS, {k: k for k in ("sqrt", "cos", "sin")}, "pr[{0}]", "NAN", "INFINITY")

#: the C kernel's preamble: scalar_ops' ``arctan2`` (Cephes' ``atan`` on the reduced range, S.
#: L. Moshier; branch-free, so the loop over inputs vectorizes; the tests hold it to numpy's)
_C_PRELUDE = r"""/* A linkage kernel generated by mechsynth (do not edit: regenerated when stale) */
#include <math.h>
#include <stdint.h>

static inline double ms_atan2(double y, double x)
{
    const double ax = fabs(x), ay = fabs(y);
    const int swap = ay > ax;
    const double big = swap ? ay : ax, small = swap ? ax : ay;
    const int red = small > 0.66 * big; /* r = small / big > 0.66: atan(r) = pi/4 + atan(u) */
    const double u = (red ? small - big : small) / (red ? small + big : (big == 0.0 ? 1.0 : big));
    const double z = u * u;
    const double p = (((-8.750608600031904122785e-1 * z - 1.615753718733365076637e1) * z
                       - 7.500855792314704667340e1) * z - 1.228866684490136173410e2) * z
                     - 6.485021904942025371773e1;
    const double q = ((((z + 2.485846490142306297962e1) * z + 1.650270098316988542046e2) * z
                       + 4.328810604912902668951e2) * z + 4.853903996359136964868e2) * z
                     + 1.945506571482613964425e2;
    const double mb = 6.123233995736765886130e-17; /* pi/2 - double(pi/2) */
    double a = u + u * (z * p / q);
    a = red ? (0.7853981633974483 + (a + 0.5 * mb)) : a;
    a = swap ? (1.5707963267948966 - a + mb) : a;
    a = x < 0.0 ? (3.141592653589793 - a + 2.0 * mb) : a;
    return y < 0.0 ? -a : a;
}

#define BLOCK 64
"""


def _c_source(f, layout, once: bool = False) -> str:
    """The C source of the traced function ``f``: one function ``kernel`` over the designs
    ``lo <= i < hi`` of a batch and every input (the same straight-line code as the numba
    kernel's, :func:`_program`; the parameter-only part once per design, the inputs in blocks
    of 64 whose finite tests and margins are reduced after each block). ``once``: the rows
    that do not vary with the input are written in the first column alone
    (:func:`_once_rows`)."""
    hoisted, body, writes, varies = _program(f, _C)
    orders = _orders(layout)
    checks = _checks(layout, writes)
    margins = {off for kind, _, off, _ in layout if kind == "margins"} | checks
    raw = dict(writes)
    fixed, finite, stores, least = [], ["fixed"], [], "INFINITY"
    once_rows, once_stores = [], []
    for r, name in sorted(writes):
        if r in margins:
            least = f"({name} < {least} ? {name} : {least})"  # Python's min(least, name)
        if r in checks:
            continue
        order, first = orders.get(r, (0, None))
        value = (name, f"w * {name}", f"w2 * {name} + e * {raw.get(first)}")[order]
        if once and not varies[name]:
            once_rows.append(r)
            once_stores.append(f"o[{r} * nm] = {value};")
        else:
            stores.append(f"o[{r} * nm + j] = {value};")
        (finite if varies[name] else fixed).append(name)
    ind, ind2 = " " * 8, " " * 16
    if once_rows:
        once_stores = ["if (m > 0) {", *("    " + s for s in once_stores), "}"]
    return "\n".join([
        _C_PRELUDE,
        *([f"/* {_ONCE} {' '.join(map(str, once_rows))} */"] if once_rows else []),
        "void kernel(int64_t n, int64_t m, int64_t lo, int64_t hi, int64_t np_,",
        "            const double *restrict p, const double *restrict phi,",
        "            const double *restrict cphi, const double *restrict sphi, double w,",
        "            double e, double *restrict out, double *restrict flags)",
        "{",
        "    const double w2 = w * w;",
        "    const int64_t nm = n * m;",
        "    for (int64_t i = lo; i < hi; ++i) {",
        ind + "const double *restrict pr = p + i * np_;",
        ind + "double *restrict o = out + i * m;",
        *(ind + f"const double {name} = {line};" for name, line in hoisted),
        ind + f"const double tf = {' + '.join(fixed or ['0.0'])};",
        ind + "const double fixed = tf - tf;",
        *(ind + line for line in once_stores),
        ind + "double bad = 0.0, least = INFINITY, chk0[BLOCK], chk1[BLOCK];",
        ind + "for (int64_t j0 = 0; j0 < m; j0 += BLOCK) {",
        ind + "    const int64_t j1 = j0 + BLOCK < m ? j0 + BLOCK : m;",
        ind + "    #pragma GCC ivdep",
        ind + "    for (int64_t j = j0; j < j1; ++j) {",
        ind2 + "const double x = phi[j], cx = cphi[j], sx = sphi[j];",
        *(ind2 + f"const double {name} = {line};" for name, line in body),
        *(ind2 + s for s in stores),
        ind2 + f"const double t = {' + '.join(finite)};",
        ind2 + "chk0[j - j0] = t - t;",
        ind2 + f"chk1[j - j0] = {least};",
        ind + "    }",
        ind + "    for (int64_t j = 0; j < j1 - j0; ++j) {",
        ind2 + "bad += chk0[j];",
        ind2 + "least = chk1[j] < least || chk1[j] != chk1[j] ? chk1[j] : least;",
        ind + "    }",
        ind + "}",
        ind + "flags[2 * i] = bad;",
        ind + "flags[2 * i + 1] = least;",
        "    }",
        "}",
        "",
    ])  # fmt: skip


def _load(source: str):
    """Import the generated module (written once under its digest; compiled or loaded from
    numba's disk cache beside it on first call)."""
    digest = hashlib.sha256(source.encode()).hexdigest()[:20]
    modname = f"mechsynth_linkage_{digest}"
    if modname in sys.modules:
        return sys.modules[modname]
    path = cache_dir() / f"{modname}.py"
    if not path.exists() or path.read_text() != source:
        tmp = path.with_suffix(f".{os.getpid()}.{threading.get_ident()}.tmp")
        tmp.write_text(source)
        os.replace(tmp, path)
    spec = importlib.util.spec_from_file_location(modname, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    sys.modules[modname] = module
    return module


def _structure(linkage, outputs: str = "all"):
    """What a kernel depends on: the groups, the ground points and the parameters' names and
    order (not their values), and which outputs it computes (every one unless told)."""
    key = (linkage._ground, linkage._groups, tuple(linkage.parameters))
    return key if outputs == "all" else (*key, outputs)


def _outputs_of(key) -> str:
    """The outputs a structure's key asks for (:func:`_structure`)."""
    return key[3] if len(key) > 3 else "all"


_LOCK = threading.Lock()
_KERNELS: dict = {}


@functools.cache
def _model_digest() -> str:
    """A digest of the kinematics' source files (the model a kernel is traced from, and the
    generator): a kernel found by its structure alone must come from this very model. (Another
    numba gives another generated module through its stamp, and numba's cache its own entry.)"""
    h = hashlib.sha256()
    for path in sorted(Path(__file__).parent.glob("*.py")):
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def _index_path(key, backend: str = "numba") -> Path | None:
    """Where the ``backend``'s kernel of structure ``key`` is recorded (its parameters' order,
    output layout and the generated module), so that a later process loads it without
    importing CasADi and tracing the solve (0.15-0.3 s); None when the structure has no stable
    text."""
    text = repr(key)
    if " at 0x" in text:  # an object without a value's repr: no stable key across processes
        return None
    if backend != "numba":
        text = f"{backend}:{text}"
    digest = hashlib.sha256((_model_digest() + text).encode()).hexdigest()[:24]
    return cache_dir() / f"structure_{digest}.json"


def _read_index(index):
    """``(names, layout, source)`` recorded at ``index``, or None (absent or unreadable)."""
    import json

    if index is None:
        return None
    try:
        data = json.loads(index.read_text())
        source = (cache_dir() / data["module"]).read_text()
        names = tuple(data["names"])
        layout = tuple((kind, key, int(off), int(size)) for kind, key, off, size in data["layout"])
    except (OSError, ValueError, KeyError, TypeError):
        return None
    if hashlib.sha256(source.encode()).hexdigest() != data.get("sha256"):
        return None
    return names, layout, source


def _write_index(index, names, layout, source, suffix: str = ".py") -> None:
    """Record a kernel's structure (written whole, then renamed into place); its module is
    ``mechsynth_linkage_<digest><suffix>`` in the cache."""
    import json

    if index is None:
        return
    digest = hashlib.sha256(source.encode()).hexdigest()
    data = {
        "module": f"mechsynth_linkage_{digest[:20]}{suffix}",
        "sha256": digest,
        "names": list(names),
        "layout": [list(item) for item in layout],
    }
    _write_atomic(index, json.dumps(data))


def _write_atomic(path: Path, text) -> bool:
    """Write ``text`` (str or bytes) to ``path`` whole, then rename it into place; False when
    the cache cannot be written (the next process then builds again)."""
    tmp = path.with_name(f"{path.name}.{os.getpid()}.{threading.get_ident()}.tmp")
    try:
        (tmp.write_bytes if isinstance(text, bytes) else tmp.write_text)(text)
        os.replace(tmp, path)
    except OSError:
        with contextlib.suppress(OSError):
            tmp.unlink()
        return False
    return True


@functools.cache
def _vectorize_wide_loops():
    """Let LLVM vectorize a kernel's loop over inputs although it writes dozens of output rows:
    its default limits on the runtime overlap checks between arrays (8, and 128 with a pragma)
    leave such a loop scalar, about 3 x slower. The checks stay: where arrays could overlap
    the scalar loop runs. (Process-wide; it only lets other compiled loops vectorize too.)"""
    import llvmlite.binding as llvm

    llvm.set_option("", "-runtime-memory-check-threshold=100000")
    llvm.set_option("", "-vectorize-memory-check-threshold=100000")


# ------------------------------------------------------------------------ choosing a backend
#: the environment variable that chooses the kernels' code generator: ``c``, ``numba`` or
#: ``auto`` (unset: ``auto``, C when a compiler is found, else numba)
BACKEND_ENV = "MECHSYNTH_KERNELS"
#: the environment variable naming the C compiler (else ``cc``, else ``gcc`` on the PATH)
COMPILER_ENV = "MECHSYNTH_CC"


def c_compiler() -> str | None:
    """The C compiler's path: ``$MECHSYNTH_CC`` when set (a name on the PATH or a path),
    else ``cc``, else ``gcc``; None when none is found."""
    return _which(os.environ.get(COMPILER_ENV) or "", os.environ.get("PATH", ""))


@functools.lru_cache(maxsize=8)
def _which(named: str, path: str) -> str | None:
    import shutil

    for name in (named,) if named else ("cc", "gcc"):
        found = shutil.which(name, path=path)
        if found:
            return found
    return None


def kernel_backend(probe: bool = True) -> str | None:
    """The code generator of this process's linkage kernels: ``"c"``, ``"numba"`` or None
    (neither: callers use the model). ``$MECHSYNTH_KERNELS`` chooses: ``c`` (None without a
    compiler), ``numba`` (None without numba), ``auto`` or unset (C when :func:`c_compiler`
    finds one, else numba), ``off`` (None: every motion and sweep on the model, whose numbers
    do not depend on what a process compiled). ``probe=False`` tells numba is installed
    without importing it."""
    choice = os.environ.get(BACKEND_ENV, "auto").strip().lower() or "auto"
    if choice == "off":
        return None
    if choice not in ("auto", "c", "numba"):
        raise MechanismError(f"${BACKEND_ENV} = {choice!r}: expected 'c', 'numba', 'auto' or 'off'")
    if choice in ("auto", "c") and c_compiler() is not None:
        return "c"
    if choice == "c":
        return None
    if probe:
        from .compiled import numba_available

        return "numba" if numba_available() else None
    return "numba" if importlib.util.find_spec("numba") is not None else None


# ------------------------------------------------------------------------ the C build
#: the C compiler's flags. ``-O2`` with the loop vectorizer (``-O1``: 0.1 s less to compile,
#: half as fast); ``-march=native``: this machine's vector units (the build's digest holds the
#: processor's identity); fused multiply-adds (``-ffp-contract=fast``, numba's ``contract``);
#: ``-fno-math-errno`` (``sqrt`` inlined: errno is never read) and ``-fno-trapping-math``
#: (the branch-free ``arctan2``'s selects if-converted: floating-point flags are never read).
#: Nothing that changes a value: no ``-ffast-math`` (NaN and inf must reach the finite test,
#: the sign of a zero picks ``arctan2``'s branch).
C_FLAGS = (
    "-O2", "-ftree-vectorize", "-fvect-cost-model=dynamic", "-march=native",
    "-ffp-contract=fast", "-fno-math-errno", "-fno-trapping-math", "-fPIC", "-shared", "-w",
)  # fmt: skip

_C_ARGS = None  # the C loop's argument types (ctypes: imported with the first kernel)
_LIBS: dict = {}  # build digest -> the loaded function


@functools.cache
def _processor() -> str:
    """This processor's identity (its model and feature flags) for ``-march=native``'s
    builds: a cache shared by machines of another processor builds its own."""
    import platform

    text = platform.machine() + platform.processor()
    with contextlib.suppress(OSError):
        with open("/proc/cpuinfo") as f:
            info = f.read(1 << 16)
        text += "".join(
            line for line in info.splitlines(True) if line.startswith(("model name", "flags"))
        )[: 1 << 12]
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _load_c(source: str):
    """The C loop of ``source``: loaded from the cache (its shared library, checked against
    the digest recorded beside it), else compiled there first. Raises ``OSError`` when the
    compiler fails."""
    global _C_ARGS
    cc = c_compiler()
    if cc is None:
        raise OSError("no C compiler found (cc or gcc on the PATH, or $MECHSYNTH_CC)")
    digest = hashlib.sha256(source.encode()).hexdigest()[:20]
    build = "\0".join((source, cc, *C_FLAGS, _processor()))
    build = hashlib.sha256(build.encode()).hexdigest()[:16]
    if build in _LIBS:
        return _LIBS[build]
    where = cache_dir()
    c_path = where / f"mechsynth_linkage_{digest}.c"
    lib_path = where / f"mechsynth_linkage_{digest}_{build}.so"
    lib = _open_c(lib_path)
    if lib is None:
        if not (c_path.is_file() and c_path.read_text() == source):
            _write_atomic(c_path, source)
        tmp = lib_path.with_name(f"{lib_path.name}.{os.getpid()}.{threading.get_ident()}.tmp")
        _compile_c(cc, c_path, tmp)
        try:
            data = tmp.read_bytes()
            _write_atomic(_digest_path(lib_path), hashlib.sha256(data).hexdigest())
            os.replace(tmp, lib_path)
        finally:
            with contextlib.suppress(OSError):
                tmp.unlink()
        lib = _open_c(lib_path)
        if lib is None:
            raise OSError(f"the compiled kernel {lib_path.name} cannot be loaded")
    if _C_ARGS is None:
        i64, ptr, dbl = ctypes.c_int64, ctypes.c_void_p, ctypes.c_double
        _C_ARGS = [i64] * 5 + [ptr] * 4 + [dbl] * 2 + [ptr] * 2
    fn = lib.kernel
    fn.argtypes, fn.restype = _C_ARGS, None
    _LIBS[build] = fn
    return fn


def _digest_path(lib_path: Path) -> Path:
    return lib_path.with_name(lib_path.name + ".sha256")


def _open_c(lib_path: Path):
    """The shared library at ``lib_path`` when it is there whole (its bytes' digest the one
    recorded beside it at its build), else None (absent, or damaged: built again)."""
    try:
        data = lib_path.read_bytes()
        recorded = _digest_path(lib_path).read_text().strip()
    except OSError:
        return None
    if hashlib.sha256(data).hexdigest() != recorded:
        return None
    try:
        return ctypes.CDLL(str(lib_path))
    except OSError:
        return None


def _compile_c(cc: str, c_path: Path, out: Path) -> None:
    """Compile ``c_path`` into the shared library ``out`` (``OSError`` with the compiler's last
    lines when it fails)."""
    import subprocess

    try:
        run = subprocess.run(
            [cc, *C_FLAGS, "-o", str(out), str(c_path), "-lm"],
            capture_output=True, text=True, timeout=600, check=False,
        )  # fmt: skip
    except (OSError, subprocess.SubprocessError) as exc:
        raise OSError(f"the C compiler {cc} could not run: {exc}") from exc
    if run.returncode != 0:
        tail = " ".join((run.stderr or run.stdout).strip().splitlines()[-3:])
        raise OSError(f"the C compiler {cc} failed on {c_path.name} ({run.returncode}): {tail}")


# ------------------------------------------------------------------------ kernels, remembered
def is_compiled(linkage) -> bool:
    """Whether ``linkage``'s structure has a kernel already: in this process, or recorded in
    the disk cache by an earlier one (then it loads without compiling). No numba import."""
    backend = kernel_backend(probe=False)
    if backend is None:
        return False
    key = _structure(linkage)
    if (backend, key) in _KERNELS:
        return _KERNELS[backend, key] is not None
    index = _index_path(key, backend)
    return index is not None and index.is_file()


def linkage_kernel(linkage, wait: bool = True, outputs: str = "all") -> LinkageKernel | None:
    """The compiled kernel of ``linkage``'s structure (built on first use, then remembered), or
    None when no backend is available (:func:`kernel_backend`: neither a C compiler nor numba),
    the linkage has a cam follower or its solve uses an operation the generator does not know.
    ``outputs="points"``: a kernel of the points' positions, velocities and accelerations
    alone (the rest of the solve left out but the groups' assembly margins, which reach its
    flags unstored: some 1.7 x faster per evaluation for a six-bar), for callers that read its
    rows or ask ``linkage_batch(..., outputs="points")`` for the points' tracks.

    ``wait=False`` never blocks on a build: it returns the kernel when this process has it and
    otherwise starts building it in a background thread and returns None at once, so that the
    caller evaluates on the numpy model meanwhile and finds the kernel on a later call
    (:func:`kernel_pending` tells a build under way). The C compiler runs in its own process;
    a numba kernel the disk cache lacks is compiled there by another Python process (on
    another core, the caller's process keeping Python's lock for its own work), then loaded by
    the thread. A process waits at exit for a build it started (its kernel then lands in the
    disk cache for the next one).
    """
    from .linkage_groups import FollowerGroup

    if outputs not in ("all", "points"):
        raise MechanismError(f"outputs must be 'all' or 'points', got {outputs!r}")
    # numba's import (about 0.5 s) is the background thread's
    backend = kernel_backend(probe=wait or "numba" in sys.modules)
    if backend is None or any(isinstance(g, FollowerGroup) for g in linkage.groups):
        return None
    key = _structure(linkage, outputs)  # frozen groups of names (not a follower's profile)
    kept = _KERNELS.get((backend, key), _NONE)
    if kept is not _NONE:
        return kept
    if wait:
        with _LOCK:
            return _built(linkage, key, backend)
    with _PENDING_LOCK:
        if (backend, key) not in _PENDING and (backend, key) not in _FAILED:
            thread = threading.Thread(
                target=_build_behind, args=(linkage, key, backend),
                name="mechsynth kernel build",
            )  # fmt: skip
            _PENDING[backend, key] = thread
            thread.start()
    return None


_NONE = object()


def kernel_pending(linkage, outputs: str = "all") -> threading.Thread | None:
    """The background thread building ``linkage``'s kernel (``linkage_kernel(..., wait=False)``)
    while it runs (``join()`` it to wait), else None."""
    key = _structure(linkage, outputs)
    for (_, k), thread in list(_PENDING.items()):
        if k == key and thread.is_alive():
            return thread
    return None


_PENDING: dict = {}
_PENDING_LOCK = threading.Lock()
_FAILED: set = set()  # structures whose background build failed: not started again


def _build_behind(linkage, key, backend) -> None:
    """A background build: the kernel remembered for the process, or on failure nothing but
    the structure's failure (no background build again; a blocking call builds and raises).

    A numba kernel the disk cache does not hold yet is compiled in another process (which
    writes it there), this thread waiting for it without Python's lock: numba's compilation is
    mostly Python, and in a thread it would hold that lock from the caller's own work several
    times over. This process then loads it (in the thread). A C kernel is traced here (some
    0.2 s of Python) and compiled by the compiler's own process."""
    try:
        index = _index_path(key, backend)
        if backend == "numba" and not (index is not None and index.is_file()):
            _compile_elsewhere(linkage, _outputs_of(key))
        with _LOCK:
            _built(linkage, key, backend)
    except Exception:  # noqa: BLE001 - a blocking call builds again and raises it
        _FAILED.add((backend, key))
    finally:
        with _PENDING_LOCK:
            _PENDING.pop((backend, key), None)


_ELSEWHERE = """
import os, pickle, sys
from pathlib import Path
os.environ["MECHSYNTH_KERNELS"] = "numba"
from mechsynth.kinematics import linkage_kernels as lkk
where = Path(sys.argv[1])
lkk.cache_dir = lambda: where  # this very cache, whatever the environment says
lkk.linkage_kernel(pickle.loads(sys.stdin.buffer.read()), outputs=sys.argv[2])
"""


def _compile_elsewhere(linkage, outputs: str = "all") -> None:
    """Compile ``linkage``'s numba kernel into the disk cache in a new Python process (nothing
    when the linkage cannot be pickled or the process fails: the caller then compiles here)."""
    import pickle
    import subprocess

    try:
        data = pickle.dumps(linkage)
    except Exception:  # noqa: BLE001 - a linkage holding a local function: compiled here
        return
    with contextlib.suppress(OSError, subprocess.SubprocessError):
        subprocess.run(
            [sys.executable, "-c", _ELSEWHERE, str(cache_dir()), outputs],
            input=data,
            capture_output=True,
            check=False,
            timeout=3600,
        )


def _built(linkage, key, backend="numba") -> LinkageKernel | None:
    """The ``backend``'s kernel of structure ``key`` (with ``_LOCK`` held): remembered,
    recorded in the disk cache, or traced, generated and compiled."""
    from .compiled import announce_compilation

    if (backend, key) in _KERNELS:
        return _KERNELS[backend, key]
    index = _index_path(key, backend)
    try:
        known = _read_index(index)
        if known is None:
            f, names, layout = _trace(linkage, _outputs_of(key))
            once = _outputs_of(key) != "all"
            source = (
                _c_source(f, layout, once) if backend == "c"
                else _source(f, layout, _stamp(), once)
            )  # fmt: skip
        else:
            names, layout, source = known
    except NotImplementedError:
        kernel = None
    else:
        n_out = sum(size for *_, size in layout)
        if backend == "c":
            with announce_compilation(f"a kernel for {linkage.name}'s structure (C)"):
                fn = _load_c(source)
            if known is None:
                _write_index(index, names, layout, source, ".c")
            kernel = LinkageKernel(
                names, layout, n_out, source, fn, None, "c", _outputs_of(key), _once_rows(source)
            )
        else:
            kernel = _built_numba(linkage, names, layout, source, index, known is None)
            if _outputs_of(key) != "all":
                kernel = dataclasses.replace(
                    kernel, kinds=_outputs_of(key), once=_once_rows(source)
                )
    _KERNELS[backend, key] = kernel
    return kernel


def _built_numba(linkage, names, layout, source, index, record) -> LinkageKernel:
    """The numba kernel of ``source`` (compiled, or loaded from numba's disk cache)."""
    from .compiled import announce_compilation

    _vectorize_wide_loops()
    module = _load(source)
    if record:
        _write_index(index, names, layout, source)
    n_out = sum(size for *_, size in layout)
    with announce_compilation(
        f"a kernel for {linkage.name}'s structure", dispatchers=[module.serial]
    ):
        grid = np.zeros(1)
        module.serial(
            np.ones((1, len(names))), grid, grid, grid, 1.0, 0.0, np.empty((n_out, 1, 1)),
            np.empty((1, 2)),
        )  # fmt: skip
    return LinkageKernel(names, layout, n_out, source, module.serial, module.parallel)


# -------------------------------------------------------------------------------- batches
def linkage_batch(
    linkage, phi, speed=None, workspace=None, kernel=None, wait=True, outputs: str = "all"
):
    """The motion of a batch of numeric designs of ``linkage`` (each parameter a number or an
    array of ``n`` designs) at the inputs ``phi`` (1-D) on its compiled kernel.

    Returns ``(motion, good, failed)`` or None (no kernel, symbolic values, ``phi`` not 1-D;
    with ``wait=False``, also while the kernel is being built: see :func:`linkage_kernel`):
    ``motion`` has ``(n, m)`` tracks, views into ``workspace``'s block (valid until its next
    use; without a workspace, a block of the call's own); ``good`` marks the designs whose
    every output is finite -- their values are the model's to round-off -- and ``failed``
    those where an assembly margin falls below -1e-6 (a group cannot close, by a margin far
    beyond round-off: the model raises there). The others (a toggle, or within round-off of
    closing) are the model's to judge.

    ``outputs="points"`` runs the kernel of the points alone (:func:`linkage_kernel`; 2-3 x
    faster than the full one for 10,000 six-bars): the motion holds every point's track
    (position, velocity, acceleration) and nothing else -- its ``links``, ``sliders``,
    ``extra``, ``pressure_angles`` and ``raw_transmission_angles`` are empty and its
    ``pressure_angle`` and ``raw_transmission_angle`` None (not computed, rather than zeros).
    The ground points' tracks are read-only views of the block's first column along the
    inputs (:attr:`LinkageKernel.once`). ``good`` then tells every point's outputs finite,
    and ``failed`` is judged on the groups' assembly margins as for every output (the kernel
    reduces them without storing them). A ``kernel`` given must be of the ``outputs`` asked
    for.
    """
    if outputs != "all" and outputs != "points":
        raise MechanismError(f"outputs must be 'all' or 'points', got {outputs!r}")
    values = linkage._values
    types = {*map(type, values.values())}
    scalars = types == _FLOAT
    if not types <= _PLAIN and ops.is_symbolic(*values.values()):
        return None
    phi = np.asarray(phi, dtype=float)
    if phi.ndim != 1:
        return None
    if kernel is None:
        kernel = linkage_kernel(linkage, wait, outputs)
        if kernel is None:
            return None
    elif kernel.kinds != outputs:
        what = "every output" if kernel.kinds == "all" else f"the {kernel.kinds} alone"
        raise MechanismError(
            f"linkage_batch(..., outputs={outputs!r}) was given a kernel of {what} "
            f"(linkage_kernel(..., outputs={kernel.kinds!r})): pass outputs={kernel.kinds!r}"
        )
    recipe = _recipe(linkage, kernel)
    if scalars:  # one design: its row at once
        params = np.array(recipe.values(values))[None]
        n = 1
    else:  # the numbers in one broadcast row, then the arrays (the varied parameters)
        got = recipe.values(values)
        arrays = [
            (j, (v if type(v) is np.ndarray and v.dtype is _F64 else np.asarray(v, float)).ravel())
            for j, v in enumerate(got)
            if type(v) is not float
        ]
        n = max(c.size for _, c in arrays)
        params = np.empty((n, len(got)))
        params[:] = [v if type(v) is float else 0.0 for v in got]
        for j, c in arrays:
            params[:, j] = c
    m = phi.size
    if workspace is not None:
        out = workspace.block(n, m, rows=kernel.outputs)
    else:
        out = np.empty((kernel.outputs, n, m))
    if speed is None:
        omega, eps = 1.0, 0.0
    elif type(speed) is float and abs(speed) <= MAX_SPEED:  # (False for NaN)
        omega, eps = speed, 0.0
    else:
        omega, eps = speed_pair(speed, 0.0)  # checked, or refused by name
    _, flags = kernel(params, phi, out, speed=(omega, eps))
    if n == 1:  # one design: its two flags as numbers (a third of the time of three ufuncs)
        ((finite, least),) = flags.tolist()
        ok = finite == 0.0
        good, failed = np.array([ok]), np.array([least < -1e-6 and not ok])
    else:
        finite, least = flags.T
        good = finite == 0.0
        failed = (least < -1e-6) > good  # and not good
    return recipe.motion(out, phi, omega, eps), good, failed


#: a batch's parameter types: one design of numbers, and what needs no symbolic test
_FLOAT, _PLAIN = {float}, {float, np.ndarray}


def held_kernel(linkage) -> LinkageKernel | None:
    """The kernel of ``linkage``'s structure that this process holds already (built or loaded
    by an earlier :func:`linkage_kernel` or batch call), else None. Never builds, never reads
    the disk: remembered per structure by the identity of the linkage's groups (hashing them
    costs microseconds), so :meth:`Linkage.motion` asks it on every call."""
    groups, ground, kernels = linkage._groups, linkage._ground, _KERNELS
    hit = _HELD.get(id(groups))
    if (
        hit is not None and hit[0] is groups and hit[1] is ground and hit[2] is kernels
        and hit[3] == len(kernels)
    ):  # fmt: skip
        return hit[4]  # (a kernel built since, of any structure, changes the count)
    backend = kernel_backend(probe=False)
    kernel = None if backend is None else kernels.get((backend, _structure(linkage)))
    if len(_HELD) > 256:  # bounded: linkages built anew in a loop add identities
        _HELD.clear()
    _HELD[id(groups)] = (groups, ground, kernels, len(kernels), kernel)
    return kernel


_HELD: dict = {}


def one_motion(linkage, phi, omega, eps, kernel) -> Motion | None:
    """The :class:`Motion` of ``linkage``'s one numeric design (every parameter a float) at the
    1-D inputs ``phi`` on ``kernel``, its tracks ``(m,)`` views of a block of its own; None
    where an output is not finite (the model then judges: it raises where a group cannot
    close) or ``omega`` or ``eps`` is not one number.

    On the C kernel the block, the design's flags and its parameters are one allocation
    whose address is taken once, and the loop is called directly (what
    :meth:`LinkageKernel.__call__` checks is known here: one design of ``len(names)``
    floats, contiguous inputs, one thread)."""
    if type(omega) is not float or type(eps) is not float:
        if np.ndim(omega) or np.ndim(eps):
            return None
        omega, eps = float(omega), float(eps)  # (the motion keeps the numbers given)
    recipe = _recipe(linkage, kernel)
    if kernel.backend != "c":
        out = np.empty((kernel.outputs, 1, phi.shape[0]))
        _, flags = kernel(np.array([recipe.values(linkage._values)]), phi, out, None, False,
                          (omega, eps))  # fmt: skip
        if flags[0, 0] != 0.0:
            return None
        return recipe.make(out.reshape(kernel.outputs, phi.shape[0]), phi, omega, eps)
    if not (type(phi) is np.ndarray and phi.dtype is _F64 and phi.flags.c_contiguous):
        phi = np.ascontiguousarray(phi, dtype=float)
    m = phi.shape[0]
    size = kernel.outputs * m
    block = np.empty(size + 2 + len(kernel.names))  # outputs, flags, parameters
    block[size + 2 :] = recipe.values(linkage._values)
    at = _address(block)
    c, s = cos_sin(phi)
    grid = _GRID_ADDRESSES[0]
    if grid is None or grid[0] is not phi or grid[1] is not c or grid[2] is not s:
        grid = _GRID_ADDRESSES[0] = (phi, c, s, *(_address(a) for a in (phi, c, s)))
    kernel.serial(1, m, 0, 1, len(kernel.names), at + 8 * (size + 2), grid[3], grid[4],
                  grid[5], omega, eps, at, at + 8 * size)  # fmt: skip
    if block[size] != 0.0:
        return None
    return recipe.make(block[:size].reshape(kernel.outputs, m), phi, omega, eps)


class _Recipe:
    """Where each field of a linkage's :class:`Motion` lies in its kernel's block, and a
    function generated from it that makes the motion of a block (:attr:`make`).

    The row indices are read back from the model's own ``Linkage._motion`` once per structure
    (which track is the main slider, whose pressure angle is the motion's); a kernel of the
    points alone has the points' rows of its layout and nothing else. ``make(block, phi,
    omega, eps)`` takes the block (its first axis the rows) and builds every track and dict
    of the motion in straight-line code (:func:`_maker`): for one design the Python around
    the kernel is what a call costs beside the kernel's own 15-25 us."""

    def __init__(self, linkage, kernel):
        names = kernel.names
        self.values = itemgetter(*names) if len(names) > 1 else (lambda v: (v[names[0]],))
        self.rows = kernel.outputs
        self._last = None  # (block's base, shape, its motion): the last workspace block's
        if kernel.kinds != "all":
            point_fields = tuple(f.name for f in dataclasses.fields(PointTrack))
            self.points = tuple(
                (key, tuple(zip(point_fields, range(off, off + size))))
                for kind, key, off, size in kernel.layout
                if kind == "points"
            )
            self.links = self.sliders = self.pressures = self.transmissions = self.extra = ()
            self.pressure = self.transmission = None
            self.once = kernel.once
            self.make = _maker(self)
            return
        rows = np.arange(1.0, kernel.outputs + 1.0).reshape(-1, 1, 1)  # row r holds r + 1
        st = _State(np.zeros(1), linkage._values, True, linkage._bodies)
        targets = {kind: getattr(st, kind) for kind in _KINDS}
        for kind, key, off, size in kernel.layout:
            block = tuple(rows[off : off + size])
            targets[kind][key] = (
                block[0] if size == 1 else (PointJet if kind == "points" else Jet)(*block)
            )
        ref = linkage._motion(st, np.zeros(1), 1.0, 0.0, scaled=True)

        def row(value):  # the row a field of the reference motion is a view of (-1: none)
            return int(np.asarray(value).reshape(-1)[0]) - 1

        def tracks(named):  # per track, (field, row) in the dataclass's order
            return tuple(
                (k, tuple((f, row(v)) for f, v in vars(t).items())) for k, t in named.items()
            )

        self.points, self.links = tracks(ref.points), tracks(ref.links)
        self.sliders = tracks(ref.sliders)
        self.pressure = row(ref.pressure_angle)  # -1: zeros (no group has a pressure angle)
        mu = ref.raw_transmission_angle
        self.transmission = None if mu is None else row(mu)
        self.pressures = tuple((k, row(v)) for k, v in ref.pressure_angles.items())
        self.transmissions = tuple((k, row(v)) for k, v in ref.raw_transmission_angles.items())
        self.extra = tuple(
            (k, tuple((kk, row(vv)) for kk, vv in v.items()) if isinstance(v, dict) else row(v))
            for k, v in ref.extra.items()
        )
        self.once = kernel.once
        self.make = _maker(self)

    def motion(self, out, phi, omega, eps) -> Motion:
        """The :class:`Motion` of the kernel's block ``out``, its tracks views of the block.
        A block of the caller's own gets tracks and dicts of its own (:attr:`make`). A
        workspace's block is the same memory call after call: its motion is made once and
        remembered while the block is (the reference kept to its base keeps that memory from
        being reused by another array), and each call gets that motion's tracks -- frozen
        views of the same rows -- in dicts of its own."""
        base = out.base
        if base is None:
            return self.make(out, phi, omega, eps)
        last = self._last
        if last is None or last[0] is not base or last[1] != out.shape:
            last = self._last = (base, out.shape, self.make(out, phi, omega, eps))
        m = last[2]  # (the tracks hold the kernel's time derivatives: no omega in them)
        return Motion._of_tracks(
            phi, omega, eps, (_Points(m.points), _Links(m.links), _Sliders(m.sliders)),
            m.pressure_angle, m.raw_transmission_angle,
            {k: dict(v) if type(v) is dict else v for k, v in m.extra.items()},
            dict(m.pressure_angles), dict(m.raw_transmission_angles),
        )  # fmt: skip


def _maker(recipe: _Recipe):
    """``make(block, phi, omega, eps)``: the :class:`Motion` of a kernel's block (its first
    axis the rows), written out for ``recipe`` as straight-line Python -- one unpacking of
    the rows (the rows written once per design, :attr:`LinkageKernel.once`, as read-only
    views of their first column along the inputs, a run of them in one broadcast), each
    track made without its dataclass's ``__init__`` (as ``PointTrack.of``), each dict a new
    one -- and compiled once per recipe (the loops over tracks and fields and the calls per
    track they replace were most of a one-design call's Python)."""
    consts: list = []

    def key(k):  # a str key as its literal, any other as a constant
        if type(k) is str:
            return repr(k)
        consts.append(k)
        return f"K[{len(consts) - 1}]"

    runs, once = [], set(recipe.once)  # [start, stop) of rows alike: written once or not
    for r in range(recipe.rows):
        if runs and (r in once) == (runs[-1][0] in once):
            runs[-1][1] = r + 1
        else:
            runs.append([r, r + 1])
    parts = [
        f"*broadcast_to(rows[{a}:{b}, ..., :1], rows[{a}:{b}].shape)" if a in once
        else f"*rows[{a}:{b}]"
        for a, b in runs
    ]  # fmt: skip
    unpacked = "rows" if len(parts) == 1 and not once else f"({', '.join(parts)},)"
    lines = [
        "def make(rows, phi, omega, eps):",
        "    " + ", ".join(f"r{i}" for i in range(recipe.rows)) + f", = {unpacked}",
    ]
    for name, kind, cls in (
        ("points", "_Points", "PointTrack"),
        ("links", "_Links", "LinkTrack"),
        ("sliders", "_Sliders", "SliderTrack"),
    ):
        lines.append(f"    {name} = {kind}()")
        for k, fields in getattr(recipe, name):
            lines.append(f"    {name}[{key(k)}] = t = new({cls})")
            lines.append("    d = t.__dict__")
            lines += [f"    d[{f!r}] = r{r}" for f, r in fields]
    p = recipe.pressure
    pressure = "None" if p is None else ("np.zeros(r0.shape)" if p < 0 else f"r{p}")
    mu = "None" if recipe.transmission is None else f"r{recipe.transmission}"

    def mapping(pairs):
        return "{" + ", ".join(f"{key(k)}: r{r}" for k, r in pairs) + "}"

    extra = ", ".join(
        f"{key(k)}: " + (mapping(v) if isinstance(v, tuple) else f"r{v}") for k, v in recipe.extra
    )
    lines.append(
        f"    return of_tracks(phi, omega, eps, (points, links, sliders), {pressure}, {mu}, "
        f"{{{extra}}}, {mapping(recipe.pressures)}, {mapping(recipe.transmissions)})"
    )
    space = {
        "new": object.__new__, "np": np, "K": tuple(consts), "of_tracks": Motion._of_tracks,
        "broadcast_to": np.broadcast_to,
        "PointTrack": PointTrack, "LinkTrack": LinkTrack, "SliderTrack": SliderTrack,
        "_Points": _Points, "_Links": _Links, "_Sliders": _Sliders,
    }  # fmt: skip
    exec(compile("\n".join(lines), "<linkage motion recipe>", "exec"), space)  # noqa: S102
    return space["make"]


_RECIPES: dict = {}


def _recipe(linkage, kernel) -> _Recipe:
    """The motion recipe of ``linkage``'s structure and main output on ``kernel``: found by
    the identity of the linkage's groups (shared by every design made from one linkage) before
    their value (hashing frozen groups costs several microseconds a call)."""
    groups = linkage._groups
    key = (id(kernel), id(groups), linkage._output)
    hit = _RECIPES.get(key)
    if hit is not None and hit[0] is kernel and hit[1] is groups:
        return hit[2]
    full = (kernel.source, _structure(linkage), linkage.default_output)
    recipe = _RECIPES.get(full)
    if recipe is None:
        if len(_RECIPES) > 512:  # bounded: linkages built anew in a loop add identities
            _RECIPES.clear()
        recipe = _RECIPES[full] = _Recipe(linkage, kernel)
    _RECIPES[key] = (kernel, groups, recipe)  # holds both: their ids stay theirs
    return recipe


_KINDS = ("points", "links", "sliders", "pressure", "transmission", "margins", "extra")
