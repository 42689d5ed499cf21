"""Sweeps whose cost per design does not grow with the grid: no whole-grid array made per chunk,
chunks sized for the compiled kernels, the crank speed applied in place, executor tasks of
several chunks -- and every chart unchanged (identical to small chunks, equal to the model to
1e-12)."""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth.kinematics.compiled import numba_available, slider_crank_batch
from mechsynth.synthesis import charts

GRID = {"rod_crank": np.linspace(1.5, 5.0, 23), "offset_crank": np.linspace(0.0, 1.5, 19)}
kernels = pytest.mark.skipif(not numba_available(), reason="numba is not installed")


def _identical(a, b):
    np.testing.assert_array_equal(a.feasible, b.feasible)
    for k in a.values:
        np.testing.assert_array_equal(a.values[k].filled(np.nan), b.values[k].filled(np.nan))
    for k in a.params:
        np.testing.assert_array_equal(a.params[k].filled(np.nan), b.params[k].filled(np.nan))
    assert a.reason == b.reason


def _close(a, b, rtol=1e-12):
    np.testing.assert_array_equal(a.feasible, b.feasible)
    for k in a.values:
        x, y = a.values[k].filled(0.0), b.values[k].filled(0.0)
        np.testing.assert_allclose(x, y, rtol=rtol, atol=1e-12 * np.abs(y).max(), err_msg=k)


@kernels
def test_default_chunks_on_the_kernels_give_the_chart_of_small_chunks_and_of_the_model():
    grid = {"crank": np.linspace(0.02, 0.08, 41), "offset": np.linspace(-0.03, 0.05, 39)}
    measures = {
        "acc": ob.peak_acceleration("slider"),
        "pressure": ob.max_pressure_angle(),
        "velocity": ob.peak_velocity("slider"),
    }
    kw = dict(fixed={"rod": 0.12}, angles=360, speed=ms.rpm(600), progress=False)
    fast = charts.sweep(ms.SliderCrank, grid, measures, **kw)
    _identical(fast, charts.sweep(ms.SliderCrank, grid, measures, chunk=7, **kw))
    _close(fast, charts.sweep(ms.SliderCrank, grid, measures, kernels=False, **kw))
    assert 0 < fast.feasible.sum() < fast.size


def test_default_chunk_rule():
    spec = charts._SweepSpec(ms.SliderCrank, {}, (1,), 1, {}, None, None, {},
                             ms.cycle(360), None, True)  # fmt: skip
    # on the kernels: a block of KERNEL_BLOCK doubles; on the model: MODEL_CHUNK evaluations
    assert charts._default_chunk(spec, 8) == charts.KERNEL_BLOCK // (8 * 360) == 5825
    assert charts._default_chunk(spec, 40) == charts.KERNEL_BLOCK // (40 * 360)
    assert charts._default_chunk(spec, None) == charts.MODEL_CHUNK // 360 == 182


class _CountingNumpy:
    """numpy, but counting the arrays of at least ``size`` elements that ``zeros`` makes."""

    def __init__(self, size):
        self.size, self.big = size, 0

    def zeros(self, shape, *a, **kw):
        if np.prod(shape) >= self.size:
            self.big += 1
        return np.zeros(shape, *a, **kw)

    def __getattr__(self, name):
        return getattr(np, name)


def test_no_whole_grid_array_is_made_per_chunk(monkeypatch):
    """A setdefault(name, np.zeros(total)) built its default every chunk (24 % of a 1e6-design
    chart's time): the whole-grid arrays are made once per sweep, whatever the chunks."""
    total = GRID["rod_crank"].size * GRID["offset_crank"].size
    counting = _CountingNumpy(total)
    monkeypatch.setattr(charts, "np", counting)
    ch = charts.slider_crank_chart(**GRID, angles=36, progress=False, chunk=5)
    # feasibility, four measures and three parameters: once each
    assert counting.big == 1 + len(ch.values) + 3
    assert len(ch.params) >= 3


