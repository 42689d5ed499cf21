"""Solve-time benchmark of the synthesis engine (not run by the test suite).

Problem: offset slider-crank at 600 rpm, minimize the peak slider acceleration subject to a
100 mm stroke and a pressure angle of at most 30 deg (crank 10-200 mm, rod 50-200 mm, offset
+-100 mm) -- the problem of tests/test_synthesis_validation.py.

Reported:
* one certified IPOPT solve (one start, grid refinement until the grid peak is the true peak),
  with the CasADi solver already built for the problem (it is cached on the Problem), median of
  repeated solves; and the first solve including the build;
* the default 8-start certified IPOPT solve;
* differential evolution (vectorized numpy population) + certified IPOPT polish, and DE alone.

Run: python benchmarks/bench_synthesis.py [--repeat N]
"""

from __future__ import annotations

import argparse
import statistics
import time

import mechsynth as ms
from mechsynth import objectives as ob


def problem():
    prob = ms.Problem(
        ms.SliderCrank,
        variables={"crank": (0.01, 0.2), "rod": (0.05, 0.2), "offset": (-0.1, 0.1)},
        speed=ms.rpm(600),
    )
    prob.minimize(ob.peak_acceleration("slider"))
    prob.subject_to(ob.stroke("slider") == 0.10, ob.max_pressure_angle() <= ms.deg(30))
    return prob


def timed(fn, repeat):
    times, res = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        res = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), min(times), res


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=15)
    args = ap.parse_args(argv)

    prob = problem()
    t = time.perf_counter()
    first = prob.solve(starts=1, seed=0)
    cold = time.perf_counter() - t
    print(f"first solve incl. CasADi build : {cold * 1e3:8.1f} ms  ({first.status})")

    rows = []
    for label, kw, rep in [
        ("IPOPT, 1 start, certified", dict(starts=1, seed=0), args.repeat),
        ("IPOPT, 8 starts, certified", dict(starts=8, seed=0), max(3, args.repeat // 5)),
        ("DE + certified IPOPT polish", dict(method="de", seed=0), 3),
        ("DE alone (no polish)", dict(method="de", seed=0, polish=False), 3),
    ]:
        med, best, res = timed(lambda kw=kw: prob.solve(**kw), rep)
        c = res.certification
        rows.append((label, med, best, res.value, res.status, c.refinement_rounds))
    print(f"{'method':32s} {'median ms':>10s} {'min ms':>9s} {'peak a, m/s^2':>15s}  status")
    for label, med, best, val, status, rounds in rows:
        print(
            f"{label:32s} {med * 1e3:10.1f} {best * 1e3:9.1f} {val:15.9f}  {status}"
            f" ({rounds} refinement rounds)"
        )
    return rows


if __name__ == "__main__":
    main()
