"""Path generation benchmark (not run by the test suite): the literature's closed paths and the
exact case, by this library, by scipy's differential evolution on the same error, and by
pylinkage's path synthesis, each timed in the same run.

Formulation (every method, every case): a four-bar whose crank turns fully (Grashof crank:
``crank + ground < coupler + rocker`` and ``|ground - crank| > |coupler - rocker|``), one
assembly branch over the whole turn (the dyad never reaches a toggle when the crank turns
fully), free timing with the order constraint (crank angles increasing, the last within one
counter-clockwise turn of the first), error = sum over the targets of the squared distance
between target and coupler point, smallest transmission angle over the turn at least the
published design's. Variables: crank, coupler, rocker, ground, the coupler point (u, v), the
crank pivot (x0, y0), the ground angle and the N crank angles. Bounds: lengths D/200 to 10 D
(the crank to 5 D), coupler point within 10 D, pivot within 5 D of the targets' box (D the
box's diagonal).

Cases (mechsynth.synthesis.path_cases): the 18- and 12-point closed paths of Bulatovic,
Miodragovic and Boskovic, Mech. Mach. Theory 95 (2016) (published 4.961e-3 at 24.7 deg and
1.515e-4 at 21.3 deg, recomputed with ordered free timing), the two 20-point closed paths of Yu,
Tang and Wang, Mech. Mach. Theory 42 (2007) (the published error not available to us: the
reference is the published linkage's error recomputed by the library's model, 3.4297 at 41.27
deg and 18.646 at 42.42 deg), and nine points of a known four-bar's coupler curve (error must
reach round-off).

* mechsynth: ``ms.path_generation`` (atlas seeds by elliptic Fourier descriptors, IPOPT with
  exact derivatives, Gauss-Newton polish), 16 starts.
* scipy DE: ``scipy.optimize.differential_evolution`` on the same variables and error,
  evaluated by the library's numpy four-bar model for the whole population at once; the order,
  full turn and transmission angle as penalties (the literature's way); stopped at the time
  budget (``--budget``, default 60 s) or its own convergence; no local polish.
* pylinkage 1.3.0 (``pip install pylinkage==1.3.0``; skipped with a message without it):
  ``pylinkage.synthesis.path_generation`` (Burmester theory over sampled coupler orientations).
  Its solutions' error is the sum of squared distances from each target to the nearest point of
  the traced curve (a lower bound of the ordered-timing error).

``--front`` adds the error-versus-transmission-angle front of each literature case (0 to 45
deg), ``--out DIR`` writes the figures and ``results.json``.

Run: python benchmarks/bench_path_generation.py [--budget S] [--front] [--out DIR]
[--cases NAME ...]; ``--bound-figure --out DIR`` draws only the lower bound's figure.
"""

from __future__ import annotations

import argparse
import json
import time
import warnings
from pathlib import Path

import numpy as np

import mechsynth as ms
from mechsynth.synthesis.path_atlas import min_transmission
from mechsynth.synthesis.path_cases import CASES, exact_case


def _cases():
    out = [(c.name, c.targets, c.reference_error, c.published_mu) for c in CASES.values()]
    pts, _, _ = exact_case()
    out.append(("exact-9", pts, None, 0.0))
    return out


def run_mechsynth(targets, mu):
    t0 = time.perf_counter()
    r = ms.path_generation(targets, min_transmission=ms.deg(mu) if mu else None, starts=16)
    dt = time.perf_counter() - t0
    return {
        "error": r.error,
        "mu": float(np.rad2deg(r.transmission[0])),
        "seconds": dt,
        "starts": r.starts,
        "distinct": r.distinct,
        "result": r,
    }


