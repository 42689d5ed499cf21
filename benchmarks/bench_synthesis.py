"""Solve-time benchmark of the synthesis engine (not run by the test suite).

Problems:

* ``crank-rocker``: four-bar with ground 1 m, crank 0.05-0.5, coupler 0.3-2, rocker 0.3-1.5 m:
  maximize the minimum transmission angle at a rocker swing of 40 deg and unit time ratio
  (Brodell & Soni; examples/optimize_crank_rocker.toml, tests/test_synthesis_validation.py).
  The certified optimum has a closed form; its relative error is printed.
* ``slider-crank``: offset slider-crank at 600 rpm, minimize the peak slider acceleration subject
  to a 100 mm stroke and a pressure angle of at most 30 deg (crank 10-200 mm, rod 50-200 mm,
  offset +-100 mm).

Reported for each: one certified IPOPT start and the default 8 starts, the first solve of a new
Problem (it builds the CasADi transcription and solver; CasADi already imported) and the median
of repeated solves (the solver is cached per problem structure), with the IPOPT iterations of
every start (``Result.certification.iterations``) and of the re-solves after grid refinement;
for the slider-crank also differential evolution with and without the certified polish.

``--iterations`` prints the IPOPT iterations of every reference problem
(:mod:`mechsynth.synthesis.reference`) and every example problem file
(``examples/optimize_*.toml``) with their solve options; ``--options '{"mu_max": 1e5}'`` passes
IPOPT options to every solve, to compare settings. ``--fresh`` times ``import mechsynth``, the
Problem's statements and its first and second solve (1 start and the default 8) in a new
interpreter each, as a script meets them (imports and the CasADi build included); the figures
depend on whether Python finds the package's bytecode cached (an installed package: yes; a
checkout under ``PYTHONDONTWRITEBYTECODE``: no, each module compiled again), which is printed.

Run: python benchmarks/bench_synthesis.py [--repeat N] [--iterations] [--options JSON] [--fresh]
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import subprocess
import sys
import time
from pathlib import Path

import mechsynth as ms
from mechsynth import objectives as ob

ROOT = Path(__file__).resolve().parents[1]


def crank_rocker():
    prob = ms.Problem(
        ms.FourBar,
        variables={"crank": (0.05, 0.5), "coupler": (0.3, 2.0), "rocker": (0.3, 1.5)},
        fixed={"ground": 1.0},
    )
    prob.maximize(ob.min_transmission_angle())
    prob.subject_to(ob.swing_angle("rocker") == ms.deg(40), ob.time_ratio() == 1.0)
    return prob


def crank_rocker_optimum():
    """Closed form (Brodell & Soni): the rocker at its lower bound 0.3 m."""
    psi, d, c = ms.deg(40), 1.0, 0.3
    a = c * math.sin(psi / 2)
    b = math.sqrt(d * d - (c * math.cos(psi / 2)) ** 2)
    return math.acos(a * d / (b * c))


def slider_crank():
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


def _iterations(res):
    c = res.certification
    per = "+".join(map(str, c.iterations))
    return f"{c.total_iterations:4d} ({per}; {c.refinement_iterations} in re-solves)"


def solve_times(build, cases, repeat, options=None, reference=None):
    """Rows (label, first solve s, median s, min s, result) for ``cases`` of solve keywords."""
    rows = []
    for label, kw, rep in cases:
        kw = dict(kw, progress=False)
        if options and kw.get("method", "ipopt") == "ipopt":
            kw["options"] = options
        prob = build()
        t = time.perf_counter()
        first = prob.solve(**kw)
        cold = time.perf_counter() - t
        med, best, res = timed(lambda kw=kw, prob=prob: prob.solve(**kw), rep)
        assert res.value == first.value or math.isnan(first.value)
        rows.append((label, cold, med, best, res))
    print(f"{'':34s} {'first s':>8s} {'median s':>9s} {'min s':>7s}  status   iterations")
    for label, cold, med, best, res in rows:
        err = ""
        if reference is not None and res.success:
            err = f"  rel. error {abs(res.value - reference) / reference:.1e}"
        iters = _iterations(res) if res.certification.iterations else "-"
        print(f"{label:34s} {cold:8.3f} {med:9.3f} {best:7.3f}  {res.status:8s} {iters}{err}")
    return rows


def iteration_table(options=None):
    """IPOPT iterations of the reference problems and the example problem files."""
    from mechsynth.synthesis.problem_file import load_problem
    from mechsynth.synthesis.reference import REFERENCE_PROBLEMS

    cases = [
        (f"crank-rocker, {s} start(s)", crank_rocker, {"starts": s}, crank_rocker_optimum())
        for s in (1, 8)
    ]
    for name, ref in REFERENCE_PROBLEMS.items():
        cases.append((f"reference {name}", ref.build, {"starts": 8}, ref.value))
    for path in sorted((ROOT / "examples").glob("optimize_*.toml")):
        spec = load_problem(path)
        cases.append((f"example {path.stem}", lambda s=spec: s.problem, spec.solve_options, None))
    total, rows = 0, []
    print(f"{'problem':46s} {'status':8s} {'iterations':>10s}  per start (+ re-solves)")
    for label, build, kw, ref in cases:
        kw = dict(kw, progress=False)
        if options:
            kw["options"] = options
        res = build().solve(**kw)
        c = res.certification
        total += c.total_iterations
        err = ""
        if ref is not None and res.success:
            err = f"  rel. error {abs(res.value - ref) / abs(ref):.1e}"
        print(
            f"{label:46s} {res.status:8s} {c.total_iterations:10d}  "
            f"{'+'.join(map(str, c.iterations))} (+{c.refinement_iterations}){err}"
        )
        rows.append((label, res.status, c.total_iterations))
    print(f"{'total':46s} {'':8s} {total:10d}")
    return rows


FRESH = """
import sys, time
t0 = time.perf_counter()
import mechsynth as ms
from mechsynth import objectives as ob
t1 = time.perf_counter()
prob = ms.Problem(ms.FourBar, variables={"crank": (0.05, 0.5), "coupler": (0.3, 2.0),
                  "rocker": (0.3, 1.5)}, fixed={"ground": 1.0})
