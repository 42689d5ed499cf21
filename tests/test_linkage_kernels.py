"""Compiled kernels generated from a Linkage's own solve: every output equal to the model's
motion to 1e-12 on batches of designs, for every kind of group, on both code generators (C and
numba); the designs the kernel marks as failed are the ones the model cannot assemble; a
linkage chart on the kernel is the model's."""

import numpy as np
import pytest
from test_linkage import FIELDS, LINK_FIELDS, nail_header_linkage, six_link
from test_linkage_cam import five_link
from test_linkage_slider import cylinder_rocker, trammel

import mechsynth as ms
from mechsynth.errors import MechanismError
from mechsynth.kinematics import linkage_kernels as lkk
from mechsynth.machines.nail_header import NailHeader
from mechsynth.objectives.kinematic import peak_velocity
from mechsynth.synthesis import charts

PHI = ms.cycle(90)


@pytest.fixture(params=["c", "numba"])
def backend(request, monkeypatch):
    """The kernels' code generator, chosen through the environment (skipped where absent)."""
    monkeypatch.setenv(lkk.BACKEND_ENV, request.param)
    if lkk.kernel_backend() != request.param:
        pytest.skip(f"no {request.param} kernels on this machine")
    return request.param


@pytest.fixture
def numba_backend(monkeypatch):
    monkeypatch.setenv(lkk.BACKEND_ENV, "numba")
    if lkk.kernel_backend() != "numba":
        pytest.skip("numba is not installed")


def carried_guide():
    """An RRP whose guide is carried by the rocker DB (a frame angle plus a parameter)."""
    base = ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)}).crank("A", about="O", length=0.03)
    return base.rrr("B", ("A", 0.12), ("D", 0.08)).rrp("C", ("A", 0.2), guide=("DB", 0.1))


LINKAGES = {
    "six-link": (six_link, "DB", 0.07, 0.09),
    "nail header (RPR)": (lambda: nail_header_linkage(NailHeader()), None, 0.0, 0.0),
    "carried guide": (carried_guide, "AB", 0.115, 0.125),
    "driving slider": (trammel, "AB", 0.18, 0.22),
    "cylinder-rocker": (cylinder_rocker, "DB", 0.095, 0.105),
}


def _batch(name, n=7):
    make, param, lo, hi = LINKAGES[name]
    lk = make()
    if param is None:  # vary the crank
        param = next(iter(k for k, kind in lk.parameter_kinds.items() if kind == "length"))
        lo, hi = 0.98 * lk.parameters[param], 1.02 * lk.parameters[param]
    return lk, lk(**{param: np.linspace(lo, hi, n)[:, None]})


def _phi(lk):
    return lk.input_grid(90)


def _same_motion(m1, m2, tol=1e-12):
    def close(a, b, what):
        a, b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
        err = np.max(np.abs(a - b)) / max(1.0, float(np.max(np.abs(a))))
        assert err < tol, (what, err)

    assert list(m1.points) == list(m2.points)
    for k, p in m1.points.items():
        for f in FIELDS:
            close(getattr(p, f), getattr(m2.points[k], f), (k, f))
    assert list(m1.links) == list(m2.links)
    for k, t in m1.links.items():
        for f in LINK_FIELDS:
            close(getattr(t, f), getattr(m2.links[k], f), (k, f))
    assert list(m1.sliders) == list(m2.sliders)
    for k, t in m1.sliders.items():
        for f in ("position", "velocity", "acceleration"):
            close(getattr(t, f), getattr(m2.sliders[k], f), (k, f))
    for k in m1.pressure_angles:
        close(m1.pressure_angles[k], m2.pressure_angles[k], ("pressure", k))
        close(m1.transmission_angles[k], m2.transmission_angles[k], ("transmission", k))
    close(m1.pressure_angle, m2.pressure_angle, "pressure angle")
    assert list(m1.extra) == list(m2.extra)
    for k, v in m1.extra["assembly margins"].items():
        close(v, m2.extra["assembly margins"][k], ("margin", k))
    for k in m1.extra:
        if k != "assembly margins":
            close(m1.extra[k], m2.extra[k], k)


@pytest.mark.parametrize("name", list(LINKAGES))
@pytest.mark.parametrize("speed", [None, ms.rpm(600)])
def test_kernel_equals_the_models_motion(name, speed, backend):
    lk, batch = _batch(name)
    kernel = lkk.linkage_kernel(lk)
    assert kernel is not None and kernel.backend == backend, name
    phi = _phi(lk)
    motion, good, failed = lkk.linkage_batch(batch, phi, speed=speed, kernel=kernel)
    assert good.all() and not failed.any()
    _same_motion(batch.motion(phi, speed=speed), motion)


