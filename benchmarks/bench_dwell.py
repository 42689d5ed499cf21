"""Benchmark: dwell chart over an (r, k) grid for one bend gamma at 720 crank angles.

Run: python3 benchmarks/bench_dwell.py [n]   (default n = 200: a 200 x 200 grid)
Reports the seconds for the coupler curves, the dwell windows (alpha_Sigma, phi_L, E, xi) and the
stroke S_max, per design and in total.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from mechsynth.machines.dwell.linkage import DwellSliderCrank
from mechsynth.machines.dwell.metrics import dwell_windows, relative_stroke


def main(n=200, n_angles=720, gamma_deg=20.0, tolerance=0.002):
    phi = np.arange(n_angles) * 2 * np.pi / n_angles
    # compile the kernels outside the timing
    x, y = DwellSliderCrank(0.3, 1.2, 0.3).coupler_curve(phi)
    dwell_windows(phi, x, y, tolerance)
    r = np.linspace(0.05, 0.5, n)
    k = np.linspace(0.3, 2.5, n)
    t0 = time.perf_counter()
    m = DwellSliderCrank(r=r[None, :, None], k=k[:, None, None], gamma=np.deg2rad(gamma_deg))
    x, y = m.coupler_curve(phi)
    t1 = time.perf_counter()
    win = dwell_windows(phi, x, y, tolerance)
    s_max = relative_stroke(x, y, win["xi"][..., None])
    t2 = time.perf_counter()
    print(f"grid {n} x {n}, gamma {gamma_deg} deg, {n_angles} crank angles, E = {tolerance}")
    print(f"  coupler curves: {t1 - t0:.3f} s")
    print(f"  dwell metrics (alpha_Sigma, phi_L, E, xi, S_max): {t2 - t1:.3f} s")
    print(f"  per design: {1e3 * (t2 - t0) / n / n:.3f} ms; total {t2 - t0:.2f} s")
    print(f"  longest dwell {np.rad2deg(win['dwell']).max():.1f} deg; max S_max {s_max.max():.3f}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 200)
