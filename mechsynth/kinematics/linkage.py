"""General planar linkages: ground points, one driver and groups added in solving order.

A :class:`Linkage` is written the way an engineer sketches one: fix the ground points, add the
crank, then each group in the order it can be solved, naming the points it joins::

    lk = (ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)})
          .crank("A", about="O", length=0.03)
          .rrr("B", ("A", 0.12), ("D", 0.08))
          .attach("K", on=("D", "B"), along=-0.05)
          .rrp("N", ("K", 0.10), guide=((0.12, 0.0), ms.deg(57))))

Every dimension is a named parameter (``lk.parameters``; default names such as ``"AB"`` for the
length of the link A-B, ``"D_x"`` for a ground coordinate, ``"N_guide_angle"``); a linkage is an
immutable value, every builder returns a new one, and ``lk.with_parameters(AB=0.13)`` (or
``lk(AB=0.13)``) gives the same linkage with other dimensions. Parameters may be numbers, numpy
arrays (a batch of designs: give them a trailing axis of length 1) or CasADi symbols, and the
motion is computed by the blocks of :mod:`~mechsynth.kinematics.blocks`, so one definition serves
numpy analysis, CasADi gradients, optimization (:class:`~mechsynth.synthesis.Problem`), charts
(:func:`~mechsynth.synthesis.sweep`) and kinetostatics (:meth:`Linkage.force_model`).

Conventions (see ``docs/linkages.md``)
--------------------------------------
* SI units; angles in rad from +x, counter-clockwise; the crank angle ``phi`` drives (analogs are
  derivatives with respect to it); the crank's link angle is ``phi + phase``. A linkage driven
  by a slider (:meth:`Linkage.slider`) takes the slider's displacement ``s`` (m) as its input
  instead: analogs per metre, speeds in m/s, a cycle over its ``travel``.
* ``branch=+1`` of an RRR group puts its point to the left of the directed line first -> second
  point; of an RRP group, the slider ahead of the foot of the rod's start along the guide
  direction; of an RPR group, the block on the positive axis of the link; of a follower, the
  outermost contact ahead along the guide.
* Link angles: the crank and the links of dyads point from the point they hang on to the new
  point (``"AB"``: A -> B); a slider's angle is its guide's direction; an RPR link's angle is its
  axis direction.
* A point rigidly attached to a body lies ``along`` its frame's x axis and ``left`` of it; the
  frame given as ``("D", "B")`` has its origin at D and its x axis along D -> B.
"""

from __future__ import annotations

import math
import numbers
import re
import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import MechanismError
from ..validate import finite
from . import ops
from .curves import Curve
from .linkage_groups import (
    FRAME,
    AttachGroup,
    Body,
    CrankGroup,
    FollowerGroup,
    Frame,
    Group,
    Guide,
    Joint,
    Param,
    RPRGroup,
    RRPGroup,
    RRRGroup,
    SliderDriverGroup,
    _State,
)
from .mechanism import Drawable, check_finite, check_length, guard_motion, speed_pair
from .tracks import Motion, PointJet, PointTrack, _as_tracks

__all__ = ["Linkage", "Param", "Topology", "GuideLine", "Profile"]

#: parameter kinds and what they must be
KINDS = {
    "length": "a positive length in m",
    "coordinate": "a finite coordinate in m",
    "offset": "a finite signed distance in m",
    "angle": "a finite angle in rad",
    "radius": "a non-negative radius in m",
}

#: crank angles of the numeric assembly screen (feasibility_constraints) and of the time ratio
_SCREEN_ANGLES = 360
_SPAN_SAMPLES = 72


def _check_value(name, kind, value):
    if ops.is_symbolic(value):
        return value
    if kind == "length":
        return check_length(name, value)
    value = check_finite(name, value)
    if kind == "radius" and np.any(np.asarray(value) < 0.0):
        raise MechanismError(f"{name} must not be negative (a radius in m), got {value}")
    return value


def _branch(value, what):
    # an int, not 1.0 or True (which equal 1): a branch is a sign, not a number that rounds
    if (
        not isinstance(value, (int, np.integer))
        or isinstance(value, (bool, np.bool_))
        or value not in (1, -1)
    ):
        raise MechanismError(f"{what}: branch must be +1 or -1 (an integer), got {value!r}")
    return int(value)


@dataclass(frozen=True)
class GuideLine:
    """A slider's straight guide, for drawings: the line through ``through`` at ``angle``.

    ``carrier`` is ``"frame"`` for a fixed guide, else the body that carries it; ``line(motion)``
    gives its point and direction at every angle of a motion.
    """

    slider: str
    carrier: str
    group: Any = field(repr=False)
    linkage: Any = field(repr=False)

    def line(self, motion: Motion):
        """``(x, y, angle)`` of the guide at the angles of ``motion`` (m, m, rad)."""
        st = self.linkage._solve(np.asarray(motion.phi, dtype=float), strict=False)
        from .linkage_groups import _guide_line

        g, theta, _ = _guide_line(st, self.group.guide, self.group)
        zero = 0.0 * st.points[self.group.key].x
        return g.x + zero, g.y + zero, theta.value + zero


@dataclass(frozen=True)
class Profile:
    """A cam profile, for drawings: the ``curve`` in the frame of ``body`` (origin at the point
    ``origin``, x axis along ``origin -> axis``, or the body's angle when ``axis`` is None)."""

    follower: str
    body: str
    origin: str
    axis: str | None
    curve: Curve
    values: dict

    def local(self, n: int = 200):
        """``(x, y)`` of ``n`` points of the curve in its frame (m)."""
        lo, hi = self.curve.domain
        sigma = np.linspace(lo, hi, int(n))
        x, y, *_ = self.curve.jet(sigma, self.values)
        return np.broadcast_to(x, sigma.shape), np.broadcast_to(y, sigma.shape)

    def world(self, motion: Motion, n: int = 200):
        """``(X, Y)`` arrays of shape ``angles x n``: the curve placed at every angle."""
        x, y = self.local(n)
        o = motion.points[self.origin]
        if self.axis is None:
            th = np.asarray(motion.links[self.body].angle, dtype=float)
        else:
            q = motion.points[self.axis]
            th = np.arctan2(np.asarray(q.y) - o.y, np.asarray(q.x) - o.x)
        c, s = np.cos(th)[..., None], np.sin(th)[..., None]
        ox, oy = np.asarray(o.x)[..., None], np.asarray(o.y)[..., None]
        return ox + c * x - s * y, oy + s * x + c * y


@dataclass(frozen=True)
class Topology:
    """What a drawing (or a reader) needs to know about a linkage's structure.

    Attributes
    ----------
    ground : ``{point: (x, y)}`` of the ground points (m).
    bodies : ``{name: Body}`` of the moving links, in solving order; ``Body.base`` is its frame's
        origin and ``points`` below lists every point it joins.
    points : ``{body: (point, ...)}``: the points each moving body joins (pins, attached points).
    joints : every kinematic pair (:class:`~mechsynth.kinematics.linkage_groups.Joint`).
    guides : ``{slider: GuideLine}`` of the sliders on straight guides.
    profiles : ``{follower: Profile}`` of the cam profiles.
    driver : the driver's body: the crank, or the block of a driving slider.
    """

    ground: dict
    bodies: dict
    points: dict
    joints: tuple
    guides: dict
    profiles: dict
    driver: str


_KERNEL_MODULE: list = [None]  # linkage_kernels, once imported


def _kernels():
    """The ``linkage_kernels`` module (imported once: a function-level import costs a
    microsecond a call)."""
    lkk = _KERNEL_MODULE[0]
    if lkk is None:
        from . import linkage_kernels as lkk

        _KERNEL_MODULE[0] = lkk
    return lkk


#: seconds of CPU a structure's kernel costs this process, per backend
#: (``linkage_kernels.kernel_backend``): ``"build"``, its first build (the C compiler's or
#: numba's), and ``"load"``, its load from the disk cache when this machine built it before
#: (measured on this 2-core machine: ``benchmarks/bench_sweep_switch.py``). A structure's
#: one-design motions run on the model until their summed time reaches this price
#: (:meth:`Linkage.motion`, ``kernel=None``): a process never spends on the kernel more than
#: it has spent on the model, and one that keeps calling gains the kernel's 3-4 x from then on.
KERNEL_COSTS = {
    "c": {"build": 0.66, "load": 0.0047},
    "numba": {"build": 5.6, "load": 0.60},
}

