"""Sweeps on other executors (a process pool, a Dask cluster) give exactly the local result."""

from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pytest

from mechsynth.cli import main
from mechsynth.synthesis.charts import slider_crank_chart, sweep_executor

GRID = {"rod_crank": np.linspace(1.5, 5.0, 9), "offset_crank": np.linspace(0.0, 1.5, 7)}


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