@kernels
def test_crank_speed_applied_in_place_equals_the_analogs_times_the_speed():
    rng = np.random.default_rng(1)
    n, w = 17, ms.rpm(600)
    crank = rng.uniform(0.05, 0.1, n)
    rod, off = crank * rng.uniform(3.0, 5.0, n), crank * rng.uniform(-1.0, 1.0, n)
    phi = ms.cycle(90)
    a = slider_crank_batch(crank, rod, off, phi)
    buf = np.empty((6, n, phi.size))
    b = slider_crank_batch(crank, rod, off, phi, speed=w, out=buf)
    assert b.velocity.base is buf or b.velocity.base is buf.base  # the caller's block, in place
    np.testing.assert_array_equal(b.position, a.position)
    np.testing.assert_array_equal(b.velocity, a.velocity * w)
    np.testing.assert_array_equal(b.acceleration, a.acceleration * (w * w))
    np.testing.assert_array_equal(b.rod_omega, a.rod_omega * w)
    np.testing.assert_array_equal(b.rod_epsilon, a.rod_epsilon * (w * w))
    model = ms.SliderCrank(crank[:, None], rod[:, None], off[:, None]).motion(phi, speed=w)
    scale = np.abs(model.slider.acceleration).max()
    assert np.abs(b.acceleration - model.slider.acceleration).max() < 1e-12 * scale


class _DaskLike(ThreadPoolExecutor):
    """An executor that says it is Dask's (its per-task overhead is Dask's) and counts tasks."""

    __module__ = "distributed.fake"
    tasks = 0

    def submit(self, fn, /, *args, **kwargs):
        type(self).tasks += 1
        return super().submit(fn, *args, **kwargs)


