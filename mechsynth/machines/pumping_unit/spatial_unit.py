"""The spatial drive of a beam pumping unit (paper 002): two cranks, two pitmans, an equalizer.

A real unit is not planar. Two crank arms on one shaft (spaced ``crank_spacing`` apart along it)
drive two pitmans; the pitmans hang from the ends B (left) and B1 (right) of the equalizer
(traverse), ``equalizer_width`` apart, which is joined to the walking beam by the spherical
equalizer bearing D; the beam turns about the saddle bearing C; E is the polished-rod point.

Frame and names
---------------
* The planar unit's frame (:mod:`.beam_unit`): origin at the crankshaft, **x toward the well**,
  **y up**, and **z = x cross y along the crankshaft**, pointing to the unit's **right** for a
  person standing behind the unit and facing the well. The mid-plane z = 0 holds the beam.
* Paper 002's names: shaft centre N; crank arms O (left, z = -s/2) and O1 (right, z = +s/2) with
  pins A and A1; pitman 2 = AB (``"left"``), pitman 3 = A1B1 (``"right"``); the equalizer B-D-B1
  (body 4) with its axis ``e`` pointing from B to B1; the beam DC (body 5) turning about the axis
  ``n_C`` through C; E the beam's point at the front arm (horsehead) radius.
* The crank angle ``theta`` is the planar unit's: from 12 o'clock in the direction of rotation.

Deviations (all zero for the ideal unit)
----------------------------------------
``phase_mismatch`` (rad; the right arm leads the left by it), ``crank_difference`` and
``pitman_difference`` (m; right minus left), ``shaft_tilt`` / ``shaft_skew`` (rad; the crankshaft
axis turned about x, i.e. out of level, and about y, i.e. not square to the beam's plane),
``beam_tilt`` / ``beam_skew`` (rad; the same for the saddle-bearing axis), ``equalizer_offset``
(m; D moved from the middle of the equalizer toward B1).

Kinematics
----------
Positions close the two vector contours of paper 002, eqs. (1)-(6): O A B D C (left) and
O1 A1 B1 D C (right), with the equalizer B-D-B1 straight. With spherical pairs at A, A1, B, B1
(the rational mechanism) the equalizer can also turn about D in the plane of the pitmans (a yaw
that does not move the beam to first order); it settles where the two pitman axes and the
equalizer axis are coplanar (the equilibrium of massless pitmans), and that condition closes the
position problem: three equations in the beam angle and the equalizer direction, solved by
Newton's method for all angles and designs at once. The same configuration is the rigid reference
of the revolute (redundant) drive, whose misfits the pitmans' elasticity takes up
(:mod:`.spatial_forces`). Velocities come from Bour's formula ``dl/dt = omega x l`` applied to
both contours, eqs. (9)-(10), and accelerations from their derivatives, eqs. (11)-(12): one
10 x 10 linear system per angle in the angular velocities of the pitmans, the equalizer and the
beam (no spin of a pitman about its own axis, nor of the equalizer about B-B1).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from ... import validate
from ...dynamics.spatial_kinetostatics import BeamSection
from ...errors import MechanismError
from ...kinematics import ops
from ...kinematics.mechanism import Mechanism, check_finite, check_length, speed_pair
from ...kinematics.spatial import (
    SpatialLinkTrack,
    SpatialPointTrack,
    cross,
    dot,
    norm,
    skew,
    tilt,
    unit,
)
from ...kinematics.tracks import LinkTrack, SliderTrack
from .beam_unit import ROTATIONS, UNIT_CLASSES, BeamPumpingUnit, _rotation, _unit_class

__all__ = [
    "SpatialPumpingUnit",
    "SpatialPumpMotion",
    "DEVIATIONS",
    "JOINTS",
    "PAPER_SECTION",
]

#: the deviation parameters, each zero for the ideal unit
DEVIATIONS = (
    "phase_mismatch",
    "crank_difference",
    "pitman_difference",
    "shaft_tilt",
    "shaft_skew",
    "beam_tilt",
    "beam_skew",
    "equalizer_offset",
)
#: the pairs at A, A1, B, B1: revolute (redundant drive) or spherical (rational drive)
JOINTS = ("revolute", "spherical")
#: the pitman section of paper 002: E = 2.1e11 Pa, J_z = 1.176e-6 m^4 as printed; the paper
#: gives nothing else, so the section is taken round with that J (d = 70.0 mm), steel nu = 0.3
PAPER_SECTION = BeamSection.round(None, E=2.1e11, poisson=0.3, J=1.176e-6)

_NEWTON_STEPS = 40


@dataclass(frozen=True)
class SpatialPumpMotion:
    """Motion of the spatial drive over the crank angles ``theta``.

    Attributes
    ----------
    theta, omega, epsilon : crank angle (rad) and the crank speed and acceleration used (1 and 0
        for analogs).
    polished_rod : :class:`~mechsynth.kinematics.SliderTrack`, position up from the bottom of the
        stroke (m), velocity, acceleration: as the planar unit's.
    torque_factor : d(polished rod)/d(theta) (m/rad), always the analog.
    beam : :class:`~mechsynth.kinematics.LinkTrack` of the horsehead direction angle in the
        beam's plane (rad from the beam frame's x axis) and its rate and acceleration.
    points : ``{name: SpatialPointTrack}`` for ``N O O1 A A1 B B1 D C E`` (see the module notes).
    links : ``{name: SpatialLinkTrack}`` angular velocity and acceleration vectors of ``crank``,
        ``pitman_left``, ``pitman_right``, ``equalizer``, ``beam``; ``axis``: the shaft axis, the
        pitman directions A->B and A1->B1, the equalizer axis B->B1, the beam axis.
    pressure_angle : ``{"left", "right"}`` angle (rad) between each pitman and the velocity of D.
    extra : ``residual`` (m): the largest violation of the loops' link lengths.
    """

    theta: Any
    omega: Any
    epsilon: Any
    polished_rod: SliderTrack
    torque_factor: Any
    beam: LinkTrack
    points: dict[str, SpatialPointTrack]
    links: dict[str, SpatialLinkTrack]
    pressure_angle: dict[str, Any]
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def phi(self):
        """The crank angles (alias of ``theta``, as in the planar motions)."""
        return self.theta

    @property
    def is_analog(self) -> bool:
        return isinstance(self.omega, float) and self.omega == 1.0 and self.epsilon == 0.0


@dataclass(frozen=True)
class SpatialPumpingUnit(Mechanism):
    """The spatial double-crank drive of a beam pumping unit (see the module notes).

    Parameters
    ----------
    crank, pitman, rear_arm, front_arm, pivot_x, pivot_y, unit_class, rotation : the planar unit
        (:class:`~mechsynth.BeamPumpingUnit`): nominal crank radius and pitman length (m), beam
        arms C and A, saddle-bearing position; ``"conventional"`` or ``"mark-ii"``, ``"cw"`` or
        ``"ccw"``.
    crank_spacing : distance along the shaft between the two crank pins' planes (m).
    equalizer_width : distance B-B1 between the pitman bearings of the equalizer (m); equal to
        ``crank_spacing`` for parallel pitmans.
    joints : ``"revolute"`` (pairs A, A1, B, B1 revolute: four-fold redundant, paper 002's
        real drive) or ``"spherical"`` (the rational drive without redundant constraints).
    phase_mismatch, crank_difference, pitman_difference, shaft_tilt, shaft_skew, beam_tilt,
    beam_skew, equalizer_offset : deviations (m, rad), see the module notes.
    pitman_section : elastic :class:`~mechsynth.dynamics.spatial_kinetostatics.BeamSection` of
        each pitman (default: paper 002's, :data:`PAPER_SECTION`); its local z axis is the pin
        axis, so ``J_z`` is for bending in the plane of motion and ``J_y`` out of it.

    Numeric parameters may be arrays of designs with a trailing axis of length 1 (broadcast
    against the crank angles), as for the planar mechanisms.

    Examples
    --------
    >>> import mechsynth as ms
    >>> u = ms.BeamPumpingUnit.from_api(A=155.0, C=111.06, I=111.02, P=132.01, R=42.01,
    ...                                 H=231.97, G=95.98, units="in")
    >>> s = ms.SpatialPumpingUnit.from_planar(u, crank_spacing=1.2, equalizer_width=1.2)
    >>> th = ms.cycle(8)
    >>> bool(abs(s.motion(th).polished_rod.position - u.motion(th).polished_rod.position).max()
    ...      < 1e-9)
    True
    """

    crank: float
    pitman: float
    rear_arm: float
    front_arm: float
    pivot_x: float
    pivot_y: float
    crank_spacing: float
    equalizer_width: float
    unit_class: str = "conventional"
    rotation: str = "cw"
    joints: str = "revolute"
    phase_mismatch: float = 0.0
    crank_difference: float = 0.0
    pitman_difference: float = 0.0
    shaft_tilt: float = 0.0
    shaft_skew: float = 0.0
    beam_tilt: float = 0.0
    beam_skew: float = 0.0
    equalizer_offset: float = 0.0
    pitman_section: BeamSection = PAPER_SECTION

    parameters: ClassVar[tuple[str, ...]] = (
        "crank",
        "pitman",
        "rear_arm",
        "front_arm",
        "pivot_x",
        "pivot_y",
        "crank_spacing",
        "equalizer_width",
        *DEVIATIONS,
    )

    def __post_init__(self):
        if ops.is_symbolic(*(getattr(self, k) for k in self.parameters)):
            raise MechanismError(
                "SpatialPumpingUnit is numeric only (its loops are closed by Newton's method): "
                "give numbers or numpy arrays, not CasADi symbols"
            )
        for name in ("crank", "pitman", "rear_arm", "front_arm", "pivot_y"):
            object.__setattr__(self, name, check_length(name, getattr(self, name)))
        for name in ("crank_spacing", "equalizer_width"):
            object.__setattr__(self, name, check_length(name, getattr(self, name)))
        object.__setattr__(self, "pivot_x", check_finite("pivot_x", self.pivot_x))
        for name in DEVIATIONS:
            object.__setattr__(self, name, check_finite(name, getattr(self, name)))
        values = {k: getattr(self, k) for k in self.parameters}
        for name, v in values.items():  # a batch of designs is a column (its angles the rows)
            if np.ndim(v) >= 1 and np.shape(v)[-1] != 1:
                raise MechanismError(
                    f"{name} has shape {np.shape(v)}: a batch of designs has a trailing axis of "
                    f"length 1 (the angles' axis), e.g. np.ravel({name})[:, None] of shape "
                    f"({np.size(v)}, 1)"
                )
        validate.broadcast(**values)
        object.__setattr__(self, "unit_class", _unit_class(self.unit_class))
        object.__setattr__(self, "rotation", _rotation(self.rotation))
        if self.joints not in JOINTS:
            raise MechanismError(f"joints must be 'revolute' or 'spherical', got {self.joints!r}")
        if not isinstance(self.pitman_section, BeamSection):
            raise MechanismError("pitman_section must be a BeamSection")
        for name, limit in (
            ("crank_difference", 2.0 * np.asarray(self.crank)),
            ("pitman_difference", 2.0 * np.asarray(self.pitman)),
            ("equalizer_offset", np.asarray(self.equalizer_width) / 2.0),
        ):
            v = np.abs(np.asarray(getattr(self, name)))
            if np.any(v >= 0.5 * limit):
                raise MechanismError(
                    f"{name} ({float(np.max(v)):.6g} m) is not a small deviation: it must stay "
                    f"below {float(np.min(0.5 * limit)):.6g} m"
                )
        for name in ("phase_mismatch", "shaft_tilt", "shaft_skew", "beam_tilt", "beam_skew"):
            v = np.abs(np.asarray(getattr(self, name)))
            if np.any(v >= 0.2):
                raise MechanismError(
                    f"{name} ({float(np.max(v)):.6g} rad) is not a small deviation: it must stay "
                    "below 0.2 rad"
                )
        half = np.abs(np.asarray(self.crank_spacing) - np.asarray(self.equalizer_width)) / 2.0
        if np.any(half >= 0.5 * np.asarray(self.pitman)):
            raise MechanismError(
                f"crank_spacing ({self.crank_spacing}) and equalizer_width "
                f"({self.equalizer_width}) differ too much for the pitman ({self.pitman} m)"
            )
        self.planar  # noqa: B018 - validates the nominal four-bar (full crank turn)

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_planar(
        cls,
        unit: BeamPumpingUnit,
        crank_spacing,
        equalizer_width=None,
        joints="revolute",
        pitman_section: BeamSection = PAPER_SECTION,
        **deviations,
    ) -> SpatialPumpingUnit:
        """The spatial drive of a planar ``unit``: two crank arms ``crank_spacing`` (m) apart,
        an equalizer ``equalizer_width`` (m, default the crank spacing) wide, ``joints`` at A,
        A1, B, B1 ``"revolute"`` or ``"spherical"``, and deviations by name (see
        :data:`DEVIATIONS`). The pitman is lengthened so that its projection on the plane of
        motion is the planar unit's (it is the planar pitman when the spacing equals the
        width)."""
        if not isinstance(unit, BeamPumpingUnit):
            raise MechanismError(f"unit must be a BeamPumpingUnit, got {type(unit).__name__}")
        unknown = set(deviations) - set(DEVIATIONS)
        if unknown:
            raise MechanismError(
                f"unknown deviation(s) {sorted(unknown)}; known: {', '.join(DEVIATIONS)}"
            )
        s = check_length("crank_spacing", crank_spacing)
        w = s if equalizer_width is None else check_length("equalizer_width", equalizer_width)
        validate.broadcast(crank_spacing=s, equalizer_width=w)
        splay = (np.asarray(s) - np.asarray(w)) / 2.0
        return cls(
            crank=unit.crank,
            pitman=np.sqrt(np.asarray(unit.pitman) ** 2 + splay**2)
            if np.any(splay)
            else unit.pitman,
            rear_arm=unit.rear_arm,
            front_arm=unit.front_arm,
            pivot_x=unit.pivot_x,
            pivot_y=unit.pivot_y,
            crank_spacing=s,
            equalizer_width=w,
            unit_class=unit.unit_class,
            rotation=unit.rotation,
            joints=joints,
            pitman_section=pitman_section,
            **deviations,
        )

    # ------------------------------------------------------------------ geometry
    @cached_property
    def planar(self) -> BeamPumpingUnit:
        """The ideal planar unit (no deviations; the pitman projected on the plane of motion)."""
        splay = (np.asarray(self.crank_spacing) - np.asarray(self.equalizer_width)) / 2.0
        pitman = np.sqrt(np.asarray(self.pitman) ** 2 - splay**2)
        if np.ndim(pitman) == 0:
            pitman = float(pitman)
        return BeamPumpingUnit(
            self.crank,
            pitman,
            self.rear_arm,
            self.front_arm,
            self.pivot_x,
            self.pivot_y,
            self.unit_class,
            self.rotation,
        )

    @property
    def sense(self) -> int:
        return ROTATIONS[self.rotation]

    @property
    def deviations(self) -> dict[str, Any]:
        """The deviations that are not zero."""
        return {k: getattr(self, k) for k in DEVIATIONS if np.any(getattr(self, k))}

    def ideal(self) -> SpatialPumpingUnit:
        """The same drive without deviations."""
        return self.replace(**{k: 0.0 for k in DEVIATIONS})

    def with_joints(self, joints: str) -> SpatialPumpingUnit:
        return self.replace(joints=joints)

    @property
    def lengths(self) -> dict[str, Any]:
        """Crank radii, pitman lengths and equalizer halves, left and right (m)."""
        half = np.asarray(self.equalizer_width) / 2.0
        return {
            "crank_left": self.crank - self.crank_difference / 2.0,
            "crank_right": self.crank + self.crank_difference / 2.0,
            "pitman_left": self.pitman - self.pitman_difference / 2.0,
            "pitman_right": self.pitman + self.pitman_difference / 2.0,
            "BD": half + self.equalizer_offset,
            "B1D": half - self.equalizer_offset,
        }

    def axes(self):
        """``(shaft frame, beam frame)``: rotation matrices whose columns are the frames' x, y
        and z axes (z: the shaft axis, the saddle-bearing axis)."""
        return tilt(self.shaft_tilt, self.shaft_skew), tilt(self.beam_tilt, self.beam_skew)

    @property
    def rod_tilt_factor(self):
        """``cos`` of the saddle-bearing axis's tilt out of level: the vertical travel of the
        polished rod per unit arc of the horsehead (1 for a level axis)."""
        _, rb = self.axes()
        return np.sqrt(1.0 - rb[..., 1, 2] ** 2)

    # ------------------------------------------------------------------ position analysis
    def _geometry(self, theta):
        """Shaft, arms, pins and beam frame at crank angles ``theta`` (broadcast)."""
        theta = np.asarray(theta, dtype=float)
        rs, rb = self.axes()
        a1, a2, n_o = rs[..., :, 0], rs[..., :, 1], rs[..., :, 2]
        b1, b2, n_c = rb[..., :, 0], rb[..., :, 1], rb[..., :, 2]
        s = self.sense
        L = self.lengths
        half = np.asarray(self.crank_spacing, dtype=float)[..., None] / 2.0
        phi = s * theta + np.pi / 2.0
        dphi = np.asarray(self.phase_mismatch, dtype=float) / 2.0
        pins = {}
        for side, sign in (("left", -1.0), ("right", 1.0)):
            ph = phi + sign * s * dphi
            r = np.asarray(L[f"crank_{side}"], dtype=float)[..., None]
            centre = sign * half * n_o
            rel = r * (np.cos(ph)[..., None] * a1 + np.sin(ph)[..., None] * a2)
            pins[side] = (centre, rel)
        c = np.stack(
            np.broadcast_arrays(
                np.asarray(self.pivot_x, dtype=float), np.asarray(self.pivot_y, dtype=float), 0.0
            ),
            axis=-1,
        )
        return dict(n_o=n_o, b1=b1, b2=b2, n_c=n_c, pins=pins, C=c, L=L)

    def _beam_point(self, g, beta, radius):
        beta = np.asarray(beta)[..., None]
        return g["C"] + np.asarray(radius, dtype=float)[..., None] * (
            np.cos(beta) * g["b1"] + np.sin(beta) * g["b2"]
        )

    def _close(self, theta):
        """Newton solution of the position problem: the horsehead direction angle ``beta`` (in
        the beam's plane, from its x axis) and the equalizer axis ``e`` at every angle."""
        theta = np.asarray(theta, dtype=float)
        g = self._geometry(theta)
        L = g["L"]
        l_bd = np.asarray(L["BD"], dtype=float)[..., None]
        l_b1d = np.asarray(L["B1D"], dtype=float)[..., None]
        lp_l = np.asarray(L["pitman_left"], dtype=float)
        lp_r = np.asarray(L["pitman_right"], dtype=float)
        (c_l, rel_l), (c_r, rel_r) = g["pins"]["left"], g["pins"]["right"]
        A_l, A_r = c_l + rel_l, c_r + rel_r
        shape = np.broadcast_shapes(
            A_l.shape[:-1],
            A_r.shape[:-1],
            np.shape(theta),
            lp_l.shape,
            lp_r.shape,
            l_bd.shape[:-1],
            l_b1d.shape[:-1],
            g["b1"].shape[:-1],
            g["C"].shape[:-1],
            np.shape(self.rear_arm),
        )
        # the unknown is the horsehead direction angle (near 0: no wrap-around); D lies at
        # angle beta + offset (offset pi for a conventional unit, 0 for a Mark II)
        beta = np.broadcast_to(np.asarray(self.planar.jets(theta)[4].value), shape).copy()
        off = self._rear_offset()
        ab = np.zeros(shape + (2,))
        scale = float(np.max(np.asarray(self.pitman)))
        rear = np.asarray(self.rear_arm, dtype=float)[..., None]

        def residuals(beta, ab):
            p = np.concatenate([ab, np.ones(shape + (1,))], axis=-1)
            e = p / norm(p)[..., None]
            D = self._beam_point(g, beta + off, self.rear_arm)
            u = D - l_bd * e - A_l
            v = D + l_b1d * e - A_r
            f = np.stack(
                [
                    (dot(u, u) - lp_l**2) / (2.0 * lp_l),
                    (dot(v, v) - lp_r**2) / (2.0 * lp_r),
                    dot(cross(u, v), e) / scale,
                ],
                axis=-1,
            )
            return f, e, D, u, v, norm(p)

        small = 0
        for _ in range(_NEWTON_STEPS):
            f, e, D, u, v, pn = residuals(beta, ab)
            bb = beta[..., None] + off
            D_b = rear * (-np.sin(bb) * g["b1"] + np.cos(bb) * g["b2"])
            e_a = (np.array([1.0, 0.0, 0.0]) - e * e[..., :1]) / pn[..., None]
            e_b = (np.array([0.0, 1.0, 0.0]) - e * e[..., 1:2]) / pn[..., None]
            uv = cross(u, v)
            J = np.empty(shape + (3, 3))
            for k, (du, dv, de) in enumerate(
                (
                    (D_b, D_b, 0.0 * e),
                    (-l_bd * e_a, l_b1d * e_a, e_a),
                    (-l_bd * e_b, l_b1d * e_b, e_b),
                )
            ):
                J[..., 0, k] = dot(u, du) / lp_l
                J[..., 1, k] = dot(v, dv) / lp_r
                J[..., 2, k] = (dot(cross(du, v) + cross(u, dv), e) + dot(uv, de)) / scale
            try:
                with np.errstate(all="ignore"):
                    step = np.linalg.solve(J, -f[..., None])[..., 0]
            except np.linalg.LinAlgError:  # a singular Jacobian: judged by the residuals below
                break
            if not np.all(np.isfinite(step)):
                break
            beta = beta + step[..., 0]
            ab = ab + step[..., 1:]
            # quadratic convergence: two more steps after the step falls below 1e-12
            small = small + 1 if np.max(np.abs(step)) < 1e-12 else 0
            if small >= 3:
                break
        f, e, D, u, v, _ = residuals(beta, ab)
        err = np.max(np.abs(f), axis=-1)
        bad = ~np.isfinite(err) | (err > 1e-10 * scale)
        if np.any(bad):
            i = np.unravel_index(int(np.argmax(bad)), bad.shape)
            th = float(np.broadcast_to(theta, shape)[i])
            raise MechanismError(
                f"the spatial drive does not assemble at crank angle {np.rad2deg(th):.6g} deg"
                f"{'' if len(i) <= 1 else f' (design index {i[:-1]})'}: deviations too large "
                "for the geometry"
            )
        return dict(g, beta=beta, e=e, D=D, u=u, v=v, A_l=A_l, A_r=A_r, shape=shape)

    # ------------------------------------------------------------------ velocity analysis
    def _solve_rates(self, k, rhs_loop_l, rhs_loop_r, rhs_coplanar):
        """The 10 x 10 Bour system: unknowns omega2, omega3, omega4 (3 each) and beta rate."""
        u, v, e = k["u"], k["v"], k["e"]
        L = k["L"]
        l_bd = np.asarray(L["BD"], dtype=float)[..., None, None]
        l_b1d = np.asarray(L["B1D"], dtype=float)[..., None, None]
        shape = k["shape"]
        rc = cross(k["n_c"], k["C"] - k["D"])
        M = np.zeros(shape + (10, 10))
        M[..., 0:3, 0:3] = -skew(u)
        M[..., 0:3, 6:9] = -l_bd * skew(e)
        M[..., 0:3, 9] = rc
        M[..., 3:6, 3:6] = -skew(v)
        M[..., 3:6, 6:9] = l_b1d * skew(e)
        M[..., 3:6, 9] = rc
        M[..., 6, 0:3] = u
        M[..., 7, 3:6] = v
        M[..., 8, 6:9] = e
        M[..., 9, 0:3] = cross(u, cross(v, e))
        M[..., 9, 3:6] = cross(v, cross(e, u))
        M[..., 9, 6:9] = cross(e, cross(u, v))
        rhs = np.zeros(shape + (10,))
        rhs[..., 0:3] = rhs_loop_l
        rhs[..., 3:6] = rhs_loop_r
        rhs[..., 9] = rhs_coplanar
        try:
            x = np.linalg.solve(M, rhs[..., None])[..., 0]
        except np.linalg.LinAlgError:
            raise MechanismError(
                "the spatial drive passes a singular position (its velocity equations have no "
                "unique solution): deviations too large for the geometry"
            ) from None
        return x[..., 0:3], x[..., 3:6], x[..., 6:9], x[..., 9]

    def _analysis(self, theta, order=2):
        """Positions and crank-angle analogs (first and second) of everything."""
        k = self._close(theta)
        g = k
        s = self.sense
        n_o, n_c = g["n_o"], g["n_c"]
        rel_l, rel_r = g["pins"]["left"][1], g["pins"]["right"][1]
        shape = k["shape"]
        w1 = np.broadcast_to(s * n_o, shape + (3,))
        u, v, e = k["u"], k["v"], k["e"]
        L = k["L"]
        l_bd = np.asarray(L["BD"], dtype=float)[..., None]
        l_b1d = np.asarray(L["B1D"], dtype=float)[..., None]
        dc = k["C"] - k["D"]
        out = dict(k)
        out["w1"] = w1
        if order < 1:
            return out
        w2, w3, w4, db = self._solve_rates(k, -cross(w1, rel_l), -cross(w1, rel_r), np.zeros(shape))
        w5 = db[..., None] * n_c
        out.update(w2=w2, w3=w3, w4=w4, w5=w5, dbeta=db)
        if order < 2:
            return out
        du, dv, de = cross(w2, u), cross(w3, v), cross(w4, e)

        def cc(w, r):
            return cross(w, cross(w, r))

        rl = -(cc(w1, rel_l) + cc(w2, u) + cc(w4, l_bd * e) + cc(w5, dc))
        rr = -(cc(w1, rel_r) + cc(w3, v) + cc(w4, -l_b1d * e) + cc(w5, dc))
        rest = (
            dot(cross(cc(w2, u), v) + 2.0 * cross(du, dv) + cross(u, cc(w3, v)), e)
            + 2.0 * dot(cross(du, v) + cross(u, dv), de)
            + dot(cross(u, v), cc(w4, e))
        )
        e2, e3, e4, ddb = self._solve_rates(k, rl, rr, -rest)
        out.update(e2=e2, e3=e3, e4=e4, e5=ddb[..., None] * n_c, ddbeta=ddb)
        return out

    def _rear_offset(self):
        """Angle from the horsehead direction to the rear arm C->D: pi for a conventional unit
        (D behind the saddle bearing), 0 for a Mark II."""
        return np.pi if not UNIT_CLASSES[self.unit_class][1] else 0.0

    # ------------------------------------------------------------------ stroke
    @cached_property
    def _limits(self):
        """Crank angles and horsehead angles at the bottom and the top of the stroke: a coarse
        scan brackets the extremes, Newton on d(beta)/d(theta) = 0 refines them."""
        n = 90
        th = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
        b = self._analysis(th, order=0)["beta"]
        out = []
        for pick in (np.argmin, np.argmax):
            i = pick(b, axis=-1)
            t = th[i][..., None]
            for _ in range(12):
                a = self._analysis(t, order=2)
                step = a["dbeta"] / a["ddbeta"]
                t = t - step
                if np.max(np.abs(step)) < 1e-13:
                    break
            t = np.mod(t, 2.0 * np.pi)
            out += [t, self._analysis(t, order=0)["beta"]]
        if not self.is_batch:
            return tuple(float(np.ravel(v)[0]) for v in out)
        return tuple(out)

    @property
    def is_batch(self) -> bool:
        """True when a parameter holds several designs (an array)."""
        sec = self.pitman_section
        return any(np.ndim(getattr(self, k)) for k in self.parameters) or any(
            np.ndim(getattr(sec, k)) for k in ("E", "G", "area", "J_y", "J_z", "J_p")
        )

    @property
    def beam_limits(self):
        """Horsehead direction angles (rad, in the beam's plane) at the bottom and the top of
        the stroke, exact (the beam's angular velocity vanishes there)."""
        _, lo, _, hi = self._limits
        return lo, hi

    @property
    def dead_centres(self):
        """Crank angles (rad, in [0, 2 pi)) of the bottom and the top of the stroke."""
        bottom, _, top, _ = self._limits
        return bottom, top

    @property
    def swing_angle(self):
        lo, hi = self.beam_limits
        return hi - lo

    @property
    def stroke(self):
        """Polished-rod stroke (m), exact."""
        return self.rod_tilt_factor * self.front_arm * self.swing_angle

    # ------------------------------------------------------------------ motion
    def motion(self, theta, speed=None, epsilon=0.0) -> SpatialPumpMotion:
        """Motion over crank angles ``theta`` (rad, the planar unit's convention).

        ``speed`` (rad/s, a number or an array over ``theta``) and ``epsilon`` (rad/s^2) give time
        derivatives; without a speed, analogs (per rad of crank angle). See
        :class:`SpatialPumpMotion` for what is returned.
        """
        omega, eps = speed_pair(speed, epsilon)
        theta = np.asarray(theta, dtype=float)
        a = self._analysis(theta, order=2)
        n_o, n_c = a["n_o"], a["n_c"]
        shape = a["shape"]
        zero = np.zeros(shape + (3,))
        w1, w2, w3, w4, w5 = a["w1"], a["w2"], a["w3"], a["w4"], a["w5"]
        e2, e3, e4, e5 = a["e2"], a["e3"], a["e4"], a["e5"]
        (c_l, rel_l), (c_r, rel_r) = a["pins"]["left"], a["pins"]["right"]
        L = a["L"]
        l_bd = np.asarray(L["BD"], dtype=float)[..., None]
        l_b1d = np.asarray(L["B1D"], dtype=float)[..., None]
        e = a["e"]
        C = np.broadcast_to(a["C"], shape + (3,))
        D = a["D"]
        head = a["beta"]
        E = self._beam_point(a, head, self.front_arm)

        def on_crank(centre, rel):
            p = np.broadcast_to(centre + rel, shape + (3,))
            return SpatialPointTrack(p, cross(w1, rel), cross(w1, cross(w1, rel)))

        def on_beam(p):
            r = p - C
            return SpatialPointTrack(p, cross(w5, r), cross(e5, r) + cross(w5, cross(w5, r)))

        A, A1 = on_crank(c_l, rel_l), on_crank(c_r, rel_r)
        pd = on_beam(D)
        B = SpatialPointTrack(
            D - l_bd * e,
            pd.velocity - l_bd * cross(w4, e),
            pd.acceleration - l_bd * (cross(e4, e) + cross(w4, cross(w4, e))),
        )
        B1 = SpatialPointTrack(
            D + l_b1d * e,
            pd.velocity + l_b1d * cross(w4, e),
            pd.acceleration + l_b1d * (cross(e4, e) + cross(w4, cross(w4, e))),
        )
        fixed = {
            "N": np.zeros(shape + (3,)),
            "O": np.broadcast_to(c_l, shape + (3,)),
            "O1": np.broadcast_to(c_r, shape + (3,)),
            "C": C,
        }
        points = {k: SpatialPointTrack(p, zero, zero) for k, p in fixed.items()}
        points.update(A=A, A1=A1, B=B, B1=B1, D=pd, E=on_beam(E))
        links = {
            "crank": SpatialLinkTrack(w1, zero, np.broadcast_to(n_o, shape + (3,))),
            "pitman_left": SpatialLinkTrack(w2, e2, unit(a["u"])),
            "pitman_right": SpatialLinkTrack(w3, e3, unit(a["v"])),
            "equalizer": SpatialLinkTrack(w4, e4, e),
            "beam": SpatialLinkTrack(w5, e5, np.broadcast_to(n_c, shape + (3,))),
        }
        lo, _ = self.beam_limits
        kappa = self.rod_tilt_factor
        rod = (
            kappa * self.front_arm * (head - lo),
            kappa * self.front_arm * a["dbeta"],
            kappa * self.front_arm * a["ddbeta"],
        )
        vd = pd.velocity
        pressure = {}
        for side, uu in (("left", a["u"]), ("right", a["v"])):
            cos = np.abs(dot(uu, vd)) / (norm(uu) * np.maximum(norm(vd), 1e-300))
            pressure[side] = np.arccos(np.clip(cos, 0.0, 1.0))
        residual = self._closure_residual(points)
        if speed is not None:
            points = {k: p.to_time(omega, eps) for k, p in points.items()}
            links = {k: t.to_time(omega, eps) for k, t in links.items()}
        w, ep = omega, eps
        return SpatialPumpMotion(
            theta=theta,
            omega=omega,
            epsilon=eps,
            polished_rod=SliderTrack(rod[0], rod[1] * w, rod[2] * w**2 + rod[1] * ep),
            torque_factor=rod[1],
            beam=LinkTrack(head, a["dbeta"] * w, a["ddbeta"] * w**2 + a["dbeta"] * ep),
            points=points,
            links=links,
            pressure_angle=pressure,
            extra={"residual": residual},
        )

    def _closure_residual(self, points):
        """Largest violation (m) of the two contours' link lengths and the straight equalizer."""
        L = self.lengths
        p = {k: v.position for k, v in points.items()}
        checks = [
            norm(p["B"] - p["A"]) - L["pitman_left"],
            norm(p["B1"] - p["A1"]) - L["pitman_right"],
            norm(p["D"] - p["B"]) - L["BD"],
            norm(p["B1"] - p["D"]) - L["B1D"],
            norm(p["D"] - p["C"]) - self.rear_arm,
            norm(p["A"] - p["O"]) - L["crank_left"],
            norm(p["A1"] - p["O1"]) - L["crank_right"],
        ]
        return np.max(np.abs(np.stack(np.broadcast_arrays(*checks), axis=-1)), axis=-1)

    def torque_factor(self, theta):
        """Torque factor d(PR)/d(theta) (m/rad)."""
        return self.motion(theta).torque_factor

    def forces(self, theta, speed, load=0.0, counterbalance=None, masses=None, **kwargs):
        """Kinetostatics over the crank angles ``theta`` at crank ``speed`` (rad/s): see
        :func:`~mechsynth.machines.pumping_unit.spatial_forces.spatial_forces`."""
        from .spatial_forces import spatial_forces

        return spatial_forces(
            self, theta, speed, load=load, counterbalance=counterbalance, masses=masses, **kwargs
        )

    def __repr__(self) -> str:
        if self.is_batch:
            return f"SpatialPumpingUnit({self.unit_class}, {self.joints}, batch)"
        dev = ", ".join(f"{k}={float(v):.4g}" for k, v in self.deviations.items())
        return (
            f"SpatialPumpingUnit({self.unit_class}, {self.rotation}, {self.joints} pairs: "
            f"R={self.crank:.4g} m, P={self.pitman:.4g} m, C={self.rear_arm:.4g} m, "
            f"A={self.front_arm:.4g} m, spacing {self.crank_spacing:.4g} m, equalizer "
            f"{self.equalizer_width:.4g} m{'; ' + dev if dev else ''})"
        )
