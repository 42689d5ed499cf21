"""Benchmark: one design x 360 crank angles, the calls a user makes on one mechanism.

Each figure is printed as a ratio to a plain-numpy reference written below, in the same run:

* ``FourBar(...).motion(phi)`` against :func:`ref_four_bar_motion` (the same outputs: the tracks
  of A and B, the coupler and rocker angles with their analogs, transmission and pressure
  angles), ``SliderCrank(...).motion(phi)`` against :func:`ref_slider_crank_motion`;
* ``four_bar_batch`` / ``slider_crank_batch`` on one design against the references of their six
  outputs (:func:`ref_four_bar_batch`, :func:`ref_slider_crank_batch`);
* batches of 1 to 10,000 designs under the default threading against one numba thread (the
  default must never be slower), median and 90th percentile of the call time.

The target is a ratio <= 1 for the single-design calls. Every reference is checked against the
package's result before it is timed.

Run: ``python benchmarks/bench_small_calls.py [--repeat N] [--json]``.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

import mechsynth as ms
from mechsynth.kinematics.compiled import four_bar_batch, slider_crank_batch


# ------------------------------------------------------------------ plain-numpy references
def ref_four_bar_batch(a, b, c, d, phi):
    """Rocker and coupler angle, analog velocity and acceleration (the batch's six outputs)."""
    cp, sp = np.cos(phi), np.sin(phi)
    ax, ay = a * cp, a * sp
    dax, day, ddax, dday = -ay, ax, -ax, -ay
    ux, uy = d - ax, -ay  # A -> O2
    r2 = ux * ux + uy * uy
    f = (b * b - c * c + r2) / (2.0 * r2)
    h = np.sqrt(b * b / r2 - f * f)
    bx, by = ax + f * ux - h * uy, ay + f * uy + h * ux
    c1, s1 = (bx - ax) / b, (by - ay) / b
    c2, s2 = (bx - d) / c, by / c
    sn = s2 * c1 - c2 * s1
    w1 = (-dax * c2 - day * s2) / (b * sn)
    w2 = (-dax * c1 - day * s1) / (c * sn)
    rx = -ddax + b * w1 * w1 * c1 - c * w2 * w2 * c2
    ry = -dday + b * w1 * w1 * s1 - c * w2 * w2 * s2
    e1 = (rx * c2 + ry * s2) / (b * sn)
    e2 = (rx * c1 + ry * s1) / (c * sn)
    t1, t2 = np.arctan2(by - ay, bx - ax), np.arctan2(by, bx - d)
    return (t2, w2, e2, t1, w1, e1), (ax, ay, dax, day, ddax, dday, bx, by, c1, s1)


def ref_four_bar_motion(a, b, c, d, phi):
    """Everything ``FourBar.motion`` returns: the above, B's velocity and acceleration, mu."""
    (t2, w2, e2, t1, w1, e1), (ax, ay, dax, day, ddax, dday, bx, by, c1, s1) = ref_four_bar_batch(
        a, b, c, d, phi
    )
    dbx, dby = dax - b * w1 * s1, day + b * w1 * c1
    ddbx = ddax - b * e1 * s1 - b * w1 * w1 * c1
    ddby = dday + b * e1 * c1 - b * w1 * w1 * s1
    mu = np.arccos(np.cos(t1 - t2))
    return (ax, ay, dax, day, ddax, dday, bx, by, dbx, dby, ddbx, ddby, t1, w1, e1, t2, w2, e2,
            mu, np.abs(np.pi / 2 - mu))  # fmt: skip


def ref_slider_crank_batch(a, b, e, phi):
    """Slider position, analog velocity and acceleration; rod angle and its analogs."""
    cp, sp = np.cos(phi), np.sin(phi)
    ax, ay = a * cp, a * sp
    hgt = ay - e
    w = np.sqrt(b * b - hgt * hgt)
    h1, h2 = a * cp, -ay
    w_1 = -hgt * h1 / w
    w_2 = -(h1 * h1 + hgt * h2) / w - (hgt * h1) ** 2 / (w * w * w)
    x, v, acc = ax + w, -ay + w_1, -ax + w_2
    theta = np.arctan2(-hgt, w)
    # rod angle analogs from b cos(theta) = x - ax, b sin(theta) = e - ay
    ct, st = w / b, -hgt / b
    om = -h1 / (b * ct)
    eps = (-h2 + b * om * om * st) / (b * ct)
    return (x, v, acc, theta, om, eps), (ax, ay, ct, st)


def ref_slider_crank_motion(a, b, e, phi):
    """Everything ``SliderCrank.motion`` returns: A's and B's tracks, the rod, pressure angle."""
    (x, v, acc, theta, om, eps), (ax, ay, ct, st) = ref_slider_crank_batch(a, b, e, phi)
    pressure = np.arcsin(np.abs(e - ay) / b)
    return (ax, ay, -ay, ax, -ax, -ay, x, e + 0 * x, v, 0 * v, acc, 0 * acc, theta, om, eps,
            pressure, np.pi / 2 - pressure)  # fmt: skip


# ------------------------------------------------------------------ timing
def per_call(fn, repeat, number=20):
    """Median and 90th percentile (s) of one call over ``repeat`` samples of ``number`` calls."""
    fn()
    samples = []
    for _ in range(repeat):
        t = time.perf_counter()
        for _ in range(number):
            fn()
        samples.append((time.perf_counter() - t) / number)
    return float(np.median(samples)), float(np.percentile(samples, 90))


def single_calls(phi, repeat):
    fb_dims = (1.0, 4.3, 3.0, 5.2)
    sc_dims = (0.07, 0.24, 0.01)
    fb, sc = ms.FourBar(*fb_dims), ms.SliderCrank(*sc_dims)
    m = fb.motion(phi)
    ref = ref_four_bar_motion(*fb_dims, phi)
    assert np.allclose(m.links["rocker"].epsilon, ref[17], atol=1e-9)
    assert np.allclose(m.points["B"].ax, ref[10], atol=1e-9)
    m = sc.motion(phi)
    ref = ref_slider_crank_motion(*sc_dims, phi)
    assert np.allclose(m.slider.acceleration, ref[10], atol=1e-12)
    assert np.allclose(m.links["rod"].epsilon, ref[14], atol=1e-9)
    r = four_bar_batch(*fb_dims, phi)
    assert np.allclose(r.rocker_epsilon[0], ref_four_bar_batch(*fb_dims, phi)[0][2], atol=1e-9)
    r = slider_crank_batch(*sc_dims, phi)
    assert np.allclose(r.rod_epsilon[0], ref_slider_crank_batch(*sc_dims, phi)[0][5], atol=1e-9)
    cases = {
        "FourBar(...).motion": (
            lambda: ms.FourBar(*fb_dims).motion(phi),
            lambda: ref_four_bar_motion(*fb_dims, phi),
        ),
        "SliderCrank(...).motion": (
            lambda: ms.SliderCrank(*sc_dims).motion(phi),
            lambda: ref_slider_crank_motion(*sc_dims, phi),
        ),
        "four_bar_batch, 1 design": (
            lambda: four_bar_batch(*fb_dims, phi),
            lambda: ref_four_bar_batch(*fb_dims, phi),
        ),
        "slider_crank_batch, 1 design": (
            lambda: slider_crank_batch(*sc_dims, phi),
            lambda: ref_slider_crank_batch(*sc_dims, phi),
        ),
    }
    rows = {}
    for name, (ours, reference) in cases.items():
        t_ours, p90 = per_call(ours, repeat)
        t_ref, _ = per_call(reference, repeat)
        rows[name] = {"us": 1e6 * t_ours, "p90_us": 1e6 * p90, "ref_us": 1e6 * t_ref,
                      "ratio": t_ours / t_ref}  # fmt: skip
    return rows


def threading(phi, repeat):
    """Default threading against one thread, for batches of growing size."""
    import numba

    rng = np.random.default_rng(1)
    rows = {}
    default = numba.get_num_threads()
    for n in (1, 10, 100, 1000, 10000):
        a = rng.uniform(0.9, 1.1, n)
        out = np.empty((6, n, phi.size))
        number = max(1, 2000 // n)
        res = {}
        for label, threads in (("default", default), ("one thread", 1)):
            numba.set_num_threads(threads)
            try:
                res[label] = per_call(
                    lambda a=a, out=out: four_bar_batch(a, 4.3, 3.0, 5.2, phi, out=out),
                    max(5, repeat // 4),
                    number,
                )
            finally:
                numba.set_num_threads(default)
        rows[n] = {
            "default_us": 1e6 * res["default"][0],
            "default_p90_us": 1e6 * res["default"][1],
            "one_thread_us": 1e6 * res["one thread"][0],
            "ratio": res["default"][0] / res["one thread"][0],
        }
    return rows, default


def bound(n=4000, m=360, repeat=5):
    """What bounds the compiled four-bar kernel: its time into a reused ``(6, n, m)`` array on
    one thread against writing that array (``fill``) and one numpy division pass over as many
    elements, in the same run."""
    import numba

    rng = np.random.default_rng(0)
    a = rng.uniform(0.9, 1.1, n)
    phi = np.linspace(0.0, 2 * np.pi, m, endpoint=False)
    out = np.empty((6, n, m))
    x, y = rng.uniform(1.0, 2.0, 6 * n * m), np.empty(6 * n * m)

    def best(fn):
        fn()
        times = []
        for _ in range(repeat):
            t = time.perf_counter()
            fn()
            times.append(time.perf_counter() - t)
        return min(times)

    before = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        t_kernel = best(lambda: four_bar_batch(a, 4.3, 3.0, 5.2, phi, out=out))
    finally:
        numba.set_num_threads(before)
    t_fill = best(lambda: out.fill(1.0))
    t_div = best(lambda: np.divide(1.0, x[: n * m], out=y[: n * m]))
    return {
        "kernel_s": t_kernel,
        "evaluations_per_s": n * m / t_kernel,
        "write_share": t_fill / t_kernel,
        "write_GBps": out.nbytes / t_kernel / 1e9,
        "fill_GBps": out.nbytes / t_fill / 1e9,
        "division_passes": t_kernel / t_div,
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--angles", type=int, default=360)
    ap.add_argument("--repeat", type=int, default=40)
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--bound", action="store_true", help="only: what bounds the kernel")
    args = ap.parse_args(argv)
    if args.bound:
        b = bound()
        if args.json:
            print(json.dumps(b, indent=2))
            return
        print(f"four-bar kernel, 4,000 designs x 360 angles, 1 thread: {b['kernel_s'] * 1e3:.1f} ms"
              f" ({b['evaluations_per_s']:.3g} evaluations/s)")  # fmt: skip
        print(f"  writes {b['write_GBps']:.2f} GB/s; writing the array alone ({b['fill_GBps']:.2f}"
              f" GB/s) takes {b['write_share']:.0%} of the kernel's time")  # fmt: skip
        print(
            f"  the kernel costs {b['division_passes']:.0f} numpy division passes over as "
            "many elements: compute-bound"
            if b["write_share"] < 0.5
            else "  memory-bound"
        )
        return
    phi = np.linspace(0.0, 2 * np.pi, args.angles, endpoint=False)
    single = single_calls(phi, args.repeat)
    threads, default = threading(phi, args.repeat)
    if args.json:
        print(json.dumps({"single": single, "threading": threads, "threads": default}, indent=2))
        return
    print(f"one design x {args.angles} angles (median per call; reference: plain numpy)")
    for name, r in single.items():
        print(f"  {name:30s} {r['us']:8.1f} us (p90 {r['p90_us']:7.1f})  numpy {r['ref_us']:7.1f}"
              f" us  ratio {r['ratio']:5.2f}")  # fmt: skip
    print(f"four_bar_batch x {args.angles} angles, default threading ({default} threads) vs one")
    for n, r in threads.items():
        print(f"  {n:6d} designs  {r['default_us']:10.1f} us (p90 {r['default_p90_us']:9.1f})"
              f"  one thread {r['one_thread_us']:10.1f} us  ratio {r['ratio']:5.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
