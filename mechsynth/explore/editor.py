"""The explorer's editing, without Panel: a moving joint dragged to a new place, a linkage
built step by step by clicks (:class:`Draft`), and the design's state as a URL query.

Everything here is plain Python and numpy; :mod:`.editor_page` turns it into the page's
widgets and tools.

>>> from mechsynth.explore.editor import Draft
>>> d = Draft().ground(0.0, 0.0).ground(0.1, 0.0).crank("O1", 0.0, 0.03)
>>> d = d.rrr("A", "O2", 0.08, 0.07)
>>> lk, message = d.check()
>>> message is None, sorted(lk.parameters)[:3]
(True, ['AB', 'O1A', 'O1_x'])
"""

from __future__ import annotations

import base64
import functools
import json
import math
import zlib
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..errors import MechanismError
from .model import KINDS, State, kind_names, linkage_kind, to_toml

__all__ = [
    "DRAGGABLE",
    "joint_dims",
    "drag_joint",
    "Draft",
    "STEP_TYPES",
    "to_query",
    "state_from_query",
]

# ------------------------------------------------------------------------------ dragging
#: the moving joints of the built-in mechanisms and the dimensions each defines, with the
#: point each length is measured from (None: no closed form, found by least squares)
DRAGGABLE: dict[str, dict[str, tuple[tuple[str, str | None], ...]]] = {
    "slider-crank": {"A": (("crank", "O"),), "B": (("rod", "A"), ("offset", None))},
    "four-bar": {"A": (("crank", "O1"),), "B": (("coupler", "A"), ("rocker", "O2"))},
    # the beam's equalizer bearing B and its horsehead H (on the beam's line through O2)
    "beam-pump": {"A": (("R", "O1"),), "B": (("P", "A"), ("C", "O2")), "H": (("A", "O2"),)},
    # paper 003's ratios: B's place scales the whole linkage (rod), C is the coupler point
    # (k, gamma), G the end of link 5's stem, set by the slot's angle xi
    "dwell": {
        "A": (("r", "O"),),
        "B": (("rod", None),),
        "C": (("k", None), ("gamma", None)),
        "G": (("xi", None),),
    },
}
# a linkage group's parameters (by their role in the group) that its point's place defines
_GROUP_ROLES = {
    "crank": ("length", "phase"),
    "RRR": ("l1", "l2"),
    "point": ("along", "left"),
    "RRP": ("length",),
    "slider input": ("x", "y", "offset"),
}


def _is_linkage(state: State) -> bool:
    return state.kind.file_data is not None


def _group_index(state: State, point: str) -> int:
    design = state.kind.build(dict(state.values))
    for i, g in enumerate(design.groups):
        if g.key == point:
            return i
    raise MechanismError(f"{point} is a fixed pivot of {state.kind.title}, not a moving joint")


def joint_dims(state: State, point: str) -> tuple[str, ...]:
    """The dimensions of ``state`` that the place of the moving joint ``point`` defines (a
    crank pin: the crank's length and phase; an RRR group's joint: its two links; an attached
    point: its offsets; a slider of an RRP group: its rod). Raises MechanismError saying why
    when the joint cannot be dragged."""
    names = {d.name for d in state.kind.dims}
    if _is_linkage(state):
        design = state.kind.build(dict(state.values))
        g = design.groups[_group_index(state, point)]
        params = dict(g.params)
        out = tuple(
            params[r] for r in _GROUP_ROLES.get(g.kind, ()) if r in params and params[r] in names
        )
        if not out:
            raise MechanismError(
                f"{point} ({g.label}) has no dimension the drawing can move: edit its fields"
            )
        return out
    table = DRAGGABLE.get(state.kind.key, {})
    if point not in table:
        raise MechanismError(
            f"{point} of the {state.kind.title} is not a joint the drawing moves "
            f"(its joints that drag: {', '.join(table) or 'none'}); edit its fields"
        )
    return tuple(name for name, _ in table[point])


def _prefix(state: State, point: str):
    """``fn(values) -> design`` solving only the groups up to the one placing ``point`` (a
    later group that cannot assemble does not stop the search; the cycle check does)."""
    if not _is_linkage(state):
        return state.kind.build
    from ..synthesis.linkage_file import linkage_from_data

    i = _group_index(state, point)
    tables = dict(state.kind.file_data)
    tables["group"] = list(tables["group"])[: i + 1]
    if "linkage" in tables:  # its output may be a later point
        tables["linkage"] = {k: v for k, v in tables["linkage"].items() if k != "output"}
    lk = linkage_from_data(tables)
    keep = tuple(lk.parameters)
    return lambda v: lk(**{k: v[k] for k in keep})