_TALLY: dict = {}  # id(groups) -> [groups, seconds on the model, the kernel's price]


def _kernel_price(linkage, lkk) -> float:
    """Seconds of model time after which ``linkage``'s structure asks for its kernel:
    :data:`KERNEL_COSTS` of this process's backend, a load when the disk cache holds the
    kernel (infinite when there is no backend or no kernel for it)."""
    from .linkage_groups import FollowerGroup

    backend = lkk.kernel_backend(probe=False)
    if backend is None or any(isinstance(g, FollowerGroup) for g in linkage.groups):
        return math.inf
    costs = KERNEL_COSTS[backend]
    return costs["load"] if lkk.is_compiled(linkage) else costs["build"]


@dataclass(frozen=True)
class _Plan:
    """What a motion reads of a linkage's structure, derived once per structure (when the
    linkage is made) instead of at every motion.

    Attributes
    ----------
    crank : the driver's point (its track gives the motion's shape).
    frame_points : the ground points (their jets hold numbers: made tracks of that shape).
    main_slider : the output group's slider or block (``motion.slider``), or None.
    out_key : the output group's key (its pressure angle is ``motion.pressure_angle``).
    """

    crank: str
    frame_points: tuple[str, ...]
    main_slider: str | None
    out_key: str

    @classmethod
    def of(cls, lk: Linkage) -> _Plan:
        out_group = lk._group_of(lk.default_output)
        main = getattr(out_group, "slider", None) or getattr(out_group, "block", None)
        frame = tuple(p for p, _, _ in lk._ground)
        return cls(lk._groups[0].key, frame, main, out_group.key)