def _population_error(X, targets, mu_min):
    """Penalized error of a population ``X`` (D, S) by the numpy four-bar model."""
    from mechsynth.kinematics import ops
    from mechsynth.kinematics.blocks import coupler_point
    from mechsynth.kinematics.four_bar import four_bar_chain

    n = len(targets)
    # penalties in the error's units: the targets' spread times their count
    big = n * float(np.sum(np.ptp(targets, axis=0) ** 2))
    crank, coupler, rocker, ground, u, v, x0, y0, ang = X[:9]
    phi = np.sort(X[9:], axis=0)  # the order: sorted (penalty below for the one-turn span)
    span = phi[-1] - phi[0]
    ok = (crank + ground < coupler + rocker) & (np.abs(ground - crank) > np.abs(coupler - rocker))
    out = np.full(X.shape[1], 1e3 * big)
    if not ok.any():
        return out
    mu = np.zeros_like(crank)
    mu[ok] = min_transmission(crank[ok], coupler[ok], rocker[ok], ground[ok])
    err = np.full(X.shape[1], np.inf)
    for sigma in (1, -1):
        idx = np.flatnonzero(ok)
        ph = phi[:, idx].T  # (S, n)
        col = [a[idx][:, None] for a in (crank, coupler, rocker, ground, u, v, x0, y0, ang)]
        a, _, cpl, _ = four_bar_chain(ops.cos(ph), ops.sin(ph), *col[:4], sigma)
        q = coupler_point(a, cpl, col[4], col[5])
        c, s = np.cos(col[8]), np.sin(col[8])
        x = col[6] + c * q.x - s * q.y
        y = col[7] + s * q.x + c * q.y
        e = np.sum((x - targets[:, 0]) ** 2 + (y - targets[:, 1]) ** 2, axis=1)
        err[idx] = np.minimum(err[idx], e)
    pen = 10.0 * big * (np.maximum(0.0, np.deg2rad(mu_min) - mu)
                        + np.maximum(0.0, span - 2 * np.pi))  # fmt: skip
    out[ok] = err[ok] + pen[ok]
    return out


def run_de(targets, mu, budget, seed=1):
    from scipy.optimize import differential_evolution

    from mechsynth.synthesis.path_generation import _default_bounds

    b = _default_bounds(targets)
    bounds = [b[k] for k in ("crank", "coupler", "rocker", "ground", "u", "v", "x0", "y0")]
    bounds += [(-np.pi, np.pi)] + [(0.0, 2 * np.pi)] * len(targets)
    t0 = time.perf_counter()
    best = [np.inf]

    def stop(xk, convergence=None):
        return time.perf_counter() - t0 > budget

    def fun(X):
        f = _population_error(np.atleast_2d(X.T).T if X.ndim == 1 else X, targets, mu)
        best[0] = min(best[0], float(f.min()))
        return f

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = differential_evolution(
            fun, bounds, seed=seed, vectorized=True, updating="deferred", maxiter=100000,
            popsize=15, tol=1e-12, polish=False, callback=stop,
        )  # fmt: skip
    dt = time.perf_counter() - t0
    x = res.x
    a, b_, c, d = x[:4]
    mu_x = float(np.rad2deg(min_transmission(a, b_, c, d)))
    err = float(_population_error(x[:, None], targets, 0.0)[0])
    return {"error": err, "mu": mu_x, "seconds": dt, "generations": int(res.nit)}


def run_pylinkage(targets):
    try:
        import pylinkage
        from pylinkage.synthesis.path_generation import _coupler_trajectory, path_generation
    except ImportError:
        return {"skipped": "pylinkage not installed (pip install pylinkage==1.3.0)"}
    pts = [tuple(map(float, p)) for p in targets]
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = path_generation(pts)
    dt = time.perf_counter() - t0
    best = None
    for lk in r.solutions:
        tr = _coupler_trajectory(lk, 720)
        if tr is None:
            continue
        d = ((np.asarray(targets)[:, None, :] - tr[None, :, :]) ** 2).sum(-1).min(1).sum()
        best = d if best is None else min(best, d)
    return {
        "version": pylinkage.__version__,
        "solutions": len(r.solutions),
        "error": None if best is None else float(best),
        "seconds": dt,
    }


