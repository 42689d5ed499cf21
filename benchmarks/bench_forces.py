"""Kinetostatics and the slider-mass minimax of the AB4115 nail header (not run by the tests).

Reported (median of repeats):
* kinetostatics of the nail header (5 moving bodies, 15 unknowns per angle) at 3,600 crank
  angles: motion + assembly + one batched solve (target under 20 ms), and the solve alone;
* the cvxpy minimax of the peak R32 over the slider mass (SOCP on 1,440 angles, Clarabel; target
  under 200 ms), and the build of its affine map.

Run: python benchmarks/bench_forces.py [--repeat N]
"""

from __future__ import annotations

import argparse
import statistics
import time

from mechsynth.dynamics.kinetostatics import kinetostatics
from mechsynth.machines.nail_header.model import NailHeader
from mechsynth.objectives.forces import reaction_affine_map
from mechsynth.synthesis.convex import minimax_affine
from mechsynth.units import cycle


def timed(fn, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args(argv)
    nh = NailHeader()
    phi = -cycle(3600)
    nh.forces(phi)  # warm-up
    t_all, _ = timed(lambda: nh.forces(phi), args.repeat)
    m = nh.motion(phi, speed=nh.omega)
    model = nh.force_model()
    t_solve, _ = timed(lambda: kinetostatics(model, m), args.repeat)
    print(
        f"kinetostatics, 3600 angles: {1e3 * t_all:.1f} ms (motion+solve), "
        f"{1e3 * t_solve:.1f} ms (solve only); target 20 ms"
    )

    phi2 = -cycle(1440)
    t_map, (A, b, rows) = timed(
        lambda: reaction_affine_map(lambda x: NailHeader(m3=x[0]), "R32", [15.0], phi2),
        args.repeat,
    )
    t_cvx, res = timed(
        lambda: minimax_affine(A, b, angles=rows, norm="euclidean", bounds=[(1.0, 200.0)]),
        args.repeat,
    )
    print(f"affine map R32(m3), 1440 angles: {1e3 * t_map:.1f} ms")
    print(
        f"cvxpy minimax of peak R32 over m3: {1e3 * t_cvx:.1f} ms ({res.status}, "
        f"m3 = {res.x[0]:.3f} kg, peak {res.value:.0f} N); target 200 ms"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
