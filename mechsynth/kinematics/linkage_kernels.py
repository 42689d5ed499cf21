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
2. the instructions become the body of a numba function of one design and one input value,
   with the parameter-only part hoisted out of the loop over inputs, the transcendental
   functions those of :mod:`~mechsynth.kinematics.scalar_ops` (as the four-bar and slider-crank
   kernels);
3. the source is written to the cache directory (:func:`cache_dir`) under the digest of its
   text and compiled with numba's disk cache: a structure compiles once per machine (a six-bar
   in 6-8 s of CPU, most of it numba's typing and LLVM; announced in one line), later
   processes load it in some 0.05 s after numba's own start (its import and set-up, 0.5-2 s
   once per process). ``linkage_kernel(..., wait=False)`` builds it in a background thread
   while the caller goes on with the model (a few milliseconds to return).

The row of the loop is compiled with fused multiply-adds (the only fast-math flag: see
:data:`_FASTMATH`); its finite test runs in functions compiled without any.

The kernel computes every output of :meth:`Linkage.motion` -- each point's, link's and slider's
jet, each group's pressure and transmission angles and assembly margin, the followers' extra
quantities -- into one ``(outputs, designs, inputs)`` block, and two numbers per design that
say whether the model must look at it: whether every output was finite, and the smallest
assembly margin. Only the structure matters (which groups, branches and parameter names); the
values are the kernel's inputs. Tests check the kernels against ``Linkage.motion`` to 1e-12.

Linkages with a cam follower get no kernel (None), nor do those whose trace holds an operation
the generator does not know; the callers then use the model. (A follower's contact is found by a
fixed number of Newton steps from sampled profile points: paper 001's five-link traces to about
3,400 lines, which numba took 93 s to compile -- more than the model needs for any chart.)
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import importlib.util
import math
import os
import sys
import tempfile
import threading
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import ops
from .linkage_groups import _State
from .mechanism import speed_pair
from .ops import cos_sin
from .tracks import Jet, LinkTrack, Motion, PointJet, PointTrack, SliderTrack

