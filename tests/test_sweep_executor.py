"""Sweeps on other executors (a process pool, a Dask cluster) give exactly the local result."""

from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.cli import main
from mechsynth.synthesis import charts
from mechsynth.synthesis.charts import slider_crank_chart, sweep_executor

GRID = {"rod_crank": np.linspace(1.5, 5.0, 9), "offset_crank": np.linspace(0.0, 1.5, 7)}


@pytest.fixture(autouse=True)
def _executors_take_the_tasks(monkeypatch):
    """These charts are too small for an executor to pay: the tests of the executors' own paths
    send them the tasks all the same (the tests of the decision turn this off)."""
    monkeypatch.setattr(charts, "ALWAYS_USE_EXECUTOR", True)


def _chart(**kw):
    # small chunks: the grid spans several tasks
    return slider_crank_chart(**GRID, angles=90, progress=False, chunk=8, **kw)


def _identical(a, b):
    np.testing.assert_array_equal(a.feasible, b.feasible)
    for k in a.values:
        np.testing.assert_array_equal(a.values[k].filled(np.nan), b.values[k].filled(np.nan))
    for k in a.params:
        np.testing.assert_array_equal(a.params[k].filled(np.nan), b.params[k].filled(np.nan))
    assert a.reason == b.reason


def test_thread_and_process_pools_give_the_local_chart():
    local = _chart()
    assert 0 < local.feasible.sum() < local.size
    with ThreadPoolExecutor(2) as pool, sweep_executor(pool):
        _identical(_chart(), local)
    # the chart's design functions are local functions: they travel by cloudpickle
    with ProcessPoolExecutor(1) as pool:
        _identical(_chart(executor=pool), local)


def test_dask_local_cluster_gives_the_local_chart():
    distributed = pytest.importorskip("dask.distributed")
    local = _chart()
    with (
        distributed.LocalCluster(
            n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster, set_as_default=False) as client,
    ):
        _identical(_chart(executor=client.get_executor()), local)


def test_cli_dask_needs_a_reachable_scheduler(capsys):
    pytest.importorskip("dask.distributed")
    code = main(["chart", "slider-crank", "--set", "n=5", "--quiet", "--dask",
                 "tcp://127.0.0.1:9"])  # fmt: skip
    assert code == 1
    assert "cannot reach the Dask scheduler" in capsys.readouterr().err


def _six_link_sweep(executor):
    from mechsynth import objectives as ob
    from mechsynth.machines.impact import six_link
    from mechsynth.synthesis.charts import sweep

    grid = {"DB": np.linspace(0.01, 0.05, 7), "KN": np.linspace(0.005, 0.11, 6)}
    measures = {"stroke": ob.stroke("N"), "pressure": ob.max_pressure_angle("N")}
    return sweep(six_link(), grid, measures, angles=72, progress=False, chunk=5,
                 executor=executor)  # fmt: skip


def test_a_linkage_sweep_on_a_pool_of_processes_gives_the_local_chart(monkeypatch):
    """``executor="processes"`` (spawned interpreters, one per core) and ``"auto"`` above its
    size threshold give exactly the chart of this process; ``"auto"`` below it, and for the
    compiled kernels, stays in this process."""
    import mechsynth.synthesis.charts as charts

    local = _six_link_sweep("local")
    assert 0 < local.feasible.sum() < local.size  # short rockers do not assemble
    _identical(_six_link_sweep("processes"), local)
    started = []
    real = charts._process_pool
    monkeypatch.setattr(charts, "_process_pool", lambda n: started.append(n) or real(n))
    _identical(_six_link_sweep("auto"), local)  # 42 designs x 72 angles: too small
    assert started == []
    monkeypatch.setattr(charts, "POOL_MIN_EVALUATIONS", 1000)
    _identical(_six_link_sweep("auto"), local)
    assert started == [min(charts.cores(), 9)]
    _identical(_chart(executor="auto"), _chart())  # compiled kernels: this process
    assert len(started) == 1
    with pytest.raises(ValueError, match="executor must be"):
        _six_link_sweep("threads")


def _spec(designs, angles):
    """A slider-crank chart's description with the default chunks of the kernels."""
    measures = {"a": None, "b": None}
    spec = charts._SweepSpec(ms.SliderCrank, {"x": np.zeros(designs)}, (designs,), 1, {}, None,
                             None, measures, ms.cycle(angles), None, True)  # fmt: skip
    return charts.replace(spec, chunk=charts._default_chunk(spec, 8))


