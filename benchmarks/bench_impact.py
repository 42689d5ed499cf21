"""The impact study's synthesis and Pareto front: time, peak memory and programs built, this
code against a baseline checkout (not run by the test suite).

Each run is a new interpreter (so its peak memory is its own) on the study's machine (the
representative six-link with the gear ratio its motor model gives, as ``mechsynth study run
impact`` solves it): the certified synthesis (3 starts) and then the Pareto front of the blow
energy against the transverse housing load (``--points``, default 3) with the synthesis as its
energy anchor. Printed per run: wall and CPU time of the synthesis and of the front, the peak
resident memory after each (``ru_maxrss``, so the second is the whole run's), the programs and
IPOPT solvers built by the synthesis and in all (``synthesis/all``, this code's
:func:`mechsynth.synthesis.transcription.cache_info`; the baseline may have no such count),
the synthesis' blow energy, the front's points and the load average when the run started.

``--baseline DIR``: a checkout of an earlier commit (e.g. ``git worktree add ../old 59fc68f``),
run with ``PYTHONPATH=DIR``; its runs alternate with this code's, so both see the same load.
The baseline runs with the same ``--housing``; one before the housing constraints (commit
59fc68f) has no such option and solves the problem without them: compare it with ``--housing
off``. ``--runs N`` repeats each.

Run: python benchmarks/bench_impact.py [--baseline DIR] [--points 3] [--housing on|off]
     [--runs 1]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

CHILD = r"""
import inspect, json, os, resource, sys, time

points, housing = int(sys.argv[1]), sys.argv[2] == "on"
from mechsynth.machines.impact.design import representative_machine
from mechsynth.machines.impact.drive import motor_for
from mechsynth.machines.impact import synthesis as S

m = representative_machine("six")
m = m.replace(gear_ratio=motor_for(m).gear_ratio)
# a baseline before the housing constraints has no such option (and no housing)
knows = "housing" in inspect.signature(S.impact_problem).parameters
options = {} if housing or not knows else {"housing": False}


def peak_mib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def built():
    try:
        from mechsynth.synthesis.transcription import cache_info
    except ImportError:
        return None
    info = cache_info()
    return {"programs": info["structures"], "solvers": info["solvers"]}


out = {"load": os.getloadavg()[0]}
t0, c0 = time.perf_counter(), time.process_time()
opt = S.synthesize(m, starts=3, **options)
out.update(
    synthesis_wall=time.perf_counter() - t0, synthesis_cpu=time.process_time() - c0,
    synthesis_peak=peak_mib(), synthesis_J=opt["blow_energy_J"], synthesis_built=built(),
)
if points >= 2:
    t1, c1 = time.perf_counter(), time.process_time()
    front = S.pareto_front(m, points, optimum=opt, **options)
    out.update(
        front_wall=time.perf_counter() - t1, front_cpu=time.process_time() - c1,
        front=[(p["first"], p["second"]) for p in front["points"] if p["success"]],
        n_points=len(front["points"]),
    )
out.update(peak=peak_mib(), built=built())
print(json.dumps(out))
"""


def run(points: int, housing: str, baseline: Path | None = None) -> dict:
    env = dict(os.environ)
    if baseline is not None:
        env["PYTHONPATH"] = str(baseline)
    proc = subprocess.run(
        [sys.executable, "-c", CHILD, str(points), housing],
        capture_output=True,
        text=True,
        check=False,
        env=env,
        cwd=str(baseline) if baseline is not None else None,
    )
    if proc.returncode != 0:
        who = "baseline" if baseline is not None else "this code"
        raise SystemExit(f"{who} failed:\n{proc.stderr[-2000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def _built(synthesis, total, key: str) -> str:
    """``synthesis/all`` of a count, or "-" when the code does not count its builds."""
    if not total:
        return "-"
    return f"{synthesis[key]}/{total[key]}" if synthesis else str(total[key])


def _row(name: str, r: dict) -> str:
    built = r.get("built") or {}
    front = r.get("front_wall")
    return (
        f"  {name:10s} {r['load']:5.1f} {r['synthesis_wall']:8.1f} {r['synthesis_cpu']:8.1f} "
        f"{r['synthesis_peak']:9.0f} "
        + (f"{front:8.1f} {r['front_cpu']:8.1f} " if front is not None else f"{'-':>8s} " * 2)
        + f"{r['peak']:9.0f} {_built(r.get('synthesis_built'), built, 'programs'):>8} "
        + f"{_built(r.get('synthesis_built'), built, 'solvers'):>7}  "
        + f"{r['synthesis_J']:.4f} J; front "
        + ", ".join(f"{a:.4f} J at {b:.1f} N" for a, b in r.get("front", []))
    )


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--baseline", type=Path, help="a checkout of the code to compare with")
    ap.add_argument("--points", type=int, default=3, help="points of the front (0: none)")
    ap.add_argument("--housing", choices=("on", "off"), default="on")
    ap.add_argument("--runs", type=int, default=1)
    a = ap.parse_args(argv)
    rows: list[tuple[str, dict]] = []
    for _ in range(a.runs):
        if a.baseline is not None:
            rows.append(("baseline", run(a.points, a.housing, a.baseline)))
        rows.append(("this code", run(a.points, a.housing)))
    print(
        f"\nimpact synthesis (3 starts) + {a.points}-point front, housing {a.housing}"
        + (f"; baseline {a.baseline}" if a.baseline is not None else "")
    )
    print(
        f"  {'code':10s} {'load':>5s} {'synth s':>8s} {'CPU s':>8s} {'peak MiB':>9s} "
        f"{'front s':>8s} {'CPU s':>8s} {'peak MiB':>9s} {'programs':>8s} {'solvers':>7s}  values"
    )
    for name, r in rows:
        print(_row(name, r))
    old = [r for n, r in rows if n == "baseline"]
    new = [r for n, r in rows if n == "this code"]
    if old and new:

        def mean(rs, k):
            return sum(r[k] for r in rs) / len(rs)

        for k, what in (("synthesis_cpu", "synthesis CPU"), ("front_cpu", "front CPU")):
            if k in old[0] and k in new[0]:
                print(f"  {what}: {mean(old, k) / mean(new, k):.2f} x faster than the baseline")
        print(f"  peak memory: {mean(old, 'peak') / mean(new, 'peak'):.2f} x lower")


if __name__ == "__main__":
    main()
