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
from typing import Any, NamedTuple

from . import ops

__all__ = ["Jet", "PointJet", "PointTrack", "LinkTrack", "SliderTrack", "Motion", "to_time"]


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
        return PointJet(x, y, 0.0 * x, 0.0 * y, 0.0 * x, 0.0 * y)


def to_time(jet: Jet, omega, epsilon):
    """(value, velocity, acceleration) in time from a crank-angle jet."""
    return jet.value, jet.d1 * omega, jet.d2 * omega**2 + jet.d1 * epsilon


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
        return cls(
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
    (rad/s^2). Analogs (rad/rad, rad/rad^2) when the motion was asked without a speed."""

    angle: Any
    omega: Any
    epsilon: Any

    @classmethod
    def from_jet(cls, j: Jet, omega, epsilon) -> LinkTrack:
        return cls(*to_time(j, omega, epsilon))


@dataclass(frozen=True)
class SliderTrack:
    """A slider's position (m) along its guide, its velocity (m/s) and acceleration (m/s^2)."""

    position: Any
    velocity: Any
    acceleration: Any

    @classmethod
    def from_jet(cls, j: Jet, omega, epsilon) -> SliderTrack:
        return cls(*to_time(j, omega, epsilon))


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
    pressure_angle : angle (rad, in [0, pi/2]) between the force a driving link transmits to the
        output and the output's velocity, at every angle.
    transmission_angle : angle (rad) between the coupler (rod) and the output link, if defined.
    extra : other named per-angle quantities of a particular mechanism.
    pressure_angles, transmission_angles : per group of a general linkage (named by the group),
        the pressure and transmission angles (rad); empty for the named mechanisms, whose
        ``pressure_angle`` is their one output's.
    """

    phi: Any
    omega: Any
    epsilon: Any
    points: dict[str, PointTrack]
    links: dict[str, LinkTrack]
    pressure_angle: Any
    sliders: dict[str, SliderTrack] = field(default_factory=dict)
    transmission_angle: Any = None
    extra: dict[str, Any] = field(default_factory=dict)
    pressure_angles: dict[str, Any] = field(default_factory=dict)
    transmission_angles: dict[str, Any] = field(default_factory=dict)

    @property
    def slider(self) -> SliderTrack:
        """The mechanism's main slider (the first one)."""
        if not self.sliders:
            raise AttributeError("this mechanism has no slider")
        return next(iter(self.sliders.values()))

    @property
    def is_analog(self) -> bool:
        """True when velocities are crank-angle analogs (no speed was given)."""
        return isinstance(self.omega, float) and self.omega == 1.0 and self.epsilon == 0.0

    def plot(self, quantities=("slider",), ax=None):
        """Plot position, velocity and acceleration of sliders/points against the crank angle.

        ``quantities`` names sliders or points; returns the matplotlib figure.
        """
        import matplotlib.pyplot as plt
        import numpy as np

        if ax is None:
            fig, axes = plt.subplots(3, 1, sharex=True, figsize=(7, 7), constrained_layout=True)
        else:
            axes = ax
            fig = axes[0].figure
        x = np.rad2deg(np.asarray(self.phi))
        v_unit, a_unit = ("m/rad", "m/rad²") if self.is_analog else ("m/s", "m/s²")
        for name in quantities:
            if name == "slider" or name in self.sliders:
                tr = self.slider if name == "slider" else self.sliders[name]
                series = (tr.position, tr.velocity, tr.acceleration)
            else:
                p = self.points[name]
                series = (p.x, p.velocity, p.acceleration)
            for axis, y in zip(axes, series):
                axis.plot(x, np.asarray(y).T, label=name)
        axes[0].set_ylabel("position, m")
        axes[1].set_ylabel(f"velocity, {v_unit}")
        axes[2].set_ylabel(f"acceleration, {a_unit}")
        axes[2].set_xlabel("crank angle, deg")
        for axis in axes:
            axis.grid(True, alpha=0.4)
        axes[0].legend()
        return fig
