"""The ``mechsynth`` command line.

Every command has ``--help``; commands that compute write figures and tables into ``--out DIR``
and print machine-readable results with ``--json``.

Exit codes: 0 success; 1 bad input or usage (a one-line message, argparse's usage errors
included); 2 a solve that failed or ended infeasible; 3 an internal error (a bug: please report
it, with the traceback ``--debug`` shows); 130 interrupted by Ctrl-C; 143 terminated by SIGTERM
(a batch system's stop), cleaned up as after Ctrl-C. No Python traceback
reaches the terminal unless ``--debug`` is given.
"""

from __future__ import annotations

import argparse
import contextlib
import sys

from . import __version__, cli_function, cli_motion, cli_nomogram, cli_path
from .errors import MechanismError, SolverError
from .fileio import WRITTEN, output_dir, save_figure, write_text
from .jsonutil import dumps

__all__ = ["main", "build_parser"]

EXIT_OK = 0
EXIT_BAD_INPUT = 1
EXIT_FAILED = 2
EXIT_INTERNAL = 3
EXIT_INTERRUPTED = 130
EXIT_TERMINATED = 143

EXIT_CODES = (
    "exit codes: 0 success; 1 bad input or usage (one line on stderr); 2 a solve failed or "
    "ended infeasible; 3 internal error (a bug: --debug shows its traceback); 130 interrupted "
    "(Ctrl-C); 143 terminated (SIGTERM). Give --debug anywhere for Python tracebacks."
)


class _Parser(argparse.ArgumentParser):
    """argparse with mechsynth's exit codes: a usage error exits 1 (bad input), not 2 (which
    means a failed solve), and every subcommand's help lists the exit codes."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("epilog", EXIT_CODES)
        super().__init__(*args, **kwargs)

    def error(self, message):
        # one line, with the nearest known option or command for a misspelled one
        hint = _suggestion(self, message)
        prog = _command_parser(self, getattr(self, "argv", None)).prog
        self.exit(
            EXIT_BAD_INPUT,
            f"{self.prog.split()[0]}: error: {message}{hint} (see '{prog} --help')\n",
        )


def _option_strings(parser) -> set[str]:
    """Every option string of ``parser`` and of its subcommands' parsers."""
    found = set()
    for action in parser._actions:
        found.update(s for s in action.option_strings if s.startswith("--"))
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                found |= _option_strings(sub)
    return found


def _command_parser(parser, argv) -> argparse.ArgumentParser:
    """The deepest subcommand parser named by the words of ``argv`` (``parser`` itself when
    none is)."""
    for word in argv or ():
        subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
        if subs and word in subs[0].choices:
            parser = subs[0].choices[word]
    return parser


def _suggestion(parser, message: str) -> str:
    """'; did you mean --out?' for an unrecognized option or an invalid choice close to a known
    one, else ''."""
    import difflib
    import re

    if message.startswith("unrecognized arguments:"):
        # argparse reports leftovers from the top parser: look up the command that was given
        known = sorted(_option_strings(_command_parser(parser, getattr(parser, "argv", None))))
        words = message.split(":", 1)[1].split()
        for word in words:
            if word.startswith("-"):
                name = word.split("=")[0]
                close = [
                    c for c in difflib.get_close_matches(name, known, n=2, cutoff=0.75) if c != name
                ]
                if close:
                    return f"; did you mean {close[0]}?"
        return ""
    m = re.match(r"argument .*: invalid choice: '(.*?)' \(choose from (.*)\)", message)
    if m:
        choices = re.findall(r"'([^']*)'", m.group(2))
        close = difflib.get_close_matches(m.group(1), choices, n=1, cutoff=0.5)
        if close:
            return f"; did you mean '{close[0]}'?"
    return ""


UNITS = ("si", "mm-deg", "oilfield")


def _add_output_options(p: argparse.ArgumentParser, units: str = "si") -> None:
    p.add_argument("--out", metavar="DIR", help="write figures and tables into DIR")
    p.add_argument("--json", action="store_true", help="print machine-readable JSON results")
    p.add_argument(
        "--units",
        choices=UNITS,
        default=units,
        help="units of printed reports, tables and figure labels (SI inside): si (m, deg, N), "
        f"mm-deg (mm, deg, N) or oilfield (in, deg, lbf, in-lb); default {units}",
    )
    p.add_argument(
        "--quiet", action="store_true", help="no progress bars (they show only on a terminal)"
    )


