"""The ``mechsynth synthesize motion`` command (registered by :mod:`mechsynth.cli`).

Reads poses ``(x, y, angle)`` from a CSV file, pairs the Burmester dyads into four-bars and
slider-cranks, ranks them, and writes the figure, the candidates and the chosen design.
"""

from __future__ import annotations

#: CSV columns: name -> (SI unit, default unit when the header gives none)
_COLUMNS = {"x": ("m", "m"), "y": ("m", "m"), "angle": ("rad", None)}


def add_parser(sub) -> None:
    """Add the ``motion`` subcommand to the subparsers ``sub``."""
    from .cli import _add_output_options

    p = sub.add_parser(
        "motion",
        help="four-bars and slider-cranks that carry a coupler through 2-5 poses (Burmester)",
        description="Motion generation: read poses from POSES.csv (a header with the columns x, "
        "y, angle, each optionally with a unit: 'x [mm]', 'angle [deg]' or 'angle_deg'; x and y "
        "default to m, the angle needs its unit; lines starting with # are comments), find the "
        "Burmester dyads (5 poses: all "
        "Burmester points; 4 poses: centre points along the centre-point curve; 3 poses: give "
        "--centres), pair them into linkages, check each for branch, order, limit and Grashof "
        "defects and rank them by the minimum transmission angle. --out writes motion.png, "
        "candidates.csv, linkage.toml (a linkage file for problem files) and design.toml (for "
        "'mechsynth animate'). Exits 2 when no defect-free linkage is found or --optimize fails.",
    )
    p.add_argument("poses", help="CSV file of poses: x, y, angle columns, one pose per row")
    p.add_argument(
        "--centres",
        nargs="+",
        metavar="X,Y",
        help="fixed pivots to pair (m): any points for 3 poses, points of the centre-point "
        "curve for 4, Burmester points for 5",
    )
    p.add_argument(
        "--samples",
        type=int,
        default=12,
        help="4 poses without --centres: centre points taken along the curve (default 12)",
    )
    p.add_argument(
        "--candidate",
        type=int,
        default=1,
        help="the ranked candidate to draw and write (default 1, the best)",
    )
    p.add_argument(
        "--optimize",
        action="store_true",
        help="refine the chosen candidate: maximize its minimum transmission angle with the "
        "pose error <= --tol (up to 5 poses), or minimize the pose error over all poses (more "
        "than 5: the exact synthesis takes the first 5)",
    )
    p.add_argument(
        "--tol",
        type=float,
        default=1e-3,
        help="pose error allowed with --optimize, m (default 0.001)",
    )
    p.add_argument(
        "--starts", type=int, default=2, help="multi-start count with --optimize (default 2)"
    )
    _add_output_options(p)
    p.set_defaults(func=run)


def read_poses(path):
    """Poses ``(n, 3)`` (SI) from a CSV file with the columns x, y, angle (see the command's
    help); every error names the file, the row or the column."""
    import csv
    import re

    import numpy as np

    from .errors import MechanismError
    from .fileio import read_text
    from .synthesis.problem_file import parse_quantity

    text, path = read_text(path, "poses file")
    lines = [ln for ln in text.splitlines() if not ln.lstrip().startswith("#")]  # comments
    rows = [r for r in csv.reader(lines) if any(c.strip() for c in r)]
    if not rows:
        raise MechanismError(f"{path}: empty; expected a header x, y, angle and one pose a row")
    factors, names = [], []
    for cell in rows[0]:
        m = re.fullmatch(r"\s*([A-Za-z]+)\s*(?:\[\s*([^\]]+?)\s*\]|_([A-Za-z]+))?\s*", cell)
        name = m.group(1).lower() if m else cell.strip()
        if not m or name not in _COLUMNS:
            raise MechanismError(
                f"{path}: unknown column {cell.strip()!r}; the header must name x, y and angle "
                "(with units: 'x [mm]', 'angle [deg]' or 'angle_deg')"
            )
        si, default = _COLUMNS[name]
        unit = m.group(2) or m.group(3) or default
        if unit is None:
            raise MechanismError(
                f"{path}: column {cell.strip()!r} needs its unit: 'angle [deg]' or 'angle [rad]'"
            )
        factors.append(parse_quantity(f"1 {unit}", f"{path}: column {cell.strip()!r}", si))
        names.append(name)
    if sorted(names) != ["angle", "x", "y"]:
        raise MechanismError(
            f"{path}: the header must name x, y and angle once each, got {', '.join(rows[0])}"
        )
    order = [names.index(k) for k in ("x", "y", "angle")]
    out = []
    for i, r in enumerate(rows[1:], start=2):
        if len(r) != len(names):
            raise MechanismError(f"{path}: row {i} has {len(r)} values, expected {len(names)}")
        try:
            vals = [float(c) for c in r]
        except ValueError:
            raise MechanismError(f"{path}: row {i}: not numbers: {', '.join(r)}") from None
        if not all(np.isfinite(vals)):
            raise MechanismError(f"{path}: row {i}: values must be finite, got {', '.join(r)}")
        out.append([vals[k] * factors[k] for k in order])
    if not out:
        raise MechanismError(f"{path}: no poses below the header")
    return np.array(out, dtype=float)