class Linkage(Drawable):
    """A planar linkage: ground points, a driver (a crank or a driving slider) and groups in
    solving order.

    Parameters
    ----------
    ground : ``{name: (x, y)}`` ground points (m); a coordinate may be a :class:`Param`.
    name : a name for reports and charts.

    Examples
    --------
    A four-bar with an extra rod and slider (the six-link of paper 001):

    >>> import mechsynth as ms
    >>> lk = (ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)})
    ...       .crank("A", about="O", length=0.03)
    ...       .rrr("B", ("A", 0.12), ("D", 0.08))
    ...       .attach("K", on=("D", "B"), along=-0.05)
    ...       .rrp("N", ("K", 0.10), guide=((0.12, 0.0), ms.deg(57))))
    >>> list(lk.parameters)[4:10]
    ['OA', 'phase', 'AB', 'DB', 'K_along', 'K_left']
    >>> m = lk.motion(ms.cycle(360), speed=ms.rpm(1500))
    >>> m.sliders["N"].velocity.shape, round(float(ms.to_deg(m.pressure_angles["N"].max())), 2)
    ((360,), 13.16)
    """

    def __init__(self, ground: Mapping[str, Any] | None = None, name: str = "linkage"):
        if not isinstance(name, str) or not name.strip():
            raise MechanismError(f"a linkage's name must be a non-empty string, got {name!r}")
        if ground is not None and not isinstance(ground, Mapping):
            raise MechanismError(
                "ground must be a dict {point name: (x, y)} of the frame's points, got "
                f"{ground!r} (a {type(ground).__name__})"
            )
        self._name = name
        self._ground: tuple = ()
        self._groups: tuple = ()
        self._values: dict = {}
        self._kinds: dict = {}
        self._roles: dict = {}
        self._output: str | None = None
        self._bodies: dict = {}
        self._owner: dict = {}
        self._members: dict = {}
        for point, xy in (ground or {}).items():
            self._add_ground(point, xy)
        self._freeze()

    # ------------------------------------------------------------------ immutability
    def __setattr__(self, key, value):
        if self.__dict__.get("_frozen", False):
            raise AttributeError("a Linkage is immutable: its builders return new linkages")
        object.__setattr__(self, key, value)

    def _copy(self) -> Linkage:
        """An unfrozen copy for a builder to extend (then ``_freeze``)."""
        new = object.__new__(Linkage)
        for k, v in self.__dict__.items():
            if k != "_frozen":
                new.__dict__[k] = dict(v) if isinstance(v, dict) else v
        return new

    def _freeze(self) -> Linkage:
        """Derive the structure (bodies, owners of points, members of bodies) and freeze."""
        bodies: dict[str, Body] = {}
        owner: dict[str, str] = {p: FRAME for p, _, _ in self._ground}
        members: dict[str, list[str]] = {}
        for g in self._groups:
            for b in g.bodies():
                bodies[b.name] = b
                members[b.name] = [x for x in (b.base, b.axis) if x]
            new = g.new_point()
            if new is not None:
                point, body = new
                owner[point] = body
                if point not in members[body]:
                    members[body].append(point)
        self._bodies, self._owner = bodies, owner
        self._members = {k: tuple(v) for k, v in members.items()}
        # the (designs x angles) arrays a motion holds at its peak, for its memory guard
        self._motion_arrays = 12 * (len(self.points) + len(bodies)) + 8
        values = self._values.values()
        self._symbolic = ops.is_symbolic(*values)
        # what the memory guard of a motion reads: no parameter of a design of numbers is a
        # batch (the guard's loop over them left out)
        plain = all(type(x) is float or type(x) is int for x in values)
        self._guarded = {} if plain else self._values
        self._floats = all(type(x) is float for x in values)  # one design of numbers
        self._plan = _Plan.of(self) if self._groups else None
        self._frozen = True
        return self

    def _param(self, raw, default_name, kind, role):
        """Register one dimension; returns its parameter name."""
        if isinstance(raw, Param):
            name, value = raw.name, raw.value
        else:
            name, value = default_name, raw
        if not name.isidentifier():
            raise MechanismError(f"parameter name {name!r} must be an identifier")
        if name in self._values:
            raise MechanismError(
                f"parameter {name!r} ({role}) is already {self._roles[name]}: name it with "
                f"Param('...', value)"
            )
        if isinstance(value, bool) or not (
            isinstance(value, numbers.Real) or hasattr(value, "shape") or ops.is_symbolic(value)
        ):
            raise MechanismError(f"{role} ({name}) must be a number, got {value!r}")
        self._values[name] = _check_value(name, kind, value)
        self._kinds[name] = kind
        self._roles[name] = role
        return name

    def _add_ground(self, point, xy):
        self._check_new_point(point)
        try:
            x, y = xy
        except (TypeError, ValueError):
            raise MechanismError(f"ground point {point!r}: expected (x, y), got {xy!r}") from None
        xp = self._param(x, f"{point}_x", "coordinate", f"x of ground point {point}")
        yp = self._param(y, f"{point}_y", "coordinate", f"y of ground point {point}")
        self._ground = self._ground + ((point, xp, yp),)

    def _check_new_point(self, point):
        if not isinstance(point, str) or not point.isidentifier():
            raise MechanismError(f"a point name must be an identifier, got {point!r}")
        if point in self.points:
            raise MechanismError(
                f"point {point!r} exists already; points: {', '.join(self.points)}"
            )

    def _known_point(self, point, what):
        if point not in self.points:
            known = ", ".join(self.points) or "none yet"
            raise MechanismError(f"{what}: unknown point {point!r}; known points: {known}")
        return point

    def _check_new_body(self, name):
        if not isinstance(name, str) or not name.isidentifier():
            raise MechanismError(f"a link name must be an identifier, got {name!r}")
        if name in self._bodies or name == FRAME:
            raise MechanismError(f"link {name!r} exists already; name it with link=...")
        return name

    def _free_body(self, name):
        """``name``, or ``name_2``, ... when a body has that name already."""
        base, k = name, 2
        while name in self._bodies:
            name, k = f"{base}_{k}", k + 1
        return name

    def _with(self, group: Group) -> Linkage:
        """This (unfrozen) copy with ``group`` appended, frozen."""
        self._groups = self._groups + (group,)
        return self._freeze()

    def _frame(self, on, what) -> Frame:
        """A body frame from ``on``: a body name, or a pair of points of one body."""
        if isinstance(on, str):
            if on not in self._bodies:
                raise MechanismError(
                    f"{what}: unknown link {on!r}; links: {', '.join(self._bodies) or 'none'}"
                )
            return Frame(on, self._bodies[on].base, None)
        try:
            p, q = on
        except (TypeError, ValueError):
            raise MechanismError(
                f"{what}: 'on' must be a link name or a pair of points (origin, axis point) of "
                f"one link, got {on!r}"
            ) from None
        self._known_point(p, what)
        self._known_point(q, what)
        if p == q:
            raise MechanismError(
                f"{what}: the frame's origin and axis point must differ, got {p!r} twice"
            )
        for name, pts in self._members.items():
            if p in pts and q in pts:
                return Frame(name, p, q)
        raise MechanismError(
            f"{what}: points {p!r} and {q!r} are not on one moving link "
            f"(links and their points: "
            + "; ".join(f"{k}: {', '.join(v)}" for k, v in self._members.items())
            + ")"
        )

    def _guide(self, guide, offset, key, what):
        """Register a guide's parameters; returns (Guide, params)."""
        try:
            through, angle = guide
        except (TypeError, ValueError):
            raise MechanismError(
                f"{what}: guide must be (through, angle): through (x, y), a ground point or a "
                f"link (name or pair of its points); got {guide!r}"
            ) from None
        params = []
        role = "guide of " + key
        if isinstance(through, str) and through in self._owner and self._owner[through] == FRAME:
            g = Guide(through=through)
        elif isinstance(through, str) or (
            isinstance(through, tuple | list) and all(isinstance(t, str) for t in through)
        ):
            frame = self._frame(through, what)
            g = Guide(through=frame.origin, frame=frame)
        else:
            try:
                gx, gy = through
            except (TypeError, ValueError):
                raise MechanismError(
                    f"{what}: guide point must be (x, y), got {through!r}"
                ) from None
            if offset is not None:
                raise MechanismError(
                    f"{what}: offset applies to a guide through a named point; move the "
                    "coordinates instead"
                )
            params.append(("x", self._param(gx, f"{key}_guide_x", "coordinate", f"x of {role}")))
            params.append(("y", self._param(gy, f"{key}_guide_y", "coordinate", f"y of {role}")))
            g = Guide()
        params.append(
            ("angle", self._param(angle, f"{key}_guide_angle", "angle", f"angle of {role}"))
        )
        if g.through is not None:
            params.append(
                (
                    "offset",
                    self._param(
                        0.0 if offset is None else offset,
                        f"{key}_guide_offset",
                        "offset",
                        f"offset of {role} to the left of {g.through}",
                    ),
                )
            )
        return g, params

    # ------------------------------------------------------------------ builders
    def ground_point(self, point: str, x, y) -> Linkage:
        """A new ground point at (x, y) (m)."""
        new = self._copy()
        new._add_ground(point, (x, y))
        return new._freeze()

    def crank(self, point: str, about: str, length, phase=0.0, link: str | None = None):
        """The driving crank: ``point`` at ``length`` (m) from the ground point ``about``, at the
        angle ``phi + phase`` (rad) from +x. Its link is named ``link`` (default
        ``about + point``, e.g. ``"OA"``); parameters ``"OA"`` (length) and ``"phase"``."""
        self._require_no_driver()
        new = self._copy()
        what = f"crank {point}"
        new._check_new_point(point)
        new._known_point(about, what)
        if new._owner[about] != FRAME:
            raise MechanismError(f"{what}: the crank turns about a ground point; {about!r} moves")
        link = new._check_new_body(f"{about}{point}" if link is None else link)
        params = (
            ("length", new._param(length, f"{about}{point}", "length", f"length of crank {link}")),
            ("phase", new._param(phase, "phase", "angle", "phase of the crank angle")),
        )
        return new._with(CrankGroup(point, params, about=about, link=link))

    def _require_no_driver(self):
        if self._groups and isinstance(self._groups[0], CrankGroup | SliderDriverGroup):
            raise MechanismError(
                f"the linkage has a driver already ({self._groups[0].label}): one driver"
            )

    def _require_crank(self, what):
        """The driver (a crank or a driving slider) comes first."""
        if not self._groups or not isinstance(self._groups[0], CrankGroup | SliderDriverGroup):
            raise MechanismError(
                f"{what}: add the driver first, .crank(...) or .slider(...) (groups are solved "
                "in order)"
            )

    def slider(self, point: str, guide, travel, offset=None, link: str | None = None) -> Linkage:
        """The driver as a linear input (a driving slider): ``point`` on a block pushed along a
        fixed straight guide by a prescribed displacement ``s``, the input of :meth:`motion`
        (m, along the guide direction from the guide's point; a speed is then in m/s).

        Parameters
        ----------
        point : the driven point's name.
        guide : ``(through, angle)`` as in :meth:`rrp`, fixed: ``through`` coordinates
            ``(x, y)`` or a ground point's name (then ``offset``, m, to its left); ``angle``
            (rad from +x) the direction in which ``s`` grows. Parameters ``point + "_guide_x"``,
            ``"_guide_y"`` (or ``"_guide_offset"``) and ``"_guide_angle"``.
        travel : ``(lo, hi)``: the displacements (m) the input covers, over which problems
            certify their peaks, charts sweep and drawings move (a stroke out; the return
            passes the same positions).
        link : the block's body name (default ``point``); the force model pushes it along its
            guide with the driving force.
        """
        what = f"driving slider {point}"
        self._require_no_driver()
        lo, hi = _travel(travel, what)
        new = self._copy()
        new._check_new_point(point)
        link = new._check_new_body(point if link is None else link)
        g, gparams = new._guide(guide, offset, point, what)
        if g.frame is not None:
            raise MechanismError(
                f"{what}: the driving slider's guide must be fixed (coordinates or a ground point)"
            )
        return new._with(
            SliderDriverGroup(point, tuple(gparams), guide=g, link=link, travel=(lo, hi))
        )

    # ------------------------------------------------------------------ the input
    @property
    def driver(self) -> str:
        """``"crank"`` (the input is the crank angle, rad) or ``"slider"`` (the input is the
        driving slider's displacement, m)."""
        self._require_crank("the input")
        return "slider" if isinstance(self._groups[0], SliderDriverGroup) else "crank"

    @property
    def input_unit(self) -> str:
        """SI unit of the input: ``"rad"`` for a crank, ``"m"`` for a driving slider."""
        return "m" if self.driver == "slider" else "rad"

    @property
    def input_label(self) -> str:
        """What the input is, for reports and figures."""
        if self.driver == "slider":
            return f"input displacement s of {self._groups[0].key}"
        return "crank angle φ"

    @property
    def input_range(self) -> tuple[float, float]:
        """The inputs a cycle covers: ``(0, 2 pi)`` for a crank (periodic), the ``travel`` of a
        driving slider (m)."""
        if self.driver == "slider":
            return self._groups[0].travel
        return (0.0, 2.0 * np.pi)

    @property
    def periodic(self) -> bool:
        """True when the input is a crank angle (a cycle is one turn and wraps around)."""
        return self.driver == "crank"

    def input_grid(self, n: int):
        """``n`` inputs over a cycle: equal crank-angle steps over a turn (``ms.cycle(n)``), or
        ``n`` equal steps over a driving slider's travel, both ends included."""
        from ..units import cycle

        if self.periodic:
            return cycle(int(n))
        lo, hi = self.input_range
        return np.linspace(lo, hi, int(n))

    def with_travel(self, lo, hi) -> Linkage:
        """The same linkage with its driving slider covering the travel ``(lo, hi)`` (m)."""
        if self.driver != "slider":
            raise MechanismError(f"{self._name} is driven by a crank: it has no travel")
        from dataclasses import replace

        g = self._groups[0]
        new = self._copy()
        new._groups = (replace(g, travel=_travel((lo, hi), g.label)), *self._groups[1:])
        return new._freeze()

    def turn(self, n: int = 48):
        """``n`` inputs over one cycle, for drawings: a crank's turn, or a driving slider's
        travel out and back (harmonic, so the motion reverses smoothly at its ends)."""
        if self.periodic:
            return super().turn(n)
        lo, hi = self.input_range
        return 0.5 * (lo + hi) - 0.5 * (hi - lo) * np.cos(2.0 * np.pi * np.arange(int(n)) / n)

    def _drawing_sketch(self, phi, n, options):
        if self.periodic:
            return super()._drawing_sketch(phi, n, options)
        from ..errors import MechanismError

        s = float(phi)
        lo, hi = self.input_range
        # out and back over the travel, starting at s (clipped to the travel)
        start = np.arccos(np.clip((0.5 * (lo + hi) - s) / (0.5 * (hi - lo)), -1.0, 1.0))
        cyc = 0.5 * (lo + hi) - 0.5 * (hi - lo) * np.cos(start + 2.0 * np.pi * np.arange(n) / n)
        try:
            return self.sketch(np.concatenate([[s], cyc]), **options)
        except MechanismError:
            return self.sketch(np.array([s]), **options)

    def rrr(self, point: str, first, second, branch: int = 1, links=None) -> Linkage:
        """RRR dyad: ``point`` at the given distances from two known points,
        ``first = (P, l1)`` and ``second = (Q, l2)``; ``branch`` +1 puts it to the left of the
        directed line P -> Q. Links ``links=(name1, name2)`` (default ``"P" + point`` and
        ``"Q" + point``), length parameters named the same."""
        what = f"RRR group {point}"
        self._require_crank(what)
        new = self._copy()
        new._check_new_point(point)
        (p, l1), (q, l2) = _pair(first, what, "first"), _pair(second, what, "second")
        new._known_point(p, what)
        new._known_point(q, what)
        if p == q:
            raise MechanismError(f"{what}: the two points must differ, got {p!r} twice")
        n1, n2 = _link_names(links, (f"{p}{point}", f"{q}{point}"), what)
        n1, n2 = new._check_new_body(n1), new._check_new_body(n2)
        params = (
            ("l1", new._param(l1, n1, "length", f"length of link {n1} ({p}-{point})")),
            ("l2", new._param(l2, n2, "length", f"length of link {n2} ({q}-{point})")),
        )
        group = RRRGroup(
            point, params, first=p, second=q, branch=_branch(branch, what), links=(n1, n2)
        )
        return new._with(group)

    def rrp(
        self,
        point: str,
        rod,
        guide,
        offset=None,
        branch: int = 1,
        link: str | None = None,
        slider: str | None = None,
    ) -> Linkage:
        """RRP dyad: a rod ``rod = (P, length)`` from the known point P to the slider ``point`` on
        a straight guide.

        ``guide = (through, angle)``: ``through`` is (x, y) for a fixed guide through those
        coordinates, a ground point's name for a fixed guide through it, or a link (its name, or
        a pair of its points ``(origin, axis point)``) for a guide carried by that moving link
        through the frame's origin, ``angle`` measured from that frame's x axis. A guide through
        a named point lies ``offset`` (m) to the left of it. ``branch`` +1 puts the slider ahead
        of the foot of P along the guide direction. The rod is the link ``link`` (default
        ``P + point``), the slider block the body ``slider`` (default ``point``).
        """
        what = f"RRP group {point}"
        self._require_crank(what)
        new = self._copy()
        new._check_new_point(point)
        p, length = _pair(rod, what, "rod")
        new._known_point(p, what)
        link = new._check_new_body(f"{p}{point}" if link is None else link)
        slider = new._check_new_body(new._free_body(point) if slider is None else slider)
        rod_param = new._param(length, link, "length", f"length of rod {link} ({p}-{point})")
        g, gparams = new._guide(guide, offset, point, what)
        params = (("length", rod_param), *gparams)
        group = RRPGroup(
            point,
            params,
            start=p,
            guide=g,
            branch=_branch(branch, what),
            link=link,
            slider=slider,
        )
        return new._with(group)

    def rpr(
        self,
        link: str,
        about: str,
        through: str,
        offset=0.0,
        branch: int = 1,
        block: str | None = None,
    ) -> Linkage:
        """RPR dyad: a new link ``link`` turning about the known point ``about`` passes through a
        block pinned at the known point ``through`` (an oscillating slotted lever, or a rod in a
        swinging block); the slot lies ``offset`` (m) to the left of the link's axis through
        ``about`` (parameter ``link + "_offset"``). ``branch`` +1 takes the block on the link's
        positive axis. The block is the body ``block`` (default ``through``)."""
        what = f"RPR group {link}"
        self._require_crank(what)
        new = self._copy()
        link = new._check_new_body(link)
        new._known_point(about, what)
        new._known_point(through, what)
        if about == through:
            raise MechanismError(f"{what}: about and through must differ, got {about!r} twice")
        block = new._check_new_body(new._free_body(through) if block is None else block)
        params = (
            ("offset", new._param(offset, f"{link}_offset", "offset", f"slot offset of {link}")),
        )
        group = RPRGroup(
            link, params, about=about, through=through, branch=_branch(branch, what), block=block
        )
        return new._with(group)

    def attach(self, point: str, on, along=0.0, left=0.0) -> Linkage:
        """A point rigidly attached to a moving link: ``along`` (m) along the frame's x axis from
        its origin and ``left`` (m) to its left. ``on`` is a link name (its own frame) or a pair
        of points of one link ``(origin, axis point)``. Parameters ``point + "_along"``,
        ``point + "_left"``."""
        what = f"point {point}"
        self._require_crank(what)
        new = self._copy()
        new._check_new_point(point)
        frame = new._frame(on, what)
        axis = f"{frame.origin}->{frame.axis}" if frame.axis else f"the axis of {frame.body}"
        params = (
            ("along", new._param(along, f"{point}_along", "offset", f"{point} along {axis}")),
            ("left", new._param(left, f"{point}_left", "offset", f"{point} left of {axis}")),
        )
        return new._with(AttachGroup(point, params, frame=frame))

    def follower(
        self,
        point: str,
        on,
        profile: Curve,
        guide,
        offset=None,
        roller=None,
        face=None,
        branch: int = 1,
        side: int = 1,
        slider: str | None = None,
    ) -> Linkage:
        """Higher pair: a translating follower ``point`` on a fixed straight guide, pressed on the
        ``profile`` curve carried by the link ``on`` (a name, or a pair of its points giving the
        profile's frame).

        Parameters
        ----------
        guide, offset : the follower's fixed guide, as in :meth:`rrp` (``(x, y)`` or a ground
            point, and the angle).
        roller : roller radius (m; 0, the default, for a point follower), or
        face : for a flat-faced follower, the angle (rad) of the face's normal from the guide
            direction (0: the face is perpendicular to the guide).
        branch : +1: the follower rests on the profile's outermost contact ahead along the
            guide direction; -1: the hindmost.
        side : +1: the roller runs on the right of the curve's direction of travel (outside a
            counter-clockwise closed profile); -1: on its left.
        slider : the follower's body name (default ``point``).

        The profile's dimensions become parameters ``point + "_profile_" + role`` (e.g.
        ``"N_profile_radius"``); the roller radius ``point + "_roller"``, the face angle
        ``point + "_face"``. The geometric contact point is ``point + "_contact"`` in the motion,
        the common normal's angle ``motion.extra[point + " normal"]``.
        """
        what = f"higher pair {point}"
        self._require_crank(what)
        if not isinstance(profile, Curve):
            raise TypeError(
                f"{what}: profile must be a curve (Circle, Involute, ParametricCurve), got "
                f"{profile!r}"
            )
        if roller is not None and face is not None:
            raise MechanismError(f"{what}: give roller (a radius) or face (an angle), not both")
        roller = 0.0 if roller is None else roller
        new = self._copy()
        new._check_new_point(point)
        new._check_new_point(f"{point}_contact")
        frame = new._frame(on, what)
        slider = new._check_new_body(new._free_body(point) if slider is None else slider)
        g, gparams = new._guide(guide, offset, point, what)
        if g.frame is not None:
            raise MechanismError(
                f"{what}: a follower's guide must be fixed (coordinates or ground)"
            )
        params = list(gparams)
        for role, (raw, kind) in profile.roles.items():
            params.append(
                (
                    f"profile_{role}",
                    new._param(
                        raw, f"{point}_profile_{role}", kind, f"{role} of the profile of {point}"
                    ),
                )
            )
        flat = face is not None
        if flat:
            params.append(("face", new._param(face, f"{point}_face", "angle", f"face of {point}")))
        else:
            params.append(
                ("roller", new._param(roller, f"{point}_roller", "radius", f"roller of {point}"))
            )
        group = FollowerGroup(
            point,
            tuple(params),
            frame=frame,
            profile=profile,
            guide=g,
            flat=flat,
            branch=_branch(branch, what),
            side=_branch(side, what + " (side)"),
            slider=slider,
        )
        return new._with(group)

    def with_output(self, point: str) -> Linkage:
        """The same linkage with ``point`` as its main output (``default_output``; its group's
        pressure angle is ``motion.pressure_angle``; a slider output is ``motion.slider``)."""
        self._known_point(point, "output")
        if self._owner.get(point) == FRAME:
            raise MechanismError(
                f"output: {point!r} is a ground point (it does not move); moving points: "
                + ", ".join(p for p in self.points if self._owner.get(p) != FRAME)
            )
        new = self._copy()
        new._output = point
        return new._freeze()

    def with_parameters(self, **values) -> Linkage:
        """The same linkage with other parameter values (validated; numbers, arrays of designs or
        CasADi symbols)."""
        new = self._copy()
        for name, value in values.items():
            if name not in self._values:
                raise MechanismError(
                    f"{self._name} has no parameter {name!r}; its parameters: "
                    + ", ".join(self._values)
                )
            new._values[name] = _check_value(name, self._kinds[name], value)
        return new._freeze()

    __call__ = with_parameters

    def rename(self, **names) -> Linkage:
        """The same linkage with parameters renamed: ``lk.rename(AB="coupler")``."""
        for old, nw in names.items():
            if old not in self._values:
                raise MechanismError(
                    f"no parameter {old!r} to rename; parameters: {', '.join(self._values)}"
                )
            if not isinstance(nw, str) or not nw.isidentifier():
                raise MechanismError(f"new name for {old!r} must be an identifier, got {nw!r}")
        order = [names.get(k, k) for k in self._values]
        if len(set(order)) != len(order):
            raise MechanismError(f"renaming {names} would give two parameters the same name")
        new = self._copy()
        new._values = {names.get(k, k): v for k, v in self._values.items()}
        new._kinds = {names.get(k, k): v for k, v in self._kinds.items()}
        new._roles = {names.get(k, k): v for k, v in self._roles.items()}
        new._ground = tuple((p, names.get(x, x), names.get(y, y)) for p, x, y in self._ground)
        new._groups = tuple(g.renamed(names) for g in self._groups)
        return new._freeze()

    # ------------------------------------------------------------------ description
    @property
    def __name__(self) -> str:
        """The linkage's name: a linkage stands where a mechanism class stands (Problem,
        sweep), and calling it with parameter values gives the design with those values."""
        return self._name

    @property
    def name(self) -> str:
        return self._name

    @property
    def parameters(self) -> dict[str, Any]:
        """``{name: value}`` of every dimension, in the order they were added."""
        return dict(self._values)

    def params(self) -> dict[str, Any]:
        """The parameters as a dict (the protocol of the named mechanisms)."""
        return dict(self._values)

    @property
    def parameter_kinds(self) -> dict[str, str]:
        """``{name: kind}``: ``"length"`` (positive), ``"coordinate"``, ``"offset"``,
        ``"angle"``, ``"radius"`` (non-negative)."""
        return dict(self._kinds)

    @property
    def parameter_roles(self) -> dict[str, str]:
        """``{name: what it is}``, e.g. ``{"AB": "length of link AB (A-B)"}``."""
        return dict(self._roles)

    @property
    def points(self) -> tuple[str, ...]:
        """Every point: ground points first, then in solving order (contact points included)."""
        out = [p for p, _, _ in self._ground]
        for g in self._groups:
            new = g.new_point()
            if new is not None:
                out.append(new[0])
            if isinstance(g, FollowerGroup):
                out.append(g.contact_point)
        return tuple(out)

    @property
    def links(self) -> tuple[str, ...]:
        """The moving bodies' names, in solving order."""
        return tuple(self._bodies)

    @property
    def groups(self) -> tuple[Group, ...]:
        return self._groups

    @property
    def sliders(self) -> tuple[str, ...]:
        """Names of the sliding blocks (RRP sliders, RPR blocks, followers)."""
        return tuple(b.name for b in self._bodies.values() if b.kind not in ("link", "crank"))

    @property
    def default_output(self) -> str:
        """The main output point: set by :meth:`with_output`, else the last group's point."""
        if self._output is not None:
            return self._output
        for g in reversed(self._groups):
            new = g.new_point()
            if new is not None:
                return new[0]
        raise MechanismError("the linkage has no moving point yet: add a crank")

    @property
    def assembly_conditions(self) -> tuple[str, ...]:
        """Names of the assembly conditions (one per dyad; a follower's contact and profile
        ends); ``motion.extra["assembly margins"]`` holds their per-angle margins."""
        return tuple(c for g in self._groups for c in g.conditions())

    @property
    def is_symbolic(self) -> bool:
        return self._symbolic

    def describe(self) -> str:
        """A readable listing of the groups and the parameters with their values."""
        lines = [f"{self._name}: ground " + ", ".join(p for p, _, _ in self._ground)]
        for g in self._groups:
            lines.append(f"  {g.label}")
        lines.append("parameters:")
        for k, v in self._values.items():
            val = f"{v:.6g}" if isinstance(v, float | int) else repr(v)
            lines.append(f"  {k:18s} = {val:>12s}   {self._roles[k]}")
        return "\n".join(lines)

    def as_dict(self) -> dict[str, Any]:
        """Every dimension as a plain Python value (``{name: float}``): enough to build the
        design again with ``linkage(**values)`` (the protocol of the named mechanisms)."""
        return {
            k: float(v) if np.ndim(v) == 0 and not ops.is_symbolic(v) else v
            for k, v in self._values.items()
        }

    def unit_of(self, name: str) -> str:
        """SI unit of the parameter ``name``: ``"rad"`` for angles, ``"m"`` for the others."""
        if name not in self._kinds:
            raise MechanismError(f"{self._name} has no parameter {name!r}")
        return "rad" if self._kinds[name] == "angle" else "m"

    # ------------------------------------------------------------------ drawing
    def sketch(self, phi, **options):
        """What the linkage looks like at crank angles ``phi`` (one design): each moving link
        as a bar (a plate when it joins three or more points), the ground points as frame
        pivots, every block on its guide (a slot through the carrying link when the guide
        moves) and each cam profile as an outline; the renderer of :meth:`draw` and
        :meth:`animate` draws it (see :mod:`mechsynth.kinematics.sketch`)."""
        from .sketch import Bar, Outline, Sketch, Slider, as_frames

        if options:
            raise MechanismError(f"unknown drawing option(s): {', '.join(sorted(options))}")
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        m = self.motion(phi)
        topo = self.topology()
        points = as_frames(m.points)
        zero = np.zeros(phi.shape)
        bars = []
        for name in topo.bodies:
            members = topo.points.get(name, ())
            if len(members) >= 2:  # links, and blocks that carry attached points
                bars.append(Bar(name, tuple(members), closed=len(members) >= 3))
        sliders = []
        for j in topo.joints:
            if j.kind != "prismatic":
                continue
            angle = np.asarray(m.links[j.direction].angle, dtype=float) + zero
            if j.by == FRAME:
                sliders.append(Slider(j.point, angle, name=j.name))
                continue
            # a guide carried by a link: the slot along the guide line through the block,
            # drawn from the foot of the carrier's base point on that line
            base = topo.bodies[j.by].base
            ux, uy = np.cos(angle), np.sin(angle)
            (bx, by), (px, py) = points[base], points[j.point]
            along = (px - bx) * ux + (py - by) * uy
            foot = f"{j.name} foot"
            points[foot] = (px - along * ux, py - along * uy)
            if len(topo.points.get(j.by, ())) < 2:  # the carrier is drawn along its slot
                end = f"{j.name} end"
                reach = along + np.sign(along.mean() or 1.0) * 0.2 * np.abs(along).max()
                points[end] = (points[foot][0] + reach * ux, points[foot][1] + reach * uy)
                bars.append(Bar(j.by, (base, foot, end)))
            sliders.append(Slider(j.point, angle, through=foot, name=j.name))
        outlines = []
        for prof in topo.profiles.values():
            x, y = prof.world(m)
            outlines.append(Outline(f"profile of {prof.follower}", x, y))
        named = tuple(p for p in self.points if p in points)
        moving = tuple(p for p in named if p not in topo.ground)
        return Sketch(
            points=points,
            bars=tuple(bars),
            ground=tuple(p for p in topo.ground if p in points),
            sliders=tuple(sliders),
            outlines=tuple(outlines),
            angles=phi,
            angle_label=self.input_label if self.periodic else "input s",
            angle_symbol="φ" if self.periodic else "s",
            angle_unit=self.input_unit,
            name=self._name,
            labels=named,
            joints=moving,
        )

    def __repr__(self) -> str:
        kinds = " + ".join(g.kind for g in self._groups) or "no groups"
        return f"<Linkage {self._name!r}: {kinds}; {len(self._values)} parameters>"

    # ------------------------------------------------------------------ solving
    def _solve(self, phi, strict=True, hold=True) -> _State:
        """The groups solved in order at ``phi``; ``strict`` raises where one cannot close (else
        NaN there); ``hold`` (symbolic input) keeps an optimizer's expressions finite there
        (:meth:`_State.relax`)."""
        if not self._groups:
            raise MechanismError(
                f"{self._name} has no driver: add one with .crank(...) or .slider(...)"
            )
        v = self._values
        st = _State(phi, v, strict, self._bodies, hold)
        points = st.points
        for p, x, y in self._ground:
            points[p] = PointJet(v[x], v[y], 0.0, 0.0, 0.0, 0.0)
        with np.errstate(invalid="ignore", divide="ignore") if not strict else _NULL:
            for g in self._groups:
                try:
                    g.solve(st)
                except MechanismError as exc:
                    angles = getattr(exc, "angles", ())
                    detail = self._failure_detail(g, exc, st)
                    text = str(exc)
                    if isinstance(self._groups[0], SliderDriverGroup):
                        text = _input_words(text, angles)
                    err = MechanismError(f"{g.label}: {text}{detail}")
                    err.angles = angles
                    err.group = g.key
                    raise err from None
        return st

    def _failure_detail(self, g: Group, exc, st) -> str:
        """The failing group's distances at the angle (and design) its error names."""
        where = getattr(exc, "angles", ())
        if not where or ops.is_symbolic(st.phi) or np.ndim(st.phi) != 1:
            return ""
        k = int(np.argmin(np.abs(np.asarray(st.phi, dtype=float) - where[0])))
        design = getattr(exc, "design", None) or ()

        def at(x):
            a = np.asarray(x, dtype=float)
            if a.ndim > 1:
                a = a[design] if design else a.reshape(-1, a.shape[-1])[0]
            return float(a[k] if a.ndim and a.size > 1 else a.reshape(-1)[0])

        v = st.v
        if isinstance(g, RRRGroup | RPRGroup):
            a, b = (g.first, g.second) if isinstance(g, RRRGroup) else (g.about, g.through)
            p, q = st.points[a], st.points[b]
            d = np.hypot(at(q.x) - at(p.x), at(q.y) - at(p.y))
            if isinstance(g, RPRGroup):
                off = abs(at(g.p(v, "offset")))
                return f"; there |{a}{b}| = {d:.6g} m, the slot offset {off:.6g} m"
            l1, l2 = at(g.p(v, "l1")), at(g.p(v, "l2"))
            return (
                f"; there |{a}{b}| = {d:.6g} m, the links {l1:.6g} and {l2:.6g} m reach "
                f"[{abs(l1 - l2):.6g}, {l1 + l2:.6g}] m"
            )
        if isinstance(g, RRPGroup) and g.key in st.margins:
            length = at(g.p(v, "length"))
            h = length * np.sqrt(max(0.0, 1.0 - at(st.margins[g.key])))
            return f"; there {g.start} is {h:.6g} m from the guide, the rod {length:.6g} m"
        return ""

    def jets(self, phi):
        """``(points, links, sliders)``: dicts of the jets (position and crank-angle analogs)."""
        st = self._solve(phi)
        return st.points, st.links, st.sliders

    def motion(self, phi, speed=None, epsilon=0.0, *, kernel: bool | None = None) -> Motion:
        """Motion over the inputs ``phi``: crank angles (rad), or the displacements ``s`` (m)
        of a driving slider (:meth:`slider`).

        One design (every parameter a number) at a 1-D array of inputs may be evaluated on the
        compiled kernel of its structure
        (:func:`~mechsynth.kinematics.linkage_kernels.linkage_kernel`) -- every output within
        1e-12 of the model's, some 4 x faster than the model for a six-bar at 360 angles:

        - ``kernel=None`` (the default) decides as a just-in-time compiler does: the model
          serves the first calls of a structure while their time is summed; once that time
          has paid for the kernel (its load from the disk cache when this machine built it
          before, about 5 ms; else its build, about 0.7 s of CPU with a C compiler:
          :data:`KERNEL_COSTS`), the kernel is loaded or built in the background
          (never waited for) and serves every later call of the structure in this process.
        - ``kernel=True`` takes the kernel at once (built or loaded on this call).
        - ``kernel=False`` always takes the model: its numbers then do not depend on what this
          process compiled before (``$MECHSYNTH_KERNELS=off`` does so for every call).

        Anything else (batches, symbols, a speed or acceleration that varies with the input, a
        cam follower, no compiler nor numba, a design whose outputs are not all finite) takes
        the model, which raises where a group cannot close.

        Parameters
        ----------
        phi : crank angles (or a driving slider's displacements), any shape (broadcast against
            array parameters).
        speed : the input's speed: crank angular velocity (rad/s, e.g. ``ms.rpm(600)``) or the
            driving slider's velocity (m/s); None gives analogs (derivatives with respect to
            the input: per rad, or per m of a driving slider).
        epsilon : the input's acceleration (rad/s^2, or m/s^2), with a speed.
        kernel : None (decide from the measured costs), True (the kernel) or False (the model).

        Returns
        -------
        Motion with every point (ground points too) in ``points``, every moving body's angle in
        ``links``, the sliders' positions along their guides in ``sliders`` (the output slider
        first), per group ``pressure_angles`` and ``transmission_angles`` (the output's group
        also as ``pressure_angle`` / ``transmission_angle``), and in ``extra`` the per-angle
        ``"assembly margins"`` and each follower's common normal (``"N normal"``, rad).

        Raises
        ------
        MechanismError
            naming the group, the crank angle and the violated condition where a group cannot
            be assembled (or its links are in line: a toggle).
        """
        omega, eps = speed_pair(speed, epsilon)
        if not ops.is_symbolic(phi):
            try:
                phi = np.asarray(phi, dtype=float) if np.ndim(phi) else float(phi)
            except (TypeError, ValueError):
                raise MechanismError(f"phi must be {self._input_words()}, got {phi!r}") from None
            if not (
                math.isfinite(phi)
                if type(phi) is float
                else (phi.dtype is _FLOAT64 and finite(phi)) or np.isfinite(phi).all()
            ):
                raise MechanismError(f"phi must be finite {self._input_words()}")
            if not self._symbolic:  # refuse up front what would not fit in memory
                guard_motion(
                    self._guarded,
                    phi if isinstance(phi, np.ndarray) else np.asarray(phi),
                    omega,
                    eps,
                    arrays=self._motion_arrays,
                )
                if (
                    kernel is not False and self._floats and type(phi) is np.ndarray
                    and phi.ndim == 1 and not np.ndim(omega) and not np.ndim(eps)
                ):  # fmt: skip
                    if kernel:
                        fast = self._on_kernel(phi, omega, eps)
                        if fast is not None:
                            return fast
                    else:
                        return self._jit(phi, omega, eps)
        return self._motion(self._solve(phi), phi, omega, eps)

    def _jit(self, phi, omega, eps) -> Motion:
        """The motion of this one numeric design at the 1-D inputs ``phi``: on its structure's
        kernel when this process holds it, else on the model, whose time is summed per
        structure until it pays for the kernel (:meth:`motion`, ``kernel=None``)."""
        lkk = _kernels()
        kernel = lkk.held_kernel(self)
        if kernel is not None:
            fast = lkk.one_motion(self, phi, omega, eps, kernel)
            if fast is not None:
                return fast
            return self._motion(self._solve(phi), phi, omega, eps)
        groups = self._groups
        tally = _TALLY.get(id(groups))
        if tally is None or tally[0] is not groups:
            if len(_TALLY) > 256:  # bounded: linkages built anew in a loop add identities
                _TALLY.clear()
            tally = _TALLY[id(groups)] = [groups, 0.0, None]
        start = time.perf_counter()
        motion = self._motion(self._solve(phi), phi, omega, eps)
        tally[1] += time.perf_counter() - start
        if tally[2] is None:  # the price of the kernel, asked once per structure
            tally[2] = _kernel_price(self, lkk)
        if tally[1] >= tally[2]:
            tally[2] = math.inf  # asked once: it arrives in the background, or never
            lkk.linkage_kernel(self, wait=False)
        return motion

    def _on_kernel(self, phi, omega, eps) -> Motion | None:
        """The motion of this one numeric design (every parameter a float) on its structure's
        kernel (built or loaded on first use), or None (no kernel, an output not finite)."""
        lkk = _kernels()
        kernel = lkk.held_kernel(self) or lkk.linkage_kernel(self)
        if kernel is None:
            return None
        return lkk.one_motion(self, phi, omega, eps, kernel)

    def _motion(self, st: _State, phi, omega, eps, scaled=False) -> Motion:
        """The :class:`Motion` of a solved state (of the model, or of the compiled kernel);
        ``scaled``: its jets are time derivatives at ``omega`` and ``eps`` already."""
        motion_omega, motion_eps = omega, eps
        if scaled:
            omega, eps = 1.0, 0.0
        plan = self._plan
        zero = 0.0 * st.points[plan.crank].x
        points = st.points
        if not scaled:
            # a frame point's jet holds its coordinates (numbers): made tracks of the motion's
            # shape (a kernel's rows are full tracks already), at rest (no scaling of zeros)
            points = dict(points)
            of = PointTrack.of
            for name in plan.frame_points:
                p = points[name]
                points[name] = of(p.x + zero, p.y + zero, zero, zero, zero, zero)
        sliders = st.sliders
        main = plan.main_slider
        if main in sliders and next(iter(sliders)) != main:
            sliders = {main: sliders[main], **{k: s for k, s in sliders.items() if k != main}}
        tracks = _as_tracks(points, st.links, sliders, omega, eps)
        pressures = st.pressure
        key = plan.out_key if plan.out_key in pressures else None
        if key is None and pressures:
            key = next(reversed(pressures))
        pressure = pressures[key] if key is not None else zero
        transmission = st.transmission[key] if key is not None else None
        return Motion._of_tracks(
            phi,
            motion_omega,
            motion_eps,
            tracks,
            pressure,
            transmission,
            {"assembly margins": st.margins, **st.extra},
            dict(pressures),
            dict(st.transmission),
        )

    def _input_words(self) -> str:
        if self._groups and isinstance(self._groups[0], SliderDriverGroup):
            return "displacements of the driving slider in m"
        return "crank angles in rad"

    def _group_of(self, point) -> Group:
        for g in self._groups:
            new = g.new_point()
            if (new is not None and new[0] == point) or g.key == point:
                return g
        return self._groups[-1]

    def assembly_margins(self, phi) -> dict[str, Any]:
        """``{condition: margin}`` per crank angle, for any design (never raises): a margin is
        negative where that group cannot be assembled; NaN where an earlier group failed.

        RRR: ``sin^2`` of the angle between its links; RRP: ``cos^2`` of the rod's angle to the
        guide; RPR: ``cos^2`` of its pressure angle; follower: its contact's ``cos^2`` of the
        pressure angle (-1 where the guide misses the profile) and, on an open profile, the
        distance of the contact from the profile's ends as a fraction of its parameter range.
        """
        if self.is_symbolic:
            return self._solve(phi, strict=True).margins
        return self._solve(np.asarray(phi, dtype=float), strict=False).margins

    # ------------------------------------------------------------------ feasibility
    def feasibility_constraints(self, params, margin=1e-3):
        """Conditions ``g >= 0`` on the parameters alone, for the optimizers and chart sweeps:
        every length positive. (Assembly is a per-angle condition, not one of the parameters
        alone: a :class:`~mechsynth.synthesis.Problem` bounds every group's
        ``assembly_margin`` on its certified crank-angle grid, and a design that cannot be
        assembled at an angle raises :class:`MechanismError` there, which sweeps and solvers
        treat as infeasible.) ``params`` may hold numbers, arrays of designs or CasADi
        symbols; ``margin`` is relative to each length's value in this linkage."""
        rows = []
        for k, kind in self._kinds.items():
            if kind == "length" and k in params:
                ref = self._values[k]
                scale = abs(float(ref)) if isinstance(ref, numbers.Real) and ref else 1.0
                rows.append((f"{k} > 0 (a length)", params[k] / scale - margin))
        return rows

    def assembles(self, n: int = 360):
        """Per design, the smallest assembly margin of every condition at ``n`` crank angles
        (``n`` inputs over a driving slider's travel): ``{condition: value}``, negative where
        it fails; -1 where an earlier group failed first. A quick screen of batches of
        designs; :meth:`assembly_margins` has them per angle."""
        out = {}
        margins = self.assembly_margins(self.input_grid(int(n)))
        for c in self.assembly_conditions:
            m = np.asarray(margins[c], dtype=float)
            worst = np.min(np.where(np.isnan(m), np.inf, m), axis=-1)
            out[c] = np.where(np.isnan(m).all(axis=-1), -1.0, worst)
        shaped = np.broadcast_arrays(*out.values()) if out else []
        return {c: (_flat(w) if w.ndim else float(w)) for c, w in zip(out, shaped)}

    # ------------------------------------------------------------------ cycle properties
    def _output_quantity(self, st: _State, of: str):
        """The jet whose extremes are the output's dead centres: a slider's position or a link's
        angle."""
        if of in st.sliders:
            return st.sliders[of]
        if of in st.links:
            return st.links[of]
        raise MechanismError(f"{of!r} is neither a slider nor a link of {self._name}")

    def _stroke_output(self) -> str:
        """The slider or link whose strokes the time ratio compares (of the default output)."""
        g = self._group_of(self.default_output)
        if isinstance(g, RRPGroup | FollowerGroup):
            return g.slider
        if isinstance(g, RRRGroup):
            return g.links[1]
        if isinstance(g, RPRGroup):
            return g.key
        if isinstance(g, AttachGroup):
            return g.frame.body
        raise MechanismError(
            f"the output {self.default_output!r} of {self._name} has no strokes (the crank)"
        )

    def _require_crank_input(self, what):
        if self.driver != "crank":
            raise MechanismError(
                f"{what} of {self._name}: defined for a crank input only; this linkage is "
                "driven by a slider (its cycle is its travel, not a turn)"
            )

    def dead_centres(self, of: str | None = None):
        """Crank angles (rad, in about [0, 2 pi)) where the output ``of`` (a slider or link name;
        default: the main output's slider or rocker) reaches its largest and its smallest value:
        ``(phi_max, phi_min)``. Found on a grid of 72 angles and refined by Newton steps on the
        velocity analog, written with ``ops``, so they are differentiable with CasADi."""
        from ..units import cycle

        self._require_crank_input("dead centres")
        of = of or self._stroke_output()
        symbolic = self.is_symbolic
        grid = cycle(_SPAN_SAMPLES)
        st = self._solve(_column_of(grid) if symbolic else grid)
        q = self._output_quantity(st, of)
        angle = of not in st.sliders

        def col(x, k):
            return x[k] if symbolic else np.asarray(x)[..., k : k + 1]

        q0 = col(q.value, 0)
        hi = lo = phi_hi = phi_lo = None
        for k in range(_SPAN_SAMPLES):
            d = col(q.value, k) - q0
            val = ops.arctan2(ops.sin(d), ops.cos(d)) if angle else d
            at = float(grid[k]) + 0.0 * val
            if hi is None:
                hi, lo, phi_hi, phi_lo = val, val, at, at
                continue
            up, down = val > hi, val < lo
            hi, phi_hi = ops.where(up, val, hi), ops.where(up, at, phi_hi)
            lo, phi_lo = ops.where(down, val, lo), ops.where(down, at, phi_lo)
        for _ in range(5):
            jh = self._output_quantity(self._solve(phi_hi), of)
            jl = self._output_quantity(self._solve(phi_lo), of)
            phi_hi = phi_hi - jh.d1 / jh.d2
            phi_lo = phi_lo - jl.d1 / jl.d2
        if not symbolic:
            phi_hi, phi_lo = np.asarray(phi_hi)[..., 0], np.asarray(phi_lo)[..., 0]
            if phi_hi.ndim == 0:
                phi_hi, phi_lo = float(phi_hi), float(phi_lo)
        return phi_hi, phi_lo

    @property
    def crank_spans(self):
        """Crank rotation (rad) from the output's largest to its smallest value and back (they
        add up to 2 pi); see :meth:`dead_centres`."""
        self._require_crank_input("crank spans")
        hi, lo = self.dead_centres()
        d = lo - hi
        d = ops.where(d < 0.0, d + 2.0 * np.pi, d)
        d = ops.where(d >= 2.0 * np.pi, d - 2.0 * np.pi, d)
        return d, 2.0 * np.pi - d

    @property
    def time_ratio(self):
        """Slower stroke over quicker stroke of the main output (>= 1) at constant crank speed."""
        self._require_crank_input("the time ratio")
        first, second = self.crank_spans
        return ops.fmax(first, second) / ops.fmin(first, second)

    # ------------------------------------------------------------------ structure
    def joints(self) -> tuple[Joint, ...]:
        """Every kinematic pair, with the names the force model reports them by: a revolute
        joint is named after its point (``"B"``; a second joint at the same point
        ``"B_<link>"``), a guide ``"<slider>_guide"``, an RPR slot ``"<link>_slot"``, a cam
        contact ``"<follower>_contact"``."""
        out, used = [], set()

        def owner(p):
            return self._owner[p]

        for g in self._groups:
            for spec in g.joints(owner):
                kind, point, on, by = spec[:4]
                if kind == "revolute":
                    name = point if point not in used else f"{point}_{on}"
                    used.add(point)
                    out.append(Joint("revolute", name, point, on, by))
                elif kind == "prismatic":
                    name = (
                        f"{on}_guide"
                        if isinstance(g, RRPGroup | FollowerGroup | SliderDriverGroup)
                        else (f"{g.key}_slot")
                    )
                    out.append(Joint("prismatic", name, point, on, by, direction=spec[4]))
                else:
                    out.append(Joint("contact", point, point, on, by, normal=spec[5]))
        return tuple(out)

    def topology(self) -> Topology:
        """Bodies, the points each joins, ground points, joints, guides and cam profiles: what
        a drawing needs (see :class:`Topology`)."""
        v = self._values
        ground = {p: (v[x], v[y]) for p, x, y in self._ground}
        guides, profiles = {}, {}
        for g in self._groups:
            if isinstance(g, RRPGroup | FollowerGroup):
                guides[g.slider] = GuideLine(g.slider, g.guide.carrier, g, self)
            if isinstance(g, SliderDriverGroup):
                guides[g.link] = GuideLine(g.link, g.guide.carrier, g, self)
            if isinstance(g, FollowerGroup):
                profiles[g.key] = Profile(
                    g.key,
                    g.frame.body,
                    g.frame.origin,
                    g.frame.axis,
                    g.profile,
                    g.profile_values(v),
                )
        return Topology(
            ground=ground,
            bodies=dict(self._bodies),
            points=dict(self._members),
            joints=self.joints(),
            guides=guides,
            profiles=profiles,
            driver=self._groups[0].link if self._groups else "",
        )

    # ------------------------------------------------------------------ forces
    def force_model(self, inertias: Mapping | None = None, loads=()):
        """The :class:`~mechsynth.dynamics.kinetostatics.ForceModel` of this linkage (see
        :func:`mechsynth.dynamics.linkage_forces.linkage_force_model`): every moving body with
        its mass properties ``inertias[name]`` (a ``LinkInertia``, or ``(mass, (u, v),
        inertia)`` in the body's frame; massless when absent), every joint (named as
        :meth:`joints`), the ``loads`` and the crank as the driver (the balancing torque) --
        or a driving slider's block, pushed along its guide by the driving force."""
        if _FORCES.builder is None:  # the forces layer registers it when imported
            from .. import load_registrations

            load_registrations()
        return _FORCES.builder(self, inertias, loads)


