"""Benchmark: full kinematics of a batch of four-bars and slider-cranks over a turn.

Positions, velocities and accelerations (analogs) of the output (rocker angle / slider position)
and of the coupler (rod) angle, for 10,000 random designs x 360 crank angles, by

* the numpy model (``backend="numpy"``: ``FourBar.jets`` / ``SliderCrank.jets`` in chunks),
* the compiled kernels (``backend="numba"``), on one thread (``numba.set_num_threads(1)``, the
  headline figure) and on all threads, with a fresh output array and into a reused one,
* a straightforward Python loop calling ``motion`` one design and one angle at a time, timed on
  a small subset and extrapolated per evaluation.

Peak memory is traced with ``tracemalloc`` in a separate, untimed run of each path.

Run: ``python benchmarks/bench_kinematics.py [--designs N] [--angles M] [--json]``.
"""

from __future__ import annotations

import argparse
import json
import resource
import time
import tracemalloc

import numpy as np

from mechsynth.kinematics import FourBar, SliderCrank
from mechsynth.kinematics.compiled import (
    four_bar_batch,
    numba_available,
    slider_crank_batch,
)


def crank_rockers(n, rng):
    """Random crank-rockers with a margin on both full-turn conditions."""
    b, c, d = rng.uniform(0.5, 3.0, (3, 4 * n))
    upper = np.minimum(b + c - d, d - np.abs(b - c))
    ok = upper > 0.1
    b, c, d, upper = b[ok][:n], c[ok][:n], d[ok][:n], upper[ok][:n]
    a = rng.uniform(0.1, 0.9, b.size) * upper
    return a, b, c, d


def slider_cranks(n, rng):
    a = rng.uniform(0.05, 1.0, n)
    e = rng.uniform(-0.5, 0.5, n) * a
    b = (a + np.abs(e)) * rng.uniform(1.2, 4.0, n)
    return a, b, e


def best_time(fn, repeat=3):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def peak_mib(fn):
    tracemalloc.start()
    fn()
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak / 2**20


def loop_four_bar(a, b, c, d, phi):
    for i in range(a.size):
        fb = FourBar(a[i], b[i], c[i], d[i])
        for p in phi:
            m = fb.motion(float(p))
            r, k = m.links["rocker"], m.links["coupler"]
            _ = (r.angle, r.omega, r.epsilon, k.angle, k.omega, k.epsilon)


def loop_slider_crank(a, b, e, phi):
    for i in range(a.size):
        sc = SliderCrank(a[i], b[i], e[i])
        for p in phi:
            m = sc.motion(float(p))
            s, r = m.slider, m.links["rod"]
            _ = (s.position, s.velocity, s.acceleration, r.angle, r.omega, r.epsilon)


def bench(name, batch, loop, params, phi, loop_designs):
    n, m = params[0].size, phi.size
    evals = n * m
    rows = {}

    def run(backend, out=None):
        return lambda: batch(*params, phi, backend=backend, out=out)

    rows["numpy"] = (best_time(run("numpy"), 2), peak_mib(run("numpy")))
    if numba_available():
        import numba

        threads = numba.get_num_threads()
        batch(*(p[:4] for p in params), phi, "numba")  # compile or load the kernels
        buf = np.empty((6, n, m))
        ref = batch(*params, phi, backend="numpy")
        fast = batch(*params, phi, backend="numba", out=buf)
        worst = max_rel_diff(fast, ref)
        numba.set_num_threads(1)
        rows["numba, 1 thread, new output"] = (best_time(run("numba")), peak_mib(run("numba")))
        rows["numba, 1 thread, reused output"] = (
            best_time(run("numba", buf)),
            peak_mib(run("numba", buf)),
        )
        numba.set_num_threads(threads)
        rows[f"numba, {threads} threads, reused output"] = (
            best_time(run("numba", buf)),
            peak_mib(run("numba", buf)),
        )
    else:
        worst = float("nan")
    sub = [p[:loop_designs] for p in params]
    t_loop = best_time(lambda: loop(*sub, phi), 1)
    per_eval_loop = t_loop / (loop_designs * m)

    print(f"\n{name}: {n} designs x {m} crank angles = {evals:.3g} evaluations")
    print(f"  {'path':36s} {'time, s':>9s} {'evals/s':>10s} {'peak MiB':>9s} {'x loop':>8s}")
    result = {"designs": n, "angles": m, "paths": {}}
    for path, (t, mem) in rows.items():
        rate = evals / t
        speedup = per_eval_loop * evals / t
        print(f"  {path:36s} {t:9.3f} {rate:10.3g} {mem:9.1f} {speedup:8.0f}")
        result["paths"][path] = {
            "seconds": t,
            "evals_per_s": rate,
            "peak_mib": mem,
            "x_loop": speedup,
        }
    print(
        f"  {'Python loop (extrapolated)':36s} {per_eval_loop * evals:9.1f} "
        f"{1 / per_eval_loop:10.3g} {'':9s} {1:8.0f}"
    )
    print(
        f"  (loop timed on {loop_designs} designs x {m} angles = {loop_designs * m} calls of "
        f"motion(), extrapolated; numba vs numpy max relative difference {worst:.2g})"
    )
    print(
        f"  (peak MiB: tracemalloc peak of one call; a reused output array of "
        f"{6 * evals * 8 / 2**20:.0f} MiB is allocated once outside it)"
    )
    result["python_loop"] = {
        "evals_per_s": 1 / per_eval_loop,
        "timed_designs": loop_designs,
        "extrapolated": True,
    }
    result["max_rel_diff_numba_numpy"] = worst
    return result


def max_rel_diff(x, y):
    """Largest difference between two batch results, relative to each array's largest entry
    (at least 1); angles compared modulo 2 pi."""
    worst = 0.0
    for f in x.__dataclass_fields__:
        if f == "backend":
            continue
        u, v = getattr(x, f), getattr(y, f)
        diff = np.angle(np.exp(1j * (u - v))) if f.endswith("angle") else u - v
        worst = max(worst, float(np.max(np.abs(diff)) / max(1.0, float(np.max(np.abs(v))))))
    return worst


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--designs", type=int, default=10_000)
    ap.add_argument("--angles", type=int, default=360)
    ap.add_argument("--loop-designs", type=int, default=10, help="designs timed in the loop")
    ap.add_argument("--json", action="store_true", help="print the figures as JSON at the end")
    args = ap.parse_args(argv)
    rng = np.random.default_rng(2024)
    phi = np.linspace(0.0, 2.0 * np.pi, args.angles, endpoint=False)

    def fb_batch(a, b, c, d, phi, backend, out=None):
        return four_bar_batch(a, b, c, d, phi, backend=backend, out=out)

    def sc_batch(a, b, e, phi, backend, out=None):
        return slider_crank_batch(a, b, e, phi, backend=backend, out=out)

    out = {
        "four_bar": bench(
            "Four-bar (rocker and coupler: angle, omega, epsilon)",
            fb_batch,
            loop_four_bar,
            crank_rockers(args.designs, rng),
            phi,
            args.loop_designs,
        ),
        "slider_crank": bench(
            "Slider-crank (slider: position, velocity, acceleration; rod: angle, omega, epsilon)",
            sc_batch,
            loop_slider_crank,
            slider_cranks(args.designs, rng),
            phi,
            args.loop_designs,
        ),
    }
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"\nprocess peak resident memory: {rss:.0f} MiB")
    out["peak_rss_mib"] = rss
    if args.json:
        print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