def _centres(items):
    from .errors import MechanismError

    out = []
    for s in items:
        try:
            x, y = (float(v) for v in s.split(","))
        except ValueError:
            raise MechanismError(f"--centres: expected X,Y (m), got {s!r}") from None
        out.append((x, y))
    return out


def run(args) -> int:
    import numpy as np

    from . import display
    from .cli import EXIT_FAILED, _manifest
    from .errors import MechanismError
    from .jsonutil import dumps
    from .synthesis.burmester import MAX_POSES, as_poses, burmester
    from .synthesis.motion_generation import motion_generation, pose_errors

    poses = read_poses(args.poses)
    n = len(poses)
    if n > MAX_POSES and not args.optimize:
        raise MechanismError(
            f"{args.poses}: {n} poses; exact motion generation takes 2 to {MAX_POSES} (give "
            "--optimize to fit more: the first 5 are met exactly, then the worst pose error over "
            "all is minimized)"
        )
    as_poses(poses, max_poses=None)  # every pose checked (coincident ones named)
    if args.tol <= 0 or not np.isfinite(args.tol):
        raise MechanismError(f"--tol must be a positive length (m), got {args.tol}")
    exact = poses[:MAX_POSES]
    centres = _centres(args.centres) if args.centres else None
    if len(exact) == MAX_POSES and centres is None:
        bm = burmester(exact)
        if sum(d.kind == "RR" for d in bm.points) < 1 or len(bm.points) < 2:
            why = (
                f"{args.poses}: these 5 poses have {len(bm.points)} real Burmester point(s): no "
                "four-bar or slider-crank takes them exactly (move a pose, or drop one and "
                "choose pivots on the 4-pose centre-point curve)"
            )
            if args.json:
                print(dumps({"poses": poses.tolist(), "burmester": bm.as_dict(),
                             "success": False, "message": why}))  # fmt: skip
            else:
                print(why)
            return EXIT_FAILED
    mg = motion_generation(exact, centres=centres, samples=args.samples)
    if not 1 <= args.candidate <= len(mg.candidates):
        raise MechanismError(
            f"--candidate must be 1 to {len(mg.candidates)} (the ranked candidates), "
            f"got {args.candidate}"
        )
    chosen = mg.candidates[args.candidate - 1]
    data = {
        "poses": poses.tolist(),
        "burmester": mg.burmester.as_dict(),
        "candidates": [c.summary() for c in mg.candidates],
        "chosen": args.candidate,
    }
    design = chosen.linkage
    ok = chosen.defect_free
    lines = [
        f"{n} poses; {len(mg.dyads)} dyads paired into {len(mg.candidates)} candidates, "
        f"{len(mg.defect_free)} without defects",
    ]
    if n == 5:
        lines.append(f"Burmester points: {len(mg.burmester.points)} real")
    for i, c in enumerate(mg.candidates[:10], start=1):
        mu = f"{np.degrees(c.min_transmission):.2f} deg"
        lines.append(
            f"  {i:2d}. {c.kind:12s} {c.grashof:15s} min transmission {mu:>10s}  defects: "
            f"{', '.join(c.defects) or 'none'}"
        )
    if args.optimize:
        if not ok:
            raise MechanismError(
                f"candidate {args.candidate} has defects ({', '.join(chosen.defects)}): "
                "--optimize starts from a defect-free one (choose it with --candidate)"
            )
        objective = "transmission" if n <= MAX_POSES else "error"
        prob = mg.problem(chosen, tol=args.tol) if n <= MAX_POSES else None
        if prob is None:
            from .synthesis.motion_generation import motion_problem

            prob = motion_problem(chosen, poses, objective="error")
        res = prob.solve(starts=args.starts, progress=False)
        data["optimize"] = {**res.to_dict(), "mode": objective}
        lines.append(f"optimize ({objective}): {res.status}, value {res.value:.6g}")
        ok = bool(res.success)
        if res.design is not None:
            design = res.design
    pos, ang = pose_errors(design, poses)
    data["pose_error"] = {"position_m": pos.tolist(), "angle_rad": ang.tolist()}
    data["success"] = ok
    du = display.current()
    lk = {k: float(v) for k, v in design.parameters.items()}
    dims = ", ".join(
        f"{name} {lk[key] / du.factor('m'):.6g}"
        for name, key in (
            ("crank", "OA"),
            ("coupler", "AB"),
            ("rocker", "DB"),
            ("slot offset", "coupler_offset"),
        )
        if key in lk
    )
    lines.append(
        f"chosen candidate {args.candidate} ({dims} {du.unit('m')}): pose errors up to "
        f"{pos.max() / du.factor('m'):.3g} {du.unit('m')} and {np.degrees(ang.max()):.3g} deg"
    )
    if not chosen.defect_free:
        lines.append("no defect-free linkage: choose other centre points or poses")
    files = []
    if args.out:
        files = _write(args.out, mg, chosen, design, poses)
        lines.append("\nWritten:")
        lines += [f"  {f}" for f in files]
        _manifest(args, files)
    if args.json:
        data["files"] = [str(f) for f in files]
        print(dumps(data))
    else:
        print("\n".join(lines))
    return 0 if ok else EXIT_FAILED