class _ForceBuilder:
    """The forces layer (:mod:`mechsynth.dynamics`) registers the force-model builder here."""

    builder = None


_FORCES = _ForceBuilder()


def register_force_builder(fn) -> None:
    """Called by :mod:`mechsynth.dynamics.linkage_forces` (the layer that owns forces)."""
    _FORCES.builder = fn


def _flat(a):
    """A per-design column ``(k, 1)`` as ``(k,)`` (scalars unchanged)."""
    a = np.asarray(a)
    return a[..., 0] if a.ndim and a.shape[-1] == 1 else a


def _column_of(grid):
    import casadi

    return casadi.DM(grid)


class _nullcontext:
    def __enter__(self):
        return None

    def __exit__(self, *exc):
        return False


#: numpy's float64 (the dtype of the angles a motion tests in one pass)
_FLOAT64 = np.dtype(np.float64)

#: the context of a strict solve (numpy's warnings as the caller has them): one, made once
_NULL = _nullcontext()


#: how the blocks name the input where they fail (a driving slider's input is a length)
_CRANK_AT = re.compile(r" at crank angle ([-+0-9.eE]+|nan|inf) deg")


def _input_words(text: str, angles) -> str:
    """A block's failure message for a linkage driven by a slider: its input is a length."""

    def words(mt):
        s = angles[0] if angles else np.deg2rad(float(mt[1]))
        return f" at input displacement {s:.6g} m"

    return _CRANK_AT.sub(words, text)


def _link_names(links, default, what):
    """The two link names of a dyad: ``links=(name1, name2)``, or the default pair."""
    if links is None:
        return default
    if isinstance(links, str) or not isinstance(links, (tuple, list)) or len(links) != 2:
        raise MechanismError(
            f"{what}: links must be a pair of link names (name1, name2), got {links!r}"
        )
    return tuple(links)


def _travel(travel, what) -> tuple[float, float]:
    """A driving slider's travel ``(lo, hi)`` (m), checked."""
    try:
        lo, hi = (float(t) for t in travel)
    except (TypeError, ValueError):
        raise MechanismError(f"{what}: travel must be (lo, hi) in m, got {travel!r}") from None
    if not (np.isfinite(lo) and np.isfinite(hi)) or not lo < hi:
        raise MechanismError(f"{what}: travel must be finite with lo < hi (m), got ({lo}, {hi})")
    return lo, hi


def _pair(value, what, role):
    try:
        p, length = value
    except (TypeError, ValueError):
        raise MechanismError(f"{what}: {role} must be (point, length), got {value!r}") from None
    if not isinstance(p, str):
        raise MechanismError(f"{what}: {role} must be (point name, length), got {value!r}")
    return p, length