def _place(build, values, point, phi) -> np.ndarray:
    sk = build(values).sketch(np.array([phi]))
    x, y = sk.points[point]
    return np.array([float(np.ravel(x)[0]), float(np.ravel(y)[0])])


def drag_joint(state: State, point: str, xy, phi: float) -> dict[str, float]:
    """The dimension values (SI) that put the moving joint ``point`` at ``xy`` (m) at the input
    ``phi`` (rad, or m for a driving slider), changing only :func:`joint_dims` (a slider's
    joint that has one dimension goes to the nearest place its guide allows).

    Raises MechanismError naming the joint when no such values exist (a joint of two links
    dragged across the line of its pivots would change the assembly branch). Whether the
    linkage still assembles over its whole cycle is :meth:`State.check_design`'s to say.
    """
    from scipy.optimize import least_squares

    dims = joint_dims(state, point)
    target = np.asarray(xy, dtype=float).reshape(2)
    if not np.all(np.isfinite(target)):
        raise MechanismError(f"{point}: the dragged place must be numbers, got {tuple(xy)}")
    build = _prefix(state, point)
    values = dict(state.values)
    try:
        here = _place(build, values, point, phi)
        design = build(values)
        sk = design.sketch(np.array([phi]))
    except (MechanismError, ValueError) as exc:
        raise MechanismError(f"cannot move {point}: the design shown is not valid ({exc})") from exc
    size = max(float(np.ptp(np.concatenate([np.ravel(v) for v in sk.points.values()]))), 1e-9)
    # a start from the closed forms where they exist: a length is the distance to its pivot
    refs = _references(state, point, dims)
    for name, ref in zip(dims, refs):
        if ref is None:
            continue
        if ref == "phase":
            o = np.array([float(np.ravel(c)[0]) for c in sk.points[_crank_centre(state, point)]])
            values[name] = math.atan2(*(target - o)[::-1]) - float(phi)
            continue
        q = np.array([float(np.ravel(c)[0]) for c in sk.points[ref]])
        values[name] = float(np.hypot(*(target - q)))
    positive = {d.name for d in state.kind.dims if d.positive}

    def residual(x):
        v = dict(values, **dict(zip(dims, x)))
        try:
            return (_place(build, v, point, phi) - target) / size
        except (MechanismError, ValueError, ZeroDivisionError):
            return np.full(2, 10.0)

    x0 = np.array([values[n] for n in dims], dtype=float)
    lo = np.array([1e-9 if n in positive else -np.inf for n in dims])
    x0 = np.maximum(x0, lo + 1e-12)
    if np.max(np.abs(residual(x0))) > 1e-10:
        fit = least_squares(
            residual, x0, bounds=(lo, np.full(len(dims), np.inf)), xtol=1e-14, ftol=1e-14,
            gtol=1e-14, max_nfev=200,
        )  # fmt: skip
        x0 = fit.x
    flat = [n for n, x, low in zip(dims, x0, lo) if np.isfinite(low) and x <= 2 * low]
    if flat:  # the nearest place wants a length of zero (or less): not a design
        raise MechanismError(
            f"cannot move {point} there: {', '.join(flat)} would have to be zero or negative"
        )
    try:
        there = _place(build, dict(values, **dict(zip(dims, x0))), point, phi)
    except (MechanismError, ValueError, ZeroDivisionError) as exc:
        raise MechanismError(f"cannot move {point} there: {exc}") from exc
    miss = float(np.hypot(*(there - target)))
    if miss > 1e-6 * size and len(dims) >= 2:
        raise MechanismError(
            f"cannot move {point} there: its dimensions ({', '.join(dims)}) reach no closer "
            f"than {miss * 1e3:.3g} mm (it would cross to the other assembly branch)"
        )
    if np.max(np.abs(there - here)) == 0:
        raise MechanismError(f"cannot move {point} there: its dimensions do not move it")
    out = dict(state.values)
    out.update({n: float(f"{float(x):.12g}") for n, x in zip(dims, x0)})
    return out


def _references(state: State, point: str, dims) -> list:
    """For each of ``dims``: the point a length is measured from, ``"phase"`` for a crank's
    phase, None when there is no closed form."""
    if not _is_linkage(state):
        return [ref for _, ref in DRAGGABLE[state.kind.key][point]]
    g = state.kind.build(dict(state.values)).groups[_group_index(state, point)]
    roles = {v: k for k, v in g.params}
    out = []
    for name in dims:
        role = roles[name]
        if g.kind == "crank":
            out.append(g.about if role == "length" else "phase")
        elif g.kind == "RRR":
            out.append(g.first if role == "l1" else g.second)
        else:
            out.append(None)
    return out