def test_executor_tasks_hold_several_chunks_and_give_the_local_chart(monkeypatch):
    monkeypatch.setattr(charts, "task_overhead", lambda executor: 8e-3)  # as measured on Dask
    monkeypatch.setattr(charts, "result_cost", lambda executor: 1e-8)
    monkeypatch.setattr(charts, "ALWAYS_USE_EXECUTOR", True)  # a chart too small to pay
    _DaskLike.tasks = 0
    local = charts.slider_crank_chart(**GRID, angles=36, progress=False, chunk=3)
    n_chunks = -(-local.size // 3)
    with _DaskLike(2) as pool:
        remote = charts.slider_crank_chart(**GRID, angles=36, progress=False, chunk=3,
                                           executor=pool)  # fmt: skip
    _identical(remote, local)
    # each task's overhead at most 5 % of its work, at least two tasks per worker
    assert 4 <= _DaskLike.tasks < n_chunks


def test_chunks_per_task_follow_the_measured_costs(monkeypatch):
    spec = charts._SweepSpec(ms.SliderCrank, {}, (1,), 1456, {}, None, None, {},
                             ms.cycle(360), None, True)  # fmt: skip
    dask, pool = _DaskLike(4), ThreadPoolExecutor(1)
    monkeypatch.setattr(charts, "_OVERHEADS", {id(dask): 8e-3})  # as if measured on it
    try:
        chunk_s = 1456 * 360 * charts.EVALUATION_COST["named kernel"]
        want = int(np.ceil(8e-3 / charts.TASK_OVERHEAD_SHARE / chunk_s))
        assert charts.TASK_OVERHEAD_SHARE == 0.05
        assert charts._chunks_per_task(dask, spec, 8, 10_000) == want > 1
        assert charts._chunks_per_task(dask, spec, 8, 16) == 2  # two tasks for each of 4
        # a pool's task costs 0.2 ms: two chunks of 3.8 ms outweigh it 20 times
        pool_want = int(np.ceil(charts.TASK_OVERHEAD["default"] / 0.05 / chunk_s))
        assert charts._chunks_per_task(pool, spec, 8, 10_000) == pool_want < want
        model = charts._SweepSpec(ms.SliderCrank, {}, (1,), 182, {}, None, None, {},
                                  ms.cycle(360), None, False)  # fmt: skip
        model_s = 182 * 360 * charts.EVALUATION_COST["model"]
        want = int(np.ceil(8e-3 / 0.05 / model_s))
        assert charts._chunks_per_task(dask, model, None, 10_000) == want > 1
    finally:
        dask.shutdown()
        pool.shutdown()


class _Scheduler:
    address = "tcp://scheduler.invalid:8786"


class _Client:
    scheduler = _Scheduler()

    def nthreads(self):
        return {"tcp://a:1": 2, "tcp://b:1": 1}


def test_a_dask_clusters_overhead_is_measured_on_it_once(monkeypatch):
    """The round trip of a task that does nothing, measured the first time a sweep meets the
    cluster's scheduler, remembered by its address; other executors: the measured constant."""
    monkeypatch.setattr(charts, "_OVERHEADS", {})
    _DaskLike.tasks = 0
    with _DaskLike(1) as dask:
        dask._client = _Client()
        first = charts.task_overhead(dask)
        assert _DaskLike.tasks == 8  # one to warm up, the median of seven
        assert 0 < first < 0.5
        assert charts.task_overhead(dask) == first and _DaskLike.tasks == 8
        assert charts._OVERHEADS == {_Scheduler.address: first}
        assert charts.executor_workers(dask) == 3  # the cluster's threads
    with ThreadPoolExecutor(1) as pool:
        assert charts.task_overhead(pool) == charts.TASK_OVERHEAD["default"]
        assert charts.executor_workers(pool) == 1


@kernels
def test_a_linkage_chart_on_its_kernel_with_default_chunks_equals_the_model(monkeypatch):
    six = (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)}, name="six-link")
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
        .attach("K", on=("D", "B"), along=-0.05)
        .rrp("N", ("K", 0.10), guide=((0.12, 0.0), ms.deg(57)))
    )
    from mechsynth.kinematics import linkage_kernels as lkk

    monkeypatch.setattr(charts, "LINKAGE_KERNEL_MIN", 0)
    monkeypatch.setattr(charts, "LINKAGE_KERNEL_CACHED_MIN", 0)
    lkk.linkage_kernel(six)  # ready before the sweeps (else their first chunks use the model)
    batches = []
    real = lkk.linkage_batch
    monkeypatch.setattr(lkk, "linkage_batch", lambda *a, **k: batches.append(1) or real(*a, **k))
    grid = {"DB": np.linspace(0.03, 0.16, 21), "AB": np.linspace(0.09, 0.15, 17)}
    measures = {"peak velocity": ob.peak_velocity(), "pressure": ob.max_pressure_angle()}
    kw = dict(angles=120, speed=ms.rpm(600), progress=False)
    fast = charts.sweep(six, grid, measures, **kw)
    assert batches  # on the kernel
    _identical(fast, charts.sweep(six, grid, measures, chunk=11, **kw))
    _close(fast, charts.sweep(six, grid, measures, kernels=False, **kw))
    assert 0 < fast.feasible.sum() < fast.size


@kernels
def test_is_compiled_knows_the_kernels_of_this_process_and_of_the_disk_cache(tmp_path,
                                                                            monkeypatch):
    from mechsynth.kinematics import linkage_kernels as lkk

    six = ms.six_link()
    lkk.linkage_kernel(six)
    assert lkk.is_compiled(six)
    monkeypatch.setattr(lkk, "_KERNELS", {})
    assert lkk.is_compiled(six)  # recorded on disk
    monkeypatch.setenv("MECHSYNTH_CACHE_DIR", str(tmp_path))
    assert not lkk.is_compiled(six)  # another cache: not compiled there
    assert not lkk.is_compiled(six.rename(DB="rocker"))