def _write(out, mg, chosen, design, poses):
    from pathlib import Path

    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .explore.model import to_toml
    from .fileio import save_figure, write_text
    from .tables import write_csv

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    files = []
    fig = mg.plot(chosen)
    files.append(save_figure(fig, out / "motion.png", dpi=120))
    plt.close(fig)
    write_csv({k: np.asarray(v) for k, v in mg.table().items()}, out / "candidates.csv")
    files.append(out / "candidates.csv")
    data = chosen.linkage_data()
    if design is not chosen.linkage:  # the refined design's dimensions
        data = _refined(data, design)
    files.append(write_text(out / "linkage.toml", to_toml(data)))
    angles = ", ".join(f"{np.degrees(a):.6g}" for a in chosen.crank_angles)
    head = (
        f"# The chosen {chosen.kind} of 'mechsynth synthesize motion' (crank angles at the "
        f"poses: {angles} deg):\n#\n#   mechsynth animate design.toml --out anim\n"
    )
    design_data = {"mechanism": "linkage", "linkage": "linkage.toml", "trace": ["P"]}
    files.append(write_text(out / "design.toml", head + to_toml(design_data)))
    return files


def _refined(data, design):
    """The linkage tables with the refined design's parameter values."""
    p = {k: float(v) for k, v in design.parameters.items()}
    data["ground"] = {k: [p[f"{k}_x"], p[f"{k}_y"]] for k in data["ground"]}
    for g in data["group"]:
        if g["type"] == "crank":
            g["length"] = p["OA"]
        elif g["type"] == "rrr":
            g["first"] = ["A", p["AB"]]
            g["second"] = ["D", p["DB"]]
        elif g["type"] == "rrp":
            g["rod"] = ["A", p["AB"]]
            g["guide"] = {
                "through": [p["B_guide_x"], p["B_guide_y"]],
                "angle": p["B_guide_angle"],
            }
        elif g["type"] == "rpr":
            g["offset"] = p["coupler_offset"]
        elif g["type"] == "attach":
            g["along"], g["left"] = p[f"{g['point']}_along"], p[f"{g['point']}_left"]
    return data
