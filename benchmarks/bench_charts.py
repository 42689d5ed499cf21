"""Throughput of design charts, the convex minimax and Pareto fronts (not run by the test suite).

Reported:
* the slider-crank chart at a fixed 100 mm stroke, 200 x 200 designs (rod/crank x offset/crank)
  at 360 crank angles, 600 rpm: peak slider acceleration, max pressure angle, time ratio and rod
  length of every design (target under 3 s); median of repeated sweeps and the throughput in
  design-angle evaluations per second;
* ``minimax_affine`` on a 3,600-angle problem with 2-D force vectors (SOCP, Clarabel): the
  shaking force of a slider-crank, affine in the counterweight moment and the slider mass;
  the same force's x component as an LP (HiGHS); and the build of the affine map;
* a 7-point Pareto front (peak slider acceleration vs max pressure angle at stroke 0.1 m).

Also with the chunks evaluated in two threads (``workers=2``).

Run: python benchmarks/bench_charts.py [--repeat N] [--no-pareto]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth.synthesis.charts import slider_crank_chart
from mechsynth.synthesis.convex import affine_map, minimax_affine
from mechsynth.synthesis.pareto import pareto_front

OMEGA = ms.rpm(600)
SC = ms.SliderCrank(crank=0.05, rod=0.2, offset=0.02)


def shaking_force(x, phi, m_pin=0.8):
    """Resultant inertia force (N): crank-pin mass, slider mass x[1], counterweight moment x[0]
    (kg m) opposite the crank pin."""
    m = SC.motion(phi, speed=OMEGA)
    a, b = m.points["A"], m.points["B"]
    fx = m_pin * a.ax + x[1] * b.ax + x[0] * OMEGA**2 * np.cos(phi)
    fy = m_pin * a.ay + x[1] * b.ay + x[0] * OMEGA**2 * np.sin(phi)
    return np.stack([fx, fy], axis=-1)


def timed(fn, repeat):
    times, res = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        res = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), min(times), res


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-pareto", action="store_true")
    args = ap.parse_args(argv)
    rows = {}

    for workers in (1, 2):
        med, best, chart = timed(
            lambda w=workers: slider_crank_chart(0.1, progress=False, workers=w), args.repeat
        )
        evals = chart.size * chart.angles
        rows[f"chart, {workers} thread(s)"] = (med, best)
        print(
            f"slider-crank chart 200 x 200 designs x 360 angles, {workers} thread(s): median "
            f"{med:.2f} s, min {best:.2f} s ({evals / med / 1e6:.1f} M design-angle "
            f"evaluations/s; {int(chart.feasible.sum())} feasible)"
        )

    bounds = [(0.0, 0.2), (0.5, 2.0)]
    minimax_affine(affine_map(shaking_force, [0.01, 1.0], 36), norm="euclidean", bounds=bounds)
    med, best, amap = timed(lambda: affine_map(shaking_force, [0.01, 1.0], 3600), 5)
    print(f"affine map, 3600 angles x 2 components x 2 variables: median {med * 1e3:.1f} ms")
    med, best, res = timed(
        lambda: minimax_affine(amap, norm="euclidean", bounds=bounds), max(5, args.repeat)
    )
    rows["socp"] = (med, best)
    print(
        f"minimax_affine SOCP, 3600 angles (2-D vectors): median {med * 1e3:.1f} ms, "
        f"min {best * 1e3:.1f} ms; peak {res.value:.6g} N at u = {res.x[0]:.6g} kg m, "
        f"m_slider = {res.x[1]:.4g} kg ({res.status})"
    )
    lp_A, lp_b = amap.A[:, 0, :], amap.b[:, 0]
    med, best, res = timed(
        lambda: minimax_affine(lp_A, lp_b, angles=amap.phi, bounds=bounds), max(5, args.repeat)
    )
    rows["lp"] = (med, best)
    print(
        f"minimax_affine LP, 3600 angles (x component): median {med * 1e3:.1f} ms, "
        f"min {best * 1e3:.1f} ms; peak {res.value:.6g} N ({res.status})"
    )

    if not args.no_pareto:
        prob = ms.Problem(
            ms.SliderCrank,
            variables={"crank": (0.01, 0.2), "rod": (0.05, 0.2), "offset": (-0.1, 0.1)},
            speed=OMEGA,
        ).subject_to(ob.stroke("slider") == 0.1)
        t = time.perf_counter()
        fr = pareto_front(prob, ob.peak_acceleration("slider"), ob.max_pressure_angle(), n=7)
        rows["pareto"] = (time.perf_counter() - t,) * 2
        print(
            f"Pareto front, 7 points (anchors 8 starts, inner points 4 starts): "
            f"{rows['pareto'][0]:.2f} s; {int(fr.nondominated.sum())} non-dominated"
        )
    return rows


if __name__ == "__main__":
    main()
