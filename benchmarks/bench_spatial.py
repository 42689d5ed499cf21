"""Throughput of the spatial pumping-unit drive (paper 002; not run by the test suite).

Reported, for the C-320D-256-120 drive with every deviation at once:
* kinematics (Newton closure, Bour velocities and accelerations) of a batch of designs x crank
  angles in one vectorized call, in design-angle evaluations per second;
* kinetostatics of the redundant (revolute) and the rational (spherical) drive over the same
  batch (the batched SVD of the 24 x 28 equilibrium matrices dominates);
* one certified counterbalance sizing (LP over the full kinetostatics, 120 angles).

Run: python benchmarks/bench_spatial.py [--repeat N]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import mechsynth as ms
from mechsynth.machines.pumping_unit import size_counterbalance

DEV = dict(
    phase_mismatch=ms.deg(0.3), crank_difference=2e-3, pitman_difference=3e-3, shaft_tilt=5e-4,
    shaft_skew=1e-3, beam_tilt=1e-3, beam_skew=-5e-4, equalizer_offset=4e-3,
)  # fmt: skip


def timed(fn, repeat):
    times, res = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        res = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), res


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    unit = ms.BeamPumpingUnit.from_api(
        A=155.0, C=111.06, I=111.02, P=132.01, R=42.01, H=231.97, G=95.98, units="in"
    )
    n_designs, n_angles = 20, 360
    phases = np.linspace(0.0, ms.deg(0.5), n_designs)[:, None]
    drive = ms.SpatialPumpingUnit.from_planar(unit, 1.2, **{**DEV, "phase_mismatch": phases})
    theta = ms.cycle(n_angles)
    n = n_designs * n_angles
    _ = drive.stroke  # the stroke's Newton search is cached per drive: not timed
    t, _ = timed(lambda: drive.motion(theta, speed=ms.spm(6)), args.repeat)
    print(f"kinematics: {n_designs} designs x {n_angles} angles in {t * 1e3:.0f} ms "
          f"= {n / t:.3g} design-angle evaluations/s")  # fmt: skip
    for joints in ("revolute", "spherical"):
        d = drive.with_joints(joints)
        _ = d.stroke
        t, _ = timed(lambda d=d: d.forces(theta, ms.spm(6), load=80e3), args.repeat)
        print(f"kinetostatics, {joints}: {t * 1e3:.0f} ms = {n / t:.3g} design-angle evaluations/s")
    one = ms.SpatialPumpingUnit.from_planar(unit, 1.2, **DEV)
    t, res = timed(lambda: size_counterbalance(one, ms.spm(6), 80e3, angles=120), 1)
    print(f"certified counterbalance sizing (120 angles): {t:.2f} s, {res.status}, "
          f"M = {res.counterbalance.moment:.0f} N m")  # fmt: skip


if __name__ == "__main__":
    main()
