"""Containers for motion over a crank cycle.

Inside the blocks a quantity travels as a *jet*: its value and its first and second derivatives
with respect to the crank angle (the velocity and acceleration *analogs*). :func:`to_time` turns
analogs into time derivatives for a crank speed ``omega`` (rad/s) and crank angular acceleration
``epsilon`` (rad/s^2):

    velocity     = analog1 * omega
    acceleration = analog2 * omega**2 + analog1 * epsilon

All fields are numpy arrays broadcast over (designs..., angles) or CasADi expressions.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar, NamedTuple

import numpy as np

from ..errors import MechanismError, UnknownNameError
from . import ops

__all__ = [
    "Jet",
    "PointJet",
    "PointTrack",
    "LinkTrack",
    "SliderTrack",
    "Motion",
    "to_time",
    "Tracks",
    "UnknownNameError",
]


class Jet(NamedTuple):
    """A scalar (length, angle, displacement) with its first and second crank-angle analogs."""

    value: Any
    d1: Any
    d2: Any


class PointJet(NamedTuple):
    """A point's coordinates (m) with their first (m/rad) and second (m/rad^2) analogs."""

    x: Any
    y: Any
    dx: Any
    dy: Any
    ddx: Any
    ddy: Any

    @staticmethod
    def fixed(x, y) -> PointJet:
        """A fixed point (frame pivot): zero analogs."""
        return PointJet(
            x, y, ops.zeros_like(x), ops.zeros_like(y), ops.zeros_like(x), ops.zeros_like(y)
        )


def to_time(jet: Jet, omega, epsilon):
    """(value, velocity, acceleration) in time from a crank-angle jet."""
    if type(epsilon) is float and epsilon == 0.0 and type(omega) is float:
        if omega == 1.0:  # the analogs themselves
            return jet.value, jet.d1, jet.d2
        return jet.value, jet.d1 * omega, jet.d2 * (omega * omega)
    return jet.value, jet.d1 * omega, jet.d2 * omega**2 + jet.d1 * epsilon


_new = object.__new__


def _fold(mu):
    """A raw transmission angle in [0, pi] folded into [0, pi/2] (the supplement when obtuse)."""
    return ops.fmin(mu, np.pi - mu)


def _point_track(x, y, vx, vy, ax, ay):
    """``PointTrack(x, y, vx, vy, ax, ay)`` without the frozen dataclass's ``__init__``, which
    sets each field through its own ``object.__setattr__`` call (a motion builds a track per
    point: for one design that overhead is a good part of the call)."""
    t = _new(PointTrack)
    d = t.__dict__
    d["x"], d["y"], d["vx"], d["vy"], d["ax"], d["ay"] = x, y, vx, vy, ax, ay
    return t


def _link_track(angle, omega, epsilon):
    """``LinkTrack(angle, omega, epsilon)``, as :func:`_point_track`."""
    t = _new(LinkTrack)
    d = t.__dict__
    d["angle"], d["omega"], d["epsilon"] = angle, omega, epsilon
    return t


def _slider_track(position, velocity, acceleration):
    """``SliderTrack(position, velocity, acceleration)``, as :func:`_point_track`."""
    t = _new(SliderTrack)
    d = t.__dict__
    d["position"], d["velocity"], d["acceleration"] = position, velocity, acceleration
    return t


