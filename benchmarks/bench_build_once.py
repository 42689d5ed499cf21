"""Build once, solve many: solver builds, time and memory of Pareto fronts (not run by the test
suite).

Cases, each run in a new interpreter (so its peak memory is its own):

* ``impact``: the impact study's certified synthesis of the six-link (3 starts) and its Pareto
  front of the blow energy against the transverse housing load (``--points``, default 3),
  :mod:`mechsynth.machines.impact.synthesis`;
* ``slider-crank``: the offset slider-crank's front of the peak slider acceleration against the
  pressure angle at a 100 mm stroke (anchors of 8 starts, points at 40, 30 and 20 deg,
  ``mechsynth chart slider-crank-pareto``'s problem).

Each case runs under two caching policies of the synthesis engine:

* ``per-problem`` -- the policy before: every Problem (each Pareto point solves a copy) builds
  its own program and IPOPT solver, and a solver for other options (a warm start's) is a full
  build (emulated here by patching :mod:`mechsynth.synthesis.transcription`);
* ``per-structure`` -- the engine's policy: one program and solver per problem structure, the
  bounds passed as parameters, other options reusing the first build's derivatives.

Printed per case and policy: programs built, IPOPT builds with their derivatives, solvers for
another options set, wall and CPU time, peak resident memory (``ru_maxrss``) and the resident
memory after each solve (flat, or climbing). ``--case`` picks one case, ``--policy`` one
policy.

Run: python benchmarks/bench_build_once.py [--case impact|slider-crank] [--points N]
     [--policy per-problem|per-structure]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

CHILD = r"""
import json, resource, sys, time, weakref
import mechsynth as ms
from mechsynth.synthesis import transcription as T
from mechsynth.synthesis.problem import Problem

case, policy, points = sys.argv[1], sys.argv[2], int(sys.argv[3])

if policy == "per-problem":  # every Problem its own build, every options set a full build
    own = weakref.WeakKeyDictionary()

    def per_problem(problem, n_extra):
        built = own.setdefault(problem, {})
        if n_extra not in built:
            built[n_extra] = T._Structure(problem, n_extra)
            T._COUNTS["structures"] += 1
        return built[n_extra]

    T._structure = per_problem
    original = T._Structure.solver

    def full_build(self, method, options=None):
        self.derivatives = None
        return original(self, method, options)

    T._Structure.solver = full_build


def rss_mib():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS"):
                return int(line.split()[1]) / 1024
    return float("nan")


after = []
solve = Problem.solve


def recorded(self, *args, **kwargs):
    res = solve(self, *args, **kwargs)
    after.append(round(rss_mib()))
    return res


Problem.solve = recorded
t0, c0 = time.perf_counter(), time.process_time()
if case == "impact":
    from mechsynth.machines.impact.design import representative_machine
    from mechsynth.machines.impact.synthesis import pareto_front, synthesize

    m = representative_machine("six")
    opt = synthesize(m, starts=3)
    front = pareto_front(m, points, optimum=opt)
    values = [(p["first"], p["second"]) for p in front["points"] if p["success"]]
    extra = {"synthesis_J": opt["blow_energy_J"], "n_success": front["n_success"]}
else:
    from mechsynth import objectives as ob
    from mechsynth.synthesis.pareto import pareto_front

    prob = ms.Problem(
        ms.SliderCrank,
        variables={"crank": (0.01, 0.2), "rod": (0.05, 0.2), "offset": (-0.1, 0.1)},
        speed=ms.rpm(600),
    ).subject_to(ob.stroke("slider") == 0.1)
    fr = pareto_front(
        prob, ob.peak_acceleration("slider"), ob.max_pressure_angle(),
        eps=ms.deg([40.0, 30.0, 20.0]), starts=3,
    )
    values = [(float(a), float(b)) for a, b in zip(*fr.front())]
    extra = {"n_success": int(fr.success.sum())}
info = T.cache_info()
print(json.dumps(dict(
    wall=time.perf_counter() - t0, cpu=time.process_time() - c0,
    peak=resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, after=after,
    programs=info["structures"], solvers=info["solvers"], variants=info["variants"],
    solves=len(after), values=values, **extra,
)))
"""


def run(case: str, policy: str, points: int) -> dict:
    out = subprocess.run(
        [sys.executable, "-c", CHILD, case, policy, str(points)],
        capture_output=True,
        text=True,
        check=False,
    )
    if out.returncode != 0:
        raise SystemExit(f"{case} / {policy} failed:\n{out.stderr[-2000:]}")
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--case", choices=("impact", "slider-crank"), action="append")
    ap.add_argument("--policy", choices=("per-problem", "per-structure"), action="append")
    ap.add_argument("--points", type=int, default=3, help="points of the impact front")
    a = ap.parse_args(argv)
    cases = a.case or ["slider-crank", "impact"]
    policies = a.policy or ["per-problem", "per-structure"]
    for case in cases:
        rows = {p: run(case, p, a.points) for p in policies}
        print(f"\n{case}" + (f" (synthesis + {a.points}-point front)" if case == "impact" else ""))
        print(
            f"  {'policy':14s} {'programs':>8s} {'IPOPT':>6s} {'variants':>8s} {'solves':>6s} "
            f"{'wall s':>7s} {'CPU s':>7s} {'peak MiB':>9s}  resident MiB after each solve"
        )
        for p, r in rows.items():
            print(
                f"  {p:14s} {r['programs']:8d} {r['solvers']:6d} {r['variants']:8d} "
                f"{r['solves']:6d} {r['wall']:7.1f} {r['cpu']:7.1f} {r['peak']:9.0f}  "
                + " ".join(map(str, r["after"]))
            )
        if len(rows) == 2:
            b, n = rows["per-problem"], rows["per-structure"]
            print(
                f"  per-structure against per-problem: CPU {b['cpu'] / n['cpu']:.1f} x faster, "
                f"peak memory {b['peak'] / n['peak']:.1f} x lower"
            )
            same = len(b["values"]) == len(n["values"]) and all(
                abs(x - y) <= 1e-6 * max(abs(x), 1.0)
                for u, v in zip(b["values"], n["values"])
                for x, y in zip(u, v)
            )
            print(f"  the same front (1e-6): {same}")
        for p, r in rows.items():
            print(f"  {p}: front {r['values']}")


if __name__ == "__main__":
    main()