def _crank_centre(state: State, point: str) -> str:
    return state.kind.build(dict(state.values)).groups[_group_index(state, point)].about


# ------------------------------------------------------------------------------ the draft
#: what a click on the drawing adds, and the step's name in the page's menu
STEP_TYPES = {
    "ground": "ground point",
    "crank": "crank (on a ground point)",
    "slider": "driving slider",
    "rrr": "RRR group (two links)",
    "rrp": "RRP group (rod and slider)",
    "rpr": "RPR group (link through a block)",
    "attach": "attached point",
}
_MOVING_NAMES = "ABCDEFGHJKLMNPRSTUVWXYZ"


def _r6(x: float) -> float:
    return float(f"{float(x):.6g}")


@dataclass(frozen=True)
class Draft:
    """A linkage built one step at a time (the page's "New linkage" mode): ground points and
    groups in the order of a linkage file, each added at a clicked place (SI, m) with its
    dimensions taken from the places the earlier points have at the input's start (a crank at
    0 rad, a driving slider at the start of its travel). Immutable: every step returns a new
    draft (so undo keeps the old one)."""

    steps: tuple[dict, ...] = ()
    name: str = "built in the page"
    output: str | None = None  # the linkage's main output point, when one was given

    # -------------------------------------------------------------- names
    @property
    def ground_points(self) -> tuple[str, ...]:
        return tuple(s["point"] for s in self.steps if s["type"] == "ground")

    @property
    def moving_points(self) -> tuple[str, ...]:
        return tuple(s["point"] for s in self.steps if s["type"] not in ("ground", "rpr"))

    @property
    def points(self) -> tuple[str, ...]:
        return self.ground_points + self.moving_points

    @property
    def has_driver(self) -> bool:
        return any(s["type"] in ("crank", "slider") for s in self.steps)

    def _new_ground(self) -> str:
        used, i = set(self.points), len(self.ground_points) + 1
        while f"O{i}" in used:
            i += 1
        return f"O{i}"

    def _new_point(self) -> str:
        used = set(self.points)
        for c in _MOVING_NAMES:
            if c not in used:
                return c
        return f"P{len(used)}"

    def _add(self, step: dict) -> Draft:
        return replace(self, steps=(*self.steps, step))

    def _known(self, point: str, what: str) -> np.ndarray:
        places = self.places()
        if point not in places:
            raise MechanismError(
                f"{what}: {point!r} is not a point of the linkage yet; its points: "
                + (", ".join(places) or "none (click to add a ground point first)")
            )
        return places[point]

    def _need_driver(self, what: str):
        if not self.has_driver:
            raise MechanismError(f"{what}: add the driver first (a crank or a driving slider)")

    # -------------------------------------------------------------- steps
    def ground(self, x: float, y: float) -> Draft:
        """A ground point (named O1, O2, ...) at (x, y), m."""
        _finite((x, y), "ground point")
        return self._add({"type": "ground", "point": self._new_ground(), "xy": [_r6(x), _r6(y)]})

    def crank(self, about: str, x: float, y: float) -> Draft:
        """The driving crank about the ground point ``about``, its pin at (x, y) at 0 rad."""
        what = "crank"
        if self.has_driver:
            raise MechanismError(f"{what}: the linkage has its driver already (one driver)")
        if about not in self.ground_points:
            raise MechanismError(
                f"{what}: it turns about a ground point "
                f"({', '.join(self.ground_points) or 'none yet'}), got {about!r}"
            )
        o = self._known(about, what)
        _finite((x, y), what)
        d = np.array([x, y]) - o
        length = float(np.hypot(*d))
        if not length > 0:
            raise MechanismError(f"{what}: click away from {about} (the crank's length is 0)")
        return self._add(
            {"type": "crank", "point": self._new_point(), "about": about, "length": _r6(length),
             "phase": _r6(math.atan2(d[1], d[0]))}
        )  # fmt: skip

    def slider(self, x: float, y: float, angle: float, travel: float) -> Draft:
        """The driver as a driving slider at (x, y) on a fixed guide at ``angle`` (rad),
        travelling ``travel`` (m) from there."""
        what = "driving slider"
        if self.has_driver:
            raise MechanismError(f"{what}: the linkage has its driver already (one driver)")
        _finite((x, y, angle, travel), what)
        if not travel > 0:
            raise MechanismError(f"{what}: the travel must be positive, got {travel:g} m")
        return self._add(
            {"type": "slider", "point": self._new_point(),
             "guide": {"through": [_r6(x), _r6(y)], "angle": _r6(angle)},
             "travel": [0.0, _r6(travel)]}
        )  # fmt: skip

    def rrr(self, first: str, second: str, x: float, y: float) -> Draft:
        """An RRR group: a new point at (x, y) joined by a link to each of ``first`` and
        ``second`` (its assembly branch the side of first -> second it is clicked on)."""
        what = "RRR group"
        self._need_driver(what)
        if first == second:
            raise MechanismError(f"{what}: its two points must differ, got {first!r} twice")
        p, q = self._known(first, what), self._known(second, what)
        _finite((x, y), what)
        c = np.array([x, y])
        side = (q[0] - p[0]) * (c[1] - p[1]) - (q[1] - p[1]) * (c[0] - p[0])
        return self._add(
            {"type": "rrr", "point": self._new_point(),
             "first": [first, _r6(np.hypot(*(c - p)))], "second": [second, _r6(np.hypot(*(c - q)))],
             "branch": 1 if side >= 0 else -1}
        )  # fmt: skip

    def rrp(self, rod_from: str, x: float, y: float, angle: float) -> Draft:
        """An RRP group: a slider at (x, y) on a fixed guide through there at ``angle`` (rad),
        joined by a rod to ``rod_from``."""
        what = "RRP group"
        self._need_driver(what)
        p = self._known(rod_from, what)
        _finite((x, y, angle), what)
        c = np.array([x, y])
        u = np.array([math.cos(angle), math.sin(angle)])
        ahead = float((c - p) @ u)
        return self._add(
            {"type": "rrp", "point": self._new_point(),
             "rod": [rod_from, _r6(np.hypot(*(c - p)))],
             "guide": {"through": [_r6(x), _r6(y)], "angle": _r6(angle)},
             "branch": 1 if ahead >= 0 else -1}
        )  # fmt: skip

    def rpr(self, about: str, through: str) -> Draft:
        """An RPR group: a link turning about ``about`` through a block pinned at ``through``."""
        what = "RPR group"
        self._need_driver(what)
        self._known(about, what)
        self._known(through, what)
        if about == through:
            raise MechanismError(f"{what}: about and through must differ, got {about!r} twice")
        link = f"{about}{through}"
        used = {s.get("link") for s in self.steps}
        while link in used:
            link += "_"
        return self._add({"type": "rpr", "link": link, "about": about, "through": through})

    def attach(self, origin: str, axis: str, x: float, y: float) -> Draft:
        """A point at (x, y) rigid with the link of ``origin`` and ``axis`` (its offsets
        along origin -> axis and to its left)."""
        what = "attached point"
        self._need_driver(what)
        if origin == axis:
            raise MechanismError(f"{what}: its link's two points must differ, got {origin!r}")
        p, q = self._known(origin, what), self._known(axis, what)
        _finite((x, y), what)
        u = (q - p) / max(float(np.hypot(*(q - p))), 1e-300)
        d = np.array([x, y]) - p
        return self._add(
            {"type": "attach", "point": self._new_point(), "on": [origin, axis],
             "along": _r6(d @ u), "left": _r6(u[0] * d[1] - u[1] * d[0])}
        )  # fmt: skip

    def delete_last(self) -> Draft:
        """The draft without its last step (the same empty draft when it has none)."""
        return replace(self, steps=self.steps[:-1])

    # -------------------------------------------------------------- any step
    @property
    def elements(self) -> tuple[str, ...]:
        """Every step's name in order: its point (an RPR group: its link)."""
        return tuple(_name(s) for s in self.steps)

    def index(self, element: str) -> int:
        """The step of ``element`` (a point, or an RPR group's link)."""
        names = self.elements
        if element not in names:
            raise MechanismError(
                f"{element!r} is not an element of the linkage; its elements: "
                + (", ".join(names) or "none")
            )
        return names.index(element)

    def dependents(self, element: str) -> tuple[str, ...]:
        """The elements placed from ``element``, directly or through others, in order."""
        i = self.index(element)
        gone = {element}
        out = []
        for s in self.steps[i + 1 :]:
            if _uses(s) & gone:
                gone.add(_name(s))
                out.append(_name(s))
        return tuple(out)

    def delete(self, element: str) -> tuple[Draft, tuple[str, ...]]:
        """The draft without ``element`` and the elements that depend on it, and the names
        of those dependents (the elements after it that do not use it stay, named as they
        were)."""
        self.index(element)
        deps = self.dependents(element)
        gone = {element, *deps}
        steps = tuple(s for s in self.steps if _name(s) not in gone)
        out = self.output if self.output not in gone else None
        return replace(self, steps=steps, output=out), deps

    def move(self, element: str, x: float, y: float) -> Draft:
        """The draft with ``element`` placed at (x, y) (m) at the input's start: a ground
        point there; a moving point's dimensions (a crank's length and phase, an RRR joint's
        links and branch, an RRP slider's rod and guide, an attached point's offsets, a
        driving slider's guide) taken from the earlier points' places, as when it was added.
        The elements after it keep their dimensions (whether they still assemble is
        :meth:`check`'s to say)."""
        i = self.index(element)
        s = self.steps[i]
        t = s["type"]
        if t == "rpr":
            raise MechanismError(
                f"{element} (an RPR group) has no place of its own: move its points instead"
            )
        _finite((x, y), f"moving {element}")
        before = replace(self, steps=self.steps[:i])
        if t == "ground":
            new = dict(s, xy=[_r6(x), _r6(y)])
        else:
            if t == "crank":
                added = before.crank(s["about"], x, y)
            elif t == "slider":
                g = s["guide"]
                angle = g.get("angle", 0.0)
                travel = s["travel"]
                if not isinstance(angle, int | float):
                    raise MechanismError(f"{element}: its guide's angle is named: edit its field")
                added = before.slider(x, y, angle, 1.0)
                new_guide = dict(g, through=added.steps[-1]["guide"]["through"])
                added = replace(
                    added, steps=(*added.steps[:-1], dict(s, guide=new_guide, travel=travel))
                )
            elif t == "rrr":
                added = before.rrr(s["first"][0], s["second"][0], x, y)
            elif t == "rrp":
                angle = s["guide"].get("angle", 0.0)
                if not isinstance(angle, int | float):
                    raise MechanismError(f"{element}: its guide's angle is named: edit its field")
                added = before.rrp(s["rod"][0], x, y, angle)
            elif t == "attach":
                added = before.attach(s["on"][0], s["on"][1], x, y)
            else:
                raise MechanismError(f"{element}: a {t} step cannot be moved by a click")
            new = dict(added.steps[-1], point=element)
            for key in ("name",):  # a named step keeps its name
                if key in s:
                    new[key] = s[key]
        return replace(self, steps=(*self.steps[:i], new, *self.steps[i + 1 :]))

    def dims_of(self, element: str) -> dict[str, tuple[float, str]]:
        """The dimensions ``element``'s step holds, by the names :meth:`with_values` takes:
        ``{name: (SI value, "m" or "rad")}`` (a dimension given by a formula is left out)."""
        s = self.steps[self.index(element)]
        t, p = s["type"], s.get("point")
        pairs: list[tuple[str, Any, str]] = []
        if t == "ground":
            pairs += [(f"{p}_x", s["xy"][0], "m"), (f"{p}_y", s["xy"][1], "m")]
        elif t == "crank":
            pairs += [(f"{s['about']}{p}", s["length"], "m"), ("phase", s.get("phase", 0.0), "rad")]
        elif t == "rrr":
            pairs += [(f"{q}{p}", v, "m") for q, v in (s["first"], s["second"])]
        elif t == "rrp":
            pairs.append((f"{s['rod'][0]}{p}", s["rod"][1], "m"))
        elif t == "attach":
            pairs += [(f"{p}_{k}", s.get(k, 0.0), "m") for k in ("along", "left")]
        elif t == "rpr":
            pairs.append((f"{s['link']}_offset", s.get("offset", 0.0), "m"))
        if t in ("rrp", "slider"):
            g = s["guide"]
            through = g.get("through")
            if isinstance(through, list) and not all(isinstance(c, str) for c in through):
                pairs += [(f"{p}_guide_x", through[0], "m"), (f"{p}_guide_y", through[1], "m")]
            pairs.append((f"{p}_guide_angle", g.get("angle", 0.0), "rad"))
        out = {}
        for name, v, unit in pairs:
            if isinstance(v, dict) and "name" in v and "value" in v:  # a named dimension
                name, v = str(v["name"]), v["value"]
            if isinstance(v, int | float) and not isinstance(v, bool):
                out[name] = (float(v), unit)
        return out

    # -------------------------------------------------------------- the linkage
    def tables(self) -> dict:
        """The linkage-file tables (``[linkage]``, ``[ground]``, ``[[group]]``, SI numbers)."""
        ground = {s["point"]: list(s["xy"]) for s in self.steps if s["type"] == "ground"}
        groups = [{k: v for k, v in s.items()} for s in self.steps if s["type"] != "ground"]
        head = {"name": self.name}
        if self.output and self.output in self.points:
            head["output"] = self.output
        out = {"linkage": head, "ground": ground, "group": groups}
        return {k: v for k, v in out.items() if v}

    def toml(self) -> str:
        """The linkage file this draft is (``mechsynth.synthesis.load_linkage`` reads it)."""
        return f"# a linkage {self.name} (SI: m, rad); groups in solving order\n" + to_toml(
            self.tables()
        )

    def check(self):
        """``(linkage, None)`` when the draft is a linkage that assembles over its whole
        cycle, else ``(None, the library's message)``."""
        if not self.ground_points:
            return None, "click on the drawing to add a ground point"
        if not self.has_driver:
            return None, "add the driver: a crank on a ground point, or a driving slider"
        if len(self.steps) - len(self.ground_points) < 2:
            return None, "add a group (RRR, RRP or RPR) to the driver"
        from ..synthesis.linkage_file import linkage_from_data

        try:
            lk = linkage_from_data(self.tables())
            design, message = State.of(self.kind()).check_design()
        except (MechanismError, ValueError) as exc:
            return None, str(exc)
        return (None, message) if message else (lk, None)

    def kind(self):
        """The page's entry for this draft (a linkage with its dimensions)."""
        title = f"Linkage {self.name}"
        if self.name != Draft.name:  # a linkage opened or found elsewhere, built on here
            title += ", edited in the page"
        kind = linkage_kind(self.tables(), title=title)
        kind.trace = tuple(p for p in self.moving_points[-1:])
        return kind

    def places(self) -> dict[str, np.ndarray]:
        """Every point's place (m) at the input's start, as far as the draft solves."""
        from ..synthesis.linkage_file import linkage_from_data
        from ..synthesis.problem_file import parse_quantity

        out = {
            s["point"]: np.array([parse_quantity(c, "ground point", "m") for c in s["xy"]])
            for s in self.steps
            if s["type"] == "ground" and not any(isinstance(c, dict) for c in s["xy"])
        }
        groups = [s for s in self.steps if s["type"] != "ground"]
        if not groups:
            return out
        try:
            lk = linkage_from_data(self.tables())
            sk = lk.sketch(np.array([0.0 if lk.periodic else lk.input_range[0]]))
        except (MechanismError, ValueError):
            return out
        for p, (x, y) in sk.points.items():
            out[p] = np.array([float(np.ravel(x)[0]), float(np.ravel(y)[0])])
        return out

    def with_values(self, values: Mapping[str, float]) -> Draft:
        """The draft with the dimensions of the linkage it builds set to ``values`` (SI; by
        their parameter names: a named dimension's, else the default of
        :class:`~mechsynth.kinematics.Linkage`), so that a dimension changed on the page is in
        the file."""

        def v(old, name):
            if isinstance(old, dict) and "name" in old:  # {name = "r", value = ...}
                key = str(old["name"])
                return dict(old, value=_r6(values[key])) if key in values else old
            return _r6(values[name]) if name in values else old

        steps = []
        for s in self.steps:
            s = json.loads(json.dumps(s))
            t, p = s["type"], s.get("point")
            if t == "ground":
                s["xy"] = [v(s["xy"][0], f"{p}_x"), v(s["xy"][1], f"{p}_y")]
            elif t == "crank":
                s["length"] = v(s["length"], f"{s['about']}{p}")
                s["phase"] = v(s.get("phase", 0.0), "phase")
            elif t == "rrr":
                s["first"][1] = v(s["first"][1], f"{s['first'][0]}{p}")
                s["second"][1] = v(s["second"][1], f"{s['second'][0]}{p}")
            elif t == "rrp":
                s["rod"][1] = v(s["rod"][1], f"{s['rod'][0]}{p}")
            elif t == "attach":
                s["along"] = v(s.get("along", 0.0), f"{p}_along")
                s["left"] = v(s.get("left", 0.0), f"{p}_left")
            elif t == "rpr":
                offset = v(s.get("offset", 0.0), f"{s['link']}_offset")
                if offset or "offset" in s:
                    s["offset"] = offset
            if t in ("rrp", "slider"):
                g = s["guide"]
                through = g.get("through")
                if isinstance(through, list) and not all(
                    isinstance(c, str) and c.isidentifier() for c in through
                ):  # coordinates (a pair of point names is a link)
                    g["through"] = [
                        v(through[0], f"{p}_guide_x"),
                        v(through[1], f"{p}_guide_y"),
                    ]
                if "offset" in g or f"{p}_guide_offset" in values:
                    g["offset"] = v(g.get("offset", 0.0), f"{p}_guide_offset")
                g["angle"] = v(g["angle"], f"{p}_guide_angle")
            steps.append(s)
        return replace(self, steps=tuple(steps))

    @classmethod
    def from_tables(cls, tables: Mapping) -> Draft:
        """The draft of a linkage's tables (``[linkage]``, ``[ground]``, ``[[group]]``, as in
        a linkage file), to go on building it."""
        tables = json.loads(json.dumps(dict(tables)))
        steps = [
            {"type": "ground", "point": str(k), "xy": list(xy)}
            for k, xy in (tables.get("ground") or {}).items()
        ]
        steps += [dict(g) for g in tables.get("group") or []]
        head = tables.get("linkage") or {}
        return cls(
            steps=tuple(steps), name=str(head.get("name", "from a file")), output=head.get("output")
        )


