"""Benchmark: the costs that decide when a Linkage's sweep runs on its compiled kernel
(``charts.LINKAGE_COSTS``, ``LINKAGE_KERNEL_MIN``, ``LINKAGE_KERNEL_CACHED_MIN``), and a sweep
that starts before its kernel exists.

For paper 001's six-link (``ms.six_link()``; a chart over the rocker DB and the extra rod KN,
360 crank angles, the striker's stroke and maximum pressure angle):

* ``model``, ``kernel``: CPU seconds per design-angle evaluation of the chart (``N x N``
  designs, chunks of the sweep's default size) on the numpy model and on the kernel (loaded
  before timing), the best of ``--repeat`` runs;
* ``compile``: a new process with an empty kernel cache builds the kernel (``linkage_kernel``,
  blocking): CPU seconds of the process and its children (a C compiler runs as a child) and
  wall seconds, after importing the package;
* ``load``: a later process loads it from the disk cache (CPU and wall seconds; numba's import
  and start included where the kernel is numba's);
* a sweep of ``--big`` x ``--big`` designs in a new process with an empty cache, on the kernel
  whatever its size: wall seconds against the same chart on the model, and the share of the
  chunks that ran on the kernel (the rest ran on the model while it was built).

Each kernel backend the kernels module offers is measured in turn (``$MECHSYNTH_KERNELS``;
numba alone when the module has one backend). The thresholds these costs give are printed.

Run: ``python benchmarks/bench_sweep_switch.py [--n 100] [--big 300] [--repeat 3] [--json]``.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time

GRID = ("DB", 0.035, 0.05), ("KN", 0.06, 0.11)


def _chart_args(n):
    import numpy as np

    from mechsynth import objectives as ob

    grid = {name: np.linspace(lo, hi, n) for name, lo, hi in GRID}
    measures = {"stroke": ob.stroke("N"), "pressure": ob.max_pressure_angle("N")}
    return grid, measures


def _cpu():
    own = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def per_evaluation(n: int, repeat: int) -> dict:
    """CPU seconds per evaluation on the model and on the loaded kernel (this process)."""
    import mechsynth as ms
    from mechsynth.kinematics import linkage_kernels as lkk
    from mechsynth.synthesis import charts

    six = ms.six_link()
    grid, measures = _chart_args(n)
    charts.LINKAGE_KERNEL_MIN = charts.LINKAGE_KERNEL_CACHED_MIN = 0
    lkk.linkage_kernel(six)
    out = {}
    for name, kernels in (("model", False), ("kernel", True)):
        best = float("inf")
        for _ in range(repeat):
            t = time.process_time()
            charts.sweep(six, grid, measures, angles=360, progress=False, kernels=kernels)
            best = min(best, time.process_time() - t)
        out[name] = best / (n * n * 360)
    return out


def build(what: str) -> dict:
    """``compile`` or ``load``: the kernel built in this (new) process, timed."""
    import mechsynth as ms
    from mechsynth.kinematics import linkage_kernels as lkk

    six = ms.six_link()
    cpu, wall = _cpu(), time.perf_counter()
    kernel = lkk.linkage_kernel(six)
    assert kernel is not None
    return {what: _cpu() - cpu, f"{what} wall": time.perf_counter() - wall}


def cold_sweep(n: int) -> dict:
    """A sweep on an empty cache, on the kernel whatever its size, against the model's."""
    import mechsynth as ms
    from mechsynth.kinematics import linkage_kernels as lkk
    from mechsynth.synthesis import charts

    six = ms.six_link()
    grid, measures = _chart_args(n)
    charts.LINKAGE_KERNEL_MIN = charts.LINKAGE_KERNEL_CACHED_MIN = 0
    used = []
    real = lkk.linkage_batch
    lkk.linkage_batch = lambda *a, **k: used.append(1) or real(*a, **k)
    t = time.perf_counter()
    fast = charts.sweep(six, grid, measures, angles=360, progress=False)
    t_fast = time.perf_counter() - t
    chunks = -(-n * n // charts._default_chunk(
        charts._SweepSpec(six, {}, (1,), 1, {}, None, None, {}, ms.cycle(360), None, True),
        None))  # fmt: skip
    pending = lkk.kernel_pending(six)
    if pending is not None:
        pending.join()
    t = time.perf_counter()
    model = charts.sweep(six, grid, measures, angles=360, progress=False, kernels=False)
    t_model = time.perf_counter() - t
    import numpy as np

    for label in measures:
        a, b = fast.values[label].filled(0.0), model.values[label].filled(0.0)
        assert np.allclose(a, b, rtol=1e-12, atol=1e-12 * np.abs(b).max()), label
    return {"cold sweep wall": t_fast, "model sweep wall": t_model,
            "share on the kernel": len(used) / chunks, "designs": n * n}  # fmt: skip


