"""Base class and parameter validation shared by all mechanisms.

A mechanism is a frozen dataclass of its parameters (SI units). A parameter may be a number, a
numpy array (a batch of designs, broadcast against the crank angles: give it a trailing axis of
length 1, e.g. ``crank=np.linspace(.05, .1, 100)[:, None]``) or a CasADi symbol (inside an
optimizer). Numeric parameters are validated on construction; symbolic ones are not.
"""

from __future__ import annotations

import dataclasses
from typing import Any, ClassVar

import numpy as np

from .. import validate
from ..errors import MechanismError
from . import ops
from .tracks import Motion

__all__ = [
    "Mechanism",
    "check_length",
    "check_finite",
    "speed_pair",
    "fail_where",
    "as_angles",
    "input_grid",
    "input_domain",
    "guard_motion",
]


def input_domain(mechanism) -> tuple[float, float, bool]:
    """``(lo, hi, periodic)`` of a mechanism's input over one cycle: ``(0, 2 pi, True)`` for a
    crank (every named mechanism), a driving slider's travel (m) with ``periodic`` False for a
    :class:`~mechsynth.kinematics.Linkage` driven by one. ``mechanism`` may be a class."""
    rng = None if isinstance(mechanism, type) else getattr(mechanism, "input_range", None)
    if rng is None:
        return 0.0, 2.0 * np.pi, True
    return float(rng[0]), float(rng[1]), bool(getattr(mechanism, "periodic", True))


def input_grid(mechanism, n: int):
    """``n`` inputs over one cycle of ``mechanism`` (see :func:`input_domain`): equal crank-angle
    steps over a turn (``ms.cycle(n)``), or equal steps over a driving slider's travel with both
    ends included."""
    from ..units import cycle

    lo, hi, periodic = input_domain(mechanism)
    if periodic:
        return cycle(int(n), start=lo)
    return np.linspace(lo, hi, int(n))


def _first_bad(arr, bad):
    idx = np.unravel_index(int(np.argmax(bad)), bad.shape)
    at = f" (design index {idx})" if arr.ndim else ""
    return arr[idx], at


def check_finite(name: str, value):
    """Return ``value`` (float or float array) or raise MechanismError (a ValueError) if it is
    not a finite real number or array of them (strings, booleans, complex numbers and empty
    arrays are refused; see :mod:`mechsynth.validate`)."""
    return validate.real(name, value)


def check_length(name: str, value):
    """Return ``value`` or raise MechanismError (a ValueError) if any entry is not finite and
    strictly positive."""
    return validate.length(name, value)


def as_angles(phi):
    """Crank angles as a float array (or number, or CasADi expression): any array-like works,
    a list, a tuple, a ``range``. NaN and infinite angles are refused (MechanismError)."""
    if type(phi) is np.ndarray and phi.dtype == np.float64:
        if ops.finite(phi):  # every angle finite (else the exact test, in validate.angles)
            return phi
    if ops.is_symbolic(phi):
        return phi
    return validate.angles(phi)


#: largest crank speed (rad/s) a motion accepts: accelerations grow with its square
MAX_SPEED = 1e100

#: how many (designs x angles) arrays a named mechanism's motion holds at its peak
MOTION_ARRAYS = 64


def guard_motion(params: dict, phi, *rates, arrays: int = MOTION_ARRAYS):
    """Check, before computing, that the parameters, the crank angles and the crank speed and
    acceleration (``rates``) broadcast together, and refuse a motion of so many designs x
    angles that its working arrays (about ``arrays`` of them) would exceed
    :data:`mechsynth.validate.MAX_BYTES`. O(parameters) work, none for scalar parameters."""
    n = phi.size if isinstance(phi, np.ndarray) else 1
    batch = False
    for v in (*params.values(), *rates):
        if isinstance(v, np.ndarray) and v.ndim:
            n *= v.size
            batch = True
    if not batch:
        if n * arrays * 8 > validate.MAX_BYTES:  # one design over a huge grid
            validate.check_size(f"a motion over {n} angles", arrays * float(n))
        return
    named = {**params, "crank angles": phi}
    named.update({k: v for k, v in zip(("speed", "epsilon"), rates)})
    shape = validate.broadcast(**named)
    if n * arrays * 8 > validate.MAX_BYTES:
        validate.check_size(
            f"a motion over {int(np.prod(shape))} designs x angles",
            arrays * float(np.prod(shape)),
        )