def _name(step: dict) -> str:
    return str(step["link"] if step["type"] == "rpr" else step["point"])


def _uses(step: dict) -> set[str]:
    """The names of the points a step is placed from."""
    t = step["type"]
    out: set[str] = set()
    if t == "crank":
        out.add(step["about"])
    elif t == "rrr":
        out |= {step["first"][0], step["second"][0]}
    elif t == "rrp":
        out.add(step["rod"][0])
    elif t == "attach":
        out |= set(step["on"])
    elif t == "rpr":
        out |= {step["about"], step["through"]}
    guide = step.get("guide") if t in ("rrp", "slider") else None
    if isinstance(guide, dict):
        through = guide.get("through")
        if isinstance(through, list) and all(isinstance(c, str) for c in through):
            out |= set(through)  # a guide along a link
        elif isinstance(through, str):
            out.add(through)
    return {str(n) for n in out}


def _finite(values, what):
    if not all(isinstance(x, int | float) and math.isfinite(x) for x in values):
        raise MechanismError(f"{what}: the place and dimensions must be numbers, got {values}")


# ------------------------------------------------------------------------------ the URL
#: the optimizers the page offers (its Method menu)
METHODS = ("ipopt", "slsqp", "de")


def to_query(state: State, draft: Draft | None = None) -> str:
    """The page's state as a URL query: ``mechanism`` (a built-in's key, or ``file`` with the
    linkage's tables packed in ``linkage``), ``units``, ``speed`` (SI) and each dimension's SI
    value by name; then the problem (``problem=1``): ``objective``, ``sense``, one
    ``constraint`` per constraint (as typed), one ``vary=name:lower:upper`` per variable (SI;
    bounds that are not numbers yet are left out), ``method`` and ``starts``."""
    from urllib.parse import urlencode

    k = state.kind
    items: list[tuple[str, str]] = []
    builtin = k.key in kind_names() and (k.file_data is None or k.title == _title(k.key))
    if builtin:
        items.append(("mechanism", k.key))
    else:
        if k.file_data is None:
            raise MechanismError(f"{k.title} has no form the URL can carry")
        packed = zlib.compress(json.dumps(k.file_data, separators=(",", ":")).encode(), 9)
        items += [
            ("mechanism", "file"),
            ("title", k.title),
            ("linkage", base64.urlsafe_b64encode(packed).decode().rstrip("=")),
        ]
    items.append(("units", state.units))
    items.append(("speed", "0" if state.speed is None else repr(float(state.speed))))
    items += [(d.name, repr(float(state.values[d.name]))) for d in k.dims]
    items += [("problem", "1"), ("objective", state.objective), ("sense", state.sense)]
    items += [("constraint", c) for c in state.constraints]
    items += [
        ("vary", f"{name}:{float(lo)!r}:{float(hi)!r}")
        for name, (lo, hi) in state.vary.items()
        if math.isfinite(lo) and math.isfinite(hi)
    ]
    items += [("method", state.method), ("starts", str(int(state.starts)))]
    return urlencode(items)


