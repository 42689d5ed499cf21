"""Paper 003 (second part): dwell linkage on a central slider-crank, synthesized for the longest
dwell.

Problem: find (r, k, gamma) maximizing the dwell duration alpha_Sigma subject to a dwell accuracy
(half-width E <= tolerance, lengths relative to the rod) and a relative stroke S_max >= a required
stroke of link 5, over the box ``R_BOUNDS`` x ``K_BOUNDS`` x ``G_BOUNDS``.

The dwell metrics are not smooth (the window length is an integer number of crank-angle samples,
and the longest window can jump from one part of the coupler curve to another), and the feasible
optimum lies on narrow ridges of the (r, k, gamma) box. So the search is:

1. *global grid* — every design of a coarse grid over all three variables, at 360 crank angles;
2. *refinement* — from the best few distinct grid designs, a neighbourhood search at 720 crank
   angles: each round evaluates the 26 neighbours ``p + h * {-1, 0, 1}^3`` of every start (one
   batch), moves to the best one when it is better, else halves ``h``;
3. *certificate* — every design of an independent grid over the whole box (all of r, k and gamma,
   720 angles) and of a dense local grid around the result, which passes only when the result is
   feasible and no grid design is longer by more than one angle step.

Design ordering everywhere: a feasible design (S_max >= stroke) ranks by its dwell, an infeasible
one below every feasible one by its stroke shortfall; equal dwells rank by the larger S_max.
"""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numba
import numpy as np

from ..errors import MechanismError
from ..fileio import output_dir
from ..machines.dwell import DwellSliderCrank
from ..machines.dwell.metrics import dwell_metrics, dwell_window
from ..options import Option, takes_options
from ..progress import Stages
from . import StudyResult

R_BOUNDS = (0.05, 0.5)
K_BOUNDS = (0.3, 2.5)
G_BOUNDS = (-60.0, 60.0)
LOWER = np.array([R_BOUNDS[0], K_BOUNDS[0], G_BOUNDS[0]])
UPPER = np.array([R_BOUNDS[1], K_BOUNDS[1], G_BOUNDS[1]])
NAMES = ("r", "k", "gamma_deg")
FIELDS = ("dwell_deg", "phi_L_deg", "deviation", "xi_deg", "S_max")

# the 26 neighbours of a point of a 3-D grid
_NEIGHBOURS = np.stack(np.meshgrid(*[[-1.0, 0.0, 1.0]] * 3, indexing="ij"), -1).reshape(-1, 3)
_NEIGHBOURS = _NEIGHBOURS[np.any(_NEIGHBOURS != 0.0, axis=1)]


def _check_positive(name, value):
    value = float(value)
    if not np.isfinite(value) or value <= 0:
        raise MechanismError(f"{name} must be positive, got {value}")
    return value


def _check_counts(name, value, minimum):
    """Grid points per axis: an int for all three axes or three ints (r, k, gamma)."""
    counts = np.broadcast_to(np.asarray(value, dtype=int), (3,))
    if np.any(counts < minimum):
        raise MechanismError(f"{name} (grid points per axis) must be >= {minimum}, got {value}")
    return tuple(int(c) for c in counts)


