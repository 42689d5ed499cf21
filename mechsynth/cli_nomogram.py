"""The ``mechsynth nomogram`` command (registered by :mod:`mechsynth.cli`).

``mechsynth nomogram NAME [--set KEY=VALUE ...] [--paper a4|letter] [--out DIR] [--json]
[--units ...]`` draws a built-in nomogram (:mod:`mechsynth.nomograms.library`) as PDF, SVG and
PNG at 1:1 on the paper, writes its description and accuracy report as JSON, and prints the
report (``--json``: the JSON). ``--set help`` lists the nomogram's options.
"""

from __future__ import annotations

import argparse

#: the built-in nomograms and one line each (kept here so ``--help`` needs no heavy import)
NAMES = {
    "slider-crank": "offset slider-crank: stroke / crank and time ratio (fitted)",
    "slider-crank-acceleration": "offset slider-crank: peak slider acceleration (compound)",
    "extreme-velocity": "paper 004: extreme slider velocity analogs over b/a and e/a (fitted)",
    "four-bar": "crank-rocker: best transmission angle's link ratios (fitted)",
    "pump-displacement": "beam pump: displacement from plunger, stroke and strokes/min",
    "pump-torque": "beam pump: gearbox torque from torque factor and net load (Z chart)",
}


def _names_text() -> str:
    return "built-in nomograms:\n" + "\n".join(f"  {k:27s} {v}" for k, v in NAMES.items())


def add_parser(sub) -> None:
    """Add the ``nomogram`` subcommand to the subparsers ``sub``."""
    from .cli import _add_output_options

    p = sub.add_parser(
        "nomogram",
        help="draw a nomogram (alignment chart) of a model, with its measured reading accuracy",
        description="Draw a built-in nomogram at 1:1 on A4 or Letter: PDF, SVG and PNG into "
        "--out, with nomogram_NAME.json (scales, example isopleth, accuracy report). The report "
        "reads the chart through its geometry at random points and the corners of its domain "
        "and compares with the model. --set help lists a nomogram's options.",
        epilog=_names_text() + "\n\nexit codes: 0 success; 1 bad input or usage (one line on "
        "stderr); 3 internal error (--debug shows its traceback).",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("name", metavar="NAME", help="nomogram name (listed below)")
    p.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="KEY=VALUE",
        help="nomogram option (repeatable), e.g. --set rod_crank=2:5; --set help lists them",
    )
    p.add_argument("--paper", choices=("a4", "letter"), default="a4",
                   help="paper size (portrait; default a4); the chart is drawn at 1:1")
    _add_output_options(p)
    for action in p._actions:  # each chart's own units unless told (oilfield for the pump's)
        if action.dest == "units":
            action.help = (
                "units of the sheet, report and JSON labels (SI inside): si, mm-deg or "
                "oilfield; default: the chart's own (oilfield for the pumping unit's, si else)"
            )
    p.set_defaults(func=run, units=None)


def run(args) -> int:
    """Build, check, draw and report the nomogram ``args.name``."""
    from pathlib import Path

    from . import display
    from .cli import _declared_options, _print_result
    from .errors import MechanismError
    from .nomograms import library
    from .report import StudyResult

    if args.name not in library.NOMOGRAMS:
        raise MechanismError(
            f"unknown nomogram {args.name!r}; built-in nomograms: "
            f"{', '.join(library.NOMOGRAMS)}"
        )
    options = _declared_options(f"nomogram {args.name!r}", library.options_of(args.name),
                                args.set)
    if options is None:
        return 0
    units = args.units or library.preferred_units(args.name)
    with display.display_units(units):
        nm = library.build(args.name, paper=args.paper, **options)
        data = nm.to_dict()
        data["units"] = units
        files = []
        if args.out:
            out = Path(args.out)
            out.mkdir(parents=True, exist_ok=True)
            stem = "nomogram_" + args.name.replace("-", "_")
            for suffix in (".pdf", ".svg", ".png"):
                files.append(nm.save(out / (stem + suffix)))
            from .fileio import write_text
            from .jsonutil import dumps

            files.append(write_text(out / (stem + ".json"), dumps(data) + "\n"))
        summary = summary_text(nm)
    return _print_result(StudyResult(args.name, summary, data, files), args)


def summary_text(nm) -> str:
    """The nomogram's report for people: scales, example, accuracy."""
    from .nomograms.scales import shown_unit
    from .nomograms.ticks import number_text

    lines = [nm.title, f"relation: {nm.relation}" if nm.relation else "", "scales:"]
    for ps in nm.scales.values():
        if ps.scale.turning:
            continue
        f, unit = shown_unit(ps.scale)
        lo, hi = (x / f for x in ps.domain)
        lines.append(f"  {ps.scale.title:32s} {number_text(lo, 6)} to {number_text(hi, 6)} {unit}  "
                     f"({ps.length():.0f} mm on paper)")
    ex = nm.isopleth(**nm.example)
    lines.append("example isopleth: " + ", ".join(
        f"{nm.variable(k).title} = "
        f"{number_text(float(ex[k]) / shown_unit(nm.variable(k))[0], 5)}"
        for k in (*nm.inputs, *nm.models) if k in ex
    ))
    for a in nm.accuracies.values():
        lines.append(a.text())
    lines.append(f"paper {nm.paper.size_text}, scale 1:1 (print at 100 %)")
    return "\n".join(x for x in lines if x)
