"""Benchmark: a design chart through ``synthesis.sweep`` against the same chart written by hand on
the package's compiled kernel, in the same run.

The chart: offset slider-cranks of a 100 mm stroke over ``N x N`` values of rod/crank x
offset/crank, 360 crank angles, 600 rpm; measures: peak slider acceleration, maximum pressure
angle, time ratio, rod length (:func:`mechsynth.synthesis.charts.slider_crank_chart`).

* ``sweep`` on the compiled path (the default), and on the numpy model (``kernels=False``);
* the reference: a loop over blocks of designs calling ``slider_crank_batch`` into one reused
  output array and reducing each block by hand (:func:`hand_written`).

Each is timed (median of ``--repeat``) and its minor page faults counted with
``resource.getrusage`` (``ru_minflt``); the targets are a ratio to the reference of at most 1.5
and at most 1 page fault per 10 designs. The values of all three are checked to agree.

Run: ``python benchmarks/bench_sweep.py [--n N] [--repeat R] [--json]``.
"""

from __future__ import annotations

import argparse
import json
import resource
import statistics
import time

import numpy as np

import mechsynth as ms
from mechsynth.kinematics.compiled import slider_crank_batch
from mechsynth.synthesis import charts

H = 0.1
ANGLES = 360


def hand_written(lam, eps, block=2048, lean=True):
    """The chart's four measures by hand on ``slider_crank_batch``; NaN where infeasible.

    ``lean``: only what the measures need -- the kernel's analogs, and the peak acceleration
    reduced from the analog and multiplied by the crank speed squared (the same bits: rounding
    is monotone); else the kernel at the crank speed, all four rates scaled (the reference
    before the sweep scaled only the rates its measures read)."""
    L, E = np.meshgrid(lam, eps, indexing="ij")
    L, E = L.ravel(), E.ravel()
    ok = L > (1.0 + np.abs(E)) * (1.0 + 1e-9)  # clear of the limit by more than round-off
    li, ei = L[ok], E[ok]
    unit = ms.SliderCrank(crank=1.0, rod=li[:, None], offset=ei[:, None])
    crank = H / np.asarray(unit.stroke)[:, 0]
    rod, off = li * crank, ei * crank
    tr = np.asarray(ms.SliderCrank(crank[:, None], rod[:, None], off[:, None]).time_ratio)[:, 0]
    phi = np.linspace(0.0, 2 * np.pi, ANGLES, endpoint=False)
    out = np.empty((6, block, ANGLES))
    acc, pres = np.empty(li.size), np.empty(li.size)
    w = ms.rpm(600)
    for i in range(0, li.size, block):
        s = slice(i, min(i + block, li.size))
        k = s.stop - s.start
        buf = out[:, :k] if k == block else np.empty((6, k, ANGLES))
        r = slider_crank_batch(crank[s], rod[s], off[s], phi, speed=None if lean else w, out=buf)
        acc[s] = np.maximum(r.acceleration.max(axis=1), -r.acceleration.min(axis=1))
        if lean:
            acc[s] *= w * w
        pres[s] = np.maximum(r.rod_angle.max(axis=1), -r.rod_angle.min(axis=1))
    res = {}
    for name, v in (("acc", acc), ("pres", pres), ("tr", tr), ("rod", rod)):
        full = np.full(L.size, np.nan)
        full[ok] = v
        res[name] = full.reshape(lam.size, eps.size)
    return res


def measured(fn, repeat):
    times, faults, res = [], [], None
    for _ in range(repeat):
        f0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
        t = time.perf_counter()
        res = fn()
        times.append(time.perf_counter() - t)
        faults.append(resource.getrusage(resource.RUSAGE_SELF).ru_minflt - f0)
    return statistics.median(times), statistics.median(faults), res


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    lam, eps = np.linspace(1.5, 8.0, args.n), np.linspace(0.0, 2.0, args.n)
    designs = args.n * args.n

    def chart(kernels):
        saved = charts.sweep

        def sweep(*a, **kw):
            return saved(*a, **kw, kernels=kernels)

        charts.sweep = sweep
        try:
            return charts.slider_crank_chart(rod_crank=lam, offset_crank=eps, progress=False)
        finally:
            charts.sweep = saved

    hand_written(lam[:5], eps[:5])  # compile / load the kernels, warm up
    chart(True)
    rows = {
        "hand-written loop on slider_crank_batch": measured(lambda: hand_written(lam, eps), 3),
        "sweep (compiled path)": measured(lambda: chart(True), args.repeat),
        "sweep (numpy model, kernels=False)": measured(lambda: chart(False), 1),
    }
    ref = rows["hand-written loop on slider_crank_batch"][2]
    for key in ("sweep (compiled path)", "sweep (numpy model, kernels=False)"):
        ch = rows[key][2]
        acc = ch.values["peak slider acceleration"].filled(np.nan)
        pres = ch.values["max pressure angle"].filled(np.nan)
        assert np.allclose(acc, ref["acc"], rtol=1e-9, equal_nan=True), key
        assert np.allclose(pres, ref["pres"], rtol=1e-9, atol=1e-12, equal_nan=True), key
    t_ref = rows["hand-written loop on slider_crank_batch"][0]
    report = {
        k: {"s": t, "ratio": t / t_ref, "faults_per_design": f / designs}
        for k, (t, f, _) in rows.items()
    }
    if args.json:
        print(json.dumps({"designs": designs, "angles": ANGLES, "rows": report}, indent=2))
        return
    print(f"slider-crank chart, {designs} designs x {ANGLES} angles (values agree)")
    for k, r in report.items():
        print(f"  {k:42s} {r['s']:7.3f} s  ratio {r['ratio']:5.2f}  "
              f"page faults/design {r['faults_per_design']:6.3f}")  # fmt: skip


if __name__ == "__main__":
    main()
