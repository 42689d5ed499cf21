"""The ``mechsynth synthesize function`` command (registered by :mod:`mechsynth.cli`)."""

from __future__ import annotations

import argparse

_DESCRIPTION = (
    "Design a four-bar (or slider-crank) function generator: its output follows y = f(x) over "
    "[x0, x1] mapped linearly to the crank rotation --input-range and the output rotation (or "
    "slider travel) --output-range. Three precision points (Chebyshev spacing by default) give "
    "Freudenstein's exact solution, more a least-squares fit; --optimize then minimizes the "
    "certified worst output error over the whole range. Without --phases the start angles are "
    "scanned. --out writes design.toml (for 'mechsynth animate'), error.csv, "
    "precision_points.csv, result.json, error.png and problem.toml (the min-max stage as a "
    "problem file for 'mechsynth optimize'). Angles take units ('60deg', '1.2 rad'; a "
    "bare number is rad), lengths too ('50 mm'; a bare number is m)."
)


def add_parser(sub) -> None:
    """Add the ``function`` subcommand to the subparsers ``sub``."""
    from .cli import _add_output_options

    p = sub.add_parser(
        "function",
        help="function generation (Freudenstein): a four-bar whose output follows y = f(x)",
        description=_DESCRIPTION,
    )
    p.add_argument("--function", metavar="EXPR", help="y = f(x), e.g. 'log10(x)' or 'x**2'")
    p.add_argument("--x", nargs=2, metavar=("X0", "X1"), help="the range of x")
    p.add_argument("--pairs", metavar="FILE.csv",
                   help="instead of a function: precision pairs, two columns (input angle, "
                   "output) in rad (a slider's output in m), an optional header line")  # fmt: skip
    p.add_argument("--input-range", metavar="ANGLE", help="crank rotation over [x0, x1]")
    p.add_argument("--output-range", metavar="ANGLE|LENGTH",
                   help="output rotation (four-bar) or slider travel (slider-crank)")  # fmt: skip
    p.add_argument("--phases", nargs="+", metavar="ANGLE",
                   help="crank angle and output angle where the ranges start (a slider-crank: "
                   "the crank angle only); default: scanned")  # fmt: skip
    p.add_argument("--points", type=int, default=3, help="precision points (default 3)")
    p.add_argument("--spacing", default="chebyshev",
                   help="chebyshev (default), uniform, or the points' x: x1,x2,x3")  # fmt: skip
    p.add_argument("--mechanism", choices=("four-bar", "slider-crank"), default="four-bar")
    p.add_argument("--ground", default="1", help="the four-bar's ground length (default 1 m)")
    p.add_argument("--crank", default="1", help="the slider-crank's crank (default 1 m)")
    p.add_argument("--optimize", action="store_true",
                   help="minimize the certified worst error over the range (min-max)")  # fmt: skip
    p.add_argument("--require-crank", action="store_true",
                   help="the four-bar's crank must make full turns")  # fmt: skip
    p.add_argument("--min-transmission", default="30deg",
                   help="least transmission angle of scanned and optimized designs "
                   "(default 30deg; 'none' for no limit)")  # fmt: skip
    p.add_argument("--starts", type=int, default=1, help="multi-starts of --optimize")
    _add_output_options(p)
    p.set_defaults(func=run)


def _quantity(text, what, unit):
    from .synthesis.problem_file import parse_quantity

    return parse_quantity(text, what, unit)


def _read_pairs(path):
    import numpy as np

    from .errors import MechanismError
    from .fileio import read_text

    text, path = read_text(path, "pairs file")
    rows, header_seen = [], False
    for n, line in enumerate(text.splitlines(), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        cells = [c.strip() for c in line.replace(";", ",").split(",")]
        try:
            row = [float(c) for c in cells]
        except ValueError:
            if rows or header_seen:  # only the first line may be a header
                raise MechanismError(
                    f"{path}: line {n}: expected two numbers, got {line!r}"
                ) from None
            header_seen = True
            continue
        if len(row) != 2:
            raise MechanismError(f"{path}: line {n}: expected two numbers, got {line!r}")
        rows.append(row)
    if not rows:
        raise MechanismError(f"{path}: no precision pairs (two numbers a line)")
    return np.array(rows)


def _options(args) -> dict:
    from .errors import MechanismError

    slider = args.mechanism == "slider-crank"
    out_unit = "m" if slider else "rad"
    opts = {
        "mechanism": args.mechanism,
        "points": args.points,
        "optimize": args.optimize,
        "require_crank": args.require_crank,
        "starts": args.starts,
        "ground": _quantity(args.ground, "--ground", "m"),
        "crank": _quantity(args.crank, "--crank", "m"),
    }
    mt = args.min_transmission
    opts["min_transmission"] = (
        None if mt.strip().lower() == "none" else _quantity(mt, "--min-transmission", "rad")
    )
    if args.pairs is not None:
        if args.function is not None:
            raise MechanismError("give either --function or --pairs, not both")
        opts["pairs"] = _read_pairs(args.pairs)
        return opts
    if args.function is None:
        raise MechanismError("give --function EXPR with --x X0 X1, or --pairs FILE.csv")
    if args.x is None:
        raise MechanismError("--function needs --x X0 X1 (the range of x)")
    if args.input_range is None or args.output_range is None:
        raise MechanismError("--function needs --input-range and --output-range")
    opts["function"] = args.function
    opts["x"] = tuple(_quantity(v, "--x", "") for v in args.x)
    opts["input_range"] = _quantity(args.input_range, "--input-range", "rad")
    opts["output_range"] = _quantity(args.output_range, "--output-range", out_unit)
    if args.phases is not None:
        want = 1 if slider else 2
        if len(args.phases) != want:
            raise MechanismError(
                f"--phases takes {want} angle{'s' if want > 1 else ''} for a {args.mechanism}, "
                f"got {len(args.phases)}"
            )
        opts["phases"] = tuple(_quantity(v, "--phases", "rad") for v in args.phases)
    sp = args.spacing.strip()
    if sp in ("chebyshev", "uniform"):
        opts["spacing"] = sp
    else:
        try:
            opts["spacing"] = [float(v) for v in sp.split(",")]
        except ValueError:
            raise MechanismError(
                f"--spacing must be chebyshev, uniform or numbers x1,x2,..., got {sp!r}"
            ) from None
    return opts


def run(args: argparse.Namespace) -> int:
    """Run ``mechsynth synthesize function``: 0 done, 2 when the min-max solve failed."""
    from .cli import _print_result
    from .report import StudyResult
    from .synthesis.function_generation import function_generation

    fg = function_generation(**_options(args))
    files = fg.write(args.out) if args.out else []
    data = fg.to_dict()
    return _print_result(StudyResult("function", fg.summary(), data, files), args)