prob.maximize(ob.min_transmission_angle())
prob.subject_to(ob.swing_angle("rocker") == ms.deg(40), ob.time_ratio() == 1.0)
t2 = time.perf_counter()
res = prob.solve(starts=int(sys.argv[1]), progress=False)
t3 = time.perf_counter()
res = prob.solve(starts=int(sys.argv[1]), progress=False)
t4 = time.perf_counter()
print(t1 - t0, t2 - t1, t3 - t2, t4 - t3, res.status)
"""


def fresh(repeat=3):
    """Per start count (1, 8): the lowest and highest over ``repeat`` new interpreters of the
    import, the Problem's statements, its first and its second solve (s)."""
    import os

    cached = not (sys.dont_write_bytecode or os.environ.get("PYTHONDONTWRITEBYTECODE"))
    print(f"new interpreter ({repeat} runs; bytecode {'cached' if cached else 'not cached'}):")
    table = {}
    for starts in (1, 8):
        out = []
        for _ in range(repeat):
            r = subprocess.run(
                [sys.executable, "-c", FRESH, str(starts)],
                capture_output=True,
                text=True,
                check=True,
                cwd=ROOT,
            )
            *times, status = r.stdout.split()
            assert status == "optimal", status
            out.append([float(v) for v in times])
        cols = [(min(c), max(c)) for c in zip(*out)]
        table[starts] = cols
        (i0, i1), (b0, b1), (f0, f1), (s0, s1) = cols
        print(
            f"  {starts} start{'s' if starts > 1 else ' '}: import mechsynth {i0:.3f}-{i1:.3f} s, "
            f"Problem {b0:.3f}-{b1:.3f} s, first solve {f0:.3f}-{f1:.3f} s (CasADi's import "
            f"and build included), second {s0:.3f}-{s1:.3f} s"
        )
    return table


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=15)
    ap.add_argument("--iterations", action="store_true", help="only: the iteration table")
    ap.add_argument("--options", type=json.loads, default=None, help="IPOPT options (JSON)")
    ap.add_argument("--fresh", action="store_true", help="also: a solve in a new interpreter")
    args = ap.parse_args(argv)
    if args.iterations:
        return iteration_table(args.options)

    rep = args.repeat
    # the first solve in a process imports CasADi (--fresh times that); the "first" column is
    # a new Problem's first solve: its CasADi build included
    import casadi  # noqa: F401

    print("crank-rocker transmission angle (3 variables):")
    solve_times(
        crank_rocker,
        [
            ("IPOPT, 1 start, certified", dict(starts=1, seed=0), rep),
            ("IPOPT, 8 starts, certified", dict(starts=8, seed=0), max(3, rep // 5)),
        ],
        rep,
        args.options,
        crank_rocker_optimum(),
    )
    print("\noffset slider-crank, stroke + pressure limit (3 variables):")
    solve_times(
        slider_crank,
        [
            ("IPOPT, 1 start, certified", dict(starts=1, seed=0), rep),
            ("IPOPT, 8 starts, certified", dict(starts=8, seed=0), max(3, rep // 5)),
            ("DE + certified IPOPT polish", dict(method="de", seed=0), 3),
            ("DE alone (no polish)", dict(method="de", seed=0, polish=False), 3),
        ],
        rep,
        args.options,
    )
    if args.fresh:
        print()
        fresh()


if __name__ == "__main__":
    main()
