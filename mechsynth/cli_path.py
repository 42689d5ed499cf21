"""The ``mechsynth synthesize path`` command (registered by :mod:`mechsynth.cli`)."""

from __future__ import annotations

_DESCRIPTION = (
    "Design a four-bar whose coupler point passes as near as possible to the points of "
    "TARGETS.csv (rows x, y in m, an optional header line; with --timing prescribed a third "
    "column gives the crank angle at each point, deg). The error is the sum over the points of "
    "the squared distance to the coupler point (--objective max: the largest one). The crank "
    "turns fully and the linkage stays on one assembly branch; --min-transmission bounds the "
    "transmission angle over the whole turn. --out writes path.png (targets, curve, linkage at "
    "the targets), solutions.csv, positions.csv, design.toml (for 'mechsynth animate' and "
    "'explore'), for a four-bar linkage.toml (for 'chart linkage' and problem files), and "
    "result.json; "
    "--animate adds path.gif. With --timing prescribed, --bound adds a proved lower bound on the "
    "error and the gap to the design found. Ctrl-C stops the search and keeps the best design "
    "so far. Exit 1 on bad input, 2 when no start ends on a feasible design."
)


def add_parser(sub) -> None:
    """Add the ``path`` subcommand to the subparsers ``sub``."""
    from .cli import _add_output_options

    p = sub.add_parser(
        "path",
        help="path generation: a four-bar whose coupler point traces given points",
        description=_DESCRIPTION,
    )
    p.add_argument("targets", metavar="TARGETS.csv", help="the points, rows x, y (m)")
    p.add_argument("--mechanism", default="four-bar", metavar="four-bar|slider-crank|FILE.toml",
                   help="four-bar (default), slider-crank (a point on its rod), or a linkage "
                   "file ([linkage], [ground], [[group]] tables) with a [variables] table of "
                   "the dimensions to vary, name = [lower, upper], and optionally "
                   "trace = 'P' (default: the linkage's output)")  # fmt: skip
    p.add_argument("--timing", choices=("free", "prescribed", "shape"), default="free",
                   help="free: crank angles are variables, in the points' order within one "
                   "turn (default); prescribed: the CSV's third column (deg); shape: a closed "
                   "path's shape only (position, orientation, size, timing free)")  # fmt: skip
    p.add_argument(
        "--min-transmission",
        default="none",
        metavar="ANGLE",
        help="smallest transmission angle over the turn, e.g. 30deg (default none)",
    )
    p.add_argument("--constraint", action="append", default=[], metavar="'MEASURE OP VALUE'",
                   help="a measure of the library bounded over the turn, e.g. "
                   "'max_pressure_angle <= 40 deg' or 'peak_acceleration(P) <= 50' (the "
                   "four-bar's tracing point is P); repeatable")  # fmt: skip
    p.add_argument(
        "--speed",
        metavar="SPEED",
        help="crank speed of the measures, e.g. '600 rpm' (default: analogs)",
    )
    p.add_argument(
        "--objective",
        choices=("squares", "max"),
        default="squares",
        help="sum of squared distances (default) or the largest (min-max)",
    )
    p.add_argument("--direction", choices=("ccw", "cw", "either"), default="ccw",
                   help="the crank's turn with free or shape timing: ccw (default, the "
                   "literature's), cw, or either (both searched)")  # fmt: skip
    p.add_argument("--starts", type=int, default=16, help="local solves (default 16)")
    p.add_argument("--time-limit", metavar="SECONDS", type=float,
                   help="start no new solve after this time")  # fmt: skip
    p.add_argument("--bound", action="store_true",
                   help="with --timing prescribed: a proved lower bound on the error of every "
                   "four-bar in the search region (branch and bound), with the gap to the best "
                   "design; says plainly when no useful bound was found")  # fmt: skip
    p.add_argument("--bound-around", metavar="LENGTH",
                   help="with --bound: search the box within LENGTH (e.g. '5 cm') of the best "
                   "design in every coordinate (pivots, crank vector, coupler, rocker) instead "
                   "of the default bounds")  # fmt: skip
    p.add_argument("--bound-time", metavar="SECONDS", type=float, default=20.0,
                   help="with --bound: time for the branch and bound (default 20 s)")
    p.add_argument("--open", action="store_true", help="the points lie on an open path")
    p.add_argument("--animate", action="store_true", help="also write path.gif into --out")
    _add_output_options(p)
    p.set_defaults(func=run)