@dataclass(frozen=True)
class PointTrack:
    """Track of a point over the cycle: position (m), velocity (m/s), acceleration (m/s^2).

    With ``speed=None`` in ``motion`` the velocity and acceleration are the analogs (m/rad,
    m/rad^2).
    """

    x: Any
    y: Any
    vx: Any
    vy: Any
    ax: Any
    ay: Any

    #: ``PointTrack.of(x, y, vx, vy, ax, ay)``: ``PointTrack(x, y, vx, vy, ax, ay)``, quicker
    #: (see :func:`_point_track`)
    of = staticmethod(_point_track)

    @property
    def velocity(self):
        """Magnitude of the velocity."""
        return ops.hypot(self.vx, self.vy)

    @property
    def acceleration(self):
        """Magnitude of the acceleration."""
        return ops.hypot(self.ax, self.ay)

    def along(self, angle):
        """Velocity and acceleration components along the direction ``angle`` (rad from +x)."""
        c, s = ops.cos(angle), ops.sin(angle)
        return self.vx * c + self.vy * s, self.ax * c + self.ay * s

    @classmethod
    def from_jet(cls, p: PointJet, omega, epsilon) -> PointTrack:
        if type(epsilon) is float and epsilon == 0.0 and type(omega) is float:
            if omega == 1.0:  # the analogs themselves
                return _point_track(*p)
            w2 = omega * omega
            return _point_track(p.x, p.y, p.dx * omega, p.dy * omega, p.ddx * w2, p.ddy * w2)
        return _point_track(
            p.x,
            p.y,
            p.dx * omega,
            p.dy * omega,
            p.ddx * omega**2 + p.dx * epsilon,
            p.ddy * omega**2 + p.dy * epsilon,
        )


@dataclass(frozen=True)
class LinkTrack:
    """Angle of a link from +x (rad, counter-clockwise), angular velocity (rad/s), acceleration
    (rad/s^2). Analogs (rad/rad, rad/rad^2) when the motion was asked without a speed.

    ``angle`` is the angle as computed, in (-pi, pi]: a link swinging through the -x direction
    jumps by 2 pi there, so ``np.ptp(angle)`` is no swing. :attr:`unwrapped_angle` and
    :attr:`swing` follow the link along the cycle instead.
    """

    angle: Any
    omega: Any
    epsilon: Any

    @property
    def unwrapped_angle(self) -> np.ndarray:
        """The angle (rad) made continuous along the cycle (the last axis, the crank angles):
        ``np.unwrap`` removes the 2 pi jumps where the link passes through the -x direction.
        Raises MechanismError for symbolic (CasADi) angles."""
        if type(self.angle).__module__.partition(".")[0] == "casadi":  # asarray makes NaN
            raise MechanismError(
                "unwrapped_angle and swing need numeric angles (a motion evaluated in numpy), "
                f"not a CasADi {type(self.angle).__name__}"
            )
        angle = np.asarray(self.angle, dtype=float)
        return np.unwrap(angle, axis=-1) if angle.ndim else angle

    @property
    def swing(self):
        """The link's swing over the cycle (rad): the range of :attr:`unwrapped_angle` along the
        crank angles (one value per design); a full turn when the link revolves. The crank
        angles must sample the cycle finely enough (steps well under pi) to follow the link."""
        return np.ptp(self.unwrapped_angle, axis=-1)

    #: ``LinkTrack.of(angle, omega, epsilon)``: ``LinkTrack(angle, omega, epsilon)``, quicker
    #: (see :func:`_point_track`)
    of = staticmethod(_link_track)

    @classmethod
    def from_jet(cls, j: Jet, omega, epsilon) -> LinkTrack:
        return _link_track(*to_time(j, omega, epsilon))


@dataclass(frozen=True)
class SliderTrack:
    """A slider's position (m) along its guide, its velocity (m/s) and acceleration (m/s^2)."""

    position: Any
    velocity: Any
    acceleration: Any

    @classmethod
    def from_jet(cls, j: Jet, omega, epsilon) -> SliderTrack:
        return _slider_track(*to_time(j, omega, epsilon))


class Tracks(dict):
    """A motion's named tracks (``motion.points``, ``.links``, ``.sliders``): a plain dict
    whose missing name raises :class:`UnknownNameError` naming the known names. Only a miss
    costs anything: lookups, iteration and ``get`` are dict's own."""

    __slots__ = ()
    what = "track"

    def __missing__(self, name):
        from difflib import get_close_matches

        known = sorted(map(str, self))
        close = [k for k in known if k.lower() == str(name).lower()]
        close = close or get_close_matches(str(name), known, n=1, cutoff=0.6)
        hint = f" (did you mean {close[0]!r}?)" if close else ""
        raise UnknownNameError(
            f"no {self.what} {name!r} in this motion{hint}; its {self.what}s: "
            + (", ".join(known) if known else "none")
        )


