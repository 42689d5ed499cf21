"""Linkages on kernels generated from their own solve (``mechsynth.kinematics.linkage_kernels``):
compilation, agreement with the model, throughput and a chart against the numpy model.

Paper 001's six-link (crank, RRR, a point on the rocker, RRP). The script reports

* the kernel's first compilation in a fresh process with an empty cache directory, and its load
  from the disk cache in another fresh process (each includes importing CasADi and tracing);
* that the kernel agrees with ``Linkage.motion`` to 1e-12 (every output, on the batch below);
* design-angle evaluations per second of the kernel (every output of the motion, one thread)
  and of the numpy model, on the sweep's chunk of designs, as a ratio in the same run;
* a ``sweep`` chart over a grid of rocker and rod lengths at 360 angles on the kernel and on the
  model (``kernels=False``), as a ratio, and that the two charts agree;
* the same chart written by hand on the kernel (a loop over chunks into one reused block, the
  measures reduced from its rows), as the sweep's reference.

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
    charts.LINKAGE_KERNEL_MIN = 0  # on the kernel whatever the chart's size
    charts.LINKAGE_KERNEL_CACHED_MIN = 0
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

    # the same chart written by hand on the kernel: chunks of designs into one reused block,
    # the two measures reduced from its rows (the feasible designs' values checked)
    at = {(kind, key): off for kind, key, off, _ in kernel.layout}
    v_row, p_row = at["sliders", "N"] + 1, at["pressure", "N"]
    db, ab = (a.ravel() for a in np.meshgrid(grid["DB"], grid["AB"], indexing="ij"))
    params = np.tile([six.parameters[k] for k in kernel.names], (db.size, 1))
    params[:, kernel.names.index("DB")], params[:, kernel.names.index("AB")] = db, ab
    block = np.empty((kernel.outputs, chunk, phi.size))
    flags = np.empty((chunk, 2))
    speed = (ms.rpm(600), 0.0)

    def by_hand():
        peak, press = np.empty(db.size), np.empty(db.size)
        for i in range(0, db.size, chunk):
            k = min(chunk, db.size - i)
            kernel(params[i : i + k], phi, block[:, :k], flags[:k], speed=speed)
            peak[i : i + k] = np.abs(block[v_row, :k]).max(axis=1)
            press[i : i + k] = block[p_row, :k].max(axis=1)
        return peak, press

    peak, press = by_hand()
    ok = fast.feasible.ravel()
    assert np.allclose(peak[ok], fast.values["peak velocity"].ravel()[ok], rtol=1e-12)
    assert np.allclose(press[ok], fast.values["pressure"].ravel()[ok], rtol=1e-12)
    t_hand = timed(by_hand, args.repeat)
    print(
        f"the chart written by hand on the kernel: {t_hand:.2f} s; sweep / by hand "
        f"x {t_fast / t_hand:.2f}"
    )


if __name__ == "__main__":
    main()
