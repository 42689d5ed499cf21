"""Applied loads for kinetostatics: gravity, point forces, torques, torsion springs, tables.

A load contributes, at every crank angle of a :class:`~mechsynth.kinematics.Motion`, forces and
torques on named bodies. :meth:`contributions` returns a list of :class:`Wrench` items (force
components in N, their point of application in m, a pure torque in N m, counter-clockwise
positive), all arrays over the angles. Load magnitudes are functions of the motion (positions,
velocities, crank angle), so speed-dependent laws such as the upsetting force of a header
(``F = F0 + c1 l_e^4`` while the punch is in contact) are written directly.
"""

from __future__ import annotations

import csv
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from ..errors import MechanismError
from ..kinematics import ops
from ..kinematics.mechanism import check_finite
from ..kinematics.tracks import Motion
from .inertia import com_track

__all__ = [
    "Wrench",
    "Gravity",
    "PointForce",
    "Torque",
    "TorsionSpring",
    "TabulatedLoad",
    "upsetting_force",
    "G",
]

G = 9.80665


class Wrench(NamedTuple):
    """Force (fx, fy) in N applied at (x, y) in m and torque tz in N m on body ``body``."""

    body: str
    fx: Any
    fy: Any
    x: Any
    y: Any
    tz: Any


def _nonnegative(name, value):
    value = check_finite(name, value)
    if not ops.is_symbolic(value) and np.any(np.asarray(value) < 0):
        raise MechanismError(f"{name} must not be negative, got {value}")
    return value


@dataclass(frozen=True)
class Gravity:
    """Gravity ``g`` (m/s^2) on every body at its centre of mass, along the direction
    ``(sin tilt, -cos tilt)``: ``tilt=0`` is -y; a tilted machine has ``tilt`` (rad, ccw)."""

    g: float = G
    tilt: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "g", _nonnegative("gravity g", self.g))
        object.__setattr__(self, "tilt", check_finite("gravity tilt", self.tilt))

    def contributions(self, motion: Motion, bodies: dict) -> list[Wrench]:
        gx, gy = self.g * np.sin(self.tilt), -self.g * np.cos(self.tilt)
        out = []
        for name, body in bodies.items():
            s = com_track(motion, body)
            out.append(Wrench(name, body.mass * gx, body.mass * gy, s.x, s.y, 0.0))
        return out


@dataclass(frozen=True)
class PointForce:
    """A force on ``body`` at the point ``point`` of the motion, ``force(motion) -> (fx, fy)``
    (N), a function of anything in the motion (positions, velocities, the crank angle)."""

    body: str
    point: str
    force: Callable[[Motion], tuple]
    name: str = "force"

    def contributions(self, motion: Motion, bodies: dict) -> list[Wrench]:
        p = motion.points[self.point]
        fx, fy = self.force(motion)
        return [Wrench(self.body, fx, fy, p.x, p.y, 0.0)]


@dataclass(frozen=True)
class Torque:
    """A pure torque ``torque(motion)`` (N m, counter-clockwise positive) on ``body``."""

    body: str
    torque: Callable[[Motion], Any]
    name: str = "torque"

    def contributions(self, motion: Motion, bodies: dict) -> list[Wrench]:
        return [Wrench(self.body, 0.0, 0.0, 0.0, 0.0, self.torque(motion))]


@dataclass(frozen=True)
class TorsionSpring:
    """Torsion spring between ``body`` (whose angle is ``motion.links[link]``) and the frame.

    Its moment magnitude is ``preload + stiffness * beta`` with the twist
    ``beta = sense * (angle0 - angle)`` (rad); it acts on the body in the direction that undoes
    the twist: torque ``= sense * (preload + stiffness * beta)`` (counter-clockwise positive)
    when ``sense=+1`` -- i.e. the spring turns the body counter-clockwise towards ``angle0``
    and beyond by the preload. ``preload`` in N m, ``stiffness`` in N m/rad (both >= 0).
    """

    body: str
    link: str
    preload: float
    stiffness: float
    angle0: float
    sense: int = 1

    def __post_init__(self):
        object.__setattr__(self, "preload", _nonnegative("spring preload", self.preload))
        object.__setattr__(self, "stiffness", _nonnegative("spring stiffness", self.stiffness))
        object.__setattr__(self, "angle0", check_finite("spring angle0", self.angle0))
        if self.sense not in (1, -1):
            raise MechanismError(f"spring sense must be +1 or -1, got {self.sense!r}")

    def twist(self, motion: Motion):
        return self.sense * (self.angle0 - motion.links[self.link].angle)

    def moment(self, motion: Motion):
        """Spring moment magnitude ``preload + stiffness * beta`` (N m)."""
        return self.preload + self.stiffness * self.twist(motion)

    def contributions(self, motion: Motion, bodies: dict) -> list[Wrench]:
        return [Wrench(self.body, 0.0, 0.0, 0.0, 0.0, self.sense * self.moment(motion))]


