"""Benchmark: one design x 360 crank angles, the calls a user makes on one mechanism.

Each figure is printed as a ratio to a plain-numpy reference written below, in the same run:

* ``FourBar(...).motion(phi)`` against :func:`ref_four_bar_motion`, ``SliderCrank(...).motion(phi)``
  against :func:`ref_slider_crank_motion`: every output the motion holds (the tracks of every
  point, the fixed pivots' included, of every link, the crank's included, and of the slider,
  the pressure and transmission angles), each its own array as in the motion;
* ``four_bar_batch`` / ``slider_crank_batch`` on one design against the references of their six
  outputs (:func:`ref_four_bar_batch`, :func:`ref_slider_crank_batch`);
* batches of 1 to 10,000 designs under the default threading against one numba thread (the
  default must never be slower), median and 90th percentile of the call time.

The target is a ratio <= 1 for the single-design calls. Every reference is checked against the
package's result before it is timed (for the motions: every output, and that no two share
memory). The calls repeat one grid of angles, as a loop over designs or a sweep does; the
package remembers the cosines and sines of the last grid (:func:`mechsynth.kinematics.ops.
cos_sin`), the references compute them on every call; ``--fresh-grid`` gives every call its own
grid (the references' cost is the same; the package's then includes them).

Run: ``python benchmarks/bench_small_calls.py [--repeat N] [--json]``.
"""

from __future__ import annotations

import argparse
import itertools
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
    """Everything ``FourBar.motion`` returns, each output its own array as there: the tracks of
    O1 (zeros), A, B (with its velocity and acceleration) and O2 (x = ground), the crank
    (angle phi, 1, 0), coupler and rocker, the transmission and pressure angles."""
    (t2, w2, e2, t1, w1, e1), (ax, ay, dax, day, ddax, dday, bx, by, c1, s1) = ref_four_bar_batch(
        a, b, c, d, phi
    )
    dbx, dby = dax - b * w1 * s1, day + b * w1 * c1
    ddbx = ddax - b * e1 * s1 - b * w1 * w1 * c1
    ddby = dday + b * e1 * c1 - b * w1 * w1 * s1
    mu = np.arccos(np.cos(t1 - t2))
    z = np.zeros((12, *phi.shape))  # O1's six, O2's five, the crank's angular acceleration
    return (*z[:6], ax, ay, dax, day.copy(), ddax, dday, bx, by, dbx, dby, ddbx, ddby,
            np.full(phi.shape, d), *z[6:11], phi.copy(), np.ones(phi.shape), z[11],
            t1, w1, e1, t2, w2, e2, np.abs(np.pi / 2 - mu), mu)  # fmt: skip


def four_bar_outputs(m):
    """The arrays of a four-bar ``Motion`` in the order of :func:`ref_four_bar_motion`."""
    out = [x for k in ("O1", "A", "B", "O2") for x in vars(m.points[k]).values()]
    out += [x for k in ("crank", "coupler", "rocker") for x in vars(m.links[k]).values()]
    return [*out, m.pressure_angle, m.transmission_angle]


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
    """Everything ``SliderCrank.motion`` returns, each output its own array as there: the tracks
    of O (zeros), A and B, the crank (angle phi, 1, 0) and the rod, the slider, the pressure and
    transmission angles."""
    (x, v, acc, theta, om, eps), (ax, ay, ct, st) = ref_slider_crank_batch(a, b, e, phi)
    pressure = np.arcsin(np.abs(e - ay) / b)
    z = np.zeros((9, *phi.shape))  # O's six, B's y analogs, the crank's angular acceleration
    return (*z[:6], ax, ay, -ay, ax.copy(), -ax, -ay, x, np.full(phi.shape, e), v, z[6], acc,
            z[7], phi.copy(), np.ones(phi.shape), z[8], theta, om, eps, x.copy(), v.copy(),
            acc.copy(), pressure, np.pi / 2 - pressure)  # fmt: skip


def slider_crank_outputs(m):
    """The arrays of a slider-crank ``Motion`` in the order of :func:`ref_slider_crank_motion`."""
    out = [x for k in ("O", "A", "B") for x in vars(m.points[k]).values()]
    out += [x for k in ("crank", "rod") for x in vars(m.links[k]).values()]
    out += list(vars(m.slider).values())
    return [*out, m.pressure_angle, m.transmission_angle]


