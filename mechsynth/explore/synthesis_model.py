"""What the page's path and function generation compute, without Panel: the typed targets and
functions read in the page's units, the library's engines run (a path search or a function
generator's min-max stage in a worker process that reports its starts), the ranked solutions
as rows, a solution's cycle for the preview, and a solution as the page's state (a linkage the
editor shows and exports).

The engines are the library's: :func:`mechsynth.path_generation` (a four-bar, its coupler point
``P`` placed anywhere; a slider-crank's rod point; or a point of the page's linkage with the
dimensions chosen to vary; the crank angles at the targets free or prescribed) and
:func:`mechsynth.function_generation` (Freudenstein's equation and the phase scan, then its
certified min-max stage). Numbers typed in the page are in its display units (lengths in its
length unit, angles in degrees); everything here returns SI (m, rad).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from ..errors import MechanismError
from .model import State, linkage_kind, parse_number

__all__ = [
    "MECHANISMS",
    "TIMINGS",
    "PathJob",
    "parse_angles",
    "even_angles",
    "linkage_variables",
    "job_linkage",
    "slider_crank_tables",
    "minmax_worker",
    "run_minmax",
    "certificate_words",
    "FunctionJob",
    "parse_points",
    "parse_pairs",
    "path_worker",
    "run_path",
    "path_rows",
    "path_tables",
    "path_state",
    "path_preview",
    "run_function",
    "function_tables",
    "function_state",
    "function_preview",
    "DEFAULT_POINTS",
]

PREVIEW_FRAMES = 120  # crank angles of a solution's preview cycle

# six points on the coupler curve of a known crank-rocker (path_cases.exact_case scaled to a
# 100 mm crank), in mm: free timing finds a four-bar through them
DEFAULT_POINTS = """61.42, 166.96
54.55, 217.67
1.02, 224.59
-50.27, 181.45
-76.07, 114.05
-62.00, 36.55"""


def _numbers(line: str) -> list[str]:
    return [p for p in re.split(r"[,\s;]+", line.split("#")[0].strip()) if p]


def _pairs_of_numbers(text, what: str, two: str, task: str, many: str, convert) -> np.ndarray:
    """Lines of two numbers each (commas, spaces or semicolons between them; ``#`` starts a
    comment; blank lines skipped), each number through ``convert``; at least three rows."""
    rows = []
    for i, line in enumerate(str(text or "").splitlines(), start=1):
        parts = _numbers(line)
        if not parts:
            continue
        if len(parts) != 2:
            raise MechanismError(
                f"{what} line {i}: give {two}, got {len(parts)}: {line.strip()!r}"
            )
        rows.append(tuple(convert(parse_number(p, f"{what} line {i}")) for p in parts))
    if len(rows) < 3:
        raise MechanismError(f"{task} takes 3 or more {many}, got {len(rows)}")
    return np.array(rows, dtype=float)


def parse_points(text: str, state: State) -> np.ndarray:
    """Target points typed one a line, ``x, y`` in the page's length unit (commas, spaces or
    semicolons between them; ``#`` starts a comment), as rows ``(x, y)`` in m. MechanismError
    names a line that is not two numbers, or too few points (path generation takes 3 or
    more)."""
    return _pairs_of_numbers(text, "point", "x and y (2 numbers)", "path generation",
                             "target points", lambda v: state.si(v, "m"))  # fmt: skip


def parse_pairs(text: str) -> np.ndarray:
    """Precision pairs typed one a line, ``crank angle, output angle`` in degrees, as rows in
    rad (at least three)."""
    return _pairs_of_numbers(text, "pair", "the crank and output angles (2 numbers, deg)",
                             "function generation", "precision pairs", math.radians)  # fmt: skip


# ------------------------------------------------------------------------------ path
#: the path generation's mechanisms: the library's four-bar and slider-crank, the page's linkage
MECHANISMS = ("four-bar", "slider-crank", "linkage")
#: the crank angles at the targets: free, the path's shape only (a four-bar), or given
TIMINGS = ("free", "shape", "prescribed")


def parse_angles(text: str, n: int) -> np.ndarray:
    """The crank angle at each of ``n`` targets, typed in degrees (commas, spaces, semicolons
    or lines between them; ``#`` starts a comment), in rad. MechanismError names a value that
    is not a number or a count that is not ``n``."""
    vals = []
    for i, line in enumerate(str(text or "").splitlines(), start=1):
        vals += [math.radians(parse_number(p, f"crank angle (line {i}), deg"))
                 for p in _numbers(line)]  # fmt: skip
    if len(vals) != n:
        raise MechanismError(
            f"prescribed timing takes one crank angle per target point: {n} points, got "
            f"{len(vals)} angles"
        )
    return np.array(vals, dtype=float)


def even_angles(n: int) -> np.ndarray:
    """``n`` crank angles evenly spaced over a turn from 0 (rad)."""
    return np.arange(int(n)) * (2.0 * np.pi / max(int(n), 1))


def linkage_variables(state: State, names, spread: float) -> dict:
    """Bounds of the page's linkage dimensions ``names`` (SI) for a search around its design:
    a length within ``spread`` (a fraction) of its value either way, a coordinate or a signed
    offset within ``spread`` of the linkage's largest length, an angle within ``spread`` of
    180 deg."""
    if not 0.0 < spread <= 10.0:
        raise MechanismError(f"the range of each dimension must be in (0, 1000] %, got "
                             f"{100 * spread:.6g} %")  # fmt: skip
    if not names:
        raise MechanismError("pick one or more dimensions of the linkage to vary")
    dims = {d.name: d for d in state.kind.dims}
    lengths = [abs(v) for k, v in state.values.items() if dims[k].positive]
    scale = max(lengths or [1.0])
    out = {}
    for k in names:
        if k not in dims:
            raise MechanismError(f"{state.kind.title} has no dimension {k!r}")
        v, d = float(state.values[k]), dims[k]
        if d.unit == "rad":
            out[k] = (v - spread * math.pi, v + spread * math.pi)
        elif d.positive:
            out[k] = (v * max(1.0 - spread, 0.05), v * (1.0 + spread))
        else:
            out[k] = (v - spread * scale, v + spread * scale)
    return out


@dataclass(frozen=True)
class PathJob:
    """A path search as the page asks it (SI).

    Attributes
    ----------
    targets : ``(N, 2)`` points (m), in the order the traced point visits them.
    timing : ``"free"`` (the crank angle at each target free, in order within one turn),
        ``"shape"`` (a four-bar's closed path's shape only: position, size and orientation
        free) or ``"prescribed"`` (``angles``).
    min_transmission : the smallest transmission angle over the turn (rad), or None.
    starts : local solves of the search.
    angles : with prescribed timing, the crank angle at each target (rad; only their
        differences count: the crank's start is free).
    mechanism : ``"four-bar"``, ``"slider-crank"`` (a point on the rod, the guide anywhere) or
        ``"linkage"``: the linkage of ``tables`` at ``values`` (its dimensions, SI), its point
        ``trace`` followed, the dimensions of ``variables`` (``{name: (lower, upper)}``)
        varied.
    """

    targets: np.ndarray
    timing: str = "free"
    min_transmission: float | None = None
    starts: int = 6
    angles: np.ndarray | None = None
    mechanism: str = "four-bar"
    tables: dict | None = None
    values: dict | None = None
    trace: str | None = None
    variables: dict | None = None

    def __post_init__(self):
        if self.timing not in TIMINGS:
            raise MechanismError(
                f"timing must be free, shape or prescribed, got {self.timing!r}"
            )
        if self.mechanism not in MECHANISMS:
            raise MechanismError(f"mechanism must be one of {', '.join(MECHANISMS)}, got "
                                 f"{self.mechanism!r}")  # fmt: skip
        if self.timing == "shape" and self.mechanism != "four-bar":
            raise MechanismError(
                "shape-only timing is the four-bar's (the curves' Fourier descriptors): pick "
                "free or prescribed timing for a slider-crank or a linkage"
            )
        if self.min_transmission is not None and not 0 <= self.min_transmission < math.pi / 2:
            raise MechanismError(
                "minimum transmission angle must be in [0, 90) deg, got "
                f"{math.degrees(self.min_transmission):.6g} deg"
            )
        if not 1 <= int(self.starts) <= 200:
            raise MechanismError(f"starts must be between 1 and 200, got {self.starts}")
        n = len(self.targets)
        if self.timing == "prescribed":
            if self.angles is None or len(self.angles) != n:
                got = 0 if self.angles is None else len(self.angles)
                raise MechanismError(
                    f"prescribed timing takes one crank angle per target point: {n} points, "
                    f"got {got} angles"
                )
        elif self.angles is not None:
            raise MechanismError("crank angles are given with prescribed timing only")
        if self.mechanism == "linkage" and not (self.tables and self.trace and self.variables):
            raise MechanismError(
                "path generation over a linkage needs its tables, the point to follow and "
                "the dimensions to vary"
            )


def job_linkage(job: PathJob):
    """The :class:`~mechsynth.Linkage` of a linkage job at its values."""
    from ..synthesis.linkage_file import linkage_from_data

    lk = linkage_from_data(job.tables)
    return lk(**job.values) if job.values else lk


def run_path(job: PathJob, report=None):
    """The library's path generation on ``job`` (``report(desc, k, total)`` is told of each
    start); returns the :class:`~mechsynth.synthesis.path_result.PathResult`."""
    from .. import progress
    from ..synthesis.path_generation import path_generation

    kw = {}
    if job.mechanism == "slider-crank":
        kw = dict(mechanism="slider-crank")
    elif job.mechanism == "linkage":
        lk = job_linkage(job)
        if not lk.periodic:
            raise MechanismError(
                f"{lk.name} is driven by a slider: path generation turns a crank (a linkage "
                "driven by a crank, or the four-bar or slider-crank)"
            )
        kw = dict(mechanism=lk, trace=job.trace, variables=dict(job.variables))

    def run():
        return path_generation(
            job.targets,
            timing=job.timing,
            angles=None if job.angles is None else np.asarray(job.angles, float),
            min_transmission=job.min_transmission,
            starts=int(job.starts),
            progress=False,
            **kw,
        )

    if report is None:
        return run()
    with progress.observe(report):
        return run()


def _worker(run, job, messages) -> None:
    try:

        def report(desc, k, total):
            messages.put(("progress", str(desc or ""), int(k), int(total or 0)))

        messages.put(("done", run(job, report)))
    except Exception as exc:  # noqa: BLE001 - every failure goes back to the page as text
        messages.put(("error", f"{type(exc).__name__}: {exc}"))


def path_worker(job: PathJob, messages) -> None:
    """A worker process's work: post ``("progress", desc, k, total)`` while the starts run,
    then ``("done", result)`` or ``("error", text)`` on ``messages``."""
    _worker(run_path, job, messages)


def path_rows(res) -> list[dict]:
    """The ranked solutions of a path result (best first), SI: ``error`` (the objective's,
    m^2), ``max_distance`` (m), ``transmission`` (smallest, rad), ``note`` (e.g. a cognate),
    ``dims`` the design's dimensions as ``(name, value, unit)`` (a four-bar's link lengths;
    a linkage's varied dimensions, ``unit`` ``"m"`` or ``"rad"``)."""
    rows = []
    for k, s in enumerate(res.solutions, start=1):
        if s.fourbar is not None:
            dims = [(n, float(getattr(s, n)), "m") for n in ("crank", "coupler", "rocker",
                                                                "ground")]  # fmt: skip
        else:
            dims = [(n, float(v), s.linkage.unit_of(n)) for n, v in s.values.items()]
        rows.append(dict(rank=k, error=float(s.error), max_distance=float(s.max_distance),
                         transmission=float(s.transmission[0]), note=s.note or "", dims=dims))
    return rows


def path_tables(sol) -> dict:
    """A four-bar path solution as a linkage file's tables (SI): ground points O1 and O2, the
    crank O1A (its phase the ground line's angle, so the linkage's crank angle is the
    solution's), the RRR group B and the coupler point P, the linkage's output."""
    c, s = math.cos(sol.angle), math.sin(sol.angle)
    x0, y0, g = float(sol.x0), float(sol.y0), float(sol.ground)
    return {
        "linkage": {"name": "path generator", "output": "P"},
        "ground": {"O1": [x0, y0], "O2": [x0 + g * c, y0 + g * s]},
        "group": [
            {"type": "crank", "point": "A", "about": "O1", "length": float(sol.crank),
             "phase": float(sol.angle)},
            {"type": "rrr", "point": "B", "first": ["A", float(sol.coupler)],
             "second": ["O2", float(sol.rocker)], "branch": 1 if sol.branch == "open" else -1},
            {"type": "attach", "point": "P", "on": ["A", "B"], "along": float(sol.u),
             "left": float(sol.v)},
        ],
    }  # fmt: skip


def slider_crank_tables(sol) -> dict:
    """A slider-crank path solution as a linkage file's tables (SI): the crank O-A, the rod
    A-B with B on the guide through the ground point G, the tracing point P on the rod (the
    library's :func:`~mechsynth.synthesis.path_linkage.slider_crank_template`, its
    dimensions the solution's)."""
    p = {k: float(v) for k, v in sol.linkage.parameters.items()}
    return {
        "linkage": {"name": "slider-crank path generator", "output": "P"},
        "ground": {"O": [p["O_x"], p["O_y"]], "G": [p["G_x"], p["G_y"]]},
        "group": [
            {"type": "crank", "point": "A", "about": "O", "length": p["OA"],
             "phase": p["phase"]},
            {"type": "rrp", "point": "B", "rod": ["A", p["AB"]],
             "guide": {"through": "G", "angle": {"name": "guide_angle",
                                                 "value": p["guide_angle"]},
                       "offset": p["B_guide_offset"]}},
            {"type": "attach", "point": "P", "on": ["A", "B"], "along": p["P_along"],
             "left": p["P_left"]},
        ],
    }  # fmt: skip


def path_state(sol, rank: int, units: str = "si", tables: dict | None = None) -> State:
    """The page's state of a path solution: its linkage with the traced point's path drawn
    (``tables``: the linkage's tables when the search was over the page's linkage; the
    solution's values replace its dimensions, and the traced point is its output)."""
    title = f"Path generation: solution {rank}"
    if sol.fourbar is not None:
        kind = linkage_kind(path_tables(sol), title=title)
        kind.trace = ("P",)
        return State.of(kind, units)
    if tables is None:
        tables = slider_crank_tables(sol)
    from .editor import Draft

    values = {k: float(v) for k, v in sol.linkage.parameters.items()}
    tables = Draft.from_tables(tables).with_values(values).tables()
    tables["linkage"] = dict(tables.get("linkage") or {}, output=sol.trace_point)
    kind = linkage_kind(tables, title=title)
    kind.trace = (sol.trace_point,)
    # the exact values (the tables carry them to 6 digits, for the sliders' ranges)
    kind.values.update({k: values[k] for k in kind.values if k in values})
    return State.of(kind, units)


def path_preview(sol, n: int = PREVIEW_FRAMES) -> dict:
    """A solution's cycle for the preview over one counter-clockwise turn of the crank:
    ``points`` (``{name: (n, 2)}``, m), ``links`` (lists of point names drawn as polylines),
    ``pins`` (the joints drawn), ``trace`` (the point that follows the targets) and
    ``targets_angle`` (the crank angles at the targets, rad)."""
    phi = np.linspace(0.0, 2.0 * np.pi, int(n), endpoint=False)
    if sol.fourbar is not None:
        points = sol.positions(phi)
        links = [["O1", "A"], ["A", "B", "P", "A"], ["B", "O2"]]
        pins, trace = ["O1", "A", "B", "O2", "P"], "P"
    else:
        sk = sol.linkage.sketch(phi)
        points = {
            k: np.column_stack(np.broadcast_arrays(np.asarray(x, float) + 0 * phi,
                                                   np.asarray(y, float) + 0 * phi))
            for k, (x, y) in sk.points.items()
        }  # fmt: skip
        links = [list(b.points) + ([b.points[0]] if b.closed else []) for b in sk.bars]
        pins, trace = [p for p in sol.linkage.points if p in points], sol.trace_point
    return dict(points=points, links=links, pins=pins, trace=trace,
                targets_angle=np.asarray(sol.angles, dtype=float))  # fmt: skip


# ------------------------------------------------------------------------------ function
@dataclass(frozen=True)
class FunctionJob:
    """A function generator as the page asks it (SI).

    Attributes
    ----------
    function : ``y = f(x)`` as text (:mod:`mechsynth.synthesis.function_expr`), or None with
        ``pairs``.
    x : ``(x0, x1)``.
    input_range, output_range : the crank's and the rocker's rotations over ``[x0, x1]``
        (rad, signed).
    pairs : precision pairs ``(crank angle, output angle)`` (rad), instead of a function.
    ground : the four-bar's ground length (m).
    min_transmission : least transmission angle (rad).
    require_crank : the crank must turn fully (the page animates cranks that turn).
    """

    function: str | None = None
    x: tuple[float, float] | None = None
    input_range: float | None = None
    output_range: float | None = None
    pairs: np.ndarray | None = None
    ground: float = 0.1
    min_transmission: float | None = math.radians(30.0)
    require_crank: bool = True


def run_function(job: FunctionJob):
    """The library's function generation on ``job`` (a four-bar)."""
    from ..synthesis.function_generation import function_generation

    if job.pairs is not None:
        return function_generation(
            pairs=job.pairs, ground=job.ground, require_crank=job.require_crank
        )
    return function_generation(
        job.function,
        x=job.x,
        input_range=job.input_range,
        output_range=job.output_range,
        ground=job.ground,
        require_crank=job.require_crank,
        min_transmission=job.min_transmission,
    )


def run_minmax(job: FunctionJob, report=None):
    """The function generator of ``job`` then its certified min-max stage (the library's
    ``function_generation(..., optimize=True)``: the worst structural error over the whole
    input range minimized from the precision-point design, the crank turning fully and the
    transmission angle kept when ``job`` asks it); ``report(desc, k, total)`` is told of its
    starts. Needs a function (precision pairs do not define the error between them)."""
    from .. import progress
    from ..synthesis.function_generation import function_generation

    if job.pairs is not None:
        raise MechanismError(
            "the min-max stage needs a function y = f(x): precision pairs alone do not define "
            "the error over the whole range (clear the pairs)"
        )

    def run():
        return function_generation(
            job.function, x=job.x, input_range=job.input_range, output_range=job.output_range,
            ground=job.ground, require_crank=job.require_crank,
            min_transmission=job.min_transmission, optimize=True,
        )  # fmt: skip

    if report is None:
        return run()
    with progress.observe(report):
        return run()


def minmax_worker(job: FunctionJob, messages) -> None:
    """A worker process's work for :func:`run_minmax` (messages as :func:`path_worker`'s)."""
    _worker(run_minmax, job, messages)


def certificate_words(fg) -> str:
    """What the min-max stage of ``fg`` established, in words (angles in deg)."""
    sol = fg.solve
    c = sol.certification
    before, after = math.degrees(fg.start_max_error), math.degrees(fg.max_error)
    head = (
        f"worst structural error {before:.4g} deg before the min-max stage, {after:.4g} deg "
        f"after (status {sol.status}: {sol.message})"
    )
    if sol.design is None:
        return head + "; no better design found: the precision-point design is kept"
    peaks = "; ".join(
        f"{p.name.replace('_', ' ')}: grid {math.degrees(p.grid_value):.6g} deg, true "
        f"{math.degrees(p.true_value):.6g} deg"
        for p in c.peaks
    )
    if c.certified:
        cert = (
            "certified: the worst error is the true one over the whole input range, ends "
            f"included (dense evaluation and a 1-D search: {peaks}; {c.refinement_rounds} "
            f"refinement round(s), {c.grid_angles} grid angles)"
        )
    else:
        cert = (
            "NOT certified: the solver's grid and the true worst error differ ("
            f"{peaks}) after {c.refinement_rounds} refinement round(s)"
        )
    return (
        f"{head}; {cert}. A local solve from the precision-point design ({c.starts_run} "
        f"start(s)): certified says the worst error is the true one, not that no better "
        "design exists"
    )


def function_tables(fg) -> dict:
    """A four-bar function generator as a linkage file's tables (SI): ground O1 at the origin
    and O2 on +x, the crank O1A, the RRR group B (the rocker O2B is the output)."""
    d = fg.design
    return {
        "linkage": {"name": "function generator", "output": "B"},
        "ground": {"O1": [0.0, 0.0], "O2": [float(d.ground), 0.0]},
        "group": [
            {"type": "crank", "point": "A", "about": "O1", "length": float(d.crank)},
            {"type": "rrr", "point": "B", "first": ["A", float(d.coupler)],
             "second": ["O2", float(d.rocker)], "branch": int(d.sigma)},
        ],
    }  # fmt: skip


def function_state(fg, units: str = "si") -> State:
    """The page's state of a function generator (its crank must turn fully: the page
    animates whole turns)."""
    if not fg.design.full_turn:
        raise MechanismError(
            "this function generator's crank does not turn fully (it rocks over its input "
            "range), and the page animates whole turns: tick 'the crank turns fully' and "
            "generate again"
        )
    kind = linkage_kind(function_tables(fg), title="Function generation: " + (
        f"y = {fg.function}" if fg.function else "precision pairs"))  # fmt: skip
    kind.trace = ("B",)
    return State.of(kind, units)


def function_preview(fg, n: int = PREVIEW_FRAMES) -> dict:
    """The generator's motion over its input range (``n`` crank angles from the first
    phase): ``{"O1", "A", "B", "O2"}`` each ``(n, 2)`` (m)."""
    d = fg.design
    phi = fg.phases[0] + np.linspace(0.0, fg.spans[0], int(n))
    m = d.motion(phi)
    out = {}
    for name in ("O1", "A", "B", "O2"):
        p = m.points[name]
        out[name] = np.column_stack(
            [np.broadcast_to(p.x, phi.shape), np.broadcast_to(p.y, phi.shape)]
        ).astype(float)
    return out