class _Points(Tracks):
    __slots__ = ()
    what = "point"


class _Links(Tracks):
    __slots__ = ()
    what = "link"


class _Sliders(Tracks):
    __slots__ = ()
    what = "slider"


def _as_tracks(points, links, sliders, omega, epsilon):
    """The named jets ``points`` (:class:`PointJet`), ``links`` and ``sliders`` (:class:`Jet`)
    as a motion's three :class:`Tracks` dicts at the crank speed ``omega`` and acceleration
    ``epsilon`` (a track given instead of a jet is kept as it is). Each track's fields are
    those its ``from_jet`` gives, made without the frozen dataclasses' ``__init__`` (see
    :func:`_point_track`) and, for a number ``omega`` and no ``epsilon``, without a call per
    track: a motion of one design makes a track per point and link, and those calls were a
    good part of its time."""
    pt, lt, st = PointTrack, LinkTrack, SliderTrack
    points, links, sliders = _Points(points), _Links(links), _Sliders(sliders)
    if not (type(epsilon) is float and epsilon == 0.0 and type(omega) is float):
        for k, p in points.items():
            if type(p) is not pt:
                points[k] = pt.from_jet(p, omega, epsilon)
        for k, j in links.items():
            if type(j) is not lt:
                links[k] = lt.from_jet(j, omega, epsilon)
        for k, j in sliders.items():
            if type(j) is not st:
                sliders[k] = st.from_jet(j, omega, epsilon)
        return points, links, sliders
    if omega == 1.0:  # the analogs themselves
        for k, p in points.items():
            if type(p) is not pt:
                points[k] = t = _new(pt)
                d = t.__dict__
                d["x"], d["y"], d["vx"], d["vy"], d["ax"], d["ay"] = p
        for k, j in links.items():
            if type(j) is not lt:
                links[k] = t = _new(lt)
                d = t.__dict__
                d["angle"], d["omega"], d["epsilon"] = j
        for k, j in sliders.items():
            if type(j) is not st:
                sliders[k] = t = _new(st)
                d = t.__dict__
                d["position"], d["velocity"], d["acceleration"] = j
        return points, links, sliders
    # from_jet's and to_time's second branch: analogs times omega, second ones times omega^2
    w2 = omega * omega
    for k, p in points.items():
        if type(p) is not pt:
            points[k] = t = _new(pt)
            d = t.__dict__
            x, y, dx, dy, ddx, ddy = p
            d["x"], d["y"], d["vx"], d["vy"] = x, y, dx * omega, dy * omega
            d["ax"], d["ay"] = ddx * w2, ddy * w2
    for k, j in links.items():
        if type(j) is not lt:
            links[k] = t = _new(lt)
            d = t.__dict__
            a, d1, d2 = j
            d["angle"], d["omega"], d["epsilon"] = a, d1 * omega, d2 * w2
    for k, j in sliders.items():
        if type(j) is not st:
            sliders[k] = t = _new(st)
            d = t.__dict__
            a, d1, d2 = j
            d["position"], d["velocity"], d["acceleration"] = a, d1 * omega, d2 * w2
    return points, links, sliders