def speed_pair(speed, epsilon):
    """(omega, epsilon) for a motion: analogs (1, 0) when ``speed`` is None."""
    if speed is None:
        if type(epsilon) is float and epsilon == 0.0:
            return 1.0, 0.0
        if not ops.is_symbolic(epsilon) and np.any(np.asarray(epsilon) != 0.0):
            raise MechanismError("epsilon (crank angular acceleration) needs a speed")
        return 1.0, 0.0
    if not ops.is_symbolic(speed):
        speed = check_finite("speed", speed)
        if (abs(speed) > MAX_SPEED) if type(speed) is float else np.any(np.abs(speed) > MAX_SPEED):
            raise MechanismError(
                f"speed must be at most {MAX_SPEED:g} rad/s in magnitude (its squares overflow), "
                f"got {np.max(np.abs(speed)):g}"
            )
    if not ops.is_symbolic(epsilon):
        epsilon = check_finite("epsilon", epsilon)
    return speed, epsilon


def fail_where(condition, template: str, **values):
    """Raise MechanismError if ``condition`` holds for any design (numpy only; symbols pass).

    ``template`` is formatted with ``values`` taken at the first failing design (as ``.6g``) and
    ``{at}``, which names that design's index in a batch (empty for a single design).
    """
    if condition is False or type(condition) is np.bool_ and not condition:
        return  # one numeric design that passes
    if ops.is_symbolic(condition, *values.values()):
        return
    cond = np.asarray(condition)
    if not np.any(cond):
        return
    idx = np.unravel_index(int(np.argmax(cond)), cond.shape) if cond.ndim else ()
    picked = {
        k: f"{float(np.broadcast_to(np.asarray(v, dtype=float), cond.shape)[idx]):.6g}"
        for k, v in values.items()
    }
    at = f" (design index {tuple(int(i) for i in idx)})" if cond.ndim else ""
    raise MechanismError(template.format(at=at, **picked))


class Drawable:
    """Drawing and animation from a :meth:`sketch` (what a mechanism looks like at a set of
    crank angles): shared by the named mechanisms and the general
    :class:`~mechsynth.kinematics.Linkage`."""

    #: +1 when the machine runs with increasing crank angle, -1 when the other way
    turn_sign: ClassVar[int] = 1
    #: points whose paths drawings and animations trace by default
    trace_points: ClassVar[tuple[str, ...]] = ()

    def turn(self, n: int = 48):
        """``n`` crank angles over one turn in the machine's direction of rotation, from 0."""
        from ..units import cycle

        return self.turn_sign * cycle(n)

    def sketch(self, phi, **options):
        """What the mechanism looks like at crank angles ``phi``: a
        :class:`~mechsynth.kinematics.sketch.Sketch` for the generic renderer."""
        raise NotImplementedError(f"{type(self).__name__} does not describe its drawing yet")

    def _drawing_sketch(self, phi, n, options):
        """The sketch for ``draw``: the angle asked first, then a turn (for guides and paths);
        the asked angle alone when the mechanism cannot make the turn."""
        from ..errors import MechanismError

        phi = as_angles(phi)
        if np.ndim(phi):
            raise MechanismError(f"draw takes one crank angle (rad), got shape {np.shape(phi)}")
        try:
            return self.sketch(np.concatenate([[phi], phi + self.turn(n)]), **options)
        except MechanismError:
            return self.sketch(np.array([phi]), **options)

    def draw(
        self,
        phi=0.0,
        ax=None,
        *,
        trace=None,
        color=None,
        alpha: float = 1.0,
        labels: bool = True,
        title=None,
        **options,
    ):
        """Draw the mechanism at crank angle ``phi`` (rad, the mechanism's convention).

        Links, joints, frame pivots with hatching, guides over the slider travel and the paths
        of the points in ``trace`` (default: the mechanism's ``trace_points``; ``()`` for none)
        over a turn, in display length units. ``options`` go to :meth:`sketch` (e.g.
        ``coupler_points``). ``title``: None titles a new axes with the design and the angle.
        Returns the matplotlib axes.
        """
        from .drawing import draw_sketch

        sk = self._drawing_sketch(phi, 180, options)
        trace = self.trace_points if trace is None else tuple(trace)
        return draw_sketch(
            sk, 0, ax, trace=trace, color=color, alpha=alpha, labels=labels, title=title
        )

    def animate(
        self,
        angles=None,
        speed=None,
        *,
        frames: int = 48,
        trace=None,
        duration=None,
        figsize=None,
        dpi: int = 80,
        title: str | None = None,
        **options,
    ):
        """Animate the mechanism over ``angles`` (rad; default: ``frames`` angles over one turn
        in the machine's direction).

        ``speed`` (rad/s): the machine's crank speed; the title then shows the time, and the
        playback runs in real time when that lasts 1-20 s, else at about 3 s per turn (the
        title says how much slower). Returns a :class:`~mechsynth.kinematics.drawing.
        MechanismAnimation` (a matplotlib ``FuncAnimation``): ``.save("x.gif")`` (pillow),
        ``.save("x.mp4")`` (ffmpeg), ``.to_html()`` for notebooks.
        """
        from .drawing import animate_sketch

        angles = self.turn(int(frames)) if angles is None else np.atleast_1d(as_angles(angles))
        if np.asarray(angles).size < 2:
            raise MechanismError("animate needs at least two crank angles")
        sk = self.sketch(np.asarray(angles, dtype=float), **options)
        trace = self.trace_points if trace is None else tuple(trace)
        return animate_sketch(
            sk,
            speed=speed,
            trace=trace,
            duration=duration,
            figsize=figsize,
            dpi=dpi,
            title=title,
        )


