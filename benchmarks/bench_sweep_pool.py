"""Benchmark: a linkage chart on the numpy model (``kernels=False``; a linkage's chart of at
least ``charts.LINKAGE_KERNEL_MIN`` evaluations would otherwise run on its compiled kernel, see
``bench_linkage_compiled.py``) evaluated in this process and on a pool of spawned processes, one
per core, in the same run. The model's charts on a pool are what a linkage with a cam follower
(no kernel) or a ``kernels=False`` sweep gets.

The chart: paper 001's six-link over ``N x N`` values of the rocker DB and the extra rod KN, 360
crank angles; measures: the striker's stroke and maximum pressure angle. The pool's time
includes starting its workers (fresh interpreters importing the package). ``executor="auto"``
(the command line's default) uses the pool above ``charts.POOL_MIN_EVALUATIONS`` design-angle
evaluations; this prints the ratio pool / one process at several sizes around it, and checks
that the two charts are identical.

Run: ``python benchmarks/bench_sweep_pool.py [--n 60 160 300] [--json]``.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from mechsynth import objectives as ob
from mechsynth.machines.impact import six_link
from mechsynth.synthesis import charts


def chart(n, executor):
    grid = {"DB": np.linspace(0.035, 0.05, n), "KN": np.linspace(0.06, 0.11, n)}
    measures = {"stroke": ob.stroke("N"), "pressure": ob.max_pressure_angle("N")}
    t = time.perf_counter()
    ch = charts.sweep(
        six_link(), grid, measures, angles=360, progress=False, executor=executor, kernels=False
    )
    return ch, time.perf_counter() - t


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="+", default=[60, 160, 300])
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    rows = []
    for n in args.n:
        local, t_local = chart(n, "local")
        pool, t_pool = chart(n, "processes")
        for k in local.values:
            np.testing.assert_array_equal(local.values[k].filled(0), pool.values[k].filled(0))
        rows.append(
            {
                "designs": n * n,
                "evaluations": n * n * 360,
                "one_process_s": round(t_local, 2),
                "pool_s": round(t_pool, 2),
                "workers": charts.cores(),
                "ratio": round(t_pool / t_local, 2),
            }
        )
    if args.json:
        print(json.dumps(rows, indent=2))
        return
    print(f"pool threshold: {charts.POOL_MIN_EVALUATIONS:.0e} design-angle evaluations")
    for r in rows:
        print(
            f"{r['designs']:>7} designs ({r['evaluations']:.1e} evaluations): one process "
            f"{r['one_process_s']:.2f} s, pool of {r['workers']} {r['pool_s']:.2f} s, "
            f"ratio {r['ratio']:.2f}"
        )


if __name__ == "__main__":
    main()