def evaluate_batch(points, tolerance, n_angles=720, workers=1, chunk=256):
    """Dwell metrics of many designs.

    Parameters
    ----------
    points : array (m, 3) of designs ``(r, k, gamma_deg)``; lengths relative to the rod, gamma in
        degrees (counter-clockwise from AB to AC).
    tolerance : admitted half-width E of the dwell band, relative to the rod.
    n_angles : crank angles per cycle (uniform, from 0); the dwell is quantized to 360/n_angles deg.
    workers : threads of the compiled window sweeps (over the designs of each chunk of
        ``chunk`` designs).

    Returns
    -------
    dict of arrays (m,): ``dwell_deg``, ``phi_L_deg`` (start of the window), ``deviation`` (E of
    the window's minimax line), ``xi_deg`` (its slope) and ``S_max`` (stroke of link 5 with the
    slot along that line).
    """
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    phi = np.arange(n_angles) * 2 * np.pi / n_angles

    def block(q):
        m = DwellSliderCrank(r=q[:, 0:1], k=q[:, 1:2], gamma=np.deg2rad(q[:, 2:3]))
        x, y = np.broadcast_arrays(*m.coupler_curve(phi))
        w = dwell_metrics(phi, x, y, tolerance)
        deg = np.rad2deg
        return np.column_stack(
            [deg(w["dwell"]), deg(w["phi_L"]), w["deviation"], deg(w["xi"]), w["S_max"]]
        )

    parts = np.array_split(p, max(1, -(-len(p) // int(chunk))))
    with _numba_threads(workers):
        cols = np.concatenate([block(q) for q in parts])
    return dict(zip(FIELDS, cols.T))


@contextmanager
def _numba_threads(workers):
    """Run the (numba-parallel) dwell sweeps on ``workers`` threads, then restore the setting.

    The parallelism is inside the compiled sweeps, over designs; calling them from several Python
    threads instead would need a thread-safe numba threading layer."""
    workers = int(workers)
    if workers < 1:
        raise MechanismError(f"workers must be >= 1, got {workers}")
    before = numba.get_num_threads()
    numba.set_num_threads(min(workers, numba.config.NUMBA_NUM_THREADS))
    try:
        yield
    finally:
        numba.set_num_threads(before)


def evaluate(r, k, gamma_deg, tolerance, n_angles=720):
    """Dwell metrics of one design: dict with r, k, gamma_deg, phi_L_deg, dwell_deg, deviation
    (E, relative to the rod), xi_deg and S_max (see :func:`evaluate_batch`)."""
    m = evaluate_batch([[r, k, gamma_deg]], tolerance, n_angles)
    design = {"r": float(r), "k": float(k), "gamma_deg": float(gamma_deg)}
    design.update({f: float(m[f][0]) for f in FIELDS})
    return design


def score(dwell_deg, s_max, stroke):
    """Dwell (deg) where the stroke constraint holds, else a penalty below every feasible value."""
    short = stroke - np.asarray(s_max)
    return np.where(short <= 0, dwell_deg, -1000.0 * short)


def _feasible(design, tolerance, stroke) -> bool:
    """The design meets E <= tolerance and S_max >= stroke."""
    return bool(design["S_max"] >= stroke and design["deviation"] <= tolerance)


def _argbest(key, s_max, axis=None):
    """Index of the best design: the largest key, ties broken by the larger S_max."""
    top = np.max(key, axis=axis, keepdims=True)
    return np.argmax(np.where(key == top, s_max, -np.inf), axis=axis)


def _design(points, metrics, i):
    d = dict(zip(NAMES, map(float, points[i])))
    d.update({f: float(metrics[f][i]) for f in FIELDS})
    return d


def _grid(lower, upper, counts):
    axes = [np.linspace(lo, hi, c) for lo, hi, c in zip(lower, upper, counts)]
    return np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)


@dataclass(frozen=True)
class Stage:
    """One stage of the search: its best design, evaluation count and crank-angle resolution."""

    name: str
    best: dict
    evaluations: int
    n_angles: int
    detail: dict

    def as_dict(self):
        return {
            "name": self.name,
            "best": self.best,
            "evaluations": self.evaluations,
            "n_angles": self.n_angles,
            **self.detail,
        }


def grid_stage(tolerance, stroke, n=(16, 23, 25), starts=6, n_angles=360, workers=1):
    """Global stage: the coarse grid ``n`` (points on r, k, gamma, bounds included) at
    ``n_angles``; returns the Stage and the ``starts`` best distinct designs (array (s, 3)),
    best first. Designs closer than two grid cells (in every variable) to a better chosen one or
    to its mirror image (gamma -> -gamma, which has the same dwell: the mirrored curve is run
    backwards) are skipped, so the starts lie on different ridges; infeasible designs are not
    chosen."""
    n = _check_counts("n", n, 2)
    pts = _grid(LOWER, UPPER, n)
    m = evaluate_batch(pts, tolerance, n_angles, workers)
    key = score(m["dwell_deg"], m["S_max"], stroke)
    cell = (UPPER - LOWER) / (np.array(n) - 1)
    free = key >= 0
    chosen = []
    while len(chosen) < int(starts) and free.any():
        i = int(_argbest(np.where(free, key, -np.inf), m["S_max"]))
        chosen.append(i)
        for twin in (pts[i], pts[i] * [1.0, 1.0, -1.0]):
            free &= np.max(np.abs(pts - twin) / cell, axis=1) > 2.0
    best = _design(pts, m, int(_argbest(key, m["S_max"])))
    detail = {"grid": list(n), "feasible": int(np.count_nonzero(key >= 0)), "starts": len(chosen)}
    return Stage("global grid", best, len(pts), n_angles, detail), pts[chosen]


def refine(starts, tolerance, stroke, step, min_scale=1 / 64, n_angles=720, workers=1, rounds=200):
    """Neighbourhood search from every start at once (vectorized over starts).

    Parameters
    ----------
    starts : array (s, 3) of designs ``(r, k, gamma_deg)``.
    step : initial step ``h`` per variable (r, k, gamma_deg).
    min_scale : a start stops when its step has been halved below ``min_scale * step``.
    rounds : cap on the rounds (each round evaluates 26 neighbours of every active start).

    Returns
    -------
    Stage with the best design found (at ``n_angles``) and the number of evaluations.
    """
    p = np.array(starts, dtype=float, ndmin=2)
    step = np.asarray(step, dtype=float)
    m = evaluate_batch(p, tolerance, n_angles, workers)
    key = score(m["dwell_deg"], m["S_max"], stroke)
    s_max = m["S_max"].copy()
    scale = np.ones(len(p))
    nfev = len(p)
    for _ in range(int(rounds)):
        act = np.flatnonzero(scale >= min_scale)
        if act.size == 0:
            break
        q = p[act, None, :] + _NEIGHBOURS[None] * (step * scale[act, None])[:, None, :]
        q = np.clip(q, LOWER, UPPER)
        mq = evaluate_batch(q.reshape(-1, 3), tolerance, n_angles, workers)
        nfev += q.shape[0] * q.shape[1]
        kq = score(mq["dwell_deg"], mq["S_max"], stroke).reshape(q.shape[:2])
        sq = mq["S_max"].reshape(q.shape[:2])
        j = _argbest(kq, sq, axis=1).ravel()
        rows = np.arange(act.size)
        kb, sb = kq[rows, j], sq[rows, j]
        better = (kb > key[act]) | ((kb == key[act]) & (sb > s_max[act]))
        moved = act[better]
        p[moved] = q[rows, j][better]
        key[moved], s_max[moved] = kb[better], sb[better]
        scale[act[~better]] *= 0.5
    i = int(_argbest(key, s_max))
    best = evaluate(*p[i], tolerance, n_angles)
    detail = {"starts": len(p), "step": step.tolist(), "min_scale": float(min_scale)}
    return Stage("refinement", best, nfev, n_angles, detail)


@dataclass(frozen=True)
class Certificate:
    """Grid certificate of a design over the whole (r, k, gamma) box.

    Attributes
    ----------
    design : the design tested, re-evaluated at ``n_angles``.
    grid_best : the best design of the two grids (dict as :func:`evaluate`).
    box_grid : points on r, k, gamma of the grid over the whole box (bounds included).
    local_grid : points per axis of the local grid, spanning ``local_half_width`` (r, k,
        gamma_deg) about the design, clipped to the box.
    evaluations : designs evaluated.
    slack_deg : admitted shortfall of the design's dwell: one angle step, 360 / n_angles deg.
    feasible : the design meets E <= tolerance and S_max >= stroke.
    passed : feasible and ``design dwell >= grid_best dwell - slack_deg``.
    """

    design: dict
    grid_best: dict
    box_grid: tuple
    local_grid: int
    local_half_width: tuple
    n_angles: int
    evaluations: int
    slack_deg: float
    feasible: bool
    passed: bool

    @property
    def margin_deg(self) -> float:
        """Design dwell minus the best grid dwell (deg); >= -slack_deg when passed."""
        return self.design["dwell_deg"] - self.grid_best["dwell_deg"]

    def as_dict(self):
        return {
            "box_grid": list(self.box_grid),
            "box": {"r": list(R_BOUNDS), "k": list(K_BOUNDS), "gamma_deg": list(G_BOUNDS)},
            "local_grid": self.local_grid,
            "local_half_width": list(self.local_half_width),
            "n_angles": self.n_angles,
            "evaluations": self.evaluations,
            "best_dwell_deg": self.grid_best["dwell_deg"],
            "grid_best": self.grid_best,
            "design_dwell_deg": self.design["dwell_deg"],
            "margin_deg": self.margin_deg,
            "slack_deg": self.slack_deg,
            "feasible": self.feasible,
            "passed": self.passed,
        }


def certify(
    r, k, gamma_deg, tolerance, stroke, dense=(13, 17, 25), local=9, n_angles=720, workers=1
):
    """Test a design against every design of a grid over the whole box and of a local grid.

    Parameters
    ----------
    r, k, gamma_deg : the design (relative lengths, bend in degrees).
    tolerance, stroke : E <= tolerance and S_max >= stroke (relative to the rod).
    dense : points on r, k, gamma of the box grid (an int for all three), bounds included.
    local : points per axis of the local grid, which spans one box-grid cell on each side of the
        design (clipped to the box).
    n_angles : crank angles of every evaluation.

    Returns
    -------
    Certificate; it fails when a grid design is longer than the design by more than one angle
    step, or when the design is infeasible.
    """
    tolerance = _check_positive("tolerance", tolerance)
    stroke = _check_positive("stroke", stroke)
    dense = _check_counts("dense", dense, 2)
    local = _check_counts("local", local, 2)[0]
    centre = np.array([r, k, gamma_deg], dtype=float)
    if not np.all((centre >= LOWER) & (centre <= UPPER)):
        raise MechanismError(f"design (r, k, gamma_deg) = {tuple(centre)} is outside the box")
    half = (UPPER - LOWER) / (np.array(dense) - 1)
    pts = np.concatenate(
        [
            _grid(LOWER, UPPER, dense),
            _grid(np.maximum(centre - half, LOWER), np.minimum(centre + half, UPPER), (local,) * 3),
        ]
    )
    m = evaluate_batch(pts, tolerance, n_angles, workers)
    grid_best = _design(
        pts, m, int(_argbest(score(m["dwell_deg"], m["S_max"], stroke), m["S_max"]))
    )
    design = evaluate(*centre, tolerance, n_angles)
    feasible = _feasible(design, tolerance, stroke)
    slack = 360.0 / n_angles
    passed = bool(feasible and design["dwell_deg"] >= grid_best["dwell_deg"] - slack - 1e-9)
    return Certificate(
        design,
        grid_best,
        dense,
        local,
        tuple(half.tolist()),
        int(n_angles),
        len(pts),
        slack,
        bool(feasible),
        passed,
    )


def _draw(best, tolerance, stroke, out: Path):
    """The best design at the start of its dwell with the coupler curve, the dwell section and
    the slot, and the displacement of link 5 with the dwell window; an animation of it."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..plotting import PALETTE, crank_axis, style
    from ..plotting import save as save_figure

    n = 720
    phi = np.arange(n) * 2 * np.pi / n
    xi = np.deg2rad(best["xi_deg"])
    m = DwellSliderCrank(best["r"], best["k"], np.deg2rad(best["gamma_deg"]), xi=xi)
    w = dwell_window(phi, *m.coupler_curve(phi), tolerance)
    idx = (w.start + np.arange(w.count)) % n
    mo = m.motion(phi)
    c = mo.points["C"]
    design = (
        f"r = {best['r']:.4f}, k = {best['k']:.4f}, γ = {best['gamma_deg']:.2f}°, "
        f"ξ = {best['xi_deg']:.2f}°"
    )
    with style():
        fig, (a1, a2) = plt.subplots(
            1, 2, figsize=(13, 5.5), layout="constrained", width_ratios=(1.25, 1)
        )
        m.draw(phi[w.start], ax=a1, trace=(), title=False)
        a1.plot(c.x, c.y, color="0.45", lw=1, ls="--", label="coupler curve of C")
        a1.plot(
            np.asarray(c.x)[idx],
            np.asarray(c.y)[idx],
            color=PALETTE[5],
            lw=3,
            label=f"dwell section ({best['dwell_deg']:.1f}°)",
        )
        a1.set_xlabel("x / l")
        a1.set_ylabel("y / l")
        a1.legend(loc="upper left", bbox_to_anchor=(0.0, -0.12), ncol=2)
        a1.set_title(
            f"Longest-dwell linkage: {design}\nat the start of the dwell, "
            f"φ_L = {best['phi_L_deg']:.1f}°",
            fontsize=9,
        )
        s5 = np.asarray(mo.sliders["5"].position)
        deg = np.rad2deg(phi)
        a2.plot(deg, s5, "k-", lw=1.2, label="displacement s5 of link 5")
        a2.plot(
            deg[idx],
            s5[idx],
            ".",
            color=PALETTE[5],
            ms=2.5,
            label=f"dwell α_Σ = {best['dwell_deg']:.1f}°",
        )
        crank_axis(a2, "crank angle φ")
        a2.set_ylabel("displacement s5 of link 5, × l")
        a2.set_title(
            f"stroke S_max = {best['S_max']:.4f} l (≥ {stroke:g} l), band 2E = "
            f"{2 * best['deviation']:.4g} l (E ≤ {tolerance:g} l)",
            fontsize=9,
        )
        a2.legend(loc="upper left", bbox_to_anchor=(0.0, -0.12), ncol=2)
        files = [save_figure(fig, out / "dwell_best.png", dpi=120)]
    anim = m.animate(frames=36, dpi=60)
    files.append(anim.save(out / "dwell_best.gif"))
    return files


def sensitivity(best, tolerance, rel=0.01):
    """How firmly the best design holds its dwell: the dwell of the same design for a tolerance
    ``rel`` tighter and looser, and of the design rounded to the printed digits (r, k to 4
    decimals, gamma to 0.01 deg). The longest dwell sits where the section's waviness just meets
    the tolerance, so a small change can cut the window at a different wave.

    Returns a dict: ``dwell_deg_tighter``, ``dwell_deg_looser`` (deg), ``rel`` and ``rounded``
    (the rounded design with its metrics at ``tolerance``)."""
    r, k, g = best["r"], best["k"], best["gamma_deg"]
    rounded = evaluate(round(r, 4), round(k, 4), round(g, 2), tolerance)
    return {
        "rel": rel,
        "dwell_deg_tighter": evaluate(r, k, g, tolerance * (1 - rel))["dwell_deg"],
        "dwell_deg_looser": evaluate(r, k, g, tolerance * (1 + rel))["dwell_deg"],
        "rounded": rounded,
    }


def _sensitivity_line(sens):
    rd = sens["rounded"]
    pct = 100 * sens["rel"]
    return (
        f"sensitivity: the same design dwells {sens['dwell_deg_tighter']:.1f} deg for E "
        f"{pct:g} % tighter, {sens['dwell_deg_looser']:.1f} deg for E {pct:g} % looser; rounded "
        f"to r={rd['r']:.4f} k={rd['k']:.4f} gamma={rd['gamma_deg']:.2f} deg it dwells "
        f"{rd['dwell_deg']:.1f} deg (E={rd['deviation']:.4g} l). Give the design at full "
        "precision, or synthesize for a smaller E than the one to hold."
    )


def _line(d):
    return (
        f"r={d['r']:.4f} k={d['k']:.4f} gamma={d['gamma_deg']:.2f} deg, "
        f"dwell {d['dwell_deg']:.1f} deg, S_max={d['S_max']:.4f}"
    )


@takes_options(
    Option(
        "tolerance",
        0.002,
        "half-width E of the dwell band, relative to the rod",
        minimum=0.0,
        exclusive=True,
        maximum=1.0,
    ),
    Option(
        "stroke",
        0.3,
        "minimum stroke S_max, relative to the rod",
        minimum=0.0,
        exclusive=True,
        maximum=10.0,
    ),
    Option(
        "n",
        (16, 23, 25),
        "global grid points on r, k, gamma (one value: all three)",
        minimum=2,
        maximum=200,
    ),
    Option("starts", 6, "distinct grid designs refined at 720 angles", minimum=1, maximum=1000),
    Option(
        "dense",
        (13, 17, 25),
        "certificate's box grid on r, k, gamma (one value: all three)",
        minimum=2,
        maximum=200,
    ),
    Option("local", 9, "points per axis of the certificate's local grid", minimum=2, maximum=101),
    Option(
        "min_scale",
        1 / 64,
        "refinement stops below this fraction of a grid half-cell",
        minimum=1e-4,
        maximum=1.0,
    ),
    Option("workers", 2, "threads for the batch evaluations", minimum=1, maximum=256),
    owner="study 'dwell'",
)
def run(
    out=None,
    tolerance=0.002,
    stroke=0.3,
    n=(16, 23, 25),
    starts=6,
    dense=(13, 17, 25),
    local=9,
    min_scale=1 / 64,
    workers=2,
):
    """Synthesize the longest-dwell linkage for half-width ``tolerance`` and stroke ``stroke``.

    Parameters
    ----------
    out : directory for the figure ``dwell_best.png`` (None: no figure).
    tolerance, stroke : E <= tolerance, S_max >= stroke (relative to the rod).
    n : points on r, k, gamma of the global grid (360 angles; an int for all three axes).
    starts : distinct grid designs refined at 720 angles.
    dense, local : the certificate's box grid and local grid (see :func:`certify`).
    min_scale : the refinement stops when its step is below ``min_scale`` of a global-grid
        half-cell.
    workers : threads for the batch evaluations.

    Returns
    -------
    StudyResult; ``data`` holds ``best``, ``seed`` (the best global-grid design at 720 angles),
    ``stages``, ``evaluations``, ``certificate`` and ``success``.
    """
    tolerance = _check_positive("tolerance", tolerance)
    stroke = _check_positive("stroke", stroke)
    n = _check_counts("n", n, 2)
    if int(starts) < 1:
        raise MechanismError(f"starts must be >= 1, got {starts}")
    names = ["1. global grid", "2. refinement", "3. certificate"]
    if out is not None:
        names.append("figure and animation")
    with Stages("dwell", names) as st:
        return _run(out, tolerance, stroke, n, starts, dense, local, min_scale, workers, st, names)


def _run(out, tolerance, stroke, n, starts, dense, local, min_scale, workers, st, names):
    st.next(names[0])
    global_stage, start_points = grid_stage(tolerance, stroke, n, starts, 360, workers)
    data = {"tolerance": tolerance, "stroke": stroke, "stages": [global_stage.as_dict()]}
    if len(start_points) == 0:
        summary = f"no design on the global grid {n} reaches the stroke {stroke:g} l"
        data.update(success=False, evaluations=global_stage.evaluations)
        return COVERAGE.attach(StudyResult("dwell", summary, data), out)
    g = global_stage.best
    seed = evaluate(g["r"], g["k"], g["gamma_deg"], tolerance)
    step = 0.5 * (UPPER - LOWER) / (np.array(n) - 1)
    st.next(names[1])
    stage2 = refine(start_points, tolerance, stroke, step, min_scale, 720, workers)
    best = stage2.best
    st.next(names[2])
    cert = certify(
        best["r"], best["k"], best["gamma_deg"], tolerance, stroke, dense, local, 720, workers
    )
    success = _feasible(best, tolerance, stroke)
    data.update(
        best=best,
        seed=seed,
        sensitivity=sensitivity(best, tolerance),
        evaluations=global_stage.evaluations + stage2.evaluations,
        certificate=cert.as_dict(),
        success=bool(success),
    )
    data["stages"].append(stage2.as_dict())
    files = []
    if out is not None:
        st.next(names[3])
        out = output_dir(out)
        files += _draw(best, tolerance, stroke, out)
    cb = cert.grid_best
    summary = "\n".join(
        [
            f"Dwell synthesis: E <= {tolerance:g} l, S_max >= {stroke:g} l, r in {R_BOUNDS}, "
            f"k in {K_BOUNDS}, gamma in {G_BOUNDS} deg",
            f"1. global grid {n[0]}x{n[1]}x{n[2]} (r, k, gamma), 360 angles, "
            f"{global_stage.evaluations} designs: best {_line(g)}; "
            f"{seed['dwell_deg']:.1f} deg at 720 angles",
            f"2. refinement from {stage2.detail['starts']} distinct grid designs, 720 angles, "
            f"{stage2.evaluations} designs: best {_line(best)}",
            f"best: dwell {best['dwell_deg']:.1f} deg from phi_L={best['phi_L_deg']:.1f} deg, "
            f"E={best['deviation']:.4g} l, xi={best['xi_deg']:.2f} deg",
            f"3. certificate: {cert.box_grid[0]}x{cert.box_grid[1]}x{cert.box_grid[2]} grid over "
            f"the whole box + {local}^3 local grid, 720 angles, {cert.evaluations} designs: "
            f"best {_line(cb)}; margin {cert.margin_deg:+.1f} deg "
            f"(slack {cert.slack_deg:g}) -> {'passed' if cert.passed else 'NOT passed'}",
            _sensitivity_line(data["sensitivity"]),
        ]
    )
    return COVERAGE.attach(StudyResult("dwell", summary, data, files), out)


# ------------------------------------------------------------------------------ coverage
def _coverage():
    from .coverage import Coverage, Item

    t = "tests/test_dwell.py::"
    s = "tests/test_dwell_study.py::"
    c = "tests/test_dwell_charts.py::"
    return Coverage(
        "Paper 003, second part (Kinytskyi et al.): dwell linkages on the coupler curve of a "
        "central slider-crank",
        "dwell",
        (
            Item(
                "scheme",
                "data",
                "central slider-crank OAB with a coupler point C off the rod (r = OA/l, k = AC/l, "
                "bend gamma at A)",
                "reproduced",
                "machines.dwell.DwellSliderCrank",
                (t + "test_k_zero_is_slider_path", t + "test_gamma_sign_convention"),
                "k = 0 gives the slider's straight path; the sign of gamma as the paper draws it",
            ),
            Item(
                "coupler curve",
                "finding",
                "C's coupler curve has a nearly straight section K_L K_R for suitable "
                "(r, k, gamma)",
                "reproduced",
                "machines.dwell.metrics.dwell_window",
                (
                    t + "test_synthetic_straight_segment_window",
                    t + "test_hoeken_straight_line_linkage",
                ),
                "found as the longest crank-angle window whose minimax straight-line fit deviates "
                "by at most E",
            ),
            Item(
                "output link 5",
                "finding",
                "an RPR group at C (C in a slot of link 5 along K_L K_R) keeps link 5 still "
                "while C runs on the section",
                "reproduced",
                "machines.dwell.DwellSliderCrank",
                (t + "test_s5_stationary_over_dwell_and_derivatives",),
                "the output's motion over the dwell equals the band width 2E",
            ),
            Item(
                "alpha_Sigma",
                "data",
                "dwell duration: the crank angle C spends on the straight section",
                "reproduced",
                "machines.dwell.metrics.dwell_metrics ('dwell')",
                (t + "test_measures_batch", t + "test_minimax_fit_matches_brute_force"),
                "from exact minimax line fits (checked against brute force)",
            ),
            Item(
                "S_max",
                "data",
                "relative maximum stroke of link 5",
                "reproduced",
                "machines.dwell.metrics.dwell_metrics ('S_max')",
                (t + "test_measures_batch", t + "test_minimax_fit_matches_brute_force"),
                "from exact minimax line fits (checked against brute force)",
            ),
            Item(
                "2E",
                "data",
                "dwell accuracy: the width of the band holding the section (link 5's "
                "residual motion)",
                "reproduced",
                "machines.dwell.metrics.dwell_metrics ('deviation')",
                (t + "test_measures_batch", t + "test_minimax_fit_matches_brute_force"),
                "from exact minimax line fits (checked against brute force)",
            ),
            Item(
                "xi",
                "data",
                "slope of the straight section (the slot of link 5)",
                "reproduced",
                "machines.dwell.metrics.dwell_metrics ('xi')",
                (t + "test_measures_batch", t + "test_minimax_fit_matches_brute_force"),
                "from exact minimax line fits (checked against brute force)",
            ),
            Item(
                "phi_L",
                "data",
                "crank angle at which the dwell starts (C at K_L)",
                "reproduced",
                "machines.dwell.metrics.dwell_metrics ('phi_L')",
                (t + "test_measures_batch", t + "test_minimax_fit_matches_brute_force"),
                "from exact minimax line fits (checked against brute force)",
            ),
            Item(
                "reference charts",
                "figure",
                "charts of the characteristics over (r, k, gamma) for preliminary synthesis",
                "added",
                "mechsynth chart dwell",
                (c + "test_chart_numbers_match_direct_evaluation", c + "test_chart_cli_renders"),
                "the paper's charts are in the lost part of the text; ours are drawn from the "
                "construction above",
            ),
            Item(
                "construction",
                "finding",
                "how the charts and the synthesis are computed",
                "added",
                "studies.dwell (grid, refinement, certificate)",
                (
                    s + "test_default_search_reaches_112_deg",
                    s + "test_default_certificate_passes_the_result",
                ),
                "the text stops before its method: the construction is ours (docs/dwell.md); "
                "112 deg for E = 0.002 l, S_max >= 0.3 l, certified over the whole box",
            ),
        ),
    )


COVERAGE = _coverage()