# ------------------------------------------------------------------------------- study
def _add_study(sub) -> None:
    p = sub.add_parser("study", help="reproduce the source papers' studies")
    ssub = p.add_subparsers(dest="study_cmd", required=True, metavar="{list,run}")
    pl = ssub.add_parser("list", help="list the studies")
    pl.add_argument("--json", action="store_true", help="print the list as JSON")
    pl.add_argument("--out", metavar="DIR", help="(unused; accepted for uniformity)")
    pl.set_defaults(func=_study_list)
    pr = ssub.add_parser(
        "run", help="run a study and compare with the published values", add_help=False
    )
    pr.add_argument("-h", "--help", action=_HelpWithOptions, epilog=_all_study_options)
    pr.add_argument("name", help="study name (see 'mechsynth study list')")
    pr.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="study option (repeatable), e.g. --set tolerance=0.001 --set stroke=0.35 for "
        "dwell; --set help lists the study's options, their defaults, units and ranges",
    )
    _add_output_options(pr)
    pr.set_defaults(func=_study_run)


def _study_list(args) -> int:
    from .studies import STUDIES

    if args.json:
        print(dumps({name: desc for name, (_, desc) in STUDIES.items()}))
    else:
        for name, (_, desc) in STUDIES.items():
            print(f"{name:20s} {desc}")
    return 0


def _study_run(args) -> int:
    from .studies import run_study

    options = _study_options(args.name, args.set)
    if options is None:
        return 0
    return _print_result(run_study(args.name, out=args.out, **options), args)


def _study_options(name, items):
    """``--set KEY=VALUE`` strings read and checked against the study's declared options
    (:mod:`mechsynth.options`). None after printing the table of options for ``--set help``."""
    from .studies import get_study

    return _declared_options(f"study {name!r}", get_study(name).run.options, items)


def _declared_options(owner, options, items):
    if any(item.strip() == "help" for item in items):
        print(options.help(f"options of {owner}"))
        return None
    return options.resolve(_set_options(items), owner)


def _set_options(items) -> dict[str, str]:
    """``--set KEY=VALUE`` strings as ``{key: value}`` (both stripped)."""
    options = {}
    for item in items:
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise MechanismError(f"--set expects KEY=VALUE (or --set help), got {item!r}")
        options[key.strip()] = value.strip()
    return options


class _HelpWithOptions(argparse.Action):
    """``-h/--help`` that appends the options of every study or chart to the help text (built
    on demand: listing them imports the studies)."""

    def __init__(self, option_strings, dest, epilog=None, **kwargs):
        self._epilog = epilog
        super().__init__(option_strings, dest, nargs=0, help="show this help message and exit")

    def __call__(self, parser, namespace, values, option_string=None):
        parser.epilog = self._epilog()
        parser.formatter_class = argparse.RawDescriptionHelpFormatter
        parser.print_help()
        parser.exit()


def _all_study_options() -> str:
    from .studies import STUDIES, get_study

    return "study options:\n" + "\n\n".join(
        get_study(name).run.options.help(name) for name in STUDIES
    )


def _all_chart_options() -> str:
    return "chart options:\n" + "\n\n".join(
        _chart_function(name).options.help(name) for name in CHARTS
    )


