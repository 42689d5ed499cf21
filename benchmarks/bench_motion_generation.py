"""Motion generation against pylinkage's (not run by the test suite).

For the same poses, the answer of ``mechsynth.motion_generation`` (Burmester points from a
quartic, refined by Newton) and of ``pylinkage.synthesis.motion_generation`` (pylinkage 1.3.0:
circle points found on a grid with a 1-2 % concyclicity tolerance) are measured by one evaluator:
each four-bar is built as a mechsynth Linkage from its fixed and moving pivots, its crank is
turned to where each pose puts the moving pivot, and the coupler's pose error is read (position
of the pose point, m; angle, deg), with the structural error (the largest deviation of a moving
pivot from its circle, m). Prints a Markdown table (docs/precision_synthesis.md quotes it).

pylinkage is not a dependency: ``pip install pylinkage==1.3.0`` to run the comparison; without
it the script says so and measures mechsynth alone.

Run: python benchmarks/bench_motion_generation.py [--repeat N]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

import mechsynth as ms
from mechsynth.synthesis.burmester import Dyad, _dyad
from mechsynth.synthesis.motion_generation import pair, pose_error_measure, pose_errors

# a crank-rocker (crank 1.2, coupler 3.5, rocker 3.0, ground 4.0 m) carrying a coupler frame
_FB = ms.FourBar(crank=1.2, coupler=3.5, rocker=3.0, ground=4.0)


def _four_bar_poses(phi_deg):
    m = _FB.motion(np.radians(phi_deg), coupler_points={"P": (1.1, 0.9)})
    return np.column_stack([m.points["P"].x, m.points["P"].y, m.links["coupler"].angle + 0.4])


CASES = {
    "5 poses of a crank-rocker": _four_bar_poses([10.0, 55.0, 110.0, 170.0, 230.0]),
    "5 random poses (4 Burmester points)": np.array(
        [
            [0.52, 0.76, -0.67],
            [-0.8, 0.7, 0.19],
            [-0.21, -0.04, -0.3],
            [-0.71, 0.4, 0.34],
            [-0.42, 0.74, -0.91],
        ]
    ),  # fmt: skip
    "4 poses of a crank-rocker": _four_bar_poses([10.0, 60.0, 120.0, 200.0]),
    "3 poses of a crank-rocker": _four_bar_poses([10.0, 90.0, 200.0]),
}


def _as_dyad(poses, centre, circle) -> Dyad:
    scale = float(np.max(np.hypot(*(poses[:, :2] - poses[0, :2]).T)))
    w = (np.asarray(centre, float) - poses[0, :2]) / scale
    u = (np.asarray(circle, float) - poses[0, :2]) / scale
    return _dyad(poses, w, u, scale, poses[0, :2])


def evaluate(poses, centre_a, circle_a, centre_b, circle_b):
    """(position error m, angle error deg, structural error m) of the four-bar of two dyads,
    the crank turned to where each pose puts its moving pivot; None where it cannot be built or
    assembled there."""
    try:
        c = pair(poses, _as_dyad(poses, centre_a, circle_a), _as_dyad(poses, centre_b, circle_b))
        pos, ang = pose_errors(c.linkage, poses)
        err = float(pose_error_measure(poses).fn(c.linkage))
    except (ms.MechanismError, ValueError):
        return None
    return float(pos.max()), float(np.degrees(ang.max())), err


def ours(poses):
    n = len(poses)
    if n == 3:  # every point is a centre point: the crank-rocker's own pivots
        return ms.motion_generation(poses, centres=[(0.0, 0.0), (_FB.ground, 0.0)]), None
    return ms.motion_generation(poses), None


def theirs(poses):
    from pylinkage.synthesis import Pose, motion_generation

    pl = [Pose(float(x), float(y), float(a)) for x, y, a in poses]
    if len(poses) == 3:
        from pylinkage.synthesis.motion_generation import motion_generation_3_poses

        return motion_generation_3_poses(pl)
    return motion_generation(pl, require_grashof=False)


def timed(fn, repeat):
    times, res = [], None
    for _ in range(repeat):
        t = time.perf_counter()
        res = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), res


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    try:
        import pylinkage

        have = True
        version = pylinkage.__version__
    except ImportError:
        have = False
        print("pylinkage is not installed (pip install pylinkage==1.3.0): mechsynth alone\n")
    rows = []
    for name, poses in CASES.items():
        t_ours, (mg, _) = timed(lambda p=poses: ours(p), args.repeat)
        errs = [
            e
            for c in mg.candidates
            if (
                e := evaluate(
                    poses, c.crank.centre, c.crank.circle, c.driven.centre, c.driven.circle
                )
            )
            is not None  # fmt: skip
            if c.driven.centre is not None
        ]
        best = min(errs, key=lambda e: e[0]) if errs else None
        row = {
            "case": name,
            "ours_n": len(mg.candidates),
            "ours_ok": len(mg.defect_free),
            "ours_err": best,
            "ours_t": t_ours,
        }
        if have:
            t_pl, res = timed(lambda p=poses: theirs(p), args.repeat)
            perrs = []
            for s in res.raw_solutions:
                e = evaluate(poses, s.ground_pivot_a, s.crank_pivot_b, s.ground_pivot_d,
                             s.coupler_pivot_c)  # fmt: skip
                if e is not None:
                    perrs.append(e)
            row.update(
                pl_n=len(res.raw_solutions),
                pl_err=min(perrs, key=lambda e: e[0]) if perrs else None,
                pl_fail=len(res.raw_solutions) - len(perrs),
                pl_t=t_pl,
            )
        rows.append(row)

    def fmt(e):
        return "-" if e is None else f"{e[0]:.2e} m, {e[1]:.2e} deg ({e[2]:.2e} m)"

    head = "| poses | mechsynth: linkages (defect-free), best pose error (structural), time |"
    sep = "|---|---|"
    if have:
        head += f" pylinkage {version}: linkages, best pose error (structural), time |"
        sep += "---|"
    print(head)
    print(sep)
    for r in rows:
        line = (
            f"| {r['case']} | {r['ours_n']} ({r['ours_ok']}), {fmt(r['ours_err'])}, "
            f"{r['ours_t'] * 1e3:.0f} ms |"
        )
        if have:
            extra = f" ({r['pl_fail']} not assembled)" if r["pl_fail"] else ""
            line += (
                f" {r['pl_n']}{extra}, {fmt(r['pl_err'])}, {r['pl_t'] * 1e3:.0f} ms |"
            )  # fmt: skip
        print(line)


if __name__ == "__main__":
    main()