@pytest.mark.parametrize("name", ["six-link", "carried guide", "driving slider"])
def test_one_design_on_the_kernel_equals_the_models_motion(name, backend):
    """A design of numbers goes to the kernel as one row (the batch path's columns skipped);
    angles that are a view, read-only or of another dtype are copied once (numba: never a new
    compiled signature)."""
    lk, _ = _batch(name)
    kernel = lkk.linkage_kernel(lk)
    phi = _phi(lk)
    motion, good, failed = lkk.linkage_batch(lk, phi, speed=ms.rpm(600), kernel=kernel)
    assert good.all() and not failed.any()
    _same_motion(lk.motion(phi, speed=ms.rpm(600)), motion)
    numba = backend == "numba"
    signatures = len(kernel.serial.signatures) if numba else 0
    frozen = phi.copy()
    frozen.flags.writeable = False
    wide = np.repeat(phi, 2)[::2]  # a strided view
    for grid in (frozen, wide, phi.astype(">f8"), list(phi)):
        again, _, _ = lkk.linkage_batch(lk, grid, speed=ms.rpm(600), kernel=kernel)
        _same_motion(motion, again, tol=1e-15)
    assert (len(kernel.serial.signatures) if numba else 0) == signatures


def test_a_workspace_motion_is_views_of_its_block_and_its_dicts_its_own(backend):
    """The motion of a batch is made of views of the kernel's block, remembered for the
    workspace's block: a later call into the same block gives a motion of fresh dicts over the
    same views, a grown block new views; another main output has its own recipe."""
    from mechsynth.kinematics.compiled import BatchWorkspace

    lk, batch = _batch("six-link", 3)
    kernel, phi, ws = lkk.linkage_kernel(lk), _phi(lk), BatchWorkspace()
    m1, _, _ = lkk.linkage_batch(batch, phi, speed=ms.rpm(600), workspace=ws, kernel=kernel)
    block = ws.block(3, phi.size, rows=kernel.outputs)
    assert np.shares_memory(m1.points["B"].x, block) and m1.points["B"].x.shape == (3, phi.size)
    m1.points.pop("B")
    m1.extra["assembly margins"].clear()
    m2, _, _ = lkk.linkage_batch(batch, phi, speed=ms.rpm(600), workspace=ws, kernel=kernel)
    assert "B" in m2.points and m2.points is not m1.points
    _same_motion(batch.motion(phi, speed=ms.rpm(600)), m2)
    big = lk(DB=np.linspace(0.07, 0.09, 40)[:, None])
    m3, _, _ = lkk.linkage_batch(big, phi, speed=ms.rpm(600), workspace=ws, kernel=kernel)
    assert m3.points["B"].x.shape == (40, phi.size)
    _same_motion(big.motion(phi, speed=ms.rpm(600)), m3)
    other = batch.with_output("B")
    m4, _, _ = lkk.linkage_batch(other, phi, kernel=kernel)
    np.testing.assert_array_equal(m4.pressure_angle, m4.pressure_angles["B"])
    _same_motion(other.motion(phi), m4)


def test_a_kernel_built_behind_the_caller_never_blocks_it(monkeypatch):
    """``wait=False``: the first call returns at once (None: the model serves) while the
    kernel is built in a background thread, one build per structure; once built, the kernel
    is the one a blocking call gives and its motion the model's."""
    import threading
    import time

    lk, batch = _batch("six-link", 5)
    phi = _phi(lk)
    monkeypatch.setattr(lkk, "_KERNELS", {})  # as in a process that has not built it
    release, calls, real = threading.Event(), [], lkk._built

    def slow_build(linkage, key, *backend):
        calls.append(key)
        assert release.wait(60)
        return real(linkage, key, *backend)

    monkeypatch.setattr(lkk, "_built", slow_build)
    t = time.perf_counter()
    assert lkk.linkage_kernel(lk, wait=False) is None
    assert lkk.linkage_batch(batch, phi, wait=False) is None  # the caller takes the model
    assert time.perf_counter() - t < 1.0
    thread = lkk.kernel_pending(lk)
    assert thread is not None and thread.is_alive()
    served = batch.motion(phi, speed=ms.rpm(600))  # the model meanwhile
    assert lkk.linkage_kernel(lk(DB=0.08), wait=False) is None  # the same structure
    release.set()
    thread.join(120)
    assert len(calls) == 1 and lkk.kernel_pending(lk) is None
    kernel = lkk.linkage_kernel(lk, wait=False)
    assert kernel is not None and lkk.linkage_kernel(lk) is kernel
    motion, good, failed = lkk.linkage_batch(batch, phi, speed=ms.rpm(600), wait=False)
    assert good.all() and not failed.any()
    _same_motion(served, motion)