__all__ = [
    "LinkageKernel",
    "linkage_kernel",
    "kernel_pending",
    "is_compiled",
    "cache_dir",
    "linkage_batch",
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
    source : the generated Python source.
    """

    names: tuple
    layout: tuple
    outputs: int
    source: str
    serial: object
    parallel: object

    def __call__(
        self, params: np.ndarray, phi: np.ndarray, out=None, flags=None, threads=None, speed=None
    ):
        """Evaluate ``params`` (``(n, len(names))``) at the inputs ``phi`` (``(m,)``) into
        ``out`` (``(outputs, n, m)``) and ``flags`` (``(n, 2)``: per design 0 where every
        output is finite (else NaN) and its smallest assembly margin). ``threads`` None: numba's
        threads for batches of at least :data:`~mechsynth.kinematics.compiled.PARALLEL_MIN`
        evaluations. ``speed``: ``(omega, epsilon)`` of the input, which the analog rows are
        turned into time derivatives with (None: the analogs)."""
        from .compiled import PARALLEL_MIN, announce_compilation

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
            with announce_compilation(
                "a linkage kernel's threaded loop", dispatchers=[self.parallel]
            ):
                self.parallel(params, phi, c, s, w, e, out, flags)
        else:
            self.serial(params, phi, c, s, w, e, out, flags)
        return out, flags


# -------------------------------------------------------------------------------- the trace
def _trace(linkage):
    """``(casadi Function (input, parameters) -> outputs, parameter names, layout)``."""
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
            put(kind, key, tuple(jet))
    for kind in ("pressure", "transmission", "margins", "extra"):
        for key, value in getattr(st, kind).items():
            put(kind, key, (value,))
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


def _source(f, layout, stamp) -> str:
    """The numba source of the traced function ``f`` (one design, a loop over inputs). The
    analogs are written as time derivatives at the input's speed ``w`` and acceleration ``e``
    (``d/dt = w d``, ``d2/dt2 = w^2 d2 + e d``); the finite test is on the analogs.

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
    hoisted, body, writes = [], [], []
    var = {}  # casadi work slot -> current SSA name
    node = {}  # SSA name -> (operation, argument names)
    varies = {"cx": True, "sx": True}  # SSA name -> depends on the input
    trig = {}  # SSA name -> (its cosine's name, its sine's name)

    def emit(name, line, dep):
        (body if dep else hoisted).append(f"{name} = {line}")
        varies[name] = dep

    def cos_sin(z):
        if z in trig:
            return trig[z]
        op, args = node[z]
        c, s = f"c_{z}", f"s_{z}"
        if not varies[z]:
            emit(c, f"so.cos({z})", False)
            emit(s, f"so.sin({z})", False)
        elif op == "OP_INPUT":
            c, s = "cx", "sx"
        elif op == "OP_ATAN2":
            y, x = args
            emit(f"r_{z}", f"so.sqrt({x} * {x} + {y} * {y})", True)
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
            emit(c, f"so.cos({z})", True)
            emit(s, f"so.sin({z})", True)
        trig[z] = (c, s)
        return c, s

    for k in range(f.n_instructions()):
        op = opname.get(f.instruction_id(k), str(f.instruction_id(k)))
        ins, outs = f.instruction_input(k), f.instruction_output(k)
        name = f"v{k}"
        args = ()
        if op == "OP_INPUT":
            line = "x" if ins[0] == 0 else f"p[i, {ins[1]}]"
            dep = ins[0] == 0
        elif op == "OP_CONST":
            c = float(f.instruction_constant(k))
            if math.isfinite(c):
                line = repr(c)
            else:
                line = "math.nan" if c != c else ("-math.inf" if c < 0 else "math.inf")
            dep = False
        elif op == "OP_OUTPUT":
            writes.append((outs[1], var[ins[0]]))
            continue
        elif op in ("OP_COS", "OP_SIN"):
            arg = var[ins[0]]
            line = cos_sin(arg)[op == "OP_SIN"]
            dep = varies[arg]
        elif op in _FORMS:
            args = tuple(var[i] for i in ins)
            line = _FORMS[op].format(*args)
            dep = any(varies[a] for a in args)
        else:
            raise NotImplementedError(f"casadi operation {op}")
        emit(name, line, dep)
        node[name] = (op, args)
        var[outs[0]] = name
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
    orders = _orders(layout)
    margins = {off for kind, _, off, _ in layout if kind == "margins"}
    raw = dict(writes)
    for r, name in sorted(writes):
        order, first = orders.get(r, (0, None))
        value = (name, f"w * {name}", f"w2 * {name} + e * {raw.get(first)}")[order]
        lines.append(ind + f"out[{r}, i, j] = {value}")
        (finite if varies[name] else fixed).append(name)
        if r in margins:
            least = [f"min({least[0]}, {name})"]
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


def _structure(linkage):
    """What a kernel depends on: the groups, the ground points and the parameters' names and
    order (not their values)."""
    return (linkage._ground, linkage._groups, tuple(linkage.parameters))


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


def _index_path(key) -> Path | None:
    """Where the kernel of structure ``key`` is recorded (its parameters' order, output layout
    and the generated module), so that a later process loads it without importing CasADi and
    tracing the solve (0.15-0.3 s); None when the structure has no stable text."""
    text = repr(key)
    if " at 0x" in text:  # an object without a value's repr: no stable key across processes
        return None
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


def _write_index(index, names, layout, source) -> None:
    """Record a kernel's structure (written whole, then renamed into place)."""
    import json

    if index is None:
        return
    digest = hashlib.sha256(source.encode()).hexdigest()
    data = {
        "module": f"mechsynth_linkage_{digest[:20]}.py",
        "sha256": digest,
        "names": list(names),
        "layout": [list(item) for item in layout],
    }
    tmp = index.with_suffix(f".{os.getpid()}.{threading.get_ident()}.tmp")
    try:
        tmp.write_text(json.dumps(data))
        os.replace(tmp, index)
    except OSError:  # a cache that cannot be written: the next process traces again
        with contextlib.suppress(OSError):
            tmp.unlink()


@functools.cache
def _vectorize_wide_loops():
    """Let LLVM vectorize a kernel's loop over inputs although it writes dozens of output rows:
    its default limits on the runtime overlap checks between arrays (8, and 128 with a pragma)
    leave such a loop scalar, about 3 x slower. The checks stay: where arrays could overlap
    the scalar loop runs. (Process-wide; it only lets other compiled loops vectorize too.)"""
    import llvmlite.binding as llvm

    llvm.set_option("", "-runtime-memory-check-threshold=100000")
    llvm.set_option("", "-vectorize-memory-check-threshold=100000")


def is_compiled(linkage) -> bool:
    """Whether ``linkage``'s structure has a kernel already: in this process, or recorded in
    the disk cache by an earlier one (then it loads without compiling). No numba import."""
    key = _structure(linkage)
    if key in _KERNELS:
        return _KERNELS[key] is not None
    index = _index_path(key)
    return index is not None and index.is_file()


def linkage_kernel(linkage, wait: bool = True) -> LinkageKernel | None:
    """The compiled kernel of ``linkage``'s structure (built on first use, then remembered), or
    None when numba is missing, the linkage has a cam follower or its solve uses an operation
    the generator does not know.

    ``wait=False`` never blocks on a build: it returns the kernel when this process has it and
    otherwise starts building it in a background thread and returns None at once, so that the
    caller evaluates on the numpy model meanwhile and finds the kernel on a later call
    (:func:`kernel_pending` tells a build under way). A kernel the disk cache lacks is compiled
    there by another Python process (on another core, the caller's process keeping Python's
    lock for its own work), then loaded by the thread. A process waits at exit for a build it
    started (its kernel then lands in the disk cache for the next one).
    """
    from .compiled import numba_available
    from .linkage_groups import FollowerGroup

    if wait or "numba" in sys.modules:
        available = numba_available()
    else:  # numba's import (about 0.5 s) is the background thread's
        available = importlib.util.find_spec("numba") is not None
    if not available or any(isinstance(g, FollowerGroup) for g in linkage.groups):
        return None
    key = _structure(linkage)  # frozen groups of names (a follower's profile is not among them)
    if key in _KERNELS:
        return _KERNELS[key]
    if wait:
        with _LOCK:
            return _built(linkage, key)
    with _PENDING_LOCK:
        if key not in _PENDING and key not in _FAILED:
            thread = threading.Thread(
                target=_build_behind, args=(linkage, key), name="mechsynth kernel build"
            )
            _PENDING[key] = thread
            thread.start()
    return None


def kernel_pending(linkage) -> threading.Thread | None:
    """The background thread building ``linkage``'s kernel (``linkage_kernel(..., wait=False)``)
    while it runs (``join()`` it to wait), else None."""
    thread = _PENDING.get(_structure(linkage))
    return thread if thread is not None and thread.is_alive() else None


_PENDING: dict = {}
_PENDING_LOCK = threading.Lock()
_FAILED: set = set()  # structures whose background build failed: not started again


def _build_behind(linkage, key) -> None:
    """A background build: the kernel remembered for the process, or on failure nothing but
    the structure's failure (no background build again; a blocking call builds and raises).

    A kernel the disk cache does not hold yet is compiled in another process (which writes it
    there), this thread waiting for it without Python's lock: numba's compilation is mostly
    Python, and in a thread it would hold that lock from the caller's own work several times
    over. This process then loads it (in the thread)."""
    try:
        if not is_compiled(linkage):
            _compile_elsewhere(linkage)
        with _LOCK:
            _built(linkage, key)
    except Exception:  # noqa: BLE001 - a blocking call builds again and raises it
        _FAILED.add(key)
    finally:
        with _PENDING_LOCK:
            _PENDING.pop(key, None)


_ELSEWHERE = """
import pickle, sys
from pathlib import Path
from mechsynth.kinematics import linkage_kernels as lkk
where = Path(sys.argv[1])
lkk.cache_dir = lambda: where  # this very cache, whatever the environment says
lkk.linkage_kernel(pickle.loads(sys.stdin.buffer.read()))
"""


def _compile_elsewhere(linkage) -> None:
    """Compile ``linkage``'s kernel into the disk cache in a new Python process (nothing when
    the linkage cannot be pickled or the process fails: the caller then compiles here)."""
    import pickle
    import subprocess

    try:
        data = pickle.dumps(linkage)
    except Exception:  # noqa: BLE001 - a linkage holding a local function: compiled here
        return
    with contextlib.suppress(OSError, subprocess.SubprocessError):
        subprocess.run(
            [sys.executable, "-c", _ELSEWHERE, str(cache_dir())],
            input=data,
            capture_output=True,
            check=False,
            timeout=3600,
        )


def _built(linkage, key) -> LinkageKernel | None:
    """The kernel of structure ``key`` (with ``_LOCK`` held): remembered, recorded in the disk
    cache, or traced, generated and compiled."""
    from .compiled import announce_compilation

    if key in _KERNELS:
        return _KERNELS[key]
    index = _index_path(key)
    try:
        known = _read_index(index)
        if known is None:
            f, names, layout = _trace(linkage)
            source = _source(f, layout, _stamp())
        else:
            names, layout, source = known
    except NotImplementedError:
        kernel = None
    else:
        _vectorize_wide_loops()
        module = _load(source)
        if known is None:
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
        kernel = LinkageKernel(names, layout, n_out, source, module.serial, module.parallel)
    _KERNELS[key] = kernel
    return kernel


# -------------------------------------------------------------------------------- batches
def linkage_batch(linkage, phi, speed=None, workspace=None, kernel=None, wait=True):
    """The motion of a batch of numeric designs of ``linkage`` (each parameter a number or an
    array of ``n`` designs) at the inputs ``phi`` (1-D) on its compiled kernel.

    Returns ``(motion, good, failed)`` or None (no kernel, symbolic values, ``phi`` not 1-D;
    with ``wait=False``, also while the kernel is being built: see :func:`linkage_kernel`):
    ``motion`` has ``(n, m)`` tracks, views into ``workspace``'s block (valid until its next
    use); ``good`` marks the designs whose every output is finite -- their values are the
    model's to round-off -- and ``failed`` those where an assembly margin falls below -1e-6
    (a group cannot close, by a margin far beyond round-off: the model raises there). The
    others (a toggle, or within round-off of closing) are the model's to judge.
    """
    values = linkage._values
    scalars = {*map(type, values.values())} == {float}
    if not scalars and any(ops.is_symbolic(v) for v in values.values()):
        return None
    phi = np.asarray(phi, dtype=float)
    if phi.ndim != 1:
        return None
    kernel = kernel or linkage_kernel(linkage, wait)
    if kernel is None:
        return None
    if scalars:  # one design: its row at once
        params = np.array([[values[k] for k in kernel.names]])
        n = 1
    else:
        cols = [np.asarray(values[k], dtype=float).reshape(-1) for k in kernel.names]
        n = max(c.size for c in cols)
        params = np.empty((n, len(cols)))
        for j, c in enumerate(cols):
            params[:, j] = c
    m = phi.size
    if workspace is not None:
        out = workspace.block(n, m, rows=kernel.outputs)
    else:
        out = np.empty((kernel.outputs, n, m))
    omega, eps = speed_pair(speed, 0.0)
    _, flags = kernel(params, phi, out, speed=(omega, eps))
    good = flags[:, 0] == 0.0
    failed = (flags[:, 1] < -1e-6) > good  # and not good
    return _recipe(linkage, kernel).motion(out, phi, omega, eps), good, failed


class _Recipe:
    """Where each field of a linkage's :class:`Motion` lies in its kernel's block: row indices
    read back from the model's own ``Linkage._motion`` once per structure (which track is the
    main slider, whose pressure angle is the motion's), so that a batch's motion is made of
    views of the block without walking the model's state again."""

    def __init__(self, linkage, kernel):
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

        def tracks(named):
            return tuple((k, tuple(row(v) for v in vars(t).values())) for k, t in named.items())

        self.points, self.links = tracks(ref.points), tracks(ref.links)
        self.sliders = tracks(ref.sliders)
        self.pressure = row(ref.pressure_angle)
        mu = ref.raw_transmission_angle
        self.transmission = None if mu is None else row(mu)
        self.pressures = tuple((k, row(v)) for k, v in ref.pressure_angles.items())
        self.transmissions = tuple((k, row(v)) for k, v in ref.raw_transmission_angles.items())
        self.extra = tuple(
            (k, tuple((kk, row(vv)) for kk, vv in v.items()) if isinstance(v, dict) else row(v))
            for k, v in ref.extra.items()
        )

        self._views = None  # (block's base, shape, fields): the last block's views

    def fields(self, out) -> tuple:
        """The motion's tracks and angles as views of the block ``out``; remembered for the
        last block (a workspace's block is the same memory call after call; the reference kept
        to its base keeps that memory from being reused by another array)."""
        base = out.base
        last = self._views
        if last is not None and last[0] is base and last[1] == out.shape and base is not None:
            return last[2]
        rows = list(out)  # the block's rows as views, made at once
        point, link = PointTrack.of, LinkTrack.of
        got = (
            {k: point(*[rows[r] for r in rs]) for k, rs in self.points},
            {k: link(*[rows[r] for r in rs]) for k, rs in self.links},
            {k: SliderTrack(*[rows[r] for r in rs]) for k, rs in self.sliders},
            rows[self.pressure] if self.pressure >= 0 else np.zeros(out.shape[1:]),
            None if self.transmission is None else rows[self.transmission],
            {
                k: {kk: rows[r] for kk, r in v} if isinstance(v, tuple) else rows[v]
                for k, v in self.extra
            },
            {k: rows[r] for k, r in self.pressures},
            {k: rows[r] for k, r in self.transmissions},
        )
        self._views = (base, out.shape, got)
        return got

    def motion(self, out, phi, omega, eps) -> Motion:
        """The :class:`Motion` of the kernel's block ``out`` (its tracks views of the block;
        its dicts its own)."""
        points, links, sliders, pressure, mu, extra, pressures, mus = self.fields(out)
        return Motion(
            phi=phi,
            omega=omega,
            epsilon=eps,
            points=points,  # copied into the motion's own Tracks dicts
            links=links,
            pressure_angle=pressure,
            sliders=sliders,
            raw_transmission_angle=mu,
            extra={k: dict(v) if type(v) is dict else v for k, v in extra.items()},
            pressure_angles=dict(pressures),
            raw_transmission_angles=dict(mus),
        )


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