def test_an_executor_gets_the_tasks_only_where_it_is_predicted_faster(monkeypatch):
    """Predicted from the measured costs: a small chart stays in this process (its chunks'
    work is less than the round trips and the workers' first load of the kernels), a large one
    goes to the cluster; two workers on this machine's two cores run at two thirds of the speed
    of one process each and share the cores with whatever else runs (a busy machine keeps the
    chart here); results that cost more to send back than their work keep it here."""
    monkeypatch.setattr(charts, "ALWAYS_USE_EXECUTOR", False)
    monkeypatch.setattr(charts, "task_overhead", lambda ex: 0.015)  # as measured on Dask
    monkeypatch.setattr(charts, "result_cost", lambda ex: 5e-9)
    monkeypatch.setattr(charts, "cores", lambda: 2)
    monkeypatch.setattr(charts, "_SEEN", set())
    monkeypatch.setattr(charts, "executor_workers", lambda ex: 2)
    with ThreadPoolExecutor(2) as pool:
        for designs, here, busy, pays in (
            (63, False, 0, False),
            (90_000, False, 0, False),  # 0.23 s of work: the kernels' load alone is 0.6 s
            (1_000_000, False, 0, True),  # two workers elsewhere
            (1_000_000, True, 0, False),  # on this machine: 2.7 s against 2.6 s (the kernels load)
            (4_000_000, True, 0, True),
            (4_000_000, True, 1, False),  # a third process running: 13 s against 10 s
            (4_000_000, True, 3, False),  # a busy machine: this process's share is as large
            (1_000_000, False, 3, True),  # workers elsewhere do not share this machine
        ):
            monkeypatch.setattr(charts, "_on_this_host", lambda ex, here=here: here)
            monkeypatch.setattr(charts, "_busy_elsewhere", lambda busy=busy: busy)
            charts._SEEN.clear()  # workers that have not loaded their kernels yet
            spec = _spec(designs, 360)
            n_chunks = -(-designs // spec.chunk)
            tasks, why = charts._executor_plan(pool, spec, 8, n_chunks)
            assert (tasks > 0) == pays, (designs, here, busy, why)
            assert why.startswith("ThreadPoolExecutor" if pays else "this process"), why
            assert tasks % 2 == 0  # as many tasks for each worker
        # workers that have loaded their kernels already: a million designs pay here too
        charts._SEEN.add(id(pool))
        monkeypatch.setattr(charts, "_busy_elsewhere", lambda: 0)
        assert charts._executor_plan(pool, _spec(10**6, 360), 8, 172)[0] > 0
        # results that cost more to send than to compute: this process at any size
        monkeypatch.setattr(charts, "result_cost", lambda ex: 1e-6)
        monkeypatch.setattr(charts, "_on_this_host", lambda ex: False)
        assert charts._executor_plan(pool, _spec(10**7, 360), 8, 1717)[0] == 0
        # the same with the executor asked for whatever the prediction
        monkeypatch.setattr(charts, "ALWAYS_USE_EXECUTOR", True)
        assert charts._executor_plan(pool, _spec(10**7, 360), 8, 1717)[0] > 0


def test_a_small_chart_given_a_dask_cluster_runs_in_this_process_and_says_so(monkeypatch):
    distributed = pytest.importorskip("dask.distributed")
    monkeypatch.setattr(charts, "ALWAYS_USE_EXECUTOR", False)
    local = _chart()
    assert local.ran_on == "this process"
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster, set_as_default=False) as client,
    ):
        ex = client.get_executor()
        small = _chart(executor=ex)
        _identical(small, local)
        assert small.ran_on.startswith("this process: a Dask cluster of 2 workers would not pay")
        # the costs measured on the cluster, once: a round trip and the results' bytes
        assert 0 < charts.task_overhead(ex) < 1.0 and 0 <= charts.result_cost(ex) < 1e-6
        # a chart with 20 times the work per design pays on the same cluster (on a machine
        # that runs nothing else: a busy one keeps it here, see the test above)
        monkeypatch.setattr(charts, "_busy_elsewhere", lambda: 0)
        spec = _spec(400_000, 7200)
        tasks, why = charts._executor_plan(ex, spec, 8, -(-400_000 // spec.chunk))
        assert tasks > 0 and why.startswith("a Dask cluster of 2 workers"), why