def test_a_failed_background_build_leaves_the_blocking_call_to_report(monkeypatch):
    lk, _ = _batch("six-link", 2)
    monkeypatch.setattr(lkk, "_KERNELS", {})
    monkeypatch.setattr(lkk, "_FAILED", set())

    def broken(linkage, key, *backend):
        raise OSError("disk full")

    monkeypatch.setattr(lkk, "_built", broken)
    assert lkk.linkage_kernel(lk, wait=False) is None
    thread = lkk.kernel_pending(lk)
    if thread is not None:
        thread.join(60)
    assert lkk.kernel_pending(lk) is None and not lkk._KERNELS
    assert lkk.linkage_kernel(lk, wait=False) is None and lkk.kernel_pending(lk) is None
    with pytest.raises(OSError, match="disk full"):
        lkk.linkage_kernel(lk)


def test_kernel_is_one_per_structure_and_kept_on_disk(backend):
    lk = six_link()
    k1 = lkk.linkage_kernel(lk)
    assert lkk.linkage_kernel(lk(DB=0.081, AB=0.121)) is k1  # values are not the structure
    assert lkk.linkage_kernel(lk.rename(DB="rocker")) is not k1
    files = list(lkk.cache_dir().glob(f"mechsynth_linkage_*.{'c' if backend == 'c' else 'py'}"))
    assert any(f.read_text() == k1.source for f in files)
    # the generated loop calls no libm sine or cosine: those of the input come from the grid,
    # those of link angles from their arctan2's arguments
    if backend == "numba":
        loop = k1.source.split("for j in range")[1]
        assert "so.cos" not in loop and "so.sin" not in loop and "so.arccos" not in loop
    else:
        loop = k1.source.split("for (int64_t j = j0")[1]
        assert "cos(" not in loop and "sin(" not in loop and "acos(" not in loop


def test_a_kernel_is_found_by_its_structure_without_tracing(monkeypatch, backend):
    """The structure's record gives the traced kernel's parameters, layout and source; a record
    whose module differs from its digest is not used (the solve is traced again)."""
    lk = six_link()
    kernel = lkk.linkage_kernel(lk)
    index = lkk._index_path(lkk._structure(lk), backend)
    assert index.is_file()
    assert lkk._read_index(index) == (kernel.names, kernel.layout, kernel.source)
    monkeypatch.setattr(lkk, "_KERNELS", {})
    monkeypatch.setattr(lkk, "_trace", lambda *a: pytest.fail("traced although recorded"))
    again = lkk.linkage_kernel(lk)
    assert (again.names, again.layout, again.source) == (kernel.names, kernel.layout, kernel.source)
    phi = ms.cycle(36)
    out, flags = again(np.array([[lk.parameters[k] for k in again.names]]), phi)
    ref, _ = kernel(np.array([[lk.parameters[k] for k in kernel.names]]), phi)
    np.testing.assert_array_equal(out, ref)
    # another structure has another record; a different model (its source files) another key
    assert lkk._index_path(lkk._structure(lk.rename(DB="rocker")), backend) != index
    other = "numba" if backend == "c" else "c"
    assert lkk._index_path(lkk._structure(lk), other) != index  # each generator its record
    monkeypatch.setattr(lkk, "_model_digest", lambda: "another model")
    assert lkk._index_path(lkk._structure(lk), backend) != index


def test_a_damaged_structure_record_is_not_used(tmp_path, monkeypatch):
    import json

    monkeypatch.setenv("MECHSYNTH_CACHE_DIR", str(tmp_path))
    index = lkk.cache_dir() / "structure_x.json"
    assert lkk._read_index(index) is None  # absent
    lkk._write_index(index, ("a",), (("points", "A", 0, 6),), "source text")
    assert lkk._read_index(index) is None  # its module is missing
    (lkk.cache_dir() / json.loads(index.read_text())["module"]).write_text("other text")
    assert lkk._read_index(index) is None  # the module is not the one recorded
    (lkk.cache_dir() / json.loads(index.read_text())["module"]).write_text("source text")
    assert lkk._read_index(index) == (("a",), (("points", "A", 0, 6),), "source text")
    index.write_text("{not json")
    assert lkk._read_index(index) is None
    assert lkk._index_path(("<object at 0x7f00>",)) is None  # no stable text, no record


def test_cache_dir_follows_the_environment(tmp_path, monkeypatch):
    monkeypatch.setenv("MECHSYNTH_CACHE_DIR", str(tmp_path / "c"))
    assert lkk.cache_dir() == tmp_path / "c" / "linkage_kernels"
    assert lkk.cache_dir().is_dir()