def _run(mode, arg, env):
    out = subprocess.run(
        [sys.executable, __file__, "--mode", mode, "--arg", str(arg)],
        capture_output=True, text=True, check=True, env=env,
    )  # fmt: skip
    return json.loads(out.stdout.strip().splitlines()[-1])


def measure(backend: str | None, n: int, big: int, repeat: int) -> dict:
    env = dict(os.environ)
    if backend:
        env["MECHSYNTH_KERNELS"] = backend
    with tempfile.TemporaryDirectory() as cache:
        env["MECHSYNTH_CACHE_DIR"] = cache
        row = {"backend": backend or "numba"}
        row.update(_run("build", "compile", env))
        row.update(_run("build", "load", env))
        row.update(_run("evaluation", f"{n},{repeat}", env))
    with tempfile.TemporaryDirectory() as cache:
        env["MECHSYNTH_CACHE_DIR"] = cache
        row.update(_run("cold", big, env))
    return row


def thresholds(c: dict) -> tuple[float, float]:
    """The sweep's rule (``charts._pays_back``) on these costs: (compile, load)."""
    saved = c["model"] - c["kernel"]
    return tuple(c[b] / saved + c[f"{b} wall"] / c["model"] for b in ("compile", "load"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100, help="per-evaluation chart: N x N designs")
    ap.add_argument("--big", type=int, default=300, help="the cold sweep: N x N designs")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--mode", help=argparse.SUPPRESS)
    ap.add_argument("--arg", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.mode == "build":
        print(json.dumps(build(args.arg)))
        return
    if args.mode == "evaluation":
        n, repeat = map(int, args.arg.split(","))
        print(json.dumps(per_evaluation(n, repeat)))
        return
    if args.mode == "cold":
        print(json.dumps(cold_sweep(int(args.arg))))
        return
    from mechsynth.kinematics import linkage_kernels as lkk

    backends = ["c", "numba"] if hasattr(lkk, "kernel_backend") else [None]
    rows = [measure(b, args.n, args.big, args.repeat) for b in backends]
    if args.json:
        print(json.dumps(rows, indent=2))
        return
    print(f"paper 001's six-link, 360 angles (load average {os.getloadavg()[0]:.1f}: the "
          "machine is shared)")  # fmt: skip
    for r in rows:
        lo, hi = thresholds(r)
        print(
            f"{r['backend']}: model {r['model'] * 1e9:.0f} ns, kernel {r['kernel'] * 1e9:.0f} ns "
            f"of CPU per evaluation; compile {r['compile']:.2f} s CPU ({r['compile wall']:.2f} "
            f"s wall), load {r['load']:.2f} s CPU ({r['load wall']:.2f} s wall)\n"
            f"   thresholds: compile from {lo:.2g}, load from {hi:.2g} evaluations\n"
            f"   {r['designs']:,d} designs from an empty cache: {r['cold sweep wall']:.2f} s "
            f"({r['share on the kernel']:.0%} of the chunks on the kernel), on the model alone "
            f"{r['model sweep wall']:.2f} s"
        )


if __name__ == "__main__":
    main()
