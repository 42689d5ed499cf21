"""A Linkage's sweep never waits for its compiled kernel: it evaluates on the numpy model while
the kernel is built in the background and on the kernel from the chunk after it is ready (the
chart equal to the model's to 1e-12 either way); workers of a pool never compile it; the
thresholds follow the measured costs."""

import os

import numpy as np
import pytest

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth.kinematics import linkage_kernels as lkk
from mechsynth.kinematics.compiled import numba_available
from mechsynth.synthesis import charts

needs_numba = pytest.mark.skipif(not numba_available(), reason="numba is not installed")
MEASURES = {"peak velocity": ob.peak_velocity(), "pressure": ob.max_pressure_angle()}
KW = dict(angles=60, speed=ms.rpm(600), progress=False)


def _four_bar(name="switch four-bar"):
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)}, name=name)
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
    )


GRID = {"DB": np.linspace(0.03, 0.16, 16), "AB": np.linspace(0.09, 0.15, 15)}


def _equal_to_the_model(chart, lk, grid=GRID, **kw):
    model = charts.sweep(lk, grid, MEASURES, kernels=False, **{**KW, **kw})
    np.testing.assert_array_equal(chart.feasible, model.feasible)
    assert chart.reason == model.reason
    for label in MEASURES:
        x, y = chart.values[label].filled(0.0), model.values[label].filled(0.0)
        np.testing.assert_allclose(x, y, rtol=1e-12, atol=1e-12 * np.abs(y).max(), err_msg=label)