def test_failed_designs_are_those_the_model_cannot_assemble(backend):
    """Rockers from far too short to far too long: the kernel's verdicts agree with the model
    design by design (good: the model's values; failed: the model raises)."""
    lk = six_link()
    db = np.linspace(0.02, 0.2, 37)
    batch = lk(DB=db[:, None])
    motion, good, failed = lkk.linkage_batch(batch, PHI)
    assert good.any() and failed.any()
    for i, v in enumerate(db):
        one = lk(DB=float(v))
        if good[i] or failed[i]:
            try:
                m = one.motion(PHI)
            except MechanismError:
                assert failed[i], v
            else:
                assert good[i], v
                np.testing.assert_allclose(
                    motion.sliders["N"].position[i], m.sliders["N"].position, atol=1e-13
                )


def test_no_kernel_for_cam_followers_symbolic_values_or_angle_arrays():
    import casadi as ca

    assert lkk.linkage_kernel(five_link()) is None
    assert lkk.linkage_batch(five_link(), PHI) is None
    lk = six_link()
    assert lkk.linkage_batch(lk(DB=ca.SX.sym("d")), PHI) is None
    assert lkk.linkage_batch(lk, PHI.reshape(9, 10)) is None


@pytest.mark.parametrize("name", ["six-link", "driving slider"])
def test_linkage_chart_on_the_kernel_is_the_models(name, monkeypatch, backend):
    lk, _ = _batch(name)
    param = LINKAGES[name][1]
    ref = lk.parameters[param]
    grid = {param: np.linspace(0.3 * ref, 1.8 * ref, 25)}
    if param != "AB":
        grid["AB"] = lk.parameters["AB"] * np.linspace(0.9, 1.1, 4)
    measures = {
        "peak velocity": peak_velocity(),
        "pressure": lambda mech, m: np.max(m.pressure_angle, axis=-1),
    }
    kw = dict(angles=60, progress=False, speed=ms.rpm(100))
    monkeypatch.setattr(charts, "LINKAGE_KERNEL_MIN", 0)
    monkeypatch.setattr(charts, "LINKAGE_KERNEL_CACHED_MIN", 0)
    lkk.linkage_kernel(lk)  # ready before the sweep (else its first chunks use the model)
    batches = []
    real = lkk.linkage_batch
    monkeypatch.setattr(lkk, "linkage_batch", lambda *a, **k: batches.append(1) or real(*a, **k))
    fast = charts.sweep(lk, grid, measures, **kw)
    assert batches  # on the kernel, not the model
    model = charts.sweep(lk, grid, measures, kernels=False, **kw)
    assert fast.feasible.any() and not fast.feasible.all()
    np.testing.assert_array_equal(fast.feasible, model.feasible)
    for label in measures:
        np.testing.assert_allclose(
            fast.values[label].filled(0.0), model.values[label].filled(0.0), rtol=1e-12, atol=1e-15
        )
    assert fast.reason == model.reason


def test_kernel_scales_the_analogs_with_speed_and_acceleration(backend):
    """The kernel's rows at (omega, epsilon) are the model's time derivatives."""
    lk, batch = _batch("six-link")
    kernel = lkk.linkage_kernel(lk)
    params = np.column_stack(
        [np.broadcast_to(np.ravel(batch.parameters[k]), (7,)) for k in kernel.names]
    )
    w, e = ms.rpm(900), 40.0
    out, flags = kernel(params, PHI, speed=(w, e))
    assert np.all(flags[:, 0] == 0.0) and np.all(flags[:, 1] > 0.0)
    ref = batch.motion(PHI, speed=w, epsilon=e)
    at = {(kind, key): off for kind, key, off, _ in kernel.layout}
    for f, r in zip(FIELDS, range(6)):
        np.testing.assert_allclose(
            out[at["points", "N"] + r], getattr(ref.points["N"], f), rtol=1e-12, atol=1e-12
        )
    for f, r in zip(("angle", "omega", "epsilon"), range(3)):
        np.testing.assert_allclose(
            out[at["links", "DB"] + r], getattr(ref.links["DB"], f), rtol=1e-12, atol=1e-12
        )


def test_threaded_loop_equals_the_serial_one(backend):
    lk, batch = _batch("six-link", n=16)
    kernel = lkk.linkage_kernel(lk)
    params = np.column_stack(
        [np.broadcast_to(np.ravel(batch.parameters[k]), (16,)) for k in kernel.names]
    )
    serial, f1 = kernel(params, PHI, threads=False)
    threaded, f2 = kernel(params[:, :].T.copy().T, PHI, threads=True)  # any layout of params
    np.testing.assert_array_equal(serial, threaded)
    np.testing.assert_array_equal(f1, f2)


