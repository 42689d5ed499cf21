"""Throughput and solve-time benchmark of the beam pumping unit (not run by the test suite).

Reported:
* exact kinematics (polished-rod position, velocity, acceleration, torque factor, pressure
  angle) of a batch of designs x crank angles in one vectorized numpy call, in design-angle
  evaluations per second;
* the counterbalance LP (cvxpy) for a 720-angle torque curve, fixed and free phase, against the
  grid scan that cross-checks it;
* the certified synthesis of examples/optimize_beam_pump.toml (IPOPT, 4 starts).

Run: python benchmarks/bench_pumping_unit.py [--repeat N]
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np

import mechsynth as ms
from mechsynth.machines.pumping_unit import (
    optimal_counterbalance,
    scan_counterbalance,
    torque_curve,
)


def timed(fn, repeat):
    times, res = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        res = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), res


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    rng = np.random.default_rng(0)
    n_designs, n_angles = 2000, 360
    crank = rng.uniform(0.9, 1.1, (n_designs, 1))
    unit = ms.BeamPumpingUnit(crank, 3.353, 2.821, 3.937, 2.82, 3.454)
    theta = ms.cycle(n_angles)

    def kin():
        m = unit.motion(theta, speed=ms.spm(8))
        return m.polished_rod.acceleration, m.torque_factor, m.pressure_angle

    t, _ = timed(kin, args.repeat)
    print(f"kinematics: {n_designs} designs x {n_angles} angles in {t * 1e3:.1f} ms "
          f"= {n_designs * n_angles / t:.3g} design-angle evaluations/s")  # fmt: skip

    single = ms.BeamPumpingUnit(1.067, 3.353, 2.821, 3.937, 2.82, 3.454)
    th = ms.cycle(720)
    base = torque_curve(single, th, 80e3).well
    for free in (False, True):

        def lp(free=free):
            return optimal_counterbalance(th, base, free_phase=free, cross_check=False)

        def scan(free=free):
            return scan_counterbalance(th, base, None if free else 0.0)

        t, res = timed(lp, args.repeat)
        ts, _ = timed(scan, args.repeat)
        print(f"counterbalance LP ({'free' if free else 'fixed'} phase): {t * 1e3:.1f} ms, "
              f"scan {ts * 1e3:.1f} ms, peak {res.peak_torque:.1f} N m")  # fmt: skip

    from mechsynth.synthesis.problem_file import load_problem

    path = Path(__file__).resolve().parents[1] / "examples" / "optimize_beam_pump.toml"
    t, res = timed(lambda: load_problem(path).solve(progress=False), max(1, args.repeat // 2))
    print(f"certified synthesis (IPOPT, {res.certification.starts_run} starts, incl. build): "
          f"{t:.2f} s, status {res.status}, peak acceleration {res.value:.6f} m/s^2")  # fmt: skip


if __name__ == "__main__":
    main()
