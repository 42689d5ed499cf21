"""The offset slider-crank: crank OA, rod AB, slider B on a straight guide parallel to +x.

Conventions
-----------
* Crank pivot O at the origin; crank angle ``phi`` from +x, counter-clockwise.
* The guide is the line ``y = offset`` (offset > 0: guide above the crank pivot).
* The slider position is the x coordinate of B (m); velocity and acceleration are along +x.
  The outer dead centre is the largest x, the inner dead centre the smallest.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .. import validate
from ..validate import MAX_LENGTH
from . import ops
from .blocks import coupler_point, crank_pin, dyad_rrp
from .mechanism import (
    Mechanism,
    as_angles,
    check_finite,
    check_length,
    fail_where,
    guard_motion,
    speed_pair,
)
from .tracks import LinkTrack, Motion, PointJet, PointTrack

__all__ = ["SliderCrank", "slider_crank_chain"]


def slider_crank_chain(c, s, crank, rod, offset, phi=None):
    """The offset slider-crank as a chain of blocks: crank pin A, then the RRP dyad A-B on the
    guide ``y = offset`` (direction +x, slider ahead of the foot of A).

    ``c, s`` are the crank's direction cosines; ``phi`` only locates assembly errors. Returns the
    jets of A and B, of the slider position (x of B) and of the rod angle. This one function is
    what :meth:`SliderCrank.jets` evaluates and what the compiled batch kernels are built from.
    """
    a = crank_pin(c, s, crank)
    b, x, rod_angle = dyad_rrp(a, rod, 0.0, offset, 0.0, 1, phi)
    return a, b, x, rod_angle


@dataclass(frozen=True)
class SliderCrank(Mechanism):
    """Offset slider-crank with a fully rotating crank.

    Parameters
    ----------
    crank : crank length OA (m), > 0.
    rod : rod (connecting rod) length AB (m); must exceed ``crank + |offset|`` so the crank turns.
    offset : signed distance (m) of the guide from the crank pivot; the guide is ``y = offset``.

    Examples
    --------
    >>> import mechsynth as ms
    >>> sc = ms.SliderCrank(crank=0.07, rod=0.24)
    >>> print(round(float(sc.stroke), 6))
    0.14
    >>> m = sc.motion(ms.cycle(360), speed=ms.rpm(600))
    >>> m.slider.velocity.shape
    (360,)
    """

    crank: float
    rod: float
    offset: float = 0.0

    parameters: ClassVar[tuple[str, ...]] = ("crank", "rod", "offset")
    length_parameters: ClassVar[tuple[str, ...]] = ("crank", "rod")
    default_output: ClassVar[str] = "slider"

    def __post_init__(self):
        a, b, e = self.crank, self.rod, self.offset
        if type(a) is float and type(b) is float and type(e) is float:  # one design
            # lengths in (0, MAX_LENGTH] (NaN fails), a finite offset, a crank that turns
            if 0.0 < a <= MAX_LENGTH and 0.0 < b <= MAX_LENGTH and abs(e) < math.inf:
                if b > a + abs(e):
                    return
        object.__setattr__(self, "crank", check_length("crank", self.crank))
        object.__setattr__(self, "rod", check_length("rod", self.rod))
        object.__setattr__(self, "offset", check_finite("offset", self.offset))
        a, b, e = self.crank, self.rod, self.offset
        if not ops.is_symbolic(a, b, e):
            if type(a) is not float or type(b) is not float or type(e) is not float:
                validate.broadcast(crank=a, rod=b, offset=e)
            reach = a + np.abs(e)
            fail_where(
                np.asarray(b) <= reach,
                "rod ({b} m) not longer than crank + |offset| ({r} m){at}: "
                "the crank cannot make a full turn",
                b=b,
                r=reach,
            )

    @classmethod
    def feasibility_constraints(cls, params, margin=1e-3):
        """Smooth conditions ``g >= 0`` (dimensionless) for a design that can make full turns:
        ``rod - crank -+ offset >= margin * rod``. Written with ``ops``, so ``params`` may hold
        CasADi symbols (optimizers add these constraints automatically)."""
        a, b, e = params["crank"], params["rod"], params.get("offset", 0.0)
        return [
            ("rod > crank + offset (full turn)", (b - a - e) / b - margin),
            ("rod > crank - offset (full turn)", (b - a + e) / b - margin),
        ]

    # ---------------------------------------------------------------- kinematics
    def jets(self, phi):
        """Jets of the crank pin A, the slider B, the slider position and the rod angle."""
        phi = as_angles(phi)
        return slider_crank_chain(
            ops.cos(phi), ops.sin(phi), self.crank, self.rod, self.offset, phi
        )

    def motion(self, phi, speed=None, epsilon=0.0, coupler_points=None) -> Motion:
        """Motion over crank angles ``phi`` (rad).

        Parameters
        ----------
        phi : crank angles, any shape (broadcast against array parameters).
        speed : crank angular velocity (rad/s, ``ms.rpm(600)``); None gives analogs.
        epsilon : crank angular acceleration (rad/s^2), with a speed.
        coupler_points : ``{name: (u, v)}`` points fixed on the rod, ``u`` (m) along A -> B from A
            and ``v`` (m) to its left; their tracks appear in ``motion.points``.

        Returns
        -------
        Motion with points ``"O"`` (crank pivot), ``"A"``, ``"B"`` (and coupler points), links
        ``"crank"`` and ``"rod"``, slider ``"B"`` (``motion.slider``), pressure and transmission
        angles.
        """
        omega, eps = speed_pair(speed, epsilon)
        phi = as_angles(phi)
        cr, rd, e = self.crank, self.rod, self.offset
        if not (  # one design at one speed: nothing to broadcast
            type(cr) is float and type(rd) is float and type(e) is float
            and type(omega) is float and type(eps) is float
        ):  # fmt: skip
            guard_motion({"crank": cr, "rod": rd, "offset": e}, phi, omega, eps)
        a, b, s, rod = slider_crank_chain(*ops.cos_sin(phi), self.crank, self.rod, self.offset, phi)
        # the crank pivot's and the crank's tracks are constants: made, not computed (the
        # zeros in one allocation: O's six and, without a crank acceleration, the crank's)
        z = ops.zero_rows(a.x, 7)
        crank = LinkTrack.of(
            ops.plus(0.0 * self.crank, phi),
            ops.full_like(a.x, omega),
            z[6] if type(eps) is float and eps == 0.0 else ops.full_like(a.x, eps),
        )
        points = {"O": PointTrack.of(z[0], z[1], z[2], z[3], z[4], z[5]), "A": a, "B": b}
        if coupler_points:
            for name, (u, v) in coupler_points.items():
                points[name] = coupler_point(a, rod, u, v)
        # the rod's angle from the guide is within (-pi/2, pi/2) (B ahead of A): its size is
        # the pressure angle, arcsin(|offset - y_A| / rod)
        pressure = ops.fabs(rod.value)
        return Motion.from_jets(
            phi,
            omega,
            eps,
            points,
            {"crank": crank, "rod": rod},
            {"B": s},
            pressure,
            np.pi / 2 - pressure,
        )

    def sketch(self, phi, coupler_points=None):
        """Drawing description at crank angles ``phi``: crank OA, rod AB (a plate with its
        coupler points), slider B on its guide ``y = offset``."""
        from .sketch import Bar, Sketch, Slider, as_frames

        m = self.motion(phi, coupler_points=coupler_points)
        extra = tuple(coupler_points or ())
        return Sketch(
            points=as_frames(m.points),
            bars=(Bar("crank", ("O", "A")), Bar("rod", ("A", "B", *extra), closed=bool(extra))),
            ground=("O",),
            sliders=(Slider("B", 0.0),),
            angles=phi,
            angle_label="crank angle φ",
            name=self.describe(),
        )

    def coupler_jet(self, phi, u, v) -> PointJet:
        """Jet of a point fixed on the rod (see ``motion``'s ``coupler_points``)."""
        a, _, _, rod = self.jets(phi)
        return coupler_point(a, rod, u, v)

    # ---------------------------------------------------------------- cycle properties
    @property
    def dead_centres(self):
        """Crank angles (rad) of the outer and inner dead centres, ``(phi_outer, phi_inner)``.

        ``phi_outer`` lies in (-pi/2, pi/2), ``phi_inner = pi + asin(offset / (rod - crank))``.
        """
        a, b, e = self.crank, self.rod, self.offset
        return ops.arcsin(e / (a + b)), np.pi + ops.arcsin(e / (b - a))

    @property
    def dead_centre_positions(self):
        """Slider positions (m) at the outer and inner dead centres:
        ``sqrt((rod +- crank)^2 - offset^2)``, evaluated as ``(rod +- crank) * sqrt(1 - u^2)``
        with ``u = offset / (rod +- crank)`` so that no square overflows."""
        a, b, e = self.crank, self.rod, self.offset
        far, near = b + a, b - a
        return (
            far * ops.sqrt(1.0 - (e / far) ** 2),
            near * ops.sqrt(1.0 - (e / near) ** 2),
        )

    @property
    def stroke(self):
        """Slider stroke (m) between the dead centres.

        ``x_outer - x_inner = 4 crank rod / (x_outer + x_inner)`` divided through by the rod:
        ``4 crank / ((1 + r) sqrt(1 - u^2) + (1 - r) sqrt(1 - v^2))`` with ``r = crank / rod``,
        ``u = offset / (rod + crank)``, ``v = offset / (rod - crank)``. Free of the cancellation
        of the plain difference, which loses every digit once rod/crank passes 1e8 (a
        ``SliderCrank(crank=0.75, rod=1e16)`` has a stroke of 1.5 m, not 0).
        """
        a, b, e = self.crank, self.rod, self.offset
        r = a / b
        u, v = e / (b + a), e / (b - a)
        return 4.0 * a / ((1.0 + r) * ops.sqrt(1.0 - u * u) + (1.0 - r) * ops.sqrt(1.0 - v * v))

    @property
    def crank_spans(self):
        """Crank rotation (rad) for the inward stroke (outer -> inner dead centre) and the outward
        stroke, with the crank turning counter-clockwise. They add up to 2 pi."""
        outer, inner = self.dead_centres
        inward = inner - outer
        return inward, 2.0 * np.pi - inward

    @property
    def time_ratio(self):
        """Time ratio of the slower stroke to the quicker one (>= 1; 1 for a centric design)."""
        inward, outward = self.crank_spans
        return ops.fmax(inward, outward) / ops.fmin(inward, outward)

    # ---------------------------------------------------------------- paper 004
    def extreme_velocity(self):
        """Both extremes of the slider velocity analog ``dx_B/dphi`` (m/rad) over a turn.

        Exact: the roots of the (correctly derived) degree-6 polynomial in ``sin(phi)`` of paper
        004, filtered to true extrema and confirmed against a sampled cycle; see
        :mod:`mechsynth.kinematics.extreme_velocity`. Works for batches of designs.

        Returns
        -------
        ExtremeVelocity with ``.maximum`` and ``.minimum`` (each ``.angle`` in rad, ``.value`` in
        m/rad, ``.lambda_s`` = peak / mean speed of its stroke), ``.stroke`` and the crank spans.

        Examples
        --------
        >>> import mechsynth as ms
        >>> ev = ms.SliderCrank(crank=1.0, rod=2.0).extreme_velocity()
        >>> print(f"{-ev.minimum.value:.6f}", ms.units.format_dms(ev.minimum.angle))
        1.123208 67°42'00"
        """
        from .extreme_velocity import extreme_velocity

        return extreme_velocity(self.crank, self.rod, self.offset)