def test_ctrl_c_inside_a_compilation_interrupts_when_it_ends():
    """A KeyboardInterrupt that LLVM's callback could only report as unraisable is held and
    raised when the compilation block ends; other unraisable errors go to the usual hook."""
    import sys
    import types

    from mechsynth.kinematics.compiled import announce_compilation

    seen = []
    previous = sys.unraisablehook
    sys.unraisablehook = seen.append
    try:
        with pytest.raises(KeyboardInterrupt):
            with announce_compilation("a test block"):
                sys.unraisablehook(types.SimpleNamespace(exc_value=KeyboardInterrupt()))
                sys.unraisablehook(types.SimpleNamespace(exc_value=ValueError("other")))
        assert [type(u.exc_value) for u in seen] == [ValueError]
        assert sys.unraisablehook == seen.append  # restored
    finally:
        sys.unraisablehook = previous


_SECOND_PROCESS = """
import mechsynth as ms
from mechsynth.kinematics import compiled, linkage_kernels as lkk
lk = ms.six_link()
kernel = lkk.linkage_kernel(lk)
import sys
print(compiled.cached_on_disk([kernel.serial]), sum(kernel.serial.stats.cache_misses.values()),
      sum(kernel.serial.stats.cache_hits.values()), "casadi" in sys.modules)
"""


@pytest.mark.slow
def test_a_later_process_loads_the_kernel_from_the_disk_cache(tmp_path):
    """The kernel's source was stamped with marshal.dumps of code objects, which differs
    between processes: every new process generated a new module and compiled it again."""
    import os
    import subprocess
    import sys

    env = {**os.environ, "MECHSYNTH_CACHE_DIR": str(tmp_path), lkk.BACKEND_ENV: "numba"}
    runs = [
        subprocess.run(
            [sys.executable, "-c", _SECOND_PROCESS],
            env=env,
            capture_output=True,
            text=True,
            timeout=600,
        )  # fmt: skip
        for _ in range(2)
    ]
    for r in runs:
        assert r.returncode == 0, r.stderr
    assert "compiling a kernel" in runs[0].stderr  # a new cache: compiled and announced
    assert runs[1].stderr == ""  # loaded, not announced
    # a cache hit, no miss; found by its structure: CasADi not imported, the solve not traced
    assert runs[0].stdout.split() == ["True", "1", "0", "True"]
    assert runs[1].stdout.split() == ["True", "0", "1", "False"]
    assert len(list(tmp_path.rglob("structure_*.json"))) == 1
    assert len(list(tmp_path.rglob("mechsynth_linkage_*.py"))) == 1  # one module, not two


_SECOND_PROCESS_C = """
import sys, time
t = time.perf_counter()
import mechsynth as ms
from mechsynth.kinematics import linkage_kernels as lkk
lk = ms.six_link()
t0 = time.perf_counter()
kernel = lkk.linkage_kernel(lk)
print(kernel.backend, time.perf_counter() - t0, "casadi" in sys.modules, "numba" in sys.modules)
"""


@pytest.mark.slow
@pytest.mark.skipif(lkk.c_compiler() is None, reason="no C compiler")
def test_a_later_process_loads_the_c_kernel_from_the_disk_cache(tmp_path):
    """C: the first process traces and compiles (one shared library in the cache); the next
    finds the structure's record and loads the library -- no CasADi, no numba, no compiler."""
    import os
    import subprocess
    import sys

    env = {**os.environ, "MECHSYNTH_CACHE_DIR": str(tmp_path), lkk.BACKEND_ENV: "c"}
    runs, libs = [], []
    for _ in range(2):
        r = subprocess.run(
            [sys.executable, "-c", _SECOND_PROCESS_C], env=env, capture_output=True, text=True,
            timeout=600,
        )  # fmt: skip
        assert r.returncode == 0, r.stderr
        runs.append(r.stdout.split())
        libs.append({p: p.stat().st_mtime_ns for p in tmp_path.rglob("mechsynth_linkage_*.so")})
    assert len(libs[0]) == 1 and libs[1] == libs[0]  # not built again
    first, second = runs
    assert first[0] == second[0] == "c" and first[2:] == ["True", "False"]
    assert second[2:] == ["False", "False"]  # neither traced nor numba imported
    assert float(second[1]) < 1.0  # a load (some 0.01 s idle), not a compilation
    assert len(list(tmp_path.rglob("structure_*.json"))) == 1


_BEHIND = """
import time
import numpy as np
import mechsynth as ms
from mechsynth.kinematics import linkage_kernels as lkk
lk = ms.six_link()
phi = ms.cycle(90)
t = time.perf_counter()
first = lkk.linkage_kernel(lk, wait=False)
returned = time.perf_counter() - t
model = lk.motion(phi)  # served by the model while the kernel compiles
thread = lkk.kernel_pending(lk)
thread.join()
built = time.perf_counter() - t
motion, good, _ = lkk.linkage_batch(lk, phi, wait=False)
err = max(float(np.max(np.abs(motion.points[p].x - model.points[p].x))) for p in model.points)
print(first is None, returned, built, bool(good.all()), err)
"""


