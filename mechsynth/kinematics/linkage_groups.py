"""The groups a :class:`~mechsynth.kinematics.linkage.Linkage` is built from, in solving order.

Each group names the points it joins and the parameters it reads, and, when solved, moves its new
points and links with the blocks of :mod:`~mechsynth.kinematics.blocks` -- the same functions the
named mechanisms use. A group also states

* its *assembly margins*: dimensionless, smooth per-angle conditions ``>= 0`` exactly where it can
  be assembled (the sine squared of the angle between an RRR dyad's links, the cosine squared of
  an RRP rod's angle to its guide, ...), computed before any square root so that they exist for
  every design;
* the bodies it adds (with their frames) and the joints it makes, for the force model and for a
  drawing.

Groups are frozen values holding parameter *names*; the values live in the linkage.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import MechanismError
from . import ops
from .blocks import (
    cam_contact,
    coupler_point,
    crank,
    crank_pin,
    dyad_rpr_on,
    dyad_rrp,
    dyad_rrp_on,
    dyad_rrr,
    link_angle,
    rrr_apart,
)
from .tracks import Jet, PointJet

__all__ = [
    "Param",
    "Body",
    "Joint",
    "Frame",
    "Guide",
    "Group",
    "CrankGroup",
    "SliderDriverGroup",
    "RRRGroup",
    "RRPGroup",
    "RPRGroup",
    "AttachGroup",
    "FollowerGroup",
    "FRAME",
]

FRAME = "frame"


@dataclass(frozen=True)
class Param:
    """A dimension with the name you choose: ``length=Param("r", 0.03)`` makes the crank length
    the linkage parameter ``"r"`` (instead of its default name, e.g. ``"OA"``)."""

    name: str
    value: Any

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name.isidentifier():
            raise MechanismError(
                f"a parameter name must be an identifier (letters, digits, _), got {self.name!r}"
            )


@dataclass(frozen=True)
class Body:
    """A moving link of the linkage.

    Attributes
    ----------
    name : its name (also the name of its angle in ``motion.links``).
    kind : ``"crank"``, ``"link"``, ``"slider"`` (a block on a straight guide), ``"block"`` (the
        block of an RPR group, sliding on its link) or ``"follower"`` (a cam follower's slider).
    base : the point at the origin of its frame.
    axis : the point on its frame's x axis, or None when the angle is not that of a segment (a
        slider's guide direction, an RPR link's axis).
    group : the key of the group that made it.
    """

    name: str
    kind: str
    base: str
    axis: str | None
    group: str


@dataclass(frozen=True)
class Joint:
    """A kinematic pair of the linkage (for the force model and drawings).

    ``kind`` is ``"revolute"`` (at ``point``), ``"prismatic"`` (the block ``on`` slides along the
    angle of the link ``direction`` through ``point``) or ``"contact"`` (a higher pair at the
    moving contact point ``point``, force along the common normal ``motion.extra[normal]``).
    The force reported for a joint acts on ``on`` from ``by`` (``"frame"``: the ground).
    """

    kind: str
    name: str
    point: str
    on: str
    by: str
    direction: str | None = None
    normal: str | None = None


@dataclass(frozen=True)
class Frame:
    """A body's frame as a group refers to it: origin at ``origin`` (a point of ``body``), x axis
    along ``origin -> axis`` (None: along the body's own angle)."""

    body: str
    origin: str
    axis: str | None = None


@dataclass(frozen=True)
class Guide:
    """A straight guide: fixed (``carrier`` None) through given coordinates (``through`` None,
    parameters ``x``, ``y``) or through a ground point, or carried by the body of ``frame``
    through the frame's origin; its direction is the parameter ``angle`` (rad, from +x for a
    fixed guide, from the frame's x axis for a carried one); a guide through a point lies the
    parameter ``offset`` to the left of it."""

    through: str | None = None
    frame: Frame | None = None

    @property
    def carrier(self) -> str:
        return FRAME if self.frame is None else self.frame.body


class _State:
    """What a solve has computed so far (jets, tracks, margins), group by group."""

    def __init__(self, phi, values, strict, bodies, hold=True):
        self.phi = phi
        self.v = values
        self.strict = strict
        self.bodies = bodies
        self.hold = hold
        self.points: dict[str, PointJet] = {}
        self.links: dict[str, Jet] = {}
        self.sliders: dict[str, Jet] = {}
        self.pressure: dict[str, Any] = {}
        self.transmission: dict[str, Any] = {}
        self.margins: dict[str, Any] = {}
        self.extra: dict[str, Any] = {}

    @property
    def check_phi(self):
        """The angles the blocks check with (None in a relaxed solve: no checks)."""
        return self.phi if self.strict else None

    def frame(self, f: Frame):
        """Origin jet and angle jet of a frame."""
        origin = self.points[f.origin]
        body = self.bodies[f.body]
        if f.axis is None or (f.origin == body.base and f.axis == body.axis):
            return origin, self.links[f.body]
        return origin, link_angle(origin, self.points[f.axis])

    def relax(self, jet: PointJet, margin, moved=None) -> PointJet:
        """The input point of a group that may not close.

        * numeric, strict solve: unchanged (the block raises where the group cannot close);
        * numeric, relaxed solve: NaN where it cannot close (its block does not raise and what
          depends on it is NaN; :meth:`Linkage.assembly_margins` reports the failure);
        * symbolic (an optimizer): the position ``moved = (x, y)``, which equals the point's
          where the group closes and is pulled to just inside the closing range where it does
          not, so that the expressions stay finite and the optimizer, seeing the group's
          negative assembly margin, steers back (a NaN would stop it);
        * symbolic with ``hold`` off (the trace a compiled kernel is generated from): unchanged,
          the numeric strict solve's expressions (NaN where the group cannot close).
        """
        if ops.is_symbolic(margin):
            if moved is None or not self.hold:
                return jet
            return PointJet(moved[0], moved[1], jet.dx, jet.dy, jet.ddx, jet.ddy)
        if self.strict:
            return jet
        ok = np.asarray(margin) >= 0.0
        return PointJet(*(np.where(ok, c, np.nan) for c in jet))


# relative distance to a closing limit at which an optimizer's symbolic model holds a group that
# does not close (see _State.relax)
_HOLD = 1e-9


# The groups' per-angle formulas beside the blocks (margins, angles), written with ops on scalars
# or arrays so that a compiled chain could call them as it calls the blocks.
def rrr_margin(d2, l1, l2):
    """sin^2 of the angle between an RRR dyad's links, from the distance squared ``d2`` of its
    pivots (:func:`~mechsynth.kinematics.blocks.rrr_apart`):
    ``((l1+l2)^2 - d^2)(d^2 - (l1-l2)^2) / (4 l1^2 l2^2)``; negative where it cannot close."""
    return ((l1 + l2) ** 2 - d2) * (d2 - (l1 - l2) ** 2) / (4.0 * l1 * l1 * l2 * l2)


def rrr_angles(t1: Jet, t2: Jet):
    """Transmission angle (between the links, in [0, pi]) and pressure angle ``|pi/2 - mu|``."""
    mu = ops.arccos(ops.cos(t1.value - t2.value))
    return mu, ops.fabs(np.pi / 2 - mu)


def fixed_guide(px, py, offset, angle):
    """The point of a fixed guide through (px, py) at ``offset`` to the left of its direction."""
    return px - offset * ops.sin(angle), py + offset * ops.cos(angle)


def guide_height(p: PointJet, gx, gy, angle):
    """Signed height of ``p`` over the guide through (gx, gy) at ``angle``."""
    return (p.x - gx) * -ops.sin(angle) + (p.y - gy) * ops.cos(angle)


def rrp_margin(hgt, length):
    """cos^2 of an RRP rod's angle to its guide: ``1 - (h / l)^2``."""
    return (length * length - hgt * hgt) / (length * length)


def rrp_pressure(hgt, length):
    """Angle between an RRP rod and its guide (rad, in [0, pi/2])."""
    return ops.arcsin(ops.fabs(hgt) / length)


def rpr_margin(p: PointJet, q: PointJet, offset):
    """cos^2 of an RPR group's pressure angle: ``(rho^2 - offset^2) / rho^2``."""
    rx, ry = p.x - q.x, p.y - q.y
    rho2 = rx * rx + ry * ry
    return (rho2 - offset * offset) / (rho2 + 1e-300)


def rpr_pressure(offset, s):
    """Pressure angle of an RPR group: ``atan(|offset| / |s|)``."""
    return ops.arctan2(ops.fabs(offset) + 0.0 * s, ops.fabs(s))


@dataclass(frozen=True)
class Group:
    """Base of the groups: ``key`` names the group (its new point, or an RPR group's link);
    ``params`` maps each role (``"length"``, ``"angle"`` ...) to its parameter name."""

    key: str
    params: tuple = ()

    kind = "group"

    def p(self, v, role):
        return v[self._roles[role]]

    def has(self, role) -> bool:
        return role in self._roles

    @functools.cached_property
    def _roles(self) -> dict:
        """``params`` as a dict, made once per group (a motion asks for each parameter)."""
        return dict(self.params)

    @property
    def label(self) -> str:
        return f"{self.kind} {self.key}"

    def renamed(self, mapping):
        """A copy with parameter names replaced by ``mapping`` (old -> new)."""
        from dataclasses import replace

        return replace(self, params=tuple((r, mapping.get(n, n)) for r, n in self.params))

    def requires(self) -> tuple[str, ...]:
        return ()

    def new_point(self) -> tuple[str, str] | None:
        """``(point, body that owns it)`` for the group's new point (None: no new point)."""
        return None

    def conditions(self) -> tuple[str, ...]:
        """Names of the assembly conditions (keys of the margins)."""
        return ()

    def solve(self, st: _State) -> None:  # pragma: no cover - abstract
        raise NotImplementedError


def _guide_line(st: _State, guide: Guide, group: Group):
    """(G jet, angle jet, fixed (gx, gy, angle) or None) of a group's guide."""
    v = st.v
    a = group.p(v, "angle")
    if guide.frame is not None:
        origin, frame_angle = st.frame(guide.frame)
        theta = Jet(frame_angle.value + a, frame_angle.d1, frame_angle.d2)
        g = coupler_point(origin, theta, 0.0, group.p(v, "offset"))
        return g, theta, None
    if guide.through is None:
        gx, gy = group.p(v, "x"), group.p(v, "y")
    else:
        p = st.points[guide.through]
        gx, gy = fixed_guide(p.x, p.y, group.p(v, "offset"), a)
    return PointJet(gx, gy, 0.0, 0.0, 0.0, 0.0), Jet(a, 0.0, 0.0), (gx, gy, a)


# ------------------------------------------------------------------------------ driver
@dataclass(frozen=True)
class CrankGroup(Group):
    """The driver: ``point`` on a crank of length ``length`` about the ground point ``about``, at
    the angle ``phi + phase`` from +x (counter-clockwise)."""

    about: str = ""
    link: str = ""

    kind = "crank"

    def requires(self):
        return (self.about,)

    def solve(self, st):
        v = st.v
        o = st.points[self.about]
        phase = self.p(v, "phase")
        if ops.is_zero(phase):  # the grid's cosines and sines, remembered (ops.cos_sin)
            c, s = ops.cos_sin(st.phi)
            a = crank_pin(c, s, self.p(v, "length"), o.x, o.y)
            zero = 0.0 * a.x
            angle = st.phi + zero
        else:
            a = crank(st.phi, self.p(v, "length"), o.x, o.y, phase)
            zero = 0.0 * a.x
            angle = st.phi + phase + zero
        st.points[self.key] = a
        st.links[self.link] = Jet(angle, 1.0 + zero, zero)

    def new_point(self):
        return self.key, self.link

    def bodies(self):
        return (Body(self.link, "crank", self.about, self.key, self.key),)

    def joints(self, owner):
        return (("revolute", self.about, self.link, owner(self.about)),)


@dataclass(frozen=True)
class SliderDriverGroup(Group):
    """The driver as a linear input: ``point`` on a block driven along a fixed straight
    ``guide`` by the prescribed displacement ``s`` (the input, m, measured along the guide from
    its point), over the ``travel`` ``(lo, hi)`` (m) that cycles, charts and drawings cover."""

    guide: Guide = field(default_factory=Guide)
    link: str = ""
    travel: tuple[float, float] = (0.0, 1.0)

    kind = "slider input"

    @property
    def label(self):
        lo, hi = self.travel
        return f"driving slider {self.key} (block {self.link}, travel {lo:.6g} to {hi:.6g} m)"

    def requires(self):
        return (self.guide.through,) if self.guide.through else ()

    def solve(self, st):
        _, _, (gx, gy, ga) = _guide_line(st, self.guide, self)
        s = st.phi
        c, sn = ops.cos(ga), ops.sin(ga)
        zero = 0.0 * (s + gx + gy + ga)
        st.points[self.key] = PointJet(
            gx + s * c + zero, gy + s * sn + zero, c + zero, sn + zero, zero, zero
        )
        st.links[self.link] = Jet(ga + zero, zero, zero)
        st.sliders[self.link] = Jet(s + zero, 1.0 + zero, zero)

    def new_point(self):
        return self.key, self.link

    def bodies(self):
        return (Body(self.link, "slider", self.key, None, self.key),)

    def joints(self, owner):
        return (("prismatic", self.key, self.link, FRAME, self.link),)


# ------------------------------------------------------------------------------ dyads
@dataclass(frozen=True)
class RRRGroup(Group):
    """RRR dyad: ``key`` at distance ``l1`` from ``first`` (link ``links[0]``) and ``l2`` from
    ``second`` (link ``links[1]``); ``branch`` +1 puts it left of ``first -> second``."""

    first: str = ""
    second: str = ""
    branch: int = 1
    links: tuple[str, str] = ("", "")

    kind = "RRR"

    @property
    def label(self):
        return f"RRR group {self.key} (links {self.links[0]}, {self.links[1]})"

    def requires(self):
        return (self.first, self.second)

    def conditions(self):
        return (self.key,)

    def solve(self, st):
        v = st.v
        p1, p2 = st.points[self.first], st.points[self.second]
        l1, l2 = self.p(v, "l1"), self.p(v, "l2")
        apart = rrr_apart(p1, p2)  # the dyad's own, shared with its margin
        margin = rrr_margin(apart[2], l1, l2)
        st.margins[self.key] = margin
        if st.strict and not ops.is_symbolic(margin):  # numbers, checked: p1 as it is
            c, t1, t2 = dyad_rrr(p1, p2, l1, l2, self.branch, phi=st.phi, apart=apart)
        else:
            moved = None
            if ops.is_symbolic(margin):
                dx, dy, d2 = apart
                d = ops.sqrt(d2)
                lo, hi = ops.fabs(l1 - l2) + _HOLD * (l1 + l2), (l1 + l2) * (1.0 - _HOLD)
                k = ops.fmin(ops.fmax(d, lo), hi) / d
                moved = (p2.x - k * dx, p2.y - k * dy)
            held = st.relax(p1, margin, moved)
            apart = apart if held is p1 else None
            c, t1, t2 = dyad_rrr(held, p2, l1, l2, self.branch, phi=st.check_phi, apart=apart)
        st.points[self.key] = c
        st.links[self.links[0]] = t1
        st.links[self.links[1]] = t2
        st.transmission[self.key], st.pressure[self.key] = rrr_angles(t1, t2)

    def new_point(self):
        return self.key, self.links[0]

    def bodies(self):
        return (
            Body(self.links[0], "link", self.first, self.key, self.key),
            Body(self.links[1], "link", self.second, self.key, self.key),
        )

    def joints(self, owner):
        a, b = self.links
        return (
            ("revolute", self.first, a, owner(self.first)),
            ("revolute", self.second, b, owner(self.second)),
            ("revolute", self.key, b, a),
        )


@dataclass(frozen=True)
class RRPGroup(Group):
    """RRP dyad: a rod ``link`` of ``length`` from ``start`` to the slider ``key`` on ``guide``;
    ``branch`` +1 puts the slider ahead of the foot of ``start`` along the guide direction."""

    start: str = ""
    guide: Guide = field(default_factory=Guide)
    branch: int = 1
    link: str = ""
    slider: str = ""

    kind = "RRP"

    @property
    def label(self):
        return f"RRP group {self.key} (rod {self.link}, slider {self.slider})"

    def requires(self):
        out = [self.start]
        if self.guide.through is not None:
            out.append(self.guide.through)
        if self.guide.frame is not None:
            out += [self.guide.frame.origin] + ([self.guide.frame.axis] or [])
        return tuple(x for x in out if x)

    def conditions(self):
        return (self.key,)

    def solve(self, st):
        v = st.v
        p = st.points[self.start]
        length = self.p(v, "length")
        g, theta, fixed = _guide_line(st, self.guide, self)
        hgt = guide_height(p, g.x, g.y, theta.value)  # of the rod's start over the guide
        margin = rrp_margin(hgt, length)
        st.margins[self.key] = margin
        if not st.strict or ops.is_symbolic(margin):  # (numbers, checked: p as it is)
            moved = None
            if ops.is_symbolic(margin):
                lim = length * (1.0 - _HOLD)
                shift = ops.fmin(ops.fmax(hgt, -lim), lim) - hgt
                moved = (p.x - shift * ops.sin(theta.value), p.y + shift * ops.cos(theta.value))
            p = st.relax(p, margin, moved)
        if fixed is not None:
            # the height over the guide is the dyad's own where p was not moved (the sum of the
            # same two products, in the other order)
            held = hgt if p is st.points[self.start] else None
            b, slide, rod = dyad_rrp(p, length, *fixed, self.branch, st.check_phi, held)
        else:
            b, slide, rod = dyad_rrp_on(p, length, g, theta, self.branch, st.check_phi)
        zero = 0.0 * b.x
        st.points[self.key] = b
        st.links[self.link] = rod
        st.links[self.slider] = Jet(theta.value + zero, theta.d1 + zero, theta.d2 + zero)
        st.sliders[self.slider] = slide
        pressure = rrp_pressure(hgt, length)
        st.pressure[self.key] = pressure
        st.transmission[self.key] = np.pi / 2 - pressure

    def new_point(self):
        return self.key, self.slider

    def bodies(self):
        return (
            Body(self.slider, "slider", self.key, None, self.key),
            Body(self.link, "link", self.start, self.key, self.key),
        )

    def joints(self, owner):
        return (
            ("revolute", self.start, self.link, owner(self.start)),
            ("revolute", self.key, self.slider, self.link),
            ("prismatic", self.key, self.slider, self.guide.carrier, self.slider),
        )


@dataclass(frozen=True)
class RPRGroup(Group):
    """RPR dyad: the link ``key`` turns about the point ``about``; a block pinned at the point
    ``through`` slides on it, the slot lying ``offset`` to the left of the link's axis through
    ``about``. ``branch`` +1 takes the block on the link's positive axis."""

    about: str = ""
    through: str = ""
    branch: int = 1
    block: str = ""

    kind = "RPR"

    @property
    def label(self):
        return f"RPR group {self.key} (link about {self.about} through block {self.block})"

    def requires(self):
        return (self.about, self.through)

    def conditions(self):
        return (self.key,)

    def solve(self, st):
        v = st.v
        p, q = st.points[self.through], st.points[self.about]
        off = self.p(v, "offset")
        margin = rpr_margin(p, q, off)
        st.margins[self.key] = margin
        if not st.strict or ops.is_symbolic(margin):  # (numbers, checked: p as it is)
            moved = None
            if ops.is_symbolic(margin):
                rx, ry = p.x - q.x, p.y - q.y
                rho = ops.sqrt(rx * rx + ry * ry + 1e-300)
                k = ops.fmax(rho, ops.fabs(off) * (1.0 + _HOLD) + 1e-300) / rho
                moved = (q.x + k * rx, q.y + k * ry)
            p = st.relax(p, margin, moved)
        th, s = dyad_rpr_on(p, q, off, self.branch, st.check_phi)
        st.links[self.key] = th
        st.links[self.block] = th
        st.sliders[self.block] = s
        pressure = rpr_pressure(off, s.value)
        st.pressure[self.key] = pressure
        st.transmission[self.key] = np.pi / 2 - pressure

    def bodies(self):
        return (
            Body(self.key, "link", self.about, None, self.key),
            Body(self.block, "block", self.through, None, self.key),
        )

    def joints(self, owner):
        return (
            ("revolute", self.about, self.key, owner(self.about)),
            ("revolute", self.through, self.block, owner(self.through)),
            ("prismatic", self.through, self.block, self.key, self.key),
        )


@dataclass(frozen=True)
class AttachGroup(Group):
    """A point fixed on a body: ``along`` (m) along the frame's x axis from its origin and
    ``left`` (m) to its left."""

    frame: Frame = field(default_factory=lambda: Frame("", ""))

    kind = "point"

    @property
    def label(self):
        return f"point {self.key} on {self.frame.body}"

    def requires(self):
        return tuple(x for x in (self.frame.origin, self.frame.axis) if x)

    def solve(self, st):
        v = st.v
        origin, angle = st.frame(self.frame)
        st.points[self.key] = coupler_point(origin, angle, self.p(v, "along"), self.p(v, "left"))

    def new_point(self):
        return self.key, self.frame.body

    def bodies(self):
        return ()

    def joints(self, owner):
        return ()


# ------------------------------------------------------------------------------ higher pair
@dataclass(frozen=True)
class FollowerGroup(Group):
    """Higher pair: a follower ``key`` on a slider on a fixed ``guide``, in contact with the
    ``profile`` curve carried by the body of ``frame``; a roller (parameter ``roller``, its
    radius; 0 for a point) or a flat face (parameter ``face``, its normal's angle from the
    guide direction)."""

    frame: Frame = field(default_factory=lambda: Frame("", ""))
    profile: Any = None
    guide: Guide = field(default_factory=Guide)
    flat: bool = False
    branch: int = 1
    side: int = 1
    slider: str = ""
    samples: int = 24
    iterations: int = 8

    kind = "higher pair"

    @property
    def label(self):
        what = "flat-faced" if self.flat else "roller"
        return f"higher pair {self.key} ({what} follower on the profile of {self.frame.body})"

    @property
    def contact_point(self) -> str:
        return f"{self.key}_contact"

    @property
    def normal_key(self) -> str:
        return f"{self.key} normal"

    def requires(self):
        out = [self.frame.origin, self.frame.axis, self.guide.through]
        return tuple(x for x in out if x)

    def conditions(self):
        if self.profile.closed:
            return (f"{self.key}:contact",) if not self.flat else ()
        base = (f"{self.key}:start", f"{self.key}:end")
        return base if self.flat else base + (f"{self.key}:contact",)

    def profile_values(self, v):
        return {role: self.p(v, f"profile_{role}") for role in self.profile.roles}

    def solve(self, st):
        v = st.v
        origin, angle = st.frame(self.frame)
        _, _, fixed = _guide_line(st, self.guide, self)
        gx, gy, ga = fixed
        res = cam_contact(
            origin,
            angle,
            self.profile,
            self.profile_values(v),
            gx,
            gy,
            ga,
            radius=0.0 if self.flat else self.p(v, "roller"),
            face=self.p(v, "face") if self.flat else None,
            branch=self.branch,
            side=self.side,
            phi=st.check_phi,
            samples=self.samples,
            iterations=self.iterations,
        )
        zero = 0.0 * res.s.value
        st.points[self.key] = res.follower
        st.points[self.contact_point] = res.point
        st.links[self.slider] = Jet(ga + zero, zero, zero)
        st.sliders[self.slider] = res.s
        st.pressure[self.key] = res.pressure
        st.transmission[self.key] = np.pi / 2 - res.pressure
        st.extra[self.normal_key] = res.normal
        st.extra[f"{self.key} sigma"] = res.sigma
        lost = -1.0 + zero

        def guard(m):
            return ops.where(res.found, m, lost)

        lo, hi = self.profile.domain
        if not self.profile.closed:
            st.margins[f"{self.key}:start"] = guard((res.sigma - lo) / (hi - lo))
            st.margins[f"{self.key}:end"] = guard((hi - res.sigma) / (hi - lo))
        if not self.flat:
            # cos^2 of the pressure angle: 0 where the guide grazes the roller's path
            cn = ops.cos(res.normal - ga)
            st.margins[f"{self.key}:contact"] = guard(cn * cn)

    def new_point(self):
        return self.key, self.slider

    def bodies(self):
        return (Body(self.slider, "follower", self.key, None, self.key),)

    def joints(self, owner):
        return (
            ("prismatic", self.key, self.slider, FRAME, self.slider),
            ("contact", self.contact_point, self.slider, self.frame.body, None, self.normal_key),
        )