@dataclass(frozen=True)
class TabulatedLoad:
    """A periodic table ``y(x)`` interpolated linearly, e.g. a dynamometer card or a measured
    force over the crank angle.

    ``x`` must be strictly increasing and, with ``period`` given, cover one period
    (``x[-1] - x[0] <= period``; the table wraps around); without a period it must cover every
    abscissa asked for.
    """

    x: np.ndarray
    y: np.ndarray
    period: float | None = None
    x_field: str = "x"
    y_field: str = "y"

    def __post_init__(self):
        x = np.asarray(check_finite(self.x_field, self.x), dtype=float).ravel()
        y = np.asarray(check_finite(self.y_field, self.y), dtype=float).ravel()
        if x.size < 2 or x.size != y.size:
            raise MechanismError(
                f"table fields {self.x_field!r} and {self.y_field!r} need the same length >= 2, "
                f"got {x.size} and {y.size}"
            )
        steps = np.diff(x)
        if np.any(steps <= 0):
            i = int(np.argmax(steps <= 0))
            raise MechanismError(
                f"table field {self.x_field!r} must be strictly increasing: "
                f"row {i + 1} ({x[i + 1]:.6g}) follows {x[i]:.6g}"
            )
        if self.period is not None:
            period = float(check_finite("period", self.period))
            if period <= 0 or x[-1] - x[0] > period * (1 + 1e-12):
                raise MechanismError(
                    f"table field {self.x_field!r} spans {x[-1] - x[0]:.6g}, more than the "
                    f"period {period:.6g}"
                )
        object.__setattr__(self, "x", x)
        object.__setattr__(self, "y", y)

    @classmethod
    def from_csv(cls, path, x_field: str, y_field: str, period=None, x_scale=1.0, y_scale=1.0):
        """Read the columns ``x_field`` and ``y_field`` of a CSV file with a header row;
        ``x_scale``/``y_scale`` convert to SI (e.g. ``np.pi / 180`` for degrees)."""
        with Path(path).open(newline="") as fh:
            rows = list(csv.DictReader(fh))
        for name in (x_field, y_field):
            if not rows or name not in rows[0]:
                raise MechanismError(f"CSV {path} has no column {name!r}")
        try:
            x = np.array([float(r[x_field]) for r in rows]) * x_scale
            y = np.array([float(r[y_field]) for r in rows]) * y_scale
        except ValueError as exc:
            raise MechanismError(f"CSV {path}: non-numeric entry ({exc})") from exc
        p = None if period is None else period
        return cls(x, y, p, x_field, y_field)

    def __call__(self, xq):
        xq = np.asarray(xq, dtype=float)
        if self.period is None:
            lo, hi = self.x[0], self.x[-1]
            if np.any(xq < lo) or np.any(xq > hi):
                raise MechanismError(
                    f"table field {self.x_field!r} covers [{lo:.6g}, {hi:.6g}], asked "
                    f"[{xq.min():.6g}, {xq.max():.6g}]"
                )
            return np.interp(xq, self.x, self.y)
        return np.interp(xq, self.x, self.y, period=self.period)


def upsetting_force(s, h=0.003, c1=571.0, sigma_t=850.0, mu=0.3, d=3.0, l_blank=20.0):
    """Upsetting force (N) of a header punch at distance ``s`` (m) from the outer dead centre
    (paper 003): ``F_e = F_e0 + c1 l_e^4`` with ``l_e = 1e3 (h - s)`` in mm while ``s < h``,
    ``F_e0 = sigma_T (1 + mu d / (3 l_blank)) pi d^2 / 4``; zero out of contact.

    ``c1`` in N/mm^4 (printed "N/mm^2" in the paper), ``sigma_t`` in N/mm^2, ``d`` and
    ``l_blank`` in mm, ``h`` in m.
    """
    f0 = sigma_t * (1 + mu * d / (3 * l_blank)) * np.pi * d * d / 4
    le = 1e3 * (h - s)
    return ops.where(le > 0, f0 + c1 * ops.fmax(le, 0.0) ** 4, 0.0 * le)