@pytest.mark.slow
@pytest.mark.parametrize("generator", ["c", "numba"])
def test_a_first_compilation_behind_the_caller_in_a_new_process(tmp_path, generator, monkeypatch):
    """In a new process with an empty cache, ``wait=False`` returns at once while the six-link's
    kernel compiles (seconds; numba's in yet another process), and the kernel's motion is then
    the model's."""
    import os
    import subprocess
    import sys

    monkeypatch.setenv(lkk.BACKEND_ENV, generator)
    if lkk.kernel_backend() != generator:
        pytest.skip(f"no {generator} kernels on this machine")
    env = {**os.environ, "MECHSYNTH_CACHE_DIR": str(tmp_path)}
    run = subprocess.run(
        [sys.executable, "-c", _BEHIND], env=env, capture_output=True, text=True, timeout=600
    )
    assert run.returncode == 0, run.stderr
    first_none, returned, built, good, err = run.stdout.split()
    assert first_none == "True" and good == "True"
    assert float(returned) < 0.5 and float(returned) < float(built)
    assert float(err) < 1e-12


def test_nan_and_failed_assembly_reach_the_flags(backend):
    """A NaN parameter gives NaN outputs and a NaN finite flag; a rocker too short to close
    gives NaN outputs and a negative margin (failed), as the model's raise; the good design
    beside them is unaffected."""
    lk = six_link()
    kernel = lkk.linkage_kernel(lk)
    rows = np.array([[lk.parameters[k] for k in kernel.names]] * 3)
    rows[1, kernel.names.index("DB")] = np.nan
    rows[2, kernel.names.index("DB")] = 0.02
    out, flags = kernel(rows, PHI)
    at = {(kind, key): off for kind, key, off, _ in kernel.layout}
    assert np.isfinite(out[:, 0]).all() and flags[0, 0] == 0.0 and flags[0, 1] > 0.0
    assert np.isnan(flags[1, 0]) and np.isnan(out[at["points", "N"], 1]).all()
    assert np.isnan(flags[2, 0]) and flags[2, 1] < -1e-6
    assert np.isnan(out[at["points", "B"], 2]).any()
    with pytest.raises(MechanismError):
        lk(DB=0.02).motion(PHI)


def test_without_a_compiler_the_kernels_are_numbas(monkeypatch):
    """No C compiler found: ``auto`` falls back to numba (or to the model without it), ``c``
    gives no kernel (the model serves); an unknown choice is refused by name."""
    monkeypatch.setenv(lkk.COMPILER_ENV, "no-such-compiler-here")
    assert lkk.c_compiler() is None
    monkeypatch.setenv(lkk.BACKEND_ENV, "auto")
    numba = lkk.kernel_backend() == "numba"
    kernel = lkk.linkage_kernel(six_link())
    assert (kernel is not None and kernel.backend == "numba") if numba else kernel is None
    monkeypatch.setenv(lkk.BACKEND_ENV, "c")
    assert lkk.kernel_backend() is None and lkk.linkage_kernel(six_link()) is None
    assert lkk.linkage_batch(six_link(), PHI) is None
    monkeypatch.delenv(lkk.COMPILER_ENV)
    monkeypatch.setenv(lkk.BACKEND_ENV, "auto")
    if lkk.c_compiler() is not None:  # a compiler on the PATH: C is the default
        assert lkk.kernel_backend() == "c" and lkk.linkage_kernel(six_link()).backend == "c"
    monkeypatch.setenv(lkk.COMPILER_ENV, "no-such-compiler-here")
    monkeypatch.setenv(lkk.BACKEND_ENV, "c")
    assert lkk.linkage_batch(six_link(), PHI) is None
    monkeypatch.setenv(lkk.BACKEND_ENV, "fortran")
    with pytest.raises(MechanismError, match="MECHSYNTH_KERNELS.*fortran"):
        lkk.kernel_backend()