class Mechanism(Drawable):
    """Base of the named mechanisms (frozen dataclasses of their parameters).

    Subclasses implement :meth:`motion`. ``parameters`` lists the numeric fields that a
    :class:`~mechsynth.synthesis.Problem` may vary.
    """

    parameters: ClassVar[tuple[str, ...]] = ()
    #: the parameters that are lengths (> 0): problems refuse bounds that reach 0
    length_parameters: ClassVar[tuple[str, ...]] = ()
    #: main output for objectives that name none ("slider" or a point name)
    default_output: ClassVar[str] = "slider"
    #: SI unit of each parameter for reports ("m" for the ones not listed)
    parameter_units: ClassVar[dict[str, str]] = {}
    #: what reports and figures call the main slider ("polished rod" on a pumping unit)
    output_label: ClassVar[str] = "slider"

    def motion(self, phi, speed=None, epsilon=0.0, **kwargs) -> Motion:  # pragma: no cover
        raise NotImplementedError

    def replace(self, **changes) -> Mechanism:
        """A copy with some parameters changed (validated again)."""
        return dataclasses.replace(self, **changes)

    def params(self) -> dict[str, Any]:
        """The parameters as a dict ``{name: value}``."""
        return {name: getattr(self, name) for name in self.parameters}

    def as_dict(self) -> dict[str, Any]:
        """Every field of the design as plain Python values (floats, strings, booleans): enough
        to build it again with ``type(design)(**design.as_dict())``."""
        out = {}
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if isinstance(v, (bool, str)) or v is None:
                out[f.name] = v
            elif isinstance(v, (int, np.integer)):
                out[f.name] = int(v)
            elif isinstance(v, (float, np.floating)) or (isinstance(v, np.ndarray) and v.size == 1):
                out[f.name] = float(v)
            else:
                out[f.name] = v
        return out

    @property
    def is_symbolic(self) -> bool:
        return ops.is_symbolic(*self.params().values())

    @classmethod
    def parameter_unit(cls, name: str) -> str:
        """SI unit of the parameter ``name`` (for reports and tables)."""
        return cls.parameter_units.get(name, "m")

    @classmethod
    def unit_of(cls, name: str) -> str:
        """SI unit of the parameter ``name`` (for reports and tables)."""
        return cls.parameter_unit(name)

    def describe(self) -> str:
        """The design in one line, in display units: ``"SliderCrank: crank 70 mm, rod 240 mm,
        offset 10 mm"``."""
        from .. import display

        name = type(self).__name__
        if self.is_symbolic:
            return f"{name} (symbolic)"
        if any(np.size(v) > 1 for v in self.params().values()):
            return f"{name} (a batch of designs)"
        parts = [f"{k} {display.fmt(v, self.unit_of(k), 4)}" for k, v in self.params().items()]
        return f"{name}: " + ", ".join(parts)