def bound_figure(out, seconds=60.0):
    """The lower bound's two regimes on nine points of the known four-bar moved by 0.05 m
    (prescribed timing): the pivots given (it closes) and all eight coordinates within 0.05 m
    of the known design (it does not, in ``seconds``). Writes ``path_bound.png``."""
    from mechsynth.plotting import save
    from mechsynth.synthesis.path_bound import COORDS, box_point, path_bound

    t, d, ang = exact_case(9)
    t = t + np.random.default_rng(1).normal(scale=0.05, size=t.shape)
    x = box_point(d, ang[0])
    free = np.array([0, 0, 0.5, 0.5, 0, 0, 0.5, 0.5]) + 1e-9
    runs = [
        (path_bound(t, ang, region={k: (v - w, v + w) for k, v, w in zip(COORDS, x, free)},
                    branch="open", time_limit=seconds),
         "pivots given; crank vector, coupler, rocker ±0.5 m"),
        (path_bound(t, ang, region={k: (v - 0.05, v + 0.05) for k, v in zip(COORDS, x)},
                    branch="open", time_limit=seconds, max_boxes=10**8),
         "all eight coordinates ±0.05 m"),
    ]  # fmt: skip
    for b, label in runs:
        print(f"bound, {label}: {b.summary()}")
    from mechsynth.synthesis.path_figures import bound_figure as draw

    fig = draw([b for b, _ in runs], [label for _, label in runs])
    return save(fig, Path(out) / "path_bound.png")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--budget", type=float, default=60.0, help="DE's time budget per case, s")
    ap.add_argument("--front", action="store_true", help="error-transmission fronts")
    ap.add_argument("--out", help="write figures and results.json here")
    ap.add_argument("--no-de", action="store_true")
    ap.add_argument("--no-pylinkage", action="store_true")
    ap.add_argument("--cases", nargs="+", help="only these cases (default: all, exact-9 last)")
    ap.add_argument("--bound-figure", action="store_true",
                    help="only the lower bound's figure (path_bound.png into --out)")
    args = ap.parse_args(argv)
    out = Path(args.out) if args.out else None
    if out:
        out.mkdir(parents=True, exist_ok=True)
    if args.bound_figure:
        print(bound_figure(out or Path(".")))
        return
    ms.path_generation(CASES["bulatovic-12"].targets, starts=1)  # atlas and CasADi warm-up
    rows = {}
    for name, targets, pub, mu in _cases():
        if args.cases and name not in args.cases:
            continue
        print(f"\n== {name}: {len(targets)} targets, smallest transmission angle >= {mu} deg")
        if pub is not None:
            what = "published" if name not in CASES or CASES[name].published_error else (
                "published linkage, recomputed")  # fmt: skip
            print(f"{what}: {pub:.5g} at {mu} deg")
        m = run_mechsynth(targets, mu)
        print(
            f"mechsynth : error {m['error']:.6g} at {m['mu']:.2f} deg, {m['seconds']:.2f} s "
            f"({m['starts']} starts, {m['distinct']} distinct optima)"
        )
        row = {k: v for k, v in m.items() if k != "result"}
        rows[name] = {"published": pub, "published_mu": mu, "mechsynth": row}
        if out:
            import matplotlib

            matplotlib.use("Agg")
            fig = m["result"].figure()
            fig.savefig(out / f"path_{name}.png")
        if not args.no_de:
            de = run_de(targets, mu, args.budget)
            print(
                f"scipy DE  : error {de['error']:.6g} at {de['mu']:.2f} deg, {de['seconds']:.2f} s"
                f" ({de['generations']} generations)"
            )
            rows[name]["de"] = de
        if not args.no_pylinkage:
            pl = run_pylinkage(targets)
            if "skipped" in pl:
                print(f"pylinkage : skipped: {pl['skipped']}")
            else:
                err = "no solution" if pl["error"] is None else f"error {pl['error']:.6g}"
                print(
                    f"pylinkage : {err} ({pl['solutions']} solutions), {pl['seconds']:.2f} s "
                    "(error: nearest curve point per target)"
                )
            rows[name]["pylinkage"] = pl
        if args.front and pub is not None:
            from mechsynth.synthesis.path_front import transmission_front

            angles = np.deg2rad(np.arange(0.0, 46.0, 5.0))
            t0 = time.perf_counter()
            fr = transmission_front(targets, angles, starts=16)
            print(f"front ({time.perf_counter() - t0:.1f} s): ")
            for a, m_, e, k in zip(fr.asked, fr.mu, fr.error, fr.nondominated):
                print(
                    f"  >= {np.rad2deg(a):4.1f} deg: error {e:.6g} at {np.rad2deg(m_):.2f} deg"
                    + ("" if k else " (dominated)")
                )
            rows[name]["front"] = {
                "mu_deg": np.rad2deg(fr.mu).tolist(),
                "error": fr.error.tolist(),
                "nondominated": fr.nondominated.tolist(),
            }
            if out:
                fig = fr.figure(
                    published=(np.deg2rad(mu), pub, "published design"),
                    title=f"{name}: error versus smallest transmission angle",
                )
                fig.savefig(out / f"path_front_{name}.png")
    if out:
        (out / "results.json").write_text(json.dumps(rows, indent=2, default=float))


if __name__ == "__main__":
    main()
