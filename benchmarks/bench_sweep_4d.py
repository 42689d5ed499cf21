"""Benchmark: a million-design four-dimensional sweep (four-bars, 32^4 designs x 360 angles).

Crank, coupler, rocker and ground lengths over 32 values each (1,048,576 designs; those whose
crank cannot turn fully are masked), 360 crank angles; measures: the minimum transmission
angle, the maximum pressure angle and the peak rocker angular acceleration (analogs). Printed:
wall time, throughput (design-angle evaluations per second), the feasible share, the process's
peak resident memory (``ru_maxrss``) and the memory the chart's arrays hold, and the ratio of
the time to the compiled kernel alone over the same designs (``four_bar_batch`` into a reused
array, measured in the same run on a 1/16 sample and scaled).

Run: ``python benchmarks/bench_sweep_4d.py [--n 32] [--dask ADDRESS|local] [--workers N]``.
With ``--dask`` the chunks are evaluated on the cluster (``client.get_executor()``); each task
returns only its chunk's measures.
"""

from __future__ import annotations

import argparse
import resource
import time

import numpy as np

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth.kinematics.compiled import four_bar_batch
from mechsynth.synthesis import sweep


def run(n, executor=None, workers=1):
    grid = {
        "crank": np.linspace(0.5, 1.5, n),
        "coupler": np.linspace(2.0, 5.0, n),
        "rocker": np.linspace(1.5, 4.5, n),
        "ground": np.linspace(2.5, 5.5, n),
    }
    measures = {
        "min transmission angle": ob.min_transmission_angle(),
        "max pressure angle": ob.max_pressure_angle(),
        "peak rocker acceleration": ob.peak_angular_acceleration("rocker"),
    }
    t = time.perf_counter()
    ch = sweep(ms.FourBar, grid, measures, angles=360, progress=False, executor=executor,
               workers=workers)  # fmt: skip
    return time.perf_counter() - t, ch


def kernel_alone(ch, sample=16):
    """Seconds of ``four_bar_batch`` over the chart's feasible designs (1/``sample`` timed)."""
    p = {k: v.compressed() for k, v in ch.params.items()}
    idx = slice(None, None, sample)
    phi = np.linspace(0.0, 2 * np.pi, 360, endpoint=False)
    a, b, c, d = (p[k][idx] for k in ("crank", "coupler", "rocker", "ground"))
    out = np.empty((6, a.size, 360))
    four_bar_batch(a[:10], b[:10], c[:10], d[:10], phi)
    t = time.perf_counter()
    four_bar_batch(a, b, c, d, phi, out=out)
    return (time.perf_counter() - t) * sample


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=32)
    ap.add_argument("--dask", metavar="ADDRESS")
    ap.add_argument("--workers", type=int, default=1)
    args = ap.parse_args(argv)
    run(4)  # load the kernels
    if args.dask:
        from dask.distributed import Client, LocalCluster

        cluster = LocalCluster(dashboard_address=None) if args.dask == "local" else None
        client = Client(cluster or args.dask)
        elapsed, ch = run(args.n, executor=client.get_executor())
        client.close()
        if cluster is not None:
            cluster.close()
    else:
        elapsed, ch = run(args.n, workers=args.workers)
    designs = ch.size
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    held = sum(v.data.nbytes + v.mask.nbytes for v in ch.values.values()) / 2**20
    held += sum(v.data.nbytes + v.mask.nbytes for v in ch.params.values()) / 2**20
    kern = kernel_alone(ch)
    print(f"{designs} designs x 360 angles ({ch.feasible.mean():.1%} feasible): {elapsed:.1f} s, "
          f"{designs * 360 / elapsed:.3g} evaluations/s")  # fmt: skip
    print(f"peak resident memory {rss:.0f} MiB; the chart's arrays {held:.0f} MiB")
    print(f"time / compiled kernel alone on the feasible designs ({kern:.1f} s): "
          f"{elapsed / kern:.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
