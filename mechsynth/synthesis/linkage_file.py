"""Linkages in TOML files, for ``mechsynth optimize`` and ``mechsynth chart linkage``.

Format
------
A ``[ground]`` table of points and a ``[[group]]`` table per group, in solving order; an optional
``[linkage]`` table names it and its output::

    [linkage]
    name = "six-link"
    output = "N"                        # optional: the main output point

    [ground]
    O = [0, 0]
    D = ["120 mm", "50 mm"]             # numbers are SI (m, rad); strings carry a unit

    [[group]]
    type = "crank"
    point = "A"
    about = "O"
    length = "30 mm"                    # optional: phase, link

    [[group]]
    type = "rrr"
    point = "B"
    first = ["A", "120 mm"]             # [point, length]
    second = ["D", "80 mm"]             # optional: branch (+1/-1), links = [name1, name2]

    [[group]]
    type = "attach"
    point = "K"
    on = ["D", "B"]                     # or a link name
    along = "-50 mm"                    # optional: left

    [[group]]
    type = "rrp"
    point = "N"
    rod = ["K", "100 mm"]
    guide = { through = ["120 mm", 0], angle = "57 deg" }   # through: [x, y], a ground point
                                        # or a link; optional offset. Optional: branch, link, slider

The driver may instead be a driving slider (a linear input)::

    [[group]]
    type = "slider"
    point = "A"
    guide = { through = [0, 0], angle = "0 deg" }   # a fixed guide (optional offset)
    travel = ["0 mm", "100 mm"]                     # the input displacements of a cycle
                                                    # optional: link (the block's name)

Further group types: ``rpr`` (``link``, ``about``, ``through``; optional ``offset``, ``branch``,
``block``) and ``follower`` (``point``, ``on``, ``guide``, ``profile = {type = "circle",
radius, center}`` or ``{type = "involute", base_radius, center, phase, roll}``; ``roller`` or
``face``; optional ``branch``, ``side``, ``slider``). Any dimension may be written
``{name = "r", value = "30 mm"}`` to give its parameter that name (default names as in
:class:`~mechsynth.kinematics.Linkage`, e.g. ``"AB"``, ``"D_x"``, ``"N_guide_angle"``).

A problem file uses it with ``mechanism = "linkage"`` and either these tables inline or
``linkage = "path/to/linkage.toml"`` (relative to the problem file); its ``[variables]`` and
``[fixed]`` name the linkage's parameters. Errors name the table and the key.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import MechanismError
from ..fileio import output_dir, save_figure
from ..kinematics.curves import Circle, Involute
from ..kinematics.linkage import Linkage, Param
from ..options import Option, chart_options
from .problem_file import parse_quantity, register_mechanism

__all__ = ["linkage_from_data", "load_linkage", "LINKAGE_TABLES", "chart_linkage"]

#: top-level keys of a linkage (in a linkage file, or inline in a problem or chart file)
LINKAGE_TABLES = ("linkage", "ground", "group")

_GROUP_KEYS = {
    "crank": ({"point", "about", "length"}, {"phase", "link"}),
    "rrr": ({"point", "first", "second"}, {"branch", "links"}),
    "rrp": ({"point", "rod", "guide"}, {"branch", "link", "slider"}),
    "rpr": ({"link", "about", "through"}, {"offset", "branch", "block"}),
    "attach": ({"point", "on"}, {"along", "left"}),
    "follower": (
        {"point", "on", "profile", "guide"},
        {"roller", "face", "branch", "side", "slider"},
    ),
    "slider": ({"point", "guide", "travel"}, {"link"}),
}
_PROFILE_KEYS = {
    "circle": ({"radius"}, {"center"}),
    "involute": ({"base_radius"}, {"center", "phase", "roll"}),
}


class LinkageFileError(MechanismError):
    """A linkage table that does not follow the format (the message names table and key)."""


def _dim(value, where, unit="m"):
    """A dimension: a number (SI), ``"<number> <unit>"`` or ``{name, value}`` -> float or Param.
    ``unit`` is the SI unit it must have (``"m"`` for lengths and coordinates, ``"rad"`` for
    angles): ``length = "30 deg"`` is refused, not read as 0.524 m."""
    if isinstance(value, dict):
        extra = set(value) - {"name", "value"}
        if extra or "name" not in value or "value" not in value:
            raise LinkageFileError(
                f'{where}: a named dimension is {{name = "...", value = ...}}, got {value!r}'
            )
        return Param(str(value["name"]), parse_quantity(value["value"], where, unit))
    return parse_quantity(value, where, unit)


def _point(value, where) -> str:
    if not isinstance(value, str) or not value.isidentifier():
        raise LinkageFileError(f"{where}: expected a point name, got {value!r}")
    return value


def _pair(value, where):
    if not isinstance(value, list) or len(value) != 2:
        raise LinkageFileError(f"{where}: expected [point, length], got {value!r}")
    return _point(value[0], where), _dim(value[1], where)


def _branch(value, where):
    if type(value) is not int or value not in (1, -1):  # not 1.0, true or a list
        raise LinkageFileError(f"{where}: expected 1 or -1, got {value!r}")
    return value


def _on(value, where):
    if isinstance(value, str):
        return value
    if isinstance(value, list) and len(value) == 2 and all(isinstance(v, str) for v in value):
        return tuple(value)
    raise LinkageFileError(f"{where}: expected a link name or [origin, axis point], got {value!r}")


def _guide(value, where):
    """``{through, angle, offset}`` -> (guide, offset)."""
    if not isinstance(value, dict):
        raise LinkageFileError(
            f"{where}: expected {{through = [x, y] or a point or link, angle = ...}}, got {value!r}"
        )
    extra = set(value) - {"through", "angle", "offset"}
    if extra or "through" not in value or "angle" not in value:
        raise LinkageFileError(
            f"{where}: keys are through, angle (and offset); got {sorted(value)}"
        )
    through = value["through"]
    if (
        isinstance(through, list)
        and len(through) == 2
        and not all(isinstance(t, str) for t in through)
    ):
        through = tuple(_dim(t, f"{where}.through") for t in through)
    elif isinstance(through, list):
        through = _on(through, f"{where}.through")
    elif not isinstance(through, str):
        raise LinkageFileError(f"{where}.through: expected [x, y], a point or a link")
    offset = _dim(value["offset"], f"{where}.offset") if "offset" in value else None
    return (through, _dim(value["angle"], f"{where}.angle", "rad")), offset


def _profile(value, where):
    if not isinstance(value, dict) or value.get("type") not in _PROFILE_KEYS:
        raise LinkageFileError(
            f"{where}: expected a table with type = {' or '.join(map(repr, _PROFILE_KEYS))}, "
            f"got {value!r} (a user's curve needs the Python API: ParametricCurve)"
        )
    kind = value["type"]
    required, optional = _PROFILE_KEYS[kind]
    keys = set(value) - {"type"}
    _check_keys(keys, required, optional, where)
    args = {}
    for k in keys:
        if k == "center":
            c = value[k]
            if not isinstance(c, list) or len(c) != 2:
                raise LinkageFileError(f"{where}.center: expected [u, v], got {c!r}")
            args[k] = tuple(_dim(x, f"{where}.center") for x in c)
        elif k == "roll":
            r = value[k]
            if not isinstance(r, list) or len(r) != 2:
                raise LinkageFileError(f"{where}.roll: expected [low, high], got {r!r}")
            args[k] = tuple(parse_quantity(x, f"{where}.roll", "rad") for x in r)
        else:
            args[k] = _dim(value[k], f"{where}.{k}", "rad" if k == "phase" else "m")
    try:
        return Circle(**args) if kind == "circle" else Involute(**args)
    except ValueError as exc:
        raise LinkageFileError(f"{where}: {exc}") from None


def _check_keys(keys, required, optional, where):
    missing = sorted(required - set(keys))
    unknown = sorted(set(keys) - required - optional)
    if missing or unknown:
        parts = [f"unknown key(s) {', '.join(unknown)}"] if unknown else []
        parts += [f"missing key(s) {', '.join(missing)}"] if missing else []
        raise LinkageFileError(
            f"{where}: {'; '.join(parts)}; keys: {', '.join(sorted(required | optional))}"
        )


def _group(lk: Linkage, g: dict, where: str) -> Linkage:
    kind = g.get("type")
    if kind not in _GROUP_KEYS:
        raise LinkageFileError(
            f"{where}: type must be one of {', '.join(_GROUP_KEYS)}, got {kind!r}"
        )
    required, optional = _GROUP_KEYS[kind]
    keys = set(g) - {"type"}
    _check_keys(keys, required, optional, where)
    label = g.get("point", g.get("link", "?"))
    where = f"{where} ({kind} {label})"

    def opt(key, parse):
        return {key: parse(g[key], f"{where}: {key}")} if key in g else {}

    def name(key):
        return opt(key, lambda v, w: _point(v, w))

    branch = opt("branch", _branch)
    if kind == "crank":
        return lk.crank(
            _point(g["point"], f"{where}: point"),
            about=_point(g["about"], f"{where}: about"),
            length=_dim(g["length"], f"{where}: length"),
            **opt("phase", lambda v, w: _dim(v, w, "rad")),
            **name("link"),
        )
    if kind == "slider":
        guide, offset = _guide(g["guide"], f"{where}: guide")
        tr = g["travel"]
        if not isinstance(tr, list) or len(tr) != 2:
            raise LinkageFileError(f"{where}: travel: expected [low, high], got {tr!r}")
        travel = tuple(parse_quantity(t, f"{where}: travel", "m") for t in tr)
        return lk.slider(
            _point(g["point"], f"{where}: point"),
            guide=guide,
            travel=travel,
            offset=offset,
            **name("link"),
        )
    if kind == "rrr":
        links = {}
        if "links" in g:
            ln = g["links"]
            if not isinstance(ln, list) or len(ln) != 2:
                raise LinkageFileError(f"{where}: links: expected [name1, name2], got {ln!r}")
            links = {"links": tuple(_point(x, f"{where}: links") for x in ln)}
        return lk.rrr(
            _point(g["point"], f"{where}: point"),
            _pair(g["first"], f"{where}: first"),
            _pair(g["second"], f"{where}: second"),
            **branch,
            **links,
        )
    if kind == "rrp":
        guide, offset = _guide(g["guide"], f"{where}: guide")
        return lk.rrp(
            _point(g["point"], f"{where}: point"),
            _pair(g["rod"], f"{where}: rod"),
            guide=guide,
            offset=offset,
            **branch,
            **name("link"),
            **name("slider"),
        )
    if kind == "rpr":
        return lk.rpr(
            _point(g["link"], f"{where}: link"),
            about=_point(g["about"], f"{where}: about"),
            through=_point(g["through"], f"{where}: through"),
            **opt("offset", _dim),
            **branch,
            **name("block"),
        )
    if kind == "attach":
        return lk.attach(
            _point(g["point"], f"{where}: point"),
            on=_on(g["on"], f"{where}: on"),
            **opt("along", _dim),
            **opt("left", _dim),
        )
    guide, offset = _guide(g["guide"], f"{where}: guide")
    if "roller" in g and "face" in g:
        raise LinkageFileError(f"{where}: give roller or face, not both")
    return lk.follower(
        _point(g["point"], f"{where}: point"),
        on=_on(g["on"], f"{where}: on"),
        profile=_profile(g["profile"], f"{where}: profile"),
        guide=guide,
        offset=offset,
        **opt("roller", _dim),
        **opt("face", _dim),
        **branch,
        **opt("side", _branch),
        **name("slider"),
    )


def linkage_from_data(data: dict, where: str = "") -> Linkage:
    """A :class:`Linkage` from the parsed tables ``[linkage]``, ``[ground]``, ``[[group]]``
    (other top-level keys are ignored: the caller checks them). ``where`` prefixes messages
    (e.g. the file name)."""
    pre = f"{where}: " if where else ""
    meta = data.get("linkage", {})
    if not isinstance(meta, dict):
        raise LinkageFileError(f"{pre}[linkage] must be a table (name, output)")
    unknown = set(meta) - {"name", "output"}
    if unknown:
        raise LinkageFileError(
            f"{pre}[linkage]: unknown key(s) {', '.join(sorted(unknown))}; keys: name, output"
        )
    ground = data.get("ground")
    if not isinstance(ground, dict) or not ground:
        raise LinkageFileError(f"{pre}[ground]: give the ground points, e.g. O = [0, 0]")
    points = {}
    for p, xy in ground.items():
        w = f"{pre}[ground] {p}"
        if not isinstance(xy, list) or len(xy) != 2:
            raise LinkageFileError(f"{w}: expected [x, y], got {xy!r}")
        points[p] = tuple(_dim(v, w) for v in xy)
    groups = data.get("group")
    if not isinstance(groups, list) or not groups or not all(isinstance(g, dict) for g in groups):
        raise LinkageFileError(
            f"{pre}[[group]]: give the driver (crank or slider) and the groups as [[group]] "
            "tables, in solving order"
        )
    try:
        lk = Linkage(ground=points, name=str(meta.get("name", "linkage")))
    except ValueError as exc:
        raise LinkageFileError(f"{pre}[ground]: {exc}") from None
    for i, g in enumerate(groups, start=1):
        w = f"{pre}[[group]] {i}"
        try:
            lk = _group(lk, g, w)
        except LinkageFileError:
            raise
        except (ValueError, TypeError) as exc:
            label = g.get("point", g.get("link", "?"))
            msg = str(exc)  # a quantity's message names its place already
            raise LinkageFileError(
                msg if msg.startswith(w) else f"{w} ({g.get('type')} {label}): {msg}"
            ) from None
    if "output" in meta:
        try:
            lk = lk.with_output(meta["output"])
        except ValueError as exc:
            raise LinkageFileError(f"{pre}[linkage] output: {exc}") from None
    return lk


def _read(path) -> dict:
    from ..fileio import read_toml

    return read_toml(path, "linkage file")[0]


def load_linkage(path) -> Linkage:
    """A :class:`Linkage` from a TOML file (see the module notes)."""
    data = _read(path)
    unknown = set(data) - set(LINKAGE_TABLES)
    if unknown:
        raise LinkageFileError(
            f"{path}: unknown top-level key(s) {', '.join(sorted(unknown))}; a linkage file has "
            "[linkage], [ground] and [[group]] tables"
        )
    return linkage_from_data(data, str(path))


def _linkage_of(data: dict, path) -> Linkage:
    """The linkage of a problem or chart file: its inline tables, or ``linkage = "file"``."""
    where = str(path) if path else ""
    ref = data.get("linkage")
    if isinstance(ref, str):
        if "ground" in data or "group" in data:
            raise LinkageFileError(
                f"{where}: give the linkage inline ([ground], [[group]]) or as linkage = "
                "'file', not both"
            )
        target = Path(ref) if path is None else Path(path).parent / ref
        if not target.exists():
            raise FileNotFoundError(f"{where}: linkage file {target} not found")
        return load_linkage(target)
    return linkage_from_data(data, where)


class _LinkageFile:
    """``mechanism = "linkage"`` in problem files: the linkage is read from the file's tables."""

    __name__ = "Linkage"
    file_keys = LINKAGE_TABLES

    @staticmethod
    def from_problem_data(data: dict, path=None) -> Linkage:
        return _linkage_of(data, path)