@pytest.mark.skipif(lkk.c_compiler() is None, reason="no C compiler")
def test_a_damaged_shared_library_is_built_again(tmp_path, monkeypatch):
    """A shared library whose bytes are not the ones recorded at its build (truncated,
    overwritten) is compiled again, not loaded; a compiler that fails says so."""
    monkeypatch.setenv("MECHSYNTH_CACHE_DIR", str(tmp_path))
    monkeypatch.setenv(lkk.BACKEND_ENV, "c")
    monkeypatch.setattr(lkk, "_KERNELS", {})
    monkeypatch.setattr(lkk, "_LIBS", {})
    lk = ms.Linkage(ground={"O": (0, 0), "D": (0.1, 0.0)}).crank("A", about="O", length=0.03)
    lk = lk.rrr("B", ("A", 0.1), ("D", 0.07))  # a four-bar: compiled in a fraction of a second
    rows = np.array([[lk.parameters[k] for k in lkk.linkage_kernel(lk).names]])
    ref, _ = lkk.linkage_kernel(lk)(rows, PHI)
    (lib,) = lkk.cache_dir().glob("mechsynth_linkage_*.so")
    good = lib.read_bytes()
    for damaged in (good[: len(good) // 2],):
        spare = lib.with_name("spare")  # a new file renamed over it: the loaded one stays mapped
        spare.write_bytes(damaged)
        spare.replace(lib)
        monkeypatch.setattr(lkk, "_KERNELS", {})
        monkeypatch.setattr(lkk, "_LIBS", {})
        again, _ = lkk.linkage_kernel(lk)(rows, PHI)
        np.testing.assert_array_equal(again, ref)
        assert lib.read_bytes() == good  # rebuilt: the same bytes as the first build
    c_path = next(lkk.cache_dir().glob("mechsynth_linkage_*.c"))
    broken = tmp_path / "broken.c"
    broken.write_text("this is not C")
    with pytest.raises(OSError, match="failed on broken.c"):
        lkk._compile_c(lkk.c_compiler(), broken, tmp_path / "x.so")
    assert c_path.read_text() == lkk.linkage_kernel(lk).source


@pytest.mark.skipif(lkk.c_compiler() is None, reason="no C compiler")
def test_the_c_arctan2_is_numpys_to_two_ulp(tmp_path, monkeypatch):
    """The C kernels' branch-free arctan2 (and arcsin, arccos through it) against numpy's, in
    every quadrant, on both sides of its range reduction, at zeros, infinities and NaN."""
    import casadi as ca

    monkeypatch.setenv("MECHSYNTH_CACHE_DIR", str(tmp_path))
    x, p = ca.SX.sym("x"), ca.SX.sym("p", 1)
    f = ca.Function("f", [x, p], [ca.vertcat(ca.atan2(p[0], x), ca.asin(x), ca.acos(x))])
    layout = (("extra", "atan2", 0, 1), ("extra", "asin", 1, 1), ("extra", "acos", 2, 1))
    source = lkk._c_source(f, layout)
    kernel = lkk.LinkageKernel(("y",), layout, 3, source, lkk._load_c(source), None, "c")
    rng = np.random.default_rng(3)
    r = np.concatenate([rng.uniform(0, 1, 500), 0.66 + rng.uniform(-1e-6, 1e-6, 50)])
    t = np.concatenate([rng.uniform(-np.pi, np.pi, 550), [0.0, np.pi / 4, np.pi / 2, 3.0]])
    y = np.concatenate([np.outer(r, np.sin(t[:550])).ravel(), [1.0, 0.0, -2.0]])[:, None]
    xs = np.concatenate([np.cos(t), [-1.0, 2.0, np.inf, -np.inf, np.nan, 0.5, 1.0, -1.0, 0.0]])
    xs = np.concatenate([xs, rng.uniform(-1, 1, 200)])
    with np.errstate(invalid="ignore"):  # the grid's cosines of inf and NaN
        out, _ = kernel(y[:60], xs)
    ref = np.arctan2(y[:60], xs)
    finite = np.isfinite(ref)
    assert np.all(np.abs(out[0][finite] - ref[finite]) <= 2 * np.spacing(np.abs(ref[finite])))
    assert np.isnan(out[0][~finite]).all() == np.isnan(ref[~finite]).all()
    with np.errstate(invalid="ignore"):
        asin, acos = np.arcsin(xs), np.arccos(xs)
    ok = np.isfinite(asin)
    assert np.allclose(out[1, 0][ok], asin[ok], rtol=0, atol=4e-16)
    assert np.allclose(out[2, 0][ok], acos[ok], rtol=0, atol=9e-16)
    assert np.isnan(out[1, 0][~ok]).all() and np.isnan(out[2, 0][~ok]).all()
    xs = np.array([1e300, -0.0, 1.0])
    big, _ = kernel(np.array([[3e-300], [-7.0], [np.nan]]), xs)
    np.testing.assert_allclose(big[0, :2], np.arctan2([[3e-300], [-7.0]], xs), rtol=4.5e-16)
    assert np.isnan(big[0, 2]).all()


@pytest.mark.parametrize("name", ["six-link", "carried guide", "driving slider", "cylinder-rocker"])
def test_one_designs_motion_on_the_kernel_is_the_models(name, backend, monkeypatch):
    """``Linkage.motion(..., kernel=True)`` of one design on its structure's kernel (built on
    first use): every output the model's to 1e-12, tracks of the inputs' shape, a block of its
    own per call; ``kernel=False`` is the model's, bit for bit, whether a kernel is held or not,
    the default the held kernel's; a design the kernel finds not finite goes to the model,
    which raises."""
    monkeypatch.setattr(lkk, "_KERNELS", {})
    lk, _ = _batch(name)
    phi, speed = _phi(lk), ms.rpm(600)
    model = lk.motion(phi, speed=speed, epsilon=3.0)
    assert lkk.held_kernel(lk) is None
    fast = lk.motion(phi, speed=speed, epsilon=3.0, kernel=True)
    kernel = lkk.held_kernel(lk)
    assert kernel is not None and kernel.backend == backend
    assert lkk.held_kernel(lk(AB=lk.parameters["AB"])) is kernel
    _same_motion(model, fast)
    assert all(np.shape(v) == phi.shape for t in fast.points.values() for v in vars(t).values())
    assert fast.omega == speed and fast.epsilon == 3.0
    again = lk.motion(phi, speed=speed, epsilon=3.0, kernel=True)
    assert not np.shares_memory(again.points["A"].x, fast.points["A"].x)  # its own block
    after = lk.motion(phi, speed=speed, epsilon=3.0, kernel=False)  # the model, held or not
    for k, t in model.points.items():
        for a, b in zip(vars(t).values(), vars(after.points[k]).values()):
            np.testing.assert_array_equal(a, b)
    held = lk.motion(phi, speed=speed, epsilon=3.0)  # the default takes a held kernel
    for k, t in fast.points.items():
        for a, b in zip(vars(t).values(), vars(held.points[k]).values()):
            np.testing.assert_array_equal(a, b)
    if name == "six-link":
        with pytest.raises(MechanismError, match="cannot|assembl"):
            lk(DB=0.02).motion(phi, kernel=True)  # not finite on the kernel: the model raises


def test_an_angle_array_of_another_shape_or_a_number_takes_the_model(backend):
    lk = six_link()
    grid = PHI.reshape(9, 10)
    np.testing.assert_array_equal(
        lk.motion(grid, kernel=True).points["N"].x, lk.motion(grid).points["N"].x
    )
    assert np.ndim(lk.motion(0.3, kernel=True).points["N"].x) == 0


@pytest.mark.parametrize("name", ["six-link"])
def test_a_kernel_of_the_points_alone_is_the_models(name, backend):
    """``outputs="points"``: the points' jets alone, each the model's to 1e-12, a kernel and a
    record of its own beside the full one's, its flags the full kernel's (the margins reduced,
    not stored); ``linkage_batch`` takes it only when asked for the points
    (``tests/test_linkage_kernels_points.py``); an unknown choice is refused by name."""
    lk, batch = _batch(name)
    full = lkk.linkage_kernel(lk)
    points = lkk.linkage_kernel(lk, outputs="points")
    assert points is not full and points.kinds == "points" and points.backend == backend
    assert lkk.linkage_kernel(lk(AB=lk.parameters["AB"]), outputs="points") is points
    assert {kind for kind, *_ in points.layout} == {"points"}
    assert points.outputs == 6 * len(lk.points) < full.outputs
    phi = _phi(lk)
    params = np.column_stack(
        [np.broadcast_to(np.ravel(batch.parameters[k]), (7,)) for k in points.names]
    )
    out, flags = points(params, phi, speed=(ms.rpm(600), 2.0))
    _, full_flags = full(params, phi)
    assert np.all(flags[:, 0] == 0.0) and np.all(flags[:, 1] > 0.0)
    np.testing.assert_allclose(flags[:, 1], full_flags[:, 1], rtol=1e-13)
    ref = batch.motion(phi, speed=ms.rpm(600), epsilon=2.0)
    model = lk.motion(phi).points
    fixed = {k for k, t in model.items() if not np.any(t.vx) and not np.any(t.vy)}
    ground = {off for _, key, off, _ in points.layout if key in fixed}
    assert len(ground) == 2  # O and D
    assert set(points.once) == {off + r for off in ground for r in range(6)}  # written once
    for _, key, off, _ in points.layout:
        for r, f in enumerate(FIELDS):
            got = out[off + r]
            if off + r in points.once:  # the first column, along the inputs
                got = np.broadcast_to(got[:, :1], got.shape)
            want = np.broadcast_to(getattr(ref.points[key], f), got.shape)
            err = np.max(np.abs(got - want)) / max(1.0, np.max(np.abs(want)))
            assert err < 1e-12, (key, f, err)
    assert full.once == ()
    with pytest.raises(MechanismError, match="outputs='points'"):
        lkk.linkage_batch(batch, phi, kernel=points)
    with pytest.raises(MechanismError, match="outputs must be"):
        lkk.linkage_kernel(lk, outputs="angles")