def check_same(ours, ref, name):
    """Every output of the package equals the reference's, as a separate array of the same
    shape (no output shares memory with another)."""
    assert len(ours) == len(ref), name
    for i, (x, y) in enumerate(zip(ours, ref)):
        assert np.shape(x) == np.shape(y) and np.allclose(x, y, rtol=1e-9, atol=1e-9), (name, i)
    for group in (ours, ref):
        arrays = [x for x in group if isinstance(x, np.ndarray)]
        assert len({id(x) for x in arrays}) == len(arrays), name
        for i, x in enumerate(arrays):
            assert not any(np.shares_memory(x, y) for y in arrays[i + 1 :]), (name, i)


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


def paired(ours, reference, repeat, number=20):
    """Median and 90th percentile (s) of one call of ``ours`` and the median of ``reference``,
    their samples of ``number`` calls taken in turns (a change of the machine's load falls on
    both)."""
    ours(), reference()
    a, b = [], []
    for _ in range(repeat):
        for fn, samples in ((ours, a), (reference, b)):
            t = time.perf_counter()
            for _ in range(number):
                fn()
            samples.append((time.perf_counter() - t) / number)
    return float(np.median(a)), float(np.percentile(a, 90)), float(np.median(b))


def single_calls(phi, repeat, fresh=False):
    """The single-design calls against their references. ``fresh``: every call on its own grid
    (the grids differ in the last bits), so nothing is remembered from the call before."""
    fb_dims = (1.0, 4.3, 3.0, 5.2)
    sc_dims = (0.07, 0.24, 0.01)
    fb, sc = ms.FourBar(*fb_dims), ms.SliderCrank(*sc_dims)
    check_same(four_bar_outputs(fb.motion(phi)), ref_four_bar_motion(*fb_dims, phi), "four-bar")
    check_same(
        slider_crank_outputs(sc.motion(phi)), ref_slider_crank_motion(*sc_dims, phi), "slider"
    )
    r = four_bar_batch(*fb_dims, phi)
    assert np.allclose(r.rocker_epsilon[0], ref_four_bar_batch(*fb_dims, phi)[0][2], atol=1e-9)
    r = slider_crank_batch(*sc_dims, phi)
    assert np.allclose(r.rod_epsilon[0], ref_slider_crank_batch(*sc_dims, phi)[0][5], atol=1e-9)
    grids = [phi * (1.0 + k * 1e-15) for k in range(64)] if fresh else [phi]
    nxt = itertools.cycle(grids).__next__
    cases = {
        "FourBar(...).motion": (
            lambda: ms.FourBar(*fb_dims).motion(nxt()),
            lambda: ref_four_bar_motion(*fb_dims, nxt()),
        ),
        "SliderCrank(...).motion": (
            lambda: ms.SliderCrank(*sc_dims).motion(nxt()),
            lambda: ref_slider_crank_motion(*sc_dims, nxt()),
        ),
        "four_bar_batch, 1 design": (
            lambda: four_bar_batch(*fb_dims, nxt()),
            lambda: ref_four_bar_batch(*fb_dims, nxt()),
        ),
        "slider_crank_batch, 1 design": (
            lambda: slider_crank_batch(*sc_dims, nxt()),
            lambda: ref_slider_crank_batch(*sc_dims, nxt()),
        ),
    }
    rows = {}
    for name, (ours, reference) in cases.items():
        t_ours, p90, t_ref = paired(ours, reference, repeat)
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
    ap.add_argument(
        "--fresh-grid", action="store_true", help="every single-design call on a new grid"
    )
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
    single = single_calls(phi, args.repeat, args.fresh_grid)
    threads, default = threading(phi, args.repeat)
    if args.json:
        print(json.dumps({"single": single, "threading": threads, "threads": default}, indent=2))
        return
    grid = "a new grid every call" if args.fresh_grid else "one grid"
    print(f"one design x {args.angles} angles, {grid} (median per call; reference: plain numpy)")
    for name, r in single.items():
        print(f"  {name:30s} {r['us']:8.1f} us (p90 {r['p90_us']:7.1f})  numpy {r['ref_us']:7.1f}"
              f" us  ratio {r['ratio']:5.2f}")  # fmt: skip
    print(f"four_bar_batch x {args.angles} angles, default threading ({default} threads) vs one")
    for n, r in threads.items():
        print(f"  {n:6d} designs  {r['default_us']:10.1f} us (p90 {r['default_p90_us']:9.1f})"
              f"  one thread {r['one_thread_us']:10.1f} us  ratio {r['ratio']:5.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