# ------------------------------------------------------------------------------- chart
#: chart name -> (module, function, description). The function takes ``(out, options)`` -- ``out``
#: a directory or None, ``options`` a dict of ``--set key=value`` strings -- and returns a
#: :class:`~mechsynth.studies.StudyResult`.
CHARTS: dict[str, tuple[str, str, str]] = {
    "dwell": (
        "mechsynth.machines.dwell.charts",
        "chart_dwell",
        "Paper 003b: dwell duration, band width 2E and stroke S_max of the dwell linkage",
    ),
    "slider-crank": (
        "mechsynth.synthesis.charts",
        "chart_slider_crank",
        "Offset slider-crank at a fixed stroke: peak slider acceleration, max pressure angle "
        "and time ratio over (rod/crank, offset/crank)",
    ),
    "linkage": (
        "mechsynth.synthesis.linkage_file",
        "chart_linkage",
        "Any linkage of a TOML file over two of its dimensions: --set file=PATH (its [chart] "
        "table: axes, measures, limits)",
    ),
    "slider-crank-pareto": (
        "mechsynth.synthesis.pareto",
        "chart_pareto_slider_crank",
        "Pareto front of peak slider acceleration vs max pressure angle at a fixed stroke "
        "(epsilon-constraint)",
    ),
}


def _add_chart(sub) -> None:
    p = sub.add_parser(
        "chart", help="sweep a design grid and draw a design chart (nomogram)", add_help=False
    )
    p.add_argument("-h", "--help", action=_HelpWithOptions, epilog=_all_chart_options)
    p.add_argument("name", help="chart name: " + ", ".join(sorted(CHARTS)) if CHARTS else "chart")
    p.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="chart option (repeatable), e.g. --set n=80 --set rod_crank=2:6 for slider-crank; "
        "--set help lists the chart's options, their defaults, units and ranges",
    )
    p.add_argument(
        "--dask",
        metavar="ADDRESS",
        help="evaluate the sweep's chunks on a Dask cluster: a scheduler address "
        "(tcp://host:8786) or 'local' for a LocalCluster on this machine (needs "
        "pip install 'mechsynth[distributed]'; charts built on sweep: slider-crank, linkage)",
    )
    _add_output_options(p)
    p.set_defaults(func=_chart_run)


def _chart_function(name):
    import importlib

    if name not in CHARTS:
        raise MechanismError(f"unknown chart {name!r}; known charts: {', '.join(sorted(CHARTS))}")
    module, function, _ = CHARTS[name]
    return getattr(importlib.import_module(module), function)


def _chart_run(args) -> int:
    chart = _chart_function(args.name)
    options = _declared_options(f"chart {args.name!r}", chart.options, args.set)
    if options is None:
        return 0
    from .synthesis.charts import sweep_executor

    if getattr(args, "dask", None) is None:
        with sweep_executor("auto"):  # big sweeps on the numpy model: one process per core
            return _print_result(chart(args.out, options), args)

    with _dask_client(args.dask) as client, sweep_executor(client.get_executor()):
        result = chart(args.out, options)
    return _print_result(result, args)


def _dask_client(address: str):
    """A ``dask.distributed.Client`` of the scheduler at ``address``, or of a new
    ``LocalCluster`` for ``"local"`` (closed with the client)."""
    import re

    if address != "local" and not re.fullmatch(
        r"(tcp|tls|inproc|ucx|ws|wss)://[^\s/:]+(:\d{1,5})?/?|[A-Za-z0-9.\-]+:\d{1,5}", address
    ):
        raise MechanismError(
            f"--dask {address!r}: not a Dask scheduler address; give one such as "
            "tcp://host:8786 (or host:8786), or 'local' for a cluster on this machine"
        )
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError as exc:
        raise MechanismError(
            "--dask needs dask.distributed: pip install 'mechsynth[distributed]'"
        ) from exc
    import contextlib

    stack = contextlib.ExitStack()
    if address == "local":
        cluster = stack.enter_context(LocalCluster(dashboard_address=None))
        client = Client(cluster, set_as_default=False)
    else:
        try:
            client = Client(address, timeout="10s", set_as_default=False)
        except (OSError, TimeoutError) as exc:
            raise MechanismError(
                f"--dask {address}: cannot reach the Dask scheduler ({exc})"
            ) from exc
    stack.push(lambda *exc: client.close())  # the client closes first, then the cluster
    return _ClientStack(client, stack)


class _ClientStack:
    """``with`` gives the client and closes it (and a cluster it was started with) on exit."""

    def __init__(self, client, stack):
        self.client, self.stack = client, stack

    def __enter__(self):
        return self.client

    def __exit__(self, *exc):
        return self.stack.__exit__(*exc)


