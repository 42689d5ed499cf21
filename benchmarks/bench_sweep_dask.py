"""Benchmark: a chart on a Dask LocalCluster against the same chart in this process: as the sweep
decides (the cluster when it is predicted faster, else this process: ``Chart.ran_on`` says
which) and sent to the cluster whatever the prediction (the sweep's task sizes), in the same
run; and the executors' per-task overhead and cost per byte of results themselves.

The chart: ``slider_crank_chart`` over ``N x N`` designs at 360 angles (compiled kernels). The
cluster: ``--workers`` worker processes of one thread each, started once and warmed up (their
kernels loaded) before timing. Each configuration is timed ``--runs`` times (wall clock); the
ratios to this process are printed, and the charts are checked identical.

The per-task overhead: the round trip of a task that does nothing as the sweep measures it on
the cluster (``charts.task_overhead``: one task at a time, the median of seven), trivial tasks
through ``Client.get_executor().map`` (many in flight) and through a spawned
``ProcessPoolExecutor`` (:data:`mechsynth.synthesis.charts.TASK_OVERHEAD`); the results' cost
per byte as the sweep measures it (``charts.result_cost``).

``--address tcp://HOST:PORT`` runs the same on a cluster started elsewhere instead of a
LocalCluster, e.g. a scheduler and two workers started from the shell on this machine::

    dask scheduler --port 8786 &
    dask worker tcp://127.0.0.1:8786 --nworkers 1 --nthreads 1 &
    dask worker tcp://127.0.0.1:8786 --nworkers 1 --nthreads 1 &
    python benchmarks/bench_sweep_dask.py --address tcp://127.0.0.1:8786

Run: ``python benchmarks/bench_sweep_dask.py [--n 300 1000] [--workers 2] [--runs 3]``.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import statistics
import time

import numpy as np


def _nothing(x):
    return x


def per_task_seconds(executor, n=400):
    list(executor.map(_nothing, range(20)))
    t = time.perf_counter()
    list(executor.map(_nothing, range(n)))
    return (time.perf_counter() - t) / n


def _identical(a, b):
    assert np.array_equal(a.feasible, b.feasible)
    for k in a.values:
        x, y = a.values[k].filled(np.nan), b.values[k].filled(np.nan)
        assert np.array_equal(x, y, equal_nan=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="+", default=[300, 1000])
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--address", help="a running scheduler (tcp://host:port); else a LocalCluster")
    args = ap.parse_args(argv)
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    from dask.distributed import Client, LocalCluster

    from mechsynth.synthesis import charts

    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as pool:
        pool_task = per_task_seconds(pool, 2000)
    if args.address:
        cluster, where = contextlib.nullcontext(), args.address
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)  # fmt: skip
        where = cluster
    with cluster, Client(where) as client:
        ex = client.get_executor()
        workers = client.scheduler_info()["workers"]
        kind = f"cluster at {args.address}" if args.address else "LocalCluster"
        print(f"{kind}: {len(workers)} workers x "
              f"{sorted({w['nthreads'] for w in workers.values()})} threads")  # fmt: skip
        t = time.perf_counter()
        trip = charts.task_overhead(ex)
        per_byte = charts.result_cost(ex)
        t_trip = time.perf_counter() - t
        dask_task = statistics.median(per_task_seconds(ex) for _ in range(3))
        print(f"per-task overhead: Dask round trip as the sweep measures it {trip * 1e3:.1f} ms, "
              f"results {per_byte * 1e9:.1f} ns/byte (both measured in {t_trip * 1e3:.0f} ms, "
              f"once per scheduler), many in flight {dask_task * 1e3:.1f} ms per task; process "
              f"pool {pool_task * 1e3:.2f} ms (load average {os.getloadavg()[0]:.1f}: a shared "
              "machine)")  # fmt: skip

        def chart(n, executor):
            lam, eps = np.linspace(1.5, 8.0, n), np.linspace(0.0, 2.0, n)
            return charts.slider_crank_chart(rod_crank=lam, offset_crank=eps, progress=False,
                                             executor=executor)  # fmt: skip

        def timed(n, executor, always=False):
            charts.ALWAYS_USE_EXECUTOR = always
            try:
                t = time.perf_counter()
                out = chart(n, executor)
                return time.perf_counter() - t, out
            finally:
                charts.ALWAYS_USE_EXECUTOR = False

        timed(20, ex, always=True)  # warm the workers: kernels loaded
        chart(20, "local")
        for n in args.n:
            timed(n, ex, always=True)  # the workers' memory for this size, untimed
            rows = {"this process": [], "as the sweep decides": [], "Dask, always": []}
            where = set()
            for _ in range(args.runs):
                t_local, local = timed(n, "local")
                t_auto, auto = timed(n, ex)
                t_dask, remote = timed(n, ex, always=True)
                _identical(auto, local)
                _identical(remote, local)
                rows["this process"].append(t_local)
                rows["as the sweep decides"].append(t_auto)
                rows["Dask, always"].append(t_dask)
                where.add(auto.ran_on)
            print(f"\n{n * n:,d} slider-crank designs x 360 angles, wall seconds, {args.runs} runs "
                  f"(load average {os.getloadavg()[0]:.1f}); the sweep ran on "
                  + " | ".join(sorted(where)) + ":")  # fmt: skip
            base = rows["this process"]
            for label, ts in rows.items():
                ratio = statistics.median(ts) / statistics.median(base)
                print(f"  {label:22s} " + " ".join(f"{t:6.2f}" for t in ts) + "   / this process "
                      + " ".join(f"{t / b:5.2f}" for t, b in zip(ts, base))
                      + f"   medians {ratio:5.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
