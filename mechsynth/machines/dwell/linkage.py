"""Dwell linkage on a central slider-crank: a coupler point C tracing a nearly straight section and
a translating slotted output link 5 driven by C.

Conventions
-----------
* Central slider-crank OAB: crank pivot O at the origin, crank OA = ``r * rod`` at angle ``phi``
  from +x (counter-clockwise), rod AB = ``rod``, slider B on the x axis (offset 0).
* Coupler point C is fixed on the rod at distance ``k * rod`` from A. The rod is *bent* at A by
  ``gamma`` (rad): AC makes the angle ``gamma`` with AB, measured counter-clockwise from AB, so
  ``gamma > 0`` puts C to the left of the directed line A -> B (above the guide when the rod points
  along +x) and ``gamma = 0`` puts C on the rod line.
* Output link 5 is a slotted link translating on a fixed guide perpendicular to its slot. The slot
  makes the angle ``xi`` with +x and C slides in it (a block jointed at C: the Assur group of class
  II with one revolute and two prismatic pairs). Its displacement ``s5`` is measured along the guide
  direction ``n = (-sin xi, cos xi)`` from the crank pivot: ``s5 = C . n`` (the signed distance of
  the slot line from O). While C runs along a straight section parallel to the slot, s5 stays
  constant: the dwell.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ...errors import MechanismError
from ...kinematics import ops
from ...kinematics.blocks import coupler_point
from ...kinematics.mechanism import (
    Mechanism,
    as_angles,
    check_finite,
    check_length,
    fail_where,
    speed_pair,
)
from ...kinematics.slider_crank import SliderCrank
from ...kinematics.tracks import Jet, LinkTrack, Motion, PointJet, PointTrack, SliderTrack

__all__ = ["DwellSliderCrank"]


@dataclass(frozen=True)
class DwellSliderCrank(Mechanism):
    """Central slider-crank with a bent rod and a translating slotted output link (dwell linkage).

    Parameters
    ----------
    r : relative crank length ``l_OA / l`` (0 < r < 1).
    k : relative coupler distance ``l_AC / l`` (>= 0).
    gamma : bend of the rod at A (rad), counter-clockwise from AB to AC (see module docstring).
    xi : slot angle of link 5 (rad from +x); None for the coupler curve only (no link 5).
    rod : rod length ``l`` (m); all lengths scale with it.

    Examples
    --------
    >>> import numpy as np
    >>> m = DwellSliderCrank(r=0.3, k=1.2, gamma=np.deg2rad(20), xi=0.1)
    >>> mo = m.motion(np.linspace(0, 2 * np.pi, 8, endpoint=False))
    >>> mo.sliders["5"].position.shape
    (8,)
    """

    r: float
    k: float
    gamma: float = 0.0
    xi: float | None = None
    rod: float = 1.0

    parameters: ClassVar[tuple[str, ...]] = ("r", "k", "gamma")
    default_output: ClassVar[str] = "C"
    parameter_units: ClassVar[dict[str, str]] = {"r": "", "k": "", "gamma": "rad", "xi": "rad"}
    trace_points: ClassVar[tuple[str, ...]] = ("C",)
    output_label: ClassVar[str] = "link 5"

    def __post_init__(self):
        object.__setattr__(self, "r", check_length("r", self.r))
        object.__setattr__(self, "rod", check_length("rod", self.rod))
        object.__setattr__(self, "k", check_finite("k", self.k))
        object.__setattr__(self, "gamma", check_finite("gamma", self.gamma))
        if self.xi is not None:
            object.__setattr__(self, "xi", check_finite("xi", self.xi))
        if not ops.is_symbolic(self.r, self.k):
            fail_where(
                np.asarray(self.r) >= 1.0,
                "r = l_OA / l ({r}) must be < 1 for the crank to turn fully{at}",
                r=self.r,
            )
            fail_where(np.asarray(self.k) < 0.0, "k = l_AC / l ({k}) must be >= 0{at}", k=self.k)

    @property
    def slider_crank(self) -> SliderCrank:
        """The underlying central slider-crank (crank ``r * rod``, rod ``rod``, offset 0)."""
        return SliderCrank(crank=self.r * self.rod, rod=self.rod, offset=0.0)

    def coupler_jet(self, phi) -> PointJet:
        """Jet of the coupler point C (position and crank-angle analogs)."""
        u = self.k * self.rod * ops.cos(self.gamma)
        v = self.k * self.rod * ops.sin(self.gamma)
        a, _, _, rod = self.slider_crank.jets(as_angles(phi))
        return coupler_point(a, rod, u, v)

    def coupler_curve(self, phi):
        """Coordinates ``(x, y)`` (m) of C over crank angles ``phi`` (rad)."""
        c = self.coupler_jet(phi)
        return c.x, c.y

    def output_jet(self, phi, xi=None) -> Jet:
        """Jet of the displacement ``s5`` of link 5 (m, along ``(-sin xi, cos xi)``)."""
        xi = self.xi if xi is None else xi
        if xi is None:
            raise MechanismError("xi (slot angle of link 5) is not set: give xi to use link 5")
        c = self.coupler_jet(phi)
        nx, ny = -ops.sin(xi), ops.cos(xi)
        return Jet(c.x * nx + c.y * ny, c.dx * nx + c.dy * ny, c.ddx * nx + c.ddy * ny)

    def motion(self, phi, speed=None, epsilon=0.0) -> Motion:
        """Motion over crank angles ``phi`` (rad).

        Returns a Motion with points ``"O"``, ``"A"``, ``"B"``, ``"C"``; links ``"crank"``,
        ``"rod"``; sliders ``"5"`` (link 5, first, when ``xi`` is set) and ``"B"``. With ``speed``
        (rad/s) velocities and accelerations are in time, otherwise crank-angle analogs.
        """
        omega, eps = speed_pair(speed, epsilon)
        phi = as_angles(phi)
        sc = self.slider_crank
        a, b, s, rod = sc.jets(phi)
        u = self.k * self.rod * ops.cos(self.gamma)
        v = self.k * self.rod * ops.sin(self.gamma)
        c = coupler_point(a, rod, u, v)
        crank_jet = Jet(phi + 0.0 * a.x, 1.0 + 0.0 * a.x, 0.0 * a.x)
        points = {"O": PointJet.fixed(0.0 * a.x, 0.0 * a.x), "A": a, "B": b, "C": c}
        sliders = {}
        if self.xi is not None:
            sliders["5"] = SliderTrack.from_jet(self.output_jet(phi), omega, eps)
        sliders["B"] = SliderTrack.from_jet(s, omega, eps)
        # pressure angle at C on link 5: between the slot normal force and link 5's guide: 0 for
        # a guide perpendicular to the slot (frictionless), so report the slider-crank's own.
        pressure = ops.arcsin(ops.fabs(a.y) / self.rod)
        return Motion(
            phi=phi,
            omega=omega,
            epsilon=eps,
            points={name: PointTrack.from_jet(p, omega, eps) for name, p in points.items()},
            links={
                "crank": LinkTrack.from_jet(crank_jet, omega, eps),
                "rod": LinkTrack.from_jet(rod, omega, eps),
            },
            sliders=sliders,
            pressure_angle=pressure,
            raw_transmission_angle=np.pi / 2 - pressure,
        )

    def sketch(self, phi):
        """Drawing description at crank angles ``phi``: crank OA, the bent rod as the plate A-B-C,
        slider B on the x axis and, with ``xi`` set, link 5: a slot through C at ``xi`` on a
        stem F-G that slides on a fixed guide perpendicular to the slot."""
        from ...kinematics.sketch import Bar, Sketch, Slider, as_frames
        from ...units import cycle

        phi = np.atleast_1d(as_angles(phi))
        m = self.motion(phi)
        points = as_frames(m.points)
        bars = [Bar("crank", ("O", "A")), Bar("rod", ("A", "B", "C"), closed=True)]
        sliders = [Slider("B", 0.0)]
        if self.xi is not None:
            xi = float(self.xi)
            u, n = np.array([np.cos(xi), np.sin(xi)]), np.array([-np.sin(xi), np.cos(xi)])
            x, y = self.coupler_curve(cycle(360))
            t = np.asarray(x) * u[0] + np.asarray(y) * u[1]
            mid = 0.5 * (float(t.min()) + float(t.max()))
            s5 = np.asarray(m.sliders["5"].position, dtype=float)
            # the stem leaves the slot on the side away from the crank pivot
            side = 1.0 if float(np.mean(s5)) >= 0 else -1.0
            f = s5[:, None] * n + mid * u
            g = f + side * 0.35 * float(self.rod) * n
            points["F"] = (f[:, 0], f[:, 1])
            points["G"] = (g[:, 0], g[:, 1])
            bars.append(Bar("link 5", ("F", "G")))
            sliders += [Slider("C", xi, through="F"), Slider("G", xi + np.pi / 2)]
        return Sketch(
            points=points,
            bars=tuple(bars),
            ground=("O",),
            sliders=tuple(sliders),
            angles=phi,
            name=self.describe(),
            labels=("O", "A", "B", "C"),
            joints=("A", "B", "C", "G"),
        )