def _manifest(args, files) -> None:
    """``manifest.json`` in ``--out``: the run's files with their SHA-256, the command's
    options and the package version (written last, atomically)."""
    if not getattr(args, "out", None) or not files:
        return
    from .fileio import write_manifest

    options = {k: v for k, v in vars(args).items() if k != "func"}
    write_manifest(args.out, files, options=options, command=" ".join(sys.argv[1:]) or None)


def _print_result(result, args) -> int:
    _manifest(args, result.files)
    if args.json:
        payload = dict(result.data)
        payload.setdefault("errata", list(result.errata))
        payload.setdefault("files", [str(f) for f in result.files])
        print(dumps(payload))
    else:
        print(result.summary)
        if result.errata:
            print("\nErrata found in the source:")
            for line in result.errata:
                print(f"  - {line}")
        if result.files:
            print("\nWritten:")
            for f in result.files:
                print(f"  {f}")
    # a study that reports an optimizer failure or infeasibility exits non-zero (as optimize)
    return 0 if result.data.get("success", True) is not False else EXIT_FAILED


# ------------------------------------------------------------------------------- optimize
def _add_optimize(sub) -> None:
    p = sub.add_parser(
        "optimize",
        help="solve a synthesis problem from a TOML file (see docs/synthesis.md)",
        description="Solve a synthesis problem file; print the report, write result.json and "
        "optimum.png (and with --animate optimum.gif) into --out. Exits 2 when the problem is "
        "infeasible or the solver fails.",
    )
    p.add_argument("problem", help="problem file (TOML)")
    p.add_argument("--method", choices=("ipopt", "slsqp", "de"), help="override the file's method")
    p.add_argument("--starts", type=int, help="override the multi-start count")
    p.add_argument("--seed", type=int, help="override the seed")
    p.add_argument(
        "--time-limit",
        type=float,
        metavar="SECONDS",
        help="no new start begins after this many seconds (the first always runs); the starts "
        "run so far are certified and reported",
    )
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument(
        "--animate",
        action="store_true",
        help="also write optimum.gif into --out: the optimum moving over a turn",
    )
    _add_output_options(p)
    p.set_defaults(func=_optimize_run)


def _optimize_run(args) -> int:

    from .synthesis.problem_file import load_problem

    if args.animate and not args.out:
        raise MechanismError("--animate writes optimum.gif: give --out DIR")
    spec = load_problem(args.problem)
    overrides = {k: getattr(args, k) for k in ("method", "starts", "seed", "time_limit")}
    overrides = {k: v for k, v in overrides.items() if v is not None}
    if args.no_progress or args.json:
        overrides["progress"] = False
    res = spec.solve(**overrides)
    files = []
    if args.out:
        out = output_dir(args.out)
        write_text(out / "result.json", dumps(res.to_dict()) + "\n")
        write_text(out / "report.txt", res.report() + "\n")
        files += [out / "result.json", out / "report.txt"]
        if res.design is not None:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt

            fig = res.plot()
            save_figure(fig, out / "optimum.png", dpi=120)
            plt.close(fig)
            files.append(out / "optimum.png")
            if args.animate:
                anim = res.design.animate(speed=res.speed, frames=48)
                files.append(anim.save(out / "optimum.gif"))
        _manifest(args, files)
    if args.json:
        print(dumps(res.to_dict()))
    else:
        print(res.report())
        if files:
            print("\nWritten:")
            for f in files:
                print(f"  {f}")
    return 0 if res.success else EXIT_FAILED


# ------------------------------------------------------------------------------- pump
def _add_pump_parser(sub) -> None:
    p = sub.add_parser("pump", help="beam pumping units: kinematics, torque, counterbalance")
    psub = p.add_subparsers(dest="pump_cmd", required=True, metavar="{analyze}")
    pa = psub.add_parser(
        "analyze",
        help="analyse a unit from its API 11E geometry (TOML), optionally with a card",
        description="Print stroke, dead centres, upstroke/downstroke spans, torque-factor "
        "extremes, peak polished-rod velocity and acceleration and the pressure-angle range; with "
        "--card the gearbox torque and the counterbalance that minimizes its peak (LP, checked "
        "by a scan). See docs/pumping_unit.md for the unit file. Exits 2 if the counterbalance "
        "optimization fails.",
    )
    pa.add_argument("unit", help="unit file (TOML)")
    pa.add_argument("--card", metavar="CSV", help="dynamometer card: position, load rows")
    _add_output_options(pa, units="oilfield")
    pa.set_defaults(func=_pump_analyze)


