"""What the page's path and function generation compute, without Panel: the typed targets and
functions read in the page's units, the library's engines run (a path search in a worker
process that reports its starts), the ranked solutions as rows, a solution's cycle for the
preview, and a solution as the page's state (a linkage the editor shows and exports).

The engines are the library's: :func:`mechsynth.path_generation` (four-bar, its coupler point
``P`` placed anywhere) and :func:`mechsynth.function_generation` (Freudenstein's equation and
the phase scan). Numbers typed in the page are in its display units (lengths in its length
unit, angles in degrees); everything here returns SI (m, rad).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np

from ..errors import MechanismError
from .model import State, linkage_kind, parse_number

__all__ = [
    "PathJob",
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
@dataclass(frozen=True)
class PathJob:
    """A path search as the page asks it (SI).

    Attributes
    ----------
    targets : ``(N, 2)`` points (m), in the order the coupler point visits them.
    timing : ``"free"`` (the crank angle at each target free, in order within one turn) or
        ``"shape"`` (the closed path's shape only: position, size and orientation free).
    min_transmission : the smallest transmission angle over the turn (rad), or None.
    starts : local solves of the search.
    """

    targets: np.ndarray
    timing: str = "free"
    min_transmission: float | None = None
    starts: int = 6

    def __post_init__(self):
        if self.timing not in ("free", "shape"):
            raise MechanismError(f"timing must be free or shape, got {self.timing!r}")
        if self.min_transmission is not None and not 0 <= self.min_transmission < math.pi / 2:
            raise MechanismError(
                "minimum transmission angle must be in [0, 90) deg, got "
                f"{math.degrees(self.min_transmission):.6g} deg"
            )
        if not 1 <= int(self.starts) <= 200:
            raise MechanismError(f"starts must be between 1 and 200, got {self.starts}")


def run_path(job: PathJob, report=None):
    """The library's path generation on ``job`` (a four-bar; ``report(desc, k, total)`` is
    told of each start); returns the :class:`~mechsynth.synthesis.path_result.PathResult`."""
    from .. import progress
    from ..synthesis.path_generation import path_generation

    def run():
        return path_generation(
            job.targets,
            timing=job.timing,
            min_transmission=job.min_transmission,
            starts=int(job.starts),
            progress=False,
        )

    if report is None:
        return run()
    with progress.observe(report):
        return run()


def path_worker(job: PathJob, messages) -> None:
    """A worker process's work: post ``("progress", desc, k, total)`` while the starts run,
    then ``("done", result)`` or ``("error", text)`` on ``messages``."""
    try:

        def report(desc, k, total):
            messages.put(("progress", str(desc or ""), int(k), int(total or 0)))

        messages.put(("done", run_path(job, report)))
    except Exception as exc:  # noqa: BLE001 - every failure goes back to the page as text
        messages.put(("error", f"{type(exc).__name__}: {exc}"))


def path_rows(res) -> list[dict]:
    """The ranked solutions of a path result (best first), SI: ``error`` (the objective's,
    m^2), ``max_distance`` (m), ``transmission`` (smallest, rad), ``note`` (e.g. a cognate),
    the link lengths (m)."""
    return [
        dict(
            rank=k,
            error=float(s.error),
            max_distance=float(s.max_distance),
            transmission=float(s.transmission[0]),
            note=s.note or "",
            crank=float(s.crank),
            coupler=float(s.coupler),
            rocker=float(s.rocker),
            ground=float(s.ground),
        )
        for k, s in enumerate(res.solutions, start=1)
    ]


def path_tables(sol) -> dict:
    """A path solution as a linkage file's tables (SI): ground points O1 and O2, the crank
    O1A (its phase the ground line's angle, so the linkage's crank angle is the solution's),
    the RRR group B and the coupler point P, the linkage's output."""
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


def path_state(sol, rank: int, units: str = "si") -> State:
    """The page's state of a path solution: its linkage with P's path traced."""
    kind = linkage_kind(path_tables(sol), title=f"Path generation: solution {rank}")
    kind.trace = ("P",)
    return State.of(kind, units)


def path_preview(sol, n: int = PREVIEW_FRAMES) -> dict:
    """A solution's cycle for the preview: ``{"O1", "A", "B", "O2", "P"}`` each ``(n, 2)``
    (m) over one counter-clockwise turn of the crank, and ``"targets_angle"`` the crank
    angles at the targets (rad)."""
    phi = np.linspace(0.0, 2.0 * np.pi, int(n), endpoint=False)
    out = sol.positions(phi)
    out["targets_angle"] = np.asarray(sol.angles, dtype=float)
    return out


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
