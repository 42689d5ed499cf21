"""Function generation against pylinkage's, on the same problem, by the same evaluator (not run by
the test suite).

Problem: a four-bar generating ``y = log10(x)`` on ``[1, 10]``, crank rotation 60 deg, rocker
rotation 90 deg, ranges starting at crank 120 deg and rocker 20 deg, ground 1 m; precision
points at Chebyshev spacing (3, 5 and 9 of them).

pylinkage (``pylinkage.synthesis.function_generation``, version printed) takes the precision
pairs and returns link lengths: exact for three pairs, least squares on Freudenstein's equation
for more. mechsynth's ``ms.function_generation`` gives the same two and then the certified
min-max of the true output error over the whole range (``optimize=True``). Every design's
*structural error* is evaluated the same way: ``FourBar.motion`` over 2001 points of the range
(pylinkage's design on the branch that passes nearest its first pair), minus the ideal output.
pylinkage's ``require_grashof`` is turned off, since the design is a non-Grashof triple rocker
(pylinkage refuses it by default). Times are of a second call (the first loads modules).

Run: python benchmarks/bench_function_generation.py [--markdown]
(pip install pylinkage==1.3.0 for the comparison; without it only mechsynth's rows are printed.)
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import mechsynth as ms
from mechsynth.synthesis.freudenstein import chebyshev_spacing

X0, X1 = 1.0, 10.0
DPHI, DPSI = ms.deg(60.0), ms.deg(90.0)
PHI0, PSI0 = ms.deg(120.0), ms.deg(20.0)
N_EVAL = 2001


def ideal(x):
    return np.log10(x) / np.log10(X1) * DPSI


def structural_error(design, phi0, psi0) -> float:
    """max |true rocker angle - ideal| (rad) over the range, phases in the design's convention."""
    x = np.linspace(X0, X1, N_EVAL)
    psi = design.motion(phi0 + (x - X0) / (X1 - X0) * DPHI).links["rocker"].angle
    d = psi - psi0 - ideal(x)
    return float(np.max(np.abs(np.arctan2(np.sin(d), np.cos(d)))))


def pairs(n):
    x = chebyshev_spacing(X0, X1, n)
    return [(PHI0 + (xi - X0) / (X1 - X0) * DPHI, PSI0 + ideal(xi)) for xi in x]


def pylinkage_row(n):
    import pylinkage
    from pylinkage.synthesis.function_generation import function_generation

    pp = pairs(n)
    t = time.perf_counter()
    res = function_generation(pp, ground_length=1.0, require_grashof=False)
    dt = time.perf_counter() - t
    if not res.raw_solutions:
        return f"pylinkage {pylinkage.__version__}", None, dt, "; ".join(res.warnings)
    s = res.raw_solutions[0]
    lengths = (s.crank_length, s.coupler_length, s.rocker_length, s.ground_length)
    best = None
    for branch in ("open", "crossed"):  # the branch nearest its first pair
        fb = ms.FourBar(*lengths, branch=branch, full_turn=False)
        try:
            miss = abs(fb.motion(np.array([pp[0][0]])).links["rocker"].angle[0] - pp[0][1])
            err = structural_error(fb, PHI0, PSI0)
        except ms.MechanismError:
            continue
        miss = abs(np.arctan2(np.sin(miss), np.cos(miss)))
        if best is None or miss < best[0]:
            best = (miss, err)
    note = "; ".join(res.warnings)
    return f"pylinkage {pylinkage.__version__}", (None if best is None else best[1]), dt, note


def mechsynth_rows(n):
    rows = []
    kw = dict(x=(X0, X1), input_range=DPHI, output_range=DPSI, phases=(PHI0, PSI0), points=n,
              n_eval=N_EVAL)  # fmt: skip
    for optimize in (False, True):
        t = time.perf_counter()
        fg = ms.function_generation("log10(x)", optimize=optimize, min_transmission=None, **kw)
        dt = time.perf_counter() - t
        err = structural_error(fg.design, *fg.phases)
        note = ""
        if optimize:
            note = f"certified {fg.solve.certification.certified}, {fg.solve.status}"
        rows.append((f"mechsynth {fg.method}", err, dt, note))
    return rows


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--markdown", action="store_true", help="print a Markdown table")
    args = p.parse_args(argv)
    table = []
    try:  # first calls load modules: not timed
        pylinkage_row(3)
    except ImportError:
        pass
    mechsynth_rows(3)
    for n in (3, 5, 9):
        try:
            table.append((n, *pylinkage_row(n)))
        except ImportError:
            pass
        for row in mechsynth_rows(n):
            table.append((n, *row))
    if args.markdown:
        print("| points | method | max structural error (deg) | time (ms) | note |")
        print("|---:|---|---:|---:|---|")
        for n, name, err, dt, note in table:
            e = "no design" if err is None else f"{np.degrees(err):.4f}"
            print(f"| {n} | {name} | {e} | {1e3 * dt:.1f} | {note} |")
    else:
        for n, name, err, dt, note in table:
            e = "no design" if err is None else f"{np.degrees(err):10.4f} deg"
            print(f"{n:3d}  {name:28s} {e}  {1e3 * dt:8.1f} ms  {note}")


if __name__ == "__main__":
    main()