def _pump_analyze(args) -> int:
    from .machines.pumping_unit.analysis import analyze

    result = analyze(args.unit, card=args.card, out=args.out, units=args.units)
    rc = _print_result(result, args)
    return EXIT_FAILED if rc else 0


# ------------------------------------------------------------------------------- animate
def _add_animate(sub) -> None:
    p = sub.add_parser(
        "animate",
        help="draw and animate a mechanism from a design file (TOML)",
        description="Draw a design at a crank angle (PNG) and animate it over one turn (GIF by "
        "pillow; MP4 where ffmpeg is installed; HTML). FILE is a design file (mechanism = ..., "
        "optional speed and trace, a [design] table; see docs/drawing.md) or a pumping-unit "
        "file as read by 'pump analyze'.",
    )
    p.add_argument("file", help="design file (TOML)")
    p.add_argument("--frames", type=int, default=48, help="frames per turn (default 48)")
    p.add_argument(
        "--format", choices=("gif", "mp4", "html"), default="gif", help="animation format"
    )
    p.add_argument("--angle", type=float, default=0.0, help="crank angle of the still, deg")
    p.add_argument("--dpi", type=int, default=80, help="resolution of the animation")
    _add_output_options(p)
    p.set_defaults(func=_animate_run)


def _read_design(path):
    """(design, speed, trace) from a design file or a pumping-unit file."""
    from .synthesis.design_file import load_design, read_toml

    data, path = read_toml(path)
    if "mechanism" not in data and {"A", "C", "P", "R"} <= set(data):
        from .machines.pumping_unit.analysis import load_unit
        from .units import spm

        unit, op = load_unit(path)
        return unit, (spm(op["spm"]) if op.get("spm") else None), None
    spec = load_design(path)  # read again: its messages name the file
    return spec.design, spec.speed, spec.trace


def _animate_run(args) -> int:
    from pathlib import Path

    import numpy as np

    if not args.out:
        raise MechanismError("animate writes its still and animation into a folder: give --out DIR")
    if not 2 <= args.frames <= 720:
        raise MechanismError(f"--frames must be 2 to 720, got {args.frames}")
    if not 10 <= args.dpi <= 300:
        raise MechanismError(f"--dpi must be 10 to 300, got {args.dpi}")
    if not np.isfinite(args.angle):
        raise MechanismError(f"--angle must be a number of degrees, got {args.angle}")
    design, speed, trace = _read_design(args.file)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = output_dir(args.out)
    stem = Path(args.file).stem
    phi = design.turn_sign * np.deg2rad(args.angle)
    ax = design.draw(phi, trace=trace)
    still = out / f"{stem}.png"
    save_figure(ax.figure, still, dpi=120)
    plt.close(ax.figure)
    anim = design.animate(speed=speed, frames=args.frames, trace=trace, dpi=args.dpi)
    moving = anim.save(out / f"{stem}.{args.format}")
    _manifest(args, [still, moving])
    data = {
        "design": design.describe(),
        "values": design.as_dict(),
        "speed": speed,
        "frames": anim.n_frames,
        "playback": anim.playback,
        "files": [str(still), str(moving)],
    }
    if args.json:
        print(dumps(data))
    else:
        print(f"{design.describe()}")
        cycle = "one turn" if getattr(design, "periodic", True) else "the travel and back"
        print(f"{anim.n_frames} frames over {cycle}, {anim.playback}")
        print("\nWritten:")
        for f in data["files"]:
            print(f"  {f}")
    return 0