register_mechanism("linkage", _LinkageFile())


# ------------------------------------------------------------------------------ chart
_CHART_KEYS = {"x", "y", "n", "angles", "speed", "measures", "limits", "best", "best_sense"}


def _axis(value, where):
    if isinstance(value, str):  # NAME:LOW:HIGH from the command line
        parts = value.split(":")
        value = parts if len(parts) == 3 else value
    if not isinstance(value, list) or len(value) != 3 or not isinstance(value[0], str):
        raise LinkageFileError(f"{where}: expected [parameter, low, high], got {value!r}")
    lo, hi = (parse_quantity(v, where) for v in value[1:])
    if not lo < hi:
        raise LinkageFileError(f"{where}: need low < high, got {lo} and {hi}")
    return value[0], lo, hi


def _axis_words(lk: Linkage, name: str) -> str:
    """A parameter in words for an axis ('angle of guide of N (N_guide_angle)'), not only its
    name."""
    role = lk.parameter_roles.get(name, "")
    return role if name in role.replace("(", " ").split() else f"{role} ({name})".strip()


@chart_options(
    Option(
        "file", None, "the chart file: a linkage and its [chart] table", kind="path", required=True
    ),
    Option(
        "n", None, "grid points per axis (overrides the file)", kind="int", minimum=3, maximum=2000
    ),
    Option(
        "angles",
        None,
        "crank angles per turn (overrides the file)",
        kind="int",
        minimum=8,
        maximum=100_000,
    ),
    Option(
        "rpm",
        None,
        "crank speed (overrides the file)",
        unit="rpm",
        kind="float",
        minimum=0.0,
        exclusive=True,
    ),
    Option("x", None, "first axis NAME:LOW:HIGH (overrides the file)", kind="str"),
    Option("y", None, "second axis NAME:LOW:HIGH (overrides the file)", kind="str"),
    owner="chart 'linkage'",
)
def chart_linkage(out, options):
    """``mechsynth chart linkage --set file=chart.toml``: a design chart of a linkage over two of
    its dimensions. The file holds the linkage (inline tables or ``linkage = "file"``) and a
    ``[chart]`` table::

        [chart]
        x = ["DB", "50 mm", "120 mm"]      # parameter, low, high
        y = ["KN", "60 mm", "200 mm"]
        n = 40                             # grid points per axis
        angles = 180                       # crank angles per cycle
        speed = "1500 rpm"                 # omit for analogs
        measures = ["stroke(N)", "max_pressure_angle(N)", "min_transmission_angle(B)"]
        limits = ["max_pressure_angle(N) <= 30 deg"]
        best = "stroke(N)"                 # mark the best grid design (best_sense = "max")

    Options (``--set``): ``file`` (required), and ``n``, ``angles``, ``rpm``,
    ``x=NAME:LOW:HIGH``, ``y=NAME:LOW:HIGH`` override the file."""
    from ..report import StudyResult
    from .charts import sweep
    from .problem_file import parse_constraint, parse_measure

    path = Path(options["file"])
    if not path.is_file():
        raise FileNotFoundError(f"chart file {path} not found")
    data = _read(path)
    unknown = set(data) - set(LINKAGE_TABLES) - {"chart"}
    if unknown:
        raise LinkageFileError(
            f"{path}: unknown top-level key(s) {', '.join(sorted(unknown))}; a chart file has "
            "[chart] and the linkage ([ground], [[group]] or linkage = 'file')"
        )
    chart = data.get("chart")
    if not isinstance(chart, dict):
        raise LinkageFileError(f"{path}: missing the [chart] table (x, y, measures, ...)")
    extra = set(chart) - _CHART_KEYS
    if extra:
        raise LinkageFileError(
            f"{path}: [chart]: unknown key(s) {', '.join(sorted(extra))}; keys: "
            + ", ".join(sorted(_CHART_KEYS))
        )
    lk = _linkage_of(data, path)
    for key in ("n", "angles", "x", "y"):
        if options[key] is not None:
            chart[key] = options[key]
    if options["rpm"] is not None:
        chart["speed"] = f"{options['rpm']} rpm"
    for key in ("x", "y", "measures"):
        if key not in chart:
            raise LinkageFileError(f"{path}: [chart]: missing key {key}")
    (xn, xlo, xhi), (yn, ylo, yhi) = (_axis(chart[k], f"{path}: [chart] {k}") for k in "xy")
    for name, key in ((xn, "x"), (yn, "y")):
        if name not in lk.parameters:
            raise LinkageFileError(
                f"{path}: [chart] {key}: {lk.name} has no parameter {name!r}; parameters: "
                + ", ".join(lk.parameters)
            )
    if xn == yn:
        raise LinkageFileError(
            f"{path}: [chart]: x and y are both {xn!r}; a chart needs two different parameters"
        )
    from .. import validate

    n = validate.integer(f"{path}: [chart] n", chart.get("n", 40))
    angles = validate.integer(f"{path}: [chart] angles", chart.get("angles", 180))
    if n < 3 or angles < 8:
        raise LinkageFileError(f"{path}: [chart]: need n >= 3 and angles >= 8, got {n}, {angles}")
    speed = chart.get("speed")
    speed = None if speed is None else parse_quantity(speed, f"{path}: [chart] speed")
    if not isinstance(chart["measures"], list) or not chart["measures"]:
        raise LinkageFileError(f"{path}: [chart] measures: a list of measures, e.g. ['stroke(N)']")
    measures = {}
    for text in chart["measures"]:
        try:
            measures[str(text)] = parse_measure(str(text))
        except ValueError as exc:
            raise LinkageFileError(f"{path}: [chart] measures: {exc}") from None
    limits = {}
    for text in chart.get("limits", []):
        try:
            c = parse_constraint(text)
        except ValueError as exc:
            raise LinkageFileError(f"{path}: [chart] limits: {exc}") from None
        label = next((k for k, m in measures.items() if m.name == c.measure.name), None)
        if label is None or c.op == "==":
            raise LinkageFileError(
                f"{path}: [chart] limits: {text!r} must bound one of the measures with <= or >="
            )
        limits[label] = (c.op, c.bound)
    best = chart.get("best", next(iter(measures)))
    if best not in measures:
        raise LinkageFileError(f"{path}: [chart] best: {best!r} is not one of the measures")
    sense = chart.get("best_sense", "min")
    kinds = lk.parameter_kinds
    # axes in display units: angles in degrees (mapped to the linkage's radians)
    scale = {k: (np.pi / 180.0 if kinds[k] == "angle" else 1.0) for k in (xn, yn)}
    unit = {k: ("deg" if kinds[k] == "angle" else "m") for k in (xn, yn)}

    def design(values):
        return {k: v * scale[k] for k, v in values.items()}

    def assembles(values):
        """Designs that assemble at the chart's angles (a screen: the batch need not be split
        on a MechanismError)."""
        params = {k: np.asarray(v, dtype=float)[:, None] for k, v in design(values).items()}
        worst = lk(**params).assembles(angles)
        return np.logical_and.reduce([np.asarray(w) >= 0.0 for w in worst.values()])

    result = sweep(
        lk,
        grid={
            xn: np.linspace(xlo, xhi, n) / scale[xn],
            yn: np.linspace(ylo, yhi, n) / scale[yn],
        },
        measures=measures,
        design=design,
        feasible=assembles,
        angles=angles,
        speed=speed,
        progress=True,  # a bar on a terminal (the command line's --quiet turns it off)
        labels={k: f"{_axis_words(lk, k)}, {unit[k]}" for k in (xn, yn)},
    )
    files = []
    if out is not None:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        out = output_dir(out)
        stem = path.stem
        files.append(result.to_csv(out / f"{stem}_chart.csv"))
        files.append(result.to_npz(out / f"{stem}_chart.npz"))
        fig = result.plot(limits=limits or None, best=best, best_sense=sense)
        save_figure(fig, out / f"{stem}_chart.png", dpi=130)
        plt.close(fig)
        files.append(out / f"{stem}_chart.png")
    try:
        pick = result.argbest(best, where=limits or None, sense=sense)
    except ValueError:
        pick = None

    def shown(label, value):
        if measures[label].unit == "rad":
            return f"{np.rad2deg(value):.6g} deg"
        return f"{value:.6g} {measures[label].unit}".rstrip()

    where_text = ", ".join(f"{k} {op} {shown(k, b)}" for k, (op, b) in limits.items())
    where_text = where_text or "no limits"
    summary = (
        f"{lk.name} chart: {n} x {n} designs over {xn} {xlo / scale[xn]:g}..{xhi / scale[xn]:g} "
        f"{unit[xn]} and {yn} {ylo / scale[yn]:g}..{yhi / scale[yn]:g} {unit[yn]}, {angles} "
        f"{'crank angles' if lk.periodic else 'inputs over the travel'}, "
        f"{int(result.feasible.sum())} feasible, {result.elapsed:.2f} s.\n"
    )
    if pick is None:
        summary += f"No feasible grid design satisfies {where_text}."
    else:
        summary += (
            f"Best grid design ({sense} {best}, {where_text}): {best} = "
            f"{shown(best, pick['values'][best])} at {xn} = {pick['grid'][xn]:.6g} {unit[xn]}, "
            f"{yn} = {pick['grid'][yn]:.6g} {unit[yn]}"
        )
    data_out = dict(
        linkage=lk.name,
        x=[xn, xlo, xhi],
        y=[yn, ylo, yhi],
        n=n,
        angles=angles,
        speed=speed,
        feasible=int(result.feasible.sum()),
        elapsed=result.elapsed,
        best_on_grid=pick,
        success=pick is not None,
    )
    return StudyResult("linkage-chart", summary, data_out, [Path(f) for f in files])