@dataclass(frozen=True)
class Motion:
    """Motion of a mechanism over the crank angles ``phi``.

    Attributes
    ----------
    phi : crank angles (rad), as given.
    omega, epsilon : crank angular velocity (rad/s) and acceleration (rad/s^2); 1 and 0 for analogs.
    points : named :class:`PointTrack` objects (``motion.points["B"]``).
    links : named :class:`LinkTrack` objects (``motion.links["rocker"]``).
    sliders : named :class:`SliderTrack` objects; the main one is also ``motion.slider``.
        The three are :class:`Tracks` dicts: a name they lack raises :class:`UnknownNameError`
        (a MechanismError and a KeyError) listing the names they have.
    pressure_angle : angle (rad, in [0, pi/2]) between the force a driving link transmits to the
        output and the output's velocity, at every angle.
    transmission_angle : the transmission angle (rad, in [0, pi/2]), the design quantity: the
        angle between the coupler (rod) and the output link counted as its supplement when
        obtuse, so ``pi/2 - transmission_angle`` is the deviation from the ideal 90 deg; None
        if the mechanism defines none. A property of ``raw_transmission_angle``.
    raw_transmission_angle : the angle (rad, in [0, pi]) between the coupler (rod) and the
        output link as drawn, not folded: its sign of ``pi/2 - angle`` tells the assembly.
    extra : other named per-angle quantities of a particular mechanism.
    pressure_angles, transmission_angles, raw_transmission_angles : per group of a general
        linkage (named by the group), the pressure angles and the (folded) and raw transmission
        angles (rad), as above; empty for the named mechanisms, whose ``pressure_angle`` is
        their one output's.
    """

    phi: Any
    omega: Any
    epsilon: Any
    points: dict[str, PointTrack]
    links: dict[str, LinkTrack]
    pressure_angle: Any
    sliders: dict[str, SliderTrack] = field(default_factory=dict)
    raw_transmission_angle: Any = None
    extra: dict[str, Any] = field(default_factory=dict)
    pressure_angles: dict[str, Any] = field(default_factory=dict)
    raw_transmission_angles: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self):
        d = self.__dict__  # the named tracks as Tracks: a missing name says what there is
        if type(self.points) is not _Points:
            d["points"] = _Points(self.points)
        if type(self.links) is not _Links:
            d["links"] = _Links(self.links)
        if type(self.sliders) is not _Sliders:
            d["sliders"] = _Sliders(self.sliders)

    @property
    def transmission_angle(self):
        """The transmission angle (rad, in [0, pi/2]): the raw angle folded, ``pi - mu`` for
        an obtuse ``mu`` (numpy arrays and CasADi expressions alike); None if undefined."""
        mu = self.raw_transmission_angle
        return None if mu is None else _fold(mu)

    @property
    def transmission_angles(self) -> dict[str, Any]:
        """Per group, the transmission angle folded into [0, pi/2] (rad), as
        :attr:`transmission_angle`."""
        return {k: _fold(v) for k, v in self.raw_transmission_angles.items()}

    @classmethod
    def from_jets(
        cls, phi, omega, epsilon, points, links, sliders, pressure_angle, raw_transmission_angle
    ) -> Motion:
        """The motion of named jets (``points``: :class:`PointJet`, ``links`` and ``sliders``:
        :class:`Jet`; a track given instead of a jet is taken as it is, e.g. a frame pivot's or
        the crank's) at the crank speed ``omega`` and acceleration ``epsilon``, with empty
        ``extra``, ``pressure_angles`` and ``raw_transmission_angles``: where the named mechanisms'
        motions end. The three dicts are copied into :class:`Tracks`, the motion's own. Built
        without the frozen dataclasses' ``__init__`` (see :func:`_point_track`)."""
        tracks = _as_tracks(points, links, sliders, omega, epsilon)
        return cls._of_tracks(
            phi, omega, epsilon, tracks, pressure_angle, raw_transmission_angle, {}, {}, {}
        )

    @classmethod
    def _of_tracks(
        cls,
        phi,
        omega,
        epsilon,
        tracks,
        pressure_angle,
        raw_transmission_angle,
        extra,
        pressure_angles,
        raw_transmission_angles,
    ) -> Motion:
        """The motion of the three :class:`Tracks` ``tracks`` (of :func:`_as_tracks`) and the
        dicts given (held, not copied), without the dataclass's ``__init__`` and
        ``__post_init__``: what :meth:`Motion` makes of the same arguments."""
        m = _new(cls)
        d = m.__dict__
        # in the fields' order, as __init__ would set them
        d["phi"], d["omega"], d["epsilon"] = phi, omega, epsilon
        d["points"], d["links"] = tracks[0], tracks[1]
        d["pressure_angle"], d["sliders"] = pressure_angle, tracks[2]
        d["raw_transmission_angle"] = raw_transmission_angle
        d["extra"], d["pressure_angles"] = extra, pressure_angles
        d["raw_transmission_angles"] = raw_transmission_angles
        return m

    @property
    def slider(self) -> SliderTrack:
        """The mechanism's main slider (the first one)."""
        if not self.sliders:
            from ..errors import UsageError

            raise UsageError(
                "this mechanism has no slider; its points: " + ", ".join(sorted(self.points))
            )
        return next(iter(self.sliders.values()))

    @property
    def is_analog(self) -> bool:
        """True when velocities are crank-angle analogs (no speed was given)."""
        return isinstance(self.omega, float) and self.omega == 1.0 and self.epsilon == 0.0

    # ---------------------------------------------------------------- tables
    #: SI units of the per-angle ``extra`` quantities a mechanism adds (``{name: unit}``)
    extra_units: ClassVar[dict[str, str]] = {}

    def _units(self):
        """(length rate, length acceleration, angle rate, angle acceleration) units."""
        if self.is_analog:
            return "m/rad", "m/rad^2", "rad/rad", "rad/rad^2"
        return "m/s", "m/s^2", "rad/s", "rad/s^2"

    def _table(self):
        from .. import tables

        v, a, w, e = self._units()

        def arr(x):
            return tables.per_angle(x, self.phi)

        cols = [("phi", "rad", arr(self.phi))]
        for name, p in self.points.items():
            for comp, unit, val in (
                ("x", "m", p.x),
                ("y", "m", p.y),
                ("vx", v, p.vx),
                ("vy", v, p.vy),
                ("ax", a, p.ax),
                ("ay", a, p.ay),
            ):
                cols.append((f"{name} {comp}", unit, arr(val)))
        for name, sl in self.sliders.items():
            cols += [
                (f"slider {name} position", "m", arr(sl.position)),
                (f"slider {name} velocity", v, arr(sl.velocity)),
                (f"slider {name} acceleration", a, arr(sl.acceleration)),
            ]
        for name, lk in self.links.items():
            cols += [
                (f"link {name} angle", "rad", arr(lk.angle)),
                (f"link {name} omega", w, arr(lk.omega)),
                (f"link {name} epsilon", e, arr(lk.epsilon)),
            ]
        cols.append(("pressure angle", "rad", arr(self.pressure_angle)))
        if self.raw_transmission_angle is not None:
            cols.append(("transmission angle", "rad", arr(self.transmission_angle)))
            cols.append(("raw transmission angle", "rad", arr(self.raw_transmission_angle)))
        for name, val in self.extra.items():
            if np.shape(val) == np.shape(self.phi):
                cols.append((name, self.extra_units.get(name, ""), arr(val)))
        return tables.table(cols)

    def to_dict(self) -> dict[str, list]:
        """The motion as columns ``{"name [unit]": values}`` in display units (one design): the
        crank angle ``phi``, every point's x, y, vx, vy, ax, ay, every slider's position,
        velocity and acceleration, every link's angle, omega and epsilon, the pressure and
        transmission angles. Velocities are analogs (per rad) when the motion has no speed."""
        from .. import tables

        return tables.as_lists(self._table())

    def to_csv(self, path=None):
        """The columns of :meth:`to_dict` as CSV, one row per crank angle: written to ``path``
        (returns the path) or returned as text when ``path`` is None."""
        from .. import tables

        return tables.write_csv(self._table(), path)

    # ---------------------------------------------------------------- figure
    def main_output(self) -> str:
        """What :meth:`plot` draws by default: the first slider, else the last link (a rocker,
        a beam), else the last point."""
        if self.sliders:
            return next(iter(self.sliders))
        if len(self.links) > 1:
            return list(self.links)[-1]
        return list(self.points)[-1]

    def plot(self, quantities=None, ax=None, title=None):
        """Position, velocity and acceleration against the crank angle, in display units.

        ``quantities`` names sliders (``"slider"`` is the main one), links (angle, angular
        velocity and acceleration) or points (x and y, then the magnitudes |v| and |a|);
        default: :meth:`main_output`. ``ax``: three axes to draw into. Returns the figure.
        """
        import matplotlib.pyplot as plt

        from .. import display
        from ..plotting import crank_axis, speed_text

        if quantities is None:
            quantities = (self.main_output(),)
        elif isinstance(quantities, str):
            quantities = (quantities,)
        if ax is None:
            fig, axes = plt.subplots(3, 1, sharex=True, figsize=(7, 7), layout="constrained")
        else:
            axes = ax
            fig = axes[0].figure
        phi = np.asarray(self.phi, dtype=float)
        x = np.rad2deg(phi)
        v, a, w, e = self._units()
        heads = []
        units: list[set] = [set(), set(), set()]
        for name in quantities:
            if name == "slider" or name in self.sliders:
                if not self.sliders:
                    raise MechanismError(
                        "this mechanism has no slider; plot a link "
                        f"({', '.join(self.links)}) or a point ({', '.join(self.points)})"
                    )
                key = next(iter(self.sliders)) if name == "slider" else name
                tr = self.sliders[key]
                series = [
                    [(f"slider {key}", "m", tr.position)],
                    [(f"slider {key}", v, tr.velocity)],
                    [(f"slider {key}", a, tr.acceleration)],
                ]
                heads.append(("position", "velocity", "acceleration"))
            elif name in self.links:
                tr = self.links[name]
                series = [
                    [(f"{name} angle", "rad", np.unwrap(np.asarray(tr.angle, dtype=float)))],
                    [(f"{name} ω", w, tr.omega)],
                    [(f"{name} ε", e, tr.epsilon)],
                ]
                heads.append(("angle", "angular velocity", "angular acceleration"))
            elif name in self.points:
                p = self.points[name]
                series = [
                    [(f"{name} x", "m", p.x), (f"{name} y", "m", p.y)],
                    [(f"|v {name}|", v, p.velocity)],
                    [(f"|a {name}|", a, p.acceleration)],
                ]
                heads.append(("position", "speed |v|", "acceleration |a|"))
            else:
                known = [*self.sliders, *self.links, *self.points]
                raise MechanismError(
                    f"unknown quantity {name!r}; this motion has {', '.join(known)}"
                )
            for k, (axis, items) in enumerate(zip(axes, series)):
                for i, (label, unit, y) in enumerate(items):
                    yv, shown = display.convert(np.asarray(y, dtype=float), unit)
                    yv, shown = display.thousands(yv, shown)
                    style = "-" if i == 0 else "--"
                    axis.plot(x, np.asarray(yv).T, style, label=f"{label}, {shown}")
                    units[k].add(shown)
        for k, axis in enumerate(axes):
            names = {h[k] for h in heads}
            head = names.pop() if len(names) == 1 else ("value", "rate", "second rate")[k]
            shown = units[k].pop() if len(units[k]) == 1 else "units in the legend"
            axis.set_ylabel(f"{head}, {shown}")
            axis.grid(True, alpha=0.35, ls=":")
            axis.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
        span = float(np.ptp(x)) if x.size > 1 else 0.0
        if 300.0 <= span <= 360.0 and x.min() >= -1e-9:
            crank_axis(axes[2], start=0.0, span=360.0)
        else:
            axes[2].set_xlabel("crank angle, deg")
        if self.is_analog:
            speed = speed_text(None)
        elif np.ndim(self.omega):
            speed = "crank speed varying over the cycle"
        else:
            speed = speed_text(self.omega)
        axes[0].set_title(title or f"motion of {', '.join(quantities)}: {speed}")
        return fig