# ------------------------------------------------------------------------------- explore
def _add_explore(sub) -> None:
    p = sub.add_parser(
        "explore",
        help="interactive explorer in the browser (needs the extra mechsynth[explore])",
        description="Start a local web page: choose a mechanism, drag its dimensions, watch it "
        "move with its motion curves and the problem's constraints, optimize (certified, in "
        "the background), sweep a chart and load a design from it, export the problem (TOML) "
        "and figures (PNG). FILE is a problem, design or linkage file (TOML). Serves until "
        "Ctrl+C. Needs Panel: pip install 'mechsynth[explore]'.",
    )
    p.add_argument("file", nargs="?", help="problem, design or linkage file (TOML) to start from")
    p.add_argument(
        "--mechanism",
        choices=("slider-crank", "four-bar", "beam-pump", "dwell", "linkage", "impact"),
        help="mechanism to start with when no FILE is given (default slider-crank)",
    )
    p.add_argument("--host", default="127.0.0.1", help="address to serve on (default 127.0.0.1)")
    p.add_argument("--port", type=int, default=0, help="port (default 0: a free port)")
    p.add_argument(
        "--no-browser", action="store_true", help="do not open the page in the default browser"
    )
    p.add_argument("--out", metavar="DIR", help="also write exports (TOML, PNG) into DIR")
    p.add_argument(
        "--json",
        action="store_true",
        help='print {"url", "host", "port", "out"} as one JSON line once serving',
    )
    p.add_argument(
        "--units",
        choices=UNITS,
        default="si",
        help="display units the page starts with: si, mm-deg or oilfield",
    )
    p.add_argument("--quiet", action="store_true", help="(accepted for uniformity)")
    p.set_defaults(func=_explore_run)


def _explore_run(args) -> int:
    from .explore import serve

    if not 0 <= args.port <= 65535:
        raise MechanismError(f"--port must be 0 to 65535, got {args.port}")
    if args.file is not None:  # the file's own faults first, named as such (not as the server's)
        from .fileio import read_toml

        read_toml(args.file, "explore file")
    try:
        return serve(
            args.file,
            host=args.host,
            port=args.port,
            browser=not args.no_browser,
            out=args.out,
            json_out=args.json,
            units=args.units,
            kind=args.mechanism,
        )
    except ImportError as exc:
        raise MechanismError(str(exc)) from None
    except OSError as exc:
        why = exc.strerror or exc
        raise MechanismError(f"cannot serve on {args.host}:{args.port}: {why}") from None


# ------------------------------------------------------------------------------- synthesize
def _add_synthesize(sub) -> None:
    p = sub.add_parser(
        "synthesize",
        help="kinematic synthesis: function, motion (Burmester) and path generation",
        description="Kinematic synthesis of four-bars and slider-cranks: a function generator "
        "(Freudenstein), a coupler carried through poses (Burmester), a coupler point tracing "
        "a path. Each writes figures, a CSV of the solutions and a TOML of the chosen design "
        "into --out.",
    )
    ssub = p.add_subparsers(dest="synthesize_cmd", required=True, metavar="TASK")
    cli_function.add_parser(ssub)
    cli_motion.add_parser(ssub)
    cli_path.add_parser(ssub)