@functools.cache
def _title(key: str) -> str:
    """A built-in mechanism's title (built once: a linkage's takes milliseconds)."""
    return KINDS[key].title


def state_from_query(args: Mapping[str, Any], units: str | None = None) -> State | None:
    """The state a URL query carries (``args``: ``{name: value or [values]}``, str or bytes,
    as :func:`to_query` wrote them), or None when it carries none. Raises MechanismError
    naming the parameter that is not valid."""

    def many(key) -> list[str]:
        v = args.get(key, [])
        v = list(v) if isinstance(v, list | tuple) else [v]
        return [x.decode() if isinstance(x, bytes) else str(x) for x in v]

    def one(key):
        return many(key)[-1]

    if "mechanism" not in args:
        return None
    key = one("mechanism")
    u = one("units") if "units" in args else (units or "si")
    if key == "file":
        if "linkage" not in args:
            raise MechanismError("the URL's mechanism=file needs its linkage=... (the tables)")
        text = one("linkage")
        try:
            raw = zlib.decompress(base64.urlsafe_b64decode(text + "=" * (-len(text) % 4)))
            tables = json.loads(raw)
        except (ValueError, zlib.error) as exc:
            raise MechanismError(f"the URL's linkage=... is not a packed linkage ({exc})") from exc
        title = one("title") if "title" in args else "Linkage from the URL"
        state = State.of(linkage_kind(tables, title=title), u)
    elif key in kind_names():
        state = State.default(key, u)
    else:
        raise MechanismError(
            f"the URL's mechanism must be one of {', '.join(kind_names())} or file, got {key!r}"
        )
    state.display  # noqa: B018 -- the units are checked here
    for d in state.kind.dims:
        if d.name in args:
            state.values[d.name] = _number(one(d.name), d.name)
    if "speed" in args:
        s = _number(one("speed"), "speed")
        if s < 0:
            raise MechanismError(f"the URL's speed must not be negative, got {s:g}")
        state.speed = None if s == 0 else s
    bad = state.field_messages()
    if bad:
        raise MechanismError("the URL's " + next(iter(bad.values())))
    if "problem" in args:
        _problem_from_query(state, many, one, args)
    return state