def _read(path, columns: int):
    """Rows of ``columns`` numbers from a CSV (one header line allowed)."""
    import numpy as np

    from .errors import MechanismError
    from .fileio import read_text

    text, p = read_text(path, "targets file")
    rows, header = [], False
    for k, line in enumerate(text.splitlines(), start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        cells = [c.strip() for c in line.replace(";", ",").split(",")]
        if len(cells) != columns:
            names = "x, y" if columns == 2 else "x, y, crank angle (deg)"
            raise MechanismError(
                f"{p}: line {k}: expected {columns} columns {names}, got {len(cells)}: {line!r}"
            )
        try:
            rows.append([float(c) for c in cells])
        except ValueError:
            if rows or header:  # only the first line may be a header
                raise MechanismError(f"{p}: line {k}: not {columns} numbers: {line!r}") from None
            header = True
    if not rows:
        raise MechanismError(f"{p}: no rows of {columns} numbers")
    return np.asarray(rows, dtype=float)


def design_toml(sol) -> str:
    """TOML of a path solution's linkage: ``mechanism = "linkage"`` with its tables (a design
    file for ``mechsynth animate`` and ``explore``)."""
    return 'mechanism = "linkage"\ntrace = ["P"]\n\n' + linkage_toml(sol)


def linkage_toml(sol) -> str:
    """TOML of a path solution's linkage tables (``[linkage]``, ``[ground]``, ``[[group]]``)."""
    import numpy as np

    c, s = np.cos(sol.angle), np.sin(sol.angle)
    o2 = (sol.x0 + sol.ground * c, sol.y0 + sol.ground * s)
    r = repr
    return "\n".join(
        [
            "# a four-bar path generator (mechsynth synthesize path); lengths in m, angles in rad",
            "[linkage]",
            'name = "path generator"',
            'output = "P"',
            "",
            "[ground]",
            f"O1 = [{r(sol.x0)}, {r(sol.y0)}]",
            f"O2 = [{r(float(o2[0]))}, {r(float(o2[1]))}]",
            "",
            "[[group]]",
            'type = "crank"',
            'point = "A"',
            'about = "O1"',
            f"length = {r(sol.crank)}",
            f"phase = {r(sol.angle)}",
            "",
            "[[group]]",
            'type = "rrr"',
            'point = "B"',
            f'first = ["A", {r(sol.coupler)}]',
            f'second = ["O2", {r(sol.rocker)}]',
            f"branch = {1 if sol.branch == 'open' else -1}",
            "",
            "[[group]]",
            'type = "attach"',
            'point = "P"',
            'on = ["A", "B"]',
            f"along = {r(sol.u)}",
            f"left = {r(sol.v)}",
            "",
        ]
    )


def run(args) -> int:
    import numpy as np

    from .errors import MechanismError
    from .progress import quiet
    from .report import StudyResult
    from .synthesis.path_generation import path_generation, read_targets
    from .synthesis.problem_file import parse_quantity

    if args.starts < 1:
        raise MechanismError(f"--starts must be at least 1, got {args.starts}")
    if args.time_limit is not None and not args.time_limit > 0:
        raise MechanismError(f"--time-limit must be positive, got {args.time_limit}")
    if args.bound and args.timing != "prescribed":
        raise MechanismError(f"--bound needs --timing prescribed, got --timing {args.timing}")
    closed = not args.open
    if args.timing == "prescribed":
        rows = _read(args.targets, 3)
        targets, angles = rows[:, :2], np.deg2rad(rows[:, 2])
    else:
        targets, angles = _read(args.targets, 2), None
    targets = read_targets(targets, closed=closed)
    mu = None
    if str(args.min_transmission).strip().lower() != "none":
        mu = parse_quantity(args.min_transmission, "--min-transmission", "rad")
    mechanism, trace, variables, tables = _mechanism(args.mechanism)
    from .synthesis.problem_file import parse_constraint

    constraints = [parse_constraint(c) for c in args.constraint]
    speed = None if args.speed is None else parse_quantity(args.speed, "--speed", "rad/s")
    bound = False
    if args.bound_around is not None and not args.bound:
        raise MechanismError("--bound-around goes with --bound")
    if args.bound:
        if not args.bound_time > 0:
            raise MechanismError(f"--bound-time must be positive, got {args.bound_time}")
        bound = {"time_limit": args.bound_time}
        if args.bound_around is not None:
            bound["around"] = parse_quantity(args.bound_around, "--bound-around", "m")
    with quiet(args.quiet or args.json):
        res = path_generation(
            targets,
            mechanism=mechanism,
            trace=trace,
            variables=variables,
            timing=args.timing,
            angles=angles,
            closed=closed,
            min_transmission=mu,
            objective=args.objective,
            starts=args.starts,
            time_limit=args.time_limit,
            constraints=constraints,
            speed=speed,
            direction=args.direction,
            bound=bound,
        )
    data = res.as_dict()
    files = []
    if args.out and res.best is not None:
        files = _write(res, args, tables)
    summary = res.summary()
    if res.status == "interrupted":
        summary += "\ninterrupted: the best design found so far"
    result = StudyResult("synthesize path", summary, data, files)
    from .cli import _print_result

    code = _print_result(result, args)
    if code == 0 and res.status == "interrupted":
        return 130
    return code


def _template_tables(sol) -> dict:
    """The slider-crank template's tables (its dimensions come from ``[design]``)."""
    return {
        "linkage": {"name": "slider-crank path generator", "output": "P"},
        "ground": {"O": [0.0, 0.0], "G": [0.0, 0.0]},
        "group": [
            {"type": "crank", "point": "A", "about": "O", "length": 1.0},
            {"type": "rrp", "point": "B", "rod": ["A", 1.0],
             "guide": {"through": "G", "angle": {"name": "guide_angle", "value": 0.0}}},
            {"type": "attach", "point": "P", "on": ["A", "B"], "along": 0.0, "left": 0.0},
        ],
    }  # fmt: skip


def _mechanism(text):
    """``(mechanism, trace, variables, tables)`` of ``--mechanism`` (``tables``: a linkage
    file's parsed tables, else None)."""
    from .errors import MechanismError

    if text in ("four-bar", "slider-crank"):
        return text, None, None, None
    if not str(text).endswith(".toml"):
        raise MechanismError(
            f"--mechanism must be four-bar, slider-crank or a linkage file (.toml), got {text!r}"
        )
    from .fileio import read_toml
    from .synthesis.linkage_file import linkage_from_data
    from .synthesis.problem_file import parse_quantity

    data, path = read_toml(text, "linkage file")
    data = dict(data)
    table = data.pop("variables", None)
    trace = data.pop("trace", None)
    data.pop("mechanism", None)
    if not isinstance(table, dict) or not table:
        raise MechanismError(
            f"{path}: give the dimensions to vary as a [variables] table, name = [lower, upper]"
        )
    if trace is not None and not isinstance(trace, str):
        raise MechanismError(f"{path}: trace must be a point name, got {trace!r}")
    variables = {}
    for k, b in table.items():
        if not isinstance(b, list) or len(b) != 2:
            raise MechanismError(f"{path}: [variables] {k}: expected [lower, upper], got {b!r}")
        variables[k] = tuple(parse_quantity(v, f"[variables] {k}") for v in b)
    return linkage_from_data(data, str(path)), trace, variables, data


def _write(res, args, tables=None) -> list:
    from pathlib import Path

    import numpy as np

    from . import display, plotting
    from .fileio import output_dir, write_csv, write_text

    out = output_dir(args.out)
    files = []
    with display.display_units(args.units):
        fig = res.figure()
        files.append(plotting.save(fig, Path(out) / "path.png"))
    tail = ["error [m^2]", "sum of squares [m^2]", "largest distance [m]",
            "transmission min [deg]", "transmission max [deg]", "note"]  # fmt: skip
    four_bar = res.best.fourbar is not None
    if four_bar:
        names = "crank coupler rocker ground u v x0 y0 angle branch".split()
    else:
        names = list(res.best.values)
    header = ["rank", *names, *tail]
    rows = [
        [k, *(getattr(s, n) if four_bar else s.values[n] for n in names),
         s.error, s.sum_squares, s.max_distance, *np.rad2deg(s.transmission), s.note]
        for k, s in enumerate(res.solutions, start=1)
    ]  # fmt: skip
    files.append(write_csv(Path(out) / "solutions.csv", header, rows))
    pos = res.positions
    moving = [k for k in pos if np.ptp(pos[k], axis=0).max() > 0]
    header = ["target", "x [m]", "y [m]", "crank angle [deg]"]
    for name in moving:
        header += [f"{name} x [m]", f"{name} y [m]"]
    rows = []
    for i, (x, y) in enumerate(res.targets):
        row = [i + 1, x, y, float(np.rad2deg(res.angles[i]))]
        for name in moving:
            row += [float(pos[name][i, 0]), float(pos[name][i, 1])]
        rows.append(row)
    files.append(write_csv(Path(out) / "positions.csv", header, rows))
    if four_bar:
        files.append(write_text(Path(out) / "design.toml", design_toml(res.best)))
        files.append(write_text(Path(out) / "linkage.toml", linkage_toml(res.best)))
    else:
        from .explore.model import to_toml

        data = {"mechanism": "linkage", "trace": [res.best.trace_point]}
        data.update(tables if tables is not None else {})
        if tables is None:  # the slider-crank template: its tables from its dimensions
            data.update(_template_tables(res.best))
        data["design"] = {k: float(v) for k, v in res.best.values.items()}
        files.append(write_text(Path(out) / "design.toml", to_toml(data)))
    from .jsonutil import dumps

    files.append(write_text(Path(out) / "result.json", dumps(res.as_dict())))
    if args.animate:
        anim = res.animate(frames=48)
        path = Path(out) / "path.gif"
        anim.save(str(path))
        files.append(path)
    return files
