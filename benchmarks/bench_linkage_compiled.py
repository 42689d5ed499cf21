"""Linkages on kernels generated from their own solve (``mechsynth.kinematics.linkage_kernels``):
compilation, agreement with the model, throughput and a chart against the numpy model.

Paper 001's six-link (crank, RRR, a point on the rocker, RRP). The script reports

* the kernel's first compilation in a fresh process with an empty cache directory, and its load
  from the disk cache in another fresh process (each includes importing CasADi and tracing);
* that the kernel agrees with ``Linkage.motion`` to 1e-12 (every output, on the batch below);
* design-angle evaluations per second of the kernel (every output of the motion, one thread)
  and of the numpy model, on the sweep's chunk of designs, as a ratio in the same run;
* a ``sweep`` chart over a grid of rocker and rod lengths at 360 angles on the kernel and on the
  model (``kernels=False``), as a ratio, and that the two charts agree.

Run: python benchmarks/bench_linkage_compiled.py [--grid N] [--repeat R]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import mechsynth as ms
from mechsynth.kinematics import linkage_kernels as lkk
from mechsynth.kinematics.compiled import BatchWorkspace
from mechsynth.objectives.kinematic import peak_velocity
from mechsynth.synthesis import charts


def six_link():
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)}, name="six-link")
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
        .attach("K", on=("D", "B"), along=-0.05)
        .rrp("N", ("K", 0.10), guide=((0.12, 0.0), ms.deg(57)))
    )


_CHILD = """
import time
t = time.perf_counter()
import mechsynth.kinematics.linkage_kernels as lkk
from bench_linkage_compiled import six_link
lkk.linkage_kernel(six_link())
print(time.perf_counter() - t)
"""


def fresh_process_seconds(cache: str) -> float:
    env = dict(os.environ, MECHSYNTH_CACHE_DIR=cache)
    here = os.path.dirname(os.path.abspath(__file__))
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [here, env.get("PYTHONPATH", "")]))
    out = subprocess.run(
        [sys.executable, "-c", _CHILD], env=env, capture_output=True, text=True, check=True
    )
    return float(out.stdout.split()[-1])


def timed(fn, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--grid", type=int, default=100, help="chart of N x N designs")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    import numba

    numba.set_num_threads(1)
    with tempfile.TemporaryDirectory() as cache:
        first = fresh_process_seconds(cache)
        again = fresh_process_seconds(cache)
    print(f"kernel of the six-link: first compilation {first:.1f} s, later processes {again:.2f} s")

    six = six_link()
    kernel = lkk.linkage_kernel(six)
    phi = ms.cycle(360)
    chunk = max(1, 2**16 // phi.size)  # the sweep's chunk of designs
    rng = np.random.default_rng(0)
    batch = six(DB=rng.uniform(0.07, 0.09, (chunk, 1)), AB=rng.uniform(0.115, 0.125, (chunk, 1)))
    ref = batch.motion(phi)
    motion, good, _ = lkk.linkage_batch(batch, phi, kernel=kernel)
    assert good.all()
    worst = 0.0
    for k, p in ref.points.items():
        for f in ("x", "y", "vx", "vy", "ax", "ay"):
            a, b = getattr(p, f), getattr(motion.points[k], f)
            worst = max(worst, float(np.max(np.abs(a - b)) / max(1.0, np.max(np.abs(a)))))
    assert worst < 1e-12, worst
    print(f"kernel = Linkage.motion to {worst:.1e} (every point's tracks; the tests check all)")

    ws = BatchWorkspace()
    tk = timed(lambda: lkk.linkage_batch(batch, phi, workspace=ws, kernel=kernel), args.repeat)
    tn = timed(lambda: batch.motion(phi), args.repeat)
    evals = chunk * phi.size
    print(
        f"{chunk} designs x {phi.size} angles (a sweep's chunk), one thread: kernel "
        f"{evals / tk:.3g} evaluations/s, numpy model {evals / tn:.3g} (kernel x {tn / tk:.2g})"
    )

    n = args.grid
    grid = {"DB": np.linspace(0.03, 0.16, n), "AB": np.linspace(0.09, 0.15, n)}
    measures = {
        "peak velocity": peak_velocity(),
        "pressure": lambda mech, m: np.max(m.pressure_angle, axis=-1),
    }
    kw = dict(angles=360, speed=ms.rpm(600), progress=False)
    fast = charts.sweep(six, grid, measures, **kw)
    t_fast = timed(lambda: charts.sweep(six, grid, measures, **kw), args.repeat)
    model = charts.sweep(six, grid, measures, kernels=False, **kw)
    t_model = timed(lambda: charts.sweep(six, grid, measures, kernels=False, **kw), 1)
    assert np.array_equal(fast.feasible, model.feasible)
    for label in measures:
        a, b = fast.values[label].filled(0.0), model.values[label].filled(0.0)
        assert np.allclose(a, b, rtol=1e-12, atol=1e-15), label
    print(
        f"chart of {n} x {n} six-links x 360 angles ({fast.feasible.mean():.0%} assemble): "
        f"kernel {t_fast:.2f} s, numpy model {t_model:.2f} s (x {t_model / t_fast:.2g}); "
        "the same feasibility and values"
    )


if __name__ == "__main__":
    main()