@pytest.fixture
def on_any_size(monkeypatch):
    """Every Linkage sweep wants its kernel, whatever its size."""
    monkeypatch.setattr(charts, "LINKAGE_KERNEL_MIN", 0)
    monkeypatch.setattr(charts, "LINKAGE_KERNEL_CACHED_MIN", 0)


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):
    """An empty kernel cache and no kernel of this process: every kernel must be built."""
    monkeypatch.setenv("MECHSYNTH_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(lkk, "_KERNELS", {})
    monkeypatch.setattr(lkk, "_PENDING", {})
    monkeypatch.setattr(lkk, "_FAILED", set())
    return tmp_path


def _count_batches(monkeypatch):
    calls = []
    real = lkk.linkage_batch

    def counted(*a, **kw):
        calls.append(1)
        return real(*a, **kw)

    monkeypatch.setattr(lkk, "linkage_batch", counted)
    return calls


@needs_numba
def test_chunks_run_on_the_model_until_the_kernel_is_ready_then_on_it(monkeypatch, on_any_size):
    lk = _four_bar()
    kernel = lkk.linkage_kernel(lk)  # built (or loaded) here, then handed out late
    asked = []

    def not_yet(linkage, wait=True):
        asked.append(wait)
        return None if len(asked) <= 3 else kernel  # the sweep's first question and 2 chunks

    monkeypatch.setattr(lkk, "linkage_kernel", not_yet)
    batches = _count_batches(monkeypatch)
    chart = charts.sweep(lk, GRID, MEASURES, chunk=20, **KW)
    n_chunks = -(-chart.size // 20)
    assert asked == [False] * (n_chunks + 1)  # never asked to wait
    assert len(batches) == n_chunks - 2  # chunks 2, 3, ... on the kernel
    assert 0 < chart.feasible.sum() < chart.size
    _equal_to_the_model(chart, lk, chunk=20)


@needs_numba
def test_a_sweep_that_wants_no_kernel_never_asks_for_one(monkeypatch):
    lk = _four_bar()
    monkeypatch.setattr(lkk, "linkage_kernel", lambda *a, **k: pytest.fail("asked"))
    charts.sweep(lk, GRID, MEASURES, **KW)  # 14,400 evaluations: below the thresholds


@needs_numba
@pytest.mark.slow
def test_a_sweep_that_starts_before_the_kernel_exists_goes_on_without_it(
    monkeypatch, on_any_size, fresh_cache
):
    """Empty cache: the kernel is compiled in the background while the first chunks run on
    the model; the third chunk waits for it (in the chart's feasibility test, so that the
    switch is certain to happen inside the sweep) and it and the rest run on the kernel."""
    # a structure of its own (a coupler point): no module of this process has its kernel
    lk = _four_bar("switch four-bar, fresh").attach("P", on=("A", "B"), along=0.04)
    pending = []

    def feasible(v):
        pending.append(lkk.kernel_pending(lk))
        if len(pending) == 3:
            pending[-1].join()  # the background build, done
        return np.ones(v["DB"].shape, dtype=bool)

    batches = _count_batches(monkeypatch)
    assert not lkk.is_compiled(lk)
    chart = charts.sweep(lk, GRID, MEASURES, chunk=20, feasible=feasible, **KW)
    n_chunks = -(-chart.size // 20)
    assert pending[0] is not None and pending[1] is not None  # under way: the sweep went on
    assert lkk.is_compiled(lk)
    assert len(batches) == n_chunks - 2
    _equal_to_the_model(chart, lk, chunk=20)


@needs_numba
@pytest.mark.slow
def test_pool_workers_never_compile_the_kernel(monkeypatch, on_any_size, fresh_cache, capfd):
    """The sweep's own process builds the kernel into the disk cache (in the background);
    the pool's workers evaluate on the model until it is there, then load it: no worker
    compiles, in its own process (a compilation announces itself on stderr) nor behind it (a
    build under way while the disk cache lacks the kernel)."""
    lk = _four_bar("switch four-bar, pool")
    marks = fresh_cache / "marks"
    marks.mkdir()
    grid = {"DB": np.linspace(0.03, 0.16, 12), "AB": np.linspace(0.09, 0.15, 10)}

    def feasible(v, where=str(marks)):
        import os as _os
        from pathlib import Path as _Path

        from mechsynth.kinematics import linkage_kernels as k

        loading = k.kernel_pending(lk)
        if loading is not None and not k.is_compiled(lk):
            (_Path(where) / "a worker builds").touch()
        if loading is not None:
            loading.join()
        (_Path(where) / f"{_os.getpid()}-{bool(k._KERNELS)}").touch()
        return np.ones(v["DB"].shape, dtype=bool)

    kw = dict(chunk=6, feasible=feasible, executor="processes")
    chart = charts.sweep(lk, grid, MEASURES, **KW, **kw)  # the kernel is in no cache
    _equal_to_the_model(chart, lk, grid=grid, chunk=6)
    assert not (marks / "a worker builds").exists()
    building = lkk.kernel_pending(lk)  # the sweep's own, in the background
    if building is not None:
        building.join()
    assert lkk.is_compiled(lk)
    assert "compiling" not in capfd.readouterr().err
    for p in marks.iterdir():
        p.unlink()
    chart = charts.sweep(lk, grid, MEASURES, **KW, **kw)  # now in the disk cache: loaded
    _equal_to_the_model(chart, lk, grid=grid, chunk=6)
    assert any(name.endswith("True") for name in os.listdir(marks))  # a worker loaded it
    assert not (marks / "a worker builds").exists()
    assert "compiling" not in capfd.readouterr().err


@pytest.mark.parametrize("backend", sorted(charts.LINKAGE_COSTS))
def test_the_thresholds_follow_the_measured_costs(monkeypatch, backend):
    monkeypatch.setattr(charts, "_backend", lambda: backend)
    c = charts.LINKAGE_COSTS[backend]
    saved = c["model"] - c["kernel"]
    assert saved > 0
    build, cached = charts.linkage_kernel_thresholds()
    assert build == pytest.approx(c["compile"] / saved + c["compile wall"] / c["model"])
    assert cached == pytest.approx(c["load"] / saved + c["load wall"] / c["model"])
    # a sweep that starts a build outlasts it on the model alone
    assert build * c["model"] > c["compile wall"]
    assert cached * c["model"] > c["load wall"]
    monkeypatch.setattr(charts, "LINKAGE_KERNEL_MIN", 5.0)
    assert charts.linkage_kernel_thresholds() == (5.0, cached)


def test_a_sweep_wants_its_kernel_from_the_thresholds(monkeypatch):
    six = ms.six_link()

    def spec(designs, kernels=True):
        return charts._SweepSpec(six, {}, (designs,), 1, {}, None, None, {}, ms.cycle(100),
                                 None, kernels)  # fmt: skip

    monkeypatch.setattr(charts, "LINKAGE_KERNEL_CACHED_MIN", 1e4)
    monkeypatch.setattr(charts, "LINKAGE_KERNEL_MIN", 1e6)
    for compiled in (False, True):
        monkeypatch.setattr(lkk, "is_compiled", lambda lk, c=compiled: c)
        assert not charts._wants_kernel(spec(99))  # 9,900 evaluations
        assert charts._wants_kernel(spec(100)) == compiled
        assert charts._wants_kernel(spec(10_000))
    assert not charts._wants_kernel(spec(10_000, kernels=False))
    assert not charts._wants_kernel(
        charts._SweepSpec(ms.SliderCrank, {}, (10_000,), 1, {}, None, None, {}, ms.cycle(100),
                          None, True)  # fmt: skip
    )


def test_a_cam_follower_wants_no_kernel(monkeypatch):
    monkeypatch.setattr(charts, "LINKAGE_KERNEL_MIN", 0)
    monkeypatch.setattr(charts, "LINKAGE_KERNEL_CACHED_MIN", 0)
    five = ms.five_link()
    spec = charts._SweepSpec(five, {}, (10_000,), 1, {}, None, None, {}, ms.cycle(100),
                             None, True)  # fmt: skip
    assert not charts._wants_kernel(spec)


def test_remote_tasks_only_load_a_kernel_the_disk_cache_holds(monkeypatch):
    lk = _four_bar()
    spec = charts._SweepSpec(lk, {}, (1,), 1, {}, None, None, {}, ms.cycle(10), None, True,
                             True)  # fmt: skip
    asked = []
    monkeypatch.setattr(lkk, "linkage_kernel", lambda linkage, wait=True: asked.append(wait))
    monkeypatch.setattr(lkk, "is_compiled", lambda linkage: False)
    assert charts._kernel_now(spec, build=False) is None and asked == []
    charts._kernel_now(spec, build=True)
    monkeypatch.setattr(lkk, "is_compiled", lambda linkage: True)
    charts._kernel_now(spec, build=False)
    assert asked == [False, False]

