"""Benchmark: ``sweep`` against a hand-written loop on the same compiled kernel, from 1e4 to
millions of designs -- whether a chart's cost per design stays flat as the grid grows.

The chart of ``bench_sweep.py`` (offset slider-cranks of a 100 mm stroke over ``N x N`` values of
rod/crank x offset/crank, 360 crank angles, 600 rpm, four measures through
:func:`mechsynth.synthesis.charts.slider_crank_chart`) against its hand-written loop on
``slider_crank_batch`` (:func:`bench_sweep.hand_written`). Each size runs in a fresh process
(warmed up by one untimed run of each at its size, so that neither pays its first touch of
its memory in the timing) so that its peak resident memory is its own; the CPU time
(``time.process_time``) of each of ``--repeat`` runs is printed with the ratio sweep / by hand
(a run of a grid under a million designs repeats each chart enough times for a million
designs, so that the timer's resolution and the machine's noise do not decide the ratio),
and the peak resident memory over the warm start per design (it holds both charts' whole-grid
arrays -- the sweep's measures, parameters and feasibility, the hand-written loop's grids and
results -- and one chunk's kinematics each: flat memory is a figure per design that does not
grow with the grid). The values of the two agree (checked at every size).

Run: ``python benchmarks/bench_sweep_scaling.py [--n 100 300 1000 2000] [--repeat 3]``.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def one_size(n: int, repeat: int, lean: bool = True) -> dict:
    """Time ``repeat`` runs of each at ``n x n`` designs in this process (``lean``: as
    :func:`bench_sweep.hand_written`)."""
    sys.path.insert(0, HERE)
    import bench_sweep as b

    from mechsynth.synthesis import charts

    lam, eps = np.linspace(1.5, 8.0, n), np.linspace(0.0, 2.0, n)
    b.hand_written(lam[:5], eps[:5])  # load the kernels
    charts.slider_crank_chart(rod_crank=lam[:5], offset_crank=eps[:5], progress=False)
    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    b.hand_written(lam, eps, lean=lean)  # each one's memory touched once
    charts.slider_crank_chart(rod_crank=lam, offset_crank=eps, progress=False)
    loops = max(1, 10**6 // (n * n))
    hand, swept = [], []
    for _ in range(repeat):
        t = time.process_time()
        for _ in range(loops):
            ref = b.hand_written(lam, eps, lean=lean)
        hand.append((time.process_time() - t) / loops)
        t = time.process_time()
        for _ in range(loops):
            ch = charts.slider_crank_chart(rod_crank=lam, offset_crank=eps, progress=False)
        swept.append((time.process_time() - t) / loops)
        both = ch.feasible & np.isfinite(ref["acc"])
        assert both.sum() >= 0.999 * ch.feasible.sum()  # the limit's round-off aside
        for key, label in (("acc", "peak slider acceleration"), ("pres", "max pressure angle")):
            np.testing.assert_allclose(ch.values[label].data[both], ref[key][both], rtol=1e-12)
        del ch, ref
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return {
        "designs": n * n,
        "hand_s": hand,
        "sweep_s": swept,
        "base_mib": base / 1024,
        "peak_mib": peak / 1024,
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, nargs="+", default=[100, 300, 1000, 2000])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--one", type=int, help=argparse.SUPPRESS)
    ap.add_argument("--all-rates", action="store_true",
                    help="the hand-written loop computes all four rates at the crank speed (the "
                    "reference before the sweep scaled only the rates it reads)")  # fmt: skip
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    if args.one:
        print(json.dumps(one_size(args.one, args.repeat, lean=not args.all_rates)))
        return
    rows = []
    for n in args.n:
        out = subprocess.run(
            [sys.executable, __file__, "--one", str(n), "--repeat", str(args.repeat)]
            + ["--all-rates"] * args.all_rates,
            capture_output=True, text=True, check=True,
        )  # fmt: skip
        rows.append(json.loads(out.stdout.strip().splitlines()[-1]))
    if args.json:
        print(json.dumps(rows, indent=2))
        return
    what = "all four rates at speed" if args.all_rates else "only what the measures need"
    print(f"slider-crank chart x 360 angles, CPU seconds, {args.repeat} runs each, by hand "
          f"{what} (load average {os.getloadavg()[0]:.1f}: the machine is shared)")  # fmt: skip
    for r in rows:
        ratios = [s / h for s, h in zip(r["sweep_s"], r["hand_s"])]
        grow = r["peak_mib"] - r["base_mib"]
        print(
            f"  {r['designs']:>9,d} designs: by hand "
            + " ".join(f"{t:.2f}" for t in r["hand_s"])
            + " s, sweep "  # per chart
            + " ".join(f"{t:.2f}" for t in r["sweep_s"])
            + " s, ratio "
            + " ".join(f"{x:.2f}" for x in ratios)
            + f"; peak memory {r['peak_mib']:.0f} MiB "
            f"(+{grow:.0f} MiB, {grow * 2**20 / r['designs']:.0f} B/design over the warm start)"
        )


if __name__ == "__main__":
    main()
