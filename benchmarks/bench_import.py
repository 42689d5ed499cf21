"""Benchmark: the cost of ``import mechsynth`` as a ratio to ``import numpy``.

Each import runs in a fresh interpreter; the time is that of the import statement alone
(``time.perf_counter`` around it, so the interpreter's start-up is not counted), the median of
``--repeat`` runs, alternating the two. ``import mechsynth`` includes numpy's own import. The
target is a ratio of at most 2.5. Also timed: the first use of the kinematics
(``ms.SliderCrank(...).motion``), which loads the model layers.

Run: ``python benchmarks/bench_import.py [--repeat N] [--json]``.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

PROBES = {
    "numpy": "import numpy",
    "mechsynth": "import mechsynth",
    "mechsynth + first motion": (
        "import mechsynth as ms; ms.SliderCrank(0.07, 0.24, 0.0).motion(ms.cycle(360))"
    ),
    "mechsynth.synthesis": "import mechsynth.synthesis",
}


def _time(stmt: str) -> float:
    code = f"import time\nt = time.perf_counter()\n{stmt}\nprint(time.perf_counter() - t)"
    out = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True
    )
    return float(out.stdout.strip().splitlines()[-1])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=15)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
    runs = {k: [] for k in PROBES}
    for _ in range(args.repeat):
        for k, stmt in PROBES.items():
            runs[k].append(_time(stmt))
    med = {k: statistics.median(v) for k, v in runs.items()}
    ratio = {k: med[k] / med["numpy"] for k in PROBES}
    if args.json:
        print(json.dumps({"median_s": med, "ratio_to_numpy": ratio}, indent=2))
        return
    print(f"import time, median of {args.repeat} fresh interpreters")
    for k in PROBES:
        print(f"  {k:28s} {1e3 * med[k]:7.1f} ms   {ratio[k]:5.2f} x import numpy")
    verdict = "meets" if ratio["mechsynth"] <= 2.5 else "MISSES"
    print(f"import mechsynth / import numpy = {ratio['mechsynth']:.2f} ({verdict} the 2.5 target)")


if __name__ == "__main__":
    main()