# ------------------------------------------------------------------------------- main
def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="mechsynth",
        description="Optimization-based mechanism synthesis: analysis, optimization, charts.",
    )
    parser.add_argument("--version", action="version", version=f"mechsynth {__version__}")
    parser.add_argument(
        "--debug",
        action="store_true",
        help="show the Python traceback of an error (accepted anywhere on the line)",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    _add_study(sub)
    _add_chart(sub)
    _add_optimize(sub)
    _add_pump_parser(sub)
    _add_animate(sub)
    _add_explore(sub)
    _add_synthesize(sub)
    cli_nomogram.add_parser(sub)
    return parser


#: set by the SIGINT handler of :func:`main` (an interrupt inside a C extension's import may
#: surface as another error)
_INTERRUPTED: list[int] = []


def main(argv=None) -> int:
    """Run the command line; returns the exit code (see the module notes). Never raises
    (``SystemExit`` of ``--help`` and ``--version`` aside) and prints no traceback unless
    ``--debug`` is given."""
    import signal
    import threading

    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    argv = [a for a in argv if a != "--debug"]
    _INTERRUPTED.clear()

    def on_sigint(signum, frame):
        _INTERRUPTED.append(signum)
        signal.default_int_handler(signum, frame)

    def quiet_interrupt(unraisable):
        # our Ctrl-C / SIGTERM raised inside a finalizer (a weakref callback during garbage
        # collection) is swallowed there and printed with a traceback; the run still ends as
        # interrupted (``_INTERRUPTED``), with its one line
        if isinstance(unraisable.exc_value, KeyboardInterrupt) and _INTERRUPTED and not debug:
            return
        previous_hook(unraisable)

    previous_hook = sys.unraisablehook
    sys.unraisablehook = quiet_interrupt
    previous = {}
    if threading.current_thread() is threading.main_thread():
        # SIGTERM (a batch system's stop) ends a run as Ctrl-C does: temporary files removed,
        # one line, its own exit code (128 + 15)
        for sig in (signal.SIGINT, signal.SIGTERM):
            previous[sig] = signal.signal(sig, on_sigint)
    try:
        rc = _run(argv, debug)
        return _interrupted() if _INTERRUPTED and not debug else rc
    except KeyboardInterrupt:
        if debug:
            raise
        return _interrupted()
    except BrokenPipeError:  # the reader of our output went away (| head)
        import os

        with contextlib.suppress(OSError):
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_OK
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        sys.unraisablehook = previous_hook


def _interrupted() -> int:
    import signal

    if signal.SIGTERM in _INTERRUPTED:
        print(
            "\nmechsynth: terminated (SIGTERM); files being written were left as they were",
            file=sys.stderr,
        )
        return EXIT_TERMINATED
    print(
        "\nmechsynth: interrupted (Ctrl-C); files being written were left as they were",
        file=sys.stderr,
    )
    return EXIT_INTERRUPTED


def _run(argv, debug) -> int:
    from . import display, progress
    from .fileio import output_dir

    parser = build_parser()
    parser.argv = list(sys.argv[1:] if argv is None else argv)
    args = parser.parse_args(argv)
    WRITTEN.clear()
    try:
        if getattr(args, "out", None) is not None:
            output_dir(args.out, create=False)
        with display.display_units(getattr(args, "units", None) or "si"):
            with progress.quiet(getattr(args, "quiet", False) or progress.is_quiet()):
                return int(args.func(args) or 0)
    except KeyboardInterrupt:
        _settle(args, "interrupted")
        raise
    except Exception as exc:
        if debug:
            raise
        if _INTERRUPTED or _was_interrupted(exc):
            _settle(args, "interrupted")
            raise KeyboardInterrupt from exc
        if isinstance(exc, BrokenPipeError):
            raise
        _settle(args, "failed")
        return _report(exc)


def _settle(args, status) -> None:
    """A run into ``--out`` that did not finish leaves a manifest true to the files on disk."""
    out = getattr(args, "out", None)
    if not out:
        return
    from .fileio import settle_manifest

    options = {k: v for k, v in vars(args).items() if k != "func"}
    with contextlib.suppress(OSError, MechanismError):
        settle_manifest(out, options, " ".join(sys.argv[1:]) or None, status)


def _report(exc) -> int:
    """One line on stderr for an error, and its exit code."""
    if isinstance(exc, (MechanismError, ValueError, SolverError)):
        _error(exc)
    elif isinstance(exc, OSError):  # a file that cannot be read or written
        where = f" {exc.filename}" if getattr(exc, "filename", None) else ""
        _error(f"{exc.strerror or exc}{where}")
    elif isinstance(exc, MemoryError):
        _error("out of memory: ask for fewer designs, angles or grid points")
    elif isinstance(exc, RecursionError):
        _error("input nested too deeply")
    else:  # a bug: say so in one line
        _error(
            f"internal error ({type(exc).__name__}: {exc}); run again with --debug for the "
            "traceback and please report it"
        )
        return EXIT_INTERNAL
    return EXIT_BAD_INPUT


def _was_interrupted(exc) -> bool:
    """True when a KeyboardInterrupt lies in ``exc``'s chain."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


def _error(exc) -> None:
    text = " ".join(str(exc).split()) or type(exc).__name__
    print(f"mechsynth: error: {text}", file=sys.stderr)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
