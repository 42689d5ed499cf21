"""General linkages: motion throughput, cam contact, certified synthesis and a chart (not run by
the tests).

Reported (median of repeats; this machine's speed varies during a day):
* the six-link of paper 001 (crank, RRR, attached point, RRP) at 360 crank angles: one design,
  and 10,000 designs in chunks of 182 (about 2**16 design-angle points, as sweeps use), in
  design-angle evaluations per second (the named four-bar's numpy model at the same time, for
  scale);
* the five-link (crank, RRR, involute cam and roller follower) at 360 angles, one design;
* the certified IPOPT solve of docs/linkages.md (stroke 60 mm, angle limits, 2 starts);
* a 40 x 40 chart of the six-link at 180 angles (``mechsynth chart linkage``'s example).

Run: python benchmarks/bench_linkage.py [--repeat N]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth.kinematics import Involute
from mechsynth.synthesis import sweep


def timed(fn, repeat):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out


def six_link():
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
        .attach("K", on=("D", "B"), along=-0.05)
        .rrp("N", ("K", 0.10), guide=((0.12, 0.0), ms.deg(57)))
    )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    r = args.repeat
    phi = ms.cycle(360)
    six = six_link()
    t1, _ = timed(lambda: six.motion(phi, speed=100.0), 5 * r)
    print(f"six-link, 1 design x 360 angles: {t1 * 1e3:.2f} ms ({360 / t1:.3g} evaluations/s)")
    n = 10_000
    db = np.random.default_rng(0).uniform(0.07, 0.09, n)[:, None]
    chunk = 2**16 // 360

    def batch():
        for i in range(0, n, chunk):
            six(DB=db[i : i + chunk]).motion(phi, speed=100.0)

    tb, _ = timed(batch, max(1, r // 2))
    print(
        f"six-link, {n} designs x 360 angles in chunks of {chunk}: {tb:.2f} s "
        f"({n * 360 / tb:.3g} evaluations/s)"
    )
    cranks = np.random.default_rng(1).uniform(0.8, 1.2, n)[:, None]

    def four_bar():
        for i in range(0, n, chunk):
            ms.FourBar(cranks[i : i + chunk], 4.3, 3.0, 5.2).motion(phi, speed=100.0)

    tf, _ = timed(four_bar, max(1, r // 2))
    print(f"  (named four-bar numpy model, same batch: {n * 360 / tf:.3g} evaluations/s)")
    five = (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
        .follower(
            "N",
            on="DB",
            profile=Involute(0.02, phase=ms.deg(-62), roll=(0.2, 4.0)),
            guide=("D", ms.deg(100)),
            offset=0.02,
            roller=0.004,
        )
    )
    t5, _ = timed(lambda: five.motion(phi, speed=100.0), 5 * r)
    print(f"five-link (involute cam), 1 design x 360 angles: {t5 * 1e3:.2f} ms")

    def solve():
        prob = ms.Problem(
            six,
            variables={
                "OA": (0.01, 0.05),
                "DB": (0.05, 0.12),
                "K_along": (-0.1, -0.02),
                "KN": (0.06, 0.2),
            },
            speed=ms.rpm(1500),
        )
        prob.minimize(ob.peak_acceleration("N"))
        prob.subject_to(
            ob.stroke("N") == 0.06,
            ob.min_transmission_angle("B") >= ms.deg(45),
            ob.max_pressure_angle("N") <= ms.deg(30),
        )
        return prob.solve(starts=2, progress=False)

    ts, res = timed(solve, max(1, r // 3))
    print(
        f"certified solve (docs/linkages.md, 2 starts): {ts:.2f} s, {res.status}, "
        f"{res.value:.4f} m/s^2"
    )

    def chart():
        return sweep(
            six,
            grid={
                "KN": np.linspace(0.06, 0.2, 40),
                "N_guide_angle": ms.deg(np.linspace(40, 140, 40)),
            },
            measures={"stroke": ob.stroke("N"), "p": ob.max_pressure_angle("N")},
            angles=180,
            speed=ms.rpm(1500),
            progress=False,
        )

    tc, _ = timed(chart, max(1, r // 2))
    print(f"chart 40 x 40 designs x 180 angles: {tc:.2f} s")


if __name__ == "__main__":
    main()