def _problem_from_query(state: State, many, one, args) -> None:
    """The problem a URL carries (see :func:`to_query`) set on ``state``; raises
    MechanismError naming the parameter that is not valid."""
    from ..synthesis.problem_file import parse_constraint, parse_measure

    if "objective" in args:
        text = one("objective").strip()
        try:
            parse_measure(text)
        except (MechanismError, ValueError) as exc:
            raise MechanismError(f"the URL's objective: {exc}") from None
        state.objective = text
    if "sense" in args:
        sense = one("sense")
        if sense not in ("minimize", "maximize"):
            raise MechanismError(f"the URL's sense must be minimize or maximize, got {sense!r}")
        state.sense = sense
    constraints = [c.strip() for c in many("constraint") if c.strip()]
    for c in constraints:
        try:
            parse_constraint(c)
        except (MechanismError, ValueError) as exc:
            raise MechanismError(f"the URL's constraint: {exc}") from None
    state.constraints = constraints
    vary = {}
    names = [d.name for d in state.kind.dims]
    for text in many("vary"):
        parts = text.split(":")
        if len(parts) != 3 or parts[0] not in names:
            raise MechanismError(
                f"the URL's vary must be name:lower:upper (SI) with a name of "
                f"{', '.join(names)}, got {text!r}"
            )
        name = parts[0]
        vary[name] = (_number(parts[1], f"{name} lower bound"),
                      _number(parts[2], f"{name} upper bound"))  # fmt: skip
    state.vary = vary
    bad = state.bound_messages()
    if bad:
        raise MechanismError("the URL's bounds: " + next(iter(bad.values())))
    if "method" in args:
        method = one("method")
        if method not in METHODS:
            raise MechanismError(
                f"the URL's method must be one of {', '.join(METHODS)}, got {method!r}"
            )
        state.method = method
    if "starts" in args:
        text = one("starts")
        try:
            starts = int(text)
        except ValueError:
            raise MechanismError(f"the URL's starts must be a whole number, got {text!r}") from None
        if not 1 <= starts <= 1000:
            raise MechanismError(f"the URL's starts must be 1 to 1000, got {starts}")
        state.starts = starts


def _number(text: str, what: str) -> float:
    try:
        x = float(text)
    except ValueError:
        raise MechanismError(f"the URL's {what} must be a number, got {text!r}") from None
    if not math.isfinite(x):
        raise MechanismError(f"the URL's {what} must be a finite number, got {text!r}")
    return x
