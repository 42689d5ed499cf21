"""The upsetting mechanism of the AB4115 nail-making machine (paper 003, first part).

Crank OA (body 1), rod AB (2), punch-slider B (3) on the x axis through O, and the nail ejector:
a rocker (5) pivoted at E whose slot, at distance ``l_DE`` from E, is driven by the point C of
the slider (``x_C = x_B + x_BC``, ``y_C``). The cam contact at C is replaced by lower pairs: a
massless block (4) pinned to the slider at C slides in the rocker's slot.

Conventions: crank angle ``phi`` counter-clockwise from +x (the model's coordinate); the machine
turns clockwise, so its speed is ``omega = -2 pi n / 60`` and the *clockwise* crank angle from the
outer dead centre is ``-phi``. Gravity acts along -y. Reactions: ``R10`` frame on crank at O,
``R21`` crank on rod at A, ``R32`` rod on slider at B, ``R30`` guide on slider (normal force),
``R43`` slider on block at C, ``R54`` ejector on block (slot normal), ``R50`` frame on ejector at
E. Magnitudes are what the paper tabulates.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ...dynamics.inertia import LinkInertia
from ...dynamics.kinetostatics import (
    FRAME,
    ForceModel,
    ForceResult,
    Prismatic,
    Revolute,
    kinetostatics,
)
from ...dynamics.loads import G, Gravity, PointForce, TorsionSpring, upsetting_force
from ...errors import MechanismError
from ...kinematics import ops
from ...kinematics.blocks import coupler_point, crank, dyad_rpr, dyad_rrp
from ...kinematics.mechanism import Mechanism, as_angles, check_finite, check_length, speed_pair
from ...kinematics.tracks import Jet, LinkTrack, Motion, PointJet, PointTrack, SliderTrack

__all__ = ["NailHeader"]


def _mass(name, value):
    value = check_finite(name, value)
    if not ops.is_symbolic(value) and np.any(np.asarray(value) < 0):
        raise MechanismError(f"{name} must not be negative, got {value}")
    return value


@dataclass(frozen=True)
class NailHeader(Mechanism):
    """AB4115 upsetting mechanism with every parameter of paper 003 as defaults (SI units).

    Lengths (m): ``l_oa, l_ab, l_de, l_os1`` (crank centre of mass, on the far side of O from A:
    the crank is counterweighted), ``l_as2, l_bs3`` (slider centre of mass ahead of B),
    ``y_c, l_es5, x_bc, x_e, y_e``. Masses (kg): ``m1, m2, m3, m5``; inertias (kg m^2) ``j_s1,
    j_s2, j_s5`` (the paper's "J_S3 = 0.0027" is the ejector's: the slider does not rotate).
    Speed ``n1`` (rpm, clockwise). Upsetting: ``h`` (m), ``c1`` (N/mm^4), ``sigma_t`` (N/mm^2),
    ``mu``, ``d`` and ``l_blank`` (mm). Ejector spring: ``m_n0`` (N m), ``c2`` (N m/rad).
    ``g`` gravity (m/s^2). ``counterweight`` (kg m): an extra crank counterweight moment
    ``m_cw r_cw`` opposite A, carried as ``counterweight / cw_radius`` kg at ``cw_radius``.
    Ejector spring ``M_n = M_n0 + c2 beta5``: with ``spring_zero="paper"`` and ``spring_sense=1``
    (the defaults) it is the paper's law as printed, ``beta5 = phi50 - phi5`` with the paper's
    ``phi50`` formula (:attr:`phi50_paper`: the ejector angle at the *inner* dead centre), acting
    counter-clockwise; the twist runs from 0 to 38.5 deg and the slot contact stays closed. This
    reproduces Table 1, the ejector reactions included (R43 = 69 N, R50 = 38 N at phi = pi).
    ``spring_zero="outer"`` measures the twist from the outer dead centre (:attr:`phi50`, the
    reading of the paper used before), with ``spring_sense=-1`` the spring acting clockwise as the
    ejector turns away from it (the maxima then lie ~15 N below the print).
    """

    l_oa: float = 0.07
    l_ab: float = 0.24
    l_de: float = 0.006
    l_os1: float = 0.0057
    l_as2: float = 0.05
    l_bs3: float = 0.097
    y_c: float = -0.01
    l_es5: float = 0.05
    x_bc: float = 0.285
    x_e: float = 0.418
    y_e: float = -0.115
    m1: float = 72.0
    m2: float = 12.0
    m3: float = 15.0
    m5: float = 0.4
    j_s1: float = 4.24
    j_s2: float = 0.543
    j_s5: float = 0.0027
    n1: float = 600.0
    h: float = 0.003
    c1: float = 571.0
    sigma_t: float = 850.0
    mu: float = 0.3
    d: float = 3.0
    l_blank: float = 20.0
    m_n0: float = 1.75
    c2: float = 4.125
    g: float = G
    counterweight: float = 0.0
    cw_radius: float = 0.1
    spring_sense: int = 1
    spring_zero: str = "paper"

    parameters: ClassVar[tuple[str, ...]] = ("l_oa", "l_ab", "m3", "counterweight")
    default_output: ClassVar[str] = "slider"
    parameter_units: ClassVar[dict[str, str]] = {"m3": "kg", "counterweight": "kg m"}
    #: the machine turns clockwise: decreasing phi
    turn_sign: ClassVar[int] = -1
    output_label: ClassVar[str] = "punch slider"

    def __post_init__(self):
        for name in ("l_oa", "l_ab", "l_de", "l_es5", "x_bc", "h", "d", "l_blank", "cw_radius"):
            object.__setattr__(self, name, check_length(name, getattr(self, name)))
        for name in ("l_os1", "l_as2", "l_bs3", "y_c", "x_e", "y_e"):
            object.__setattr__(self, name, check_finite(name, getattr(self, name)))
        for name in ("m1", "m2", "m3", "m5", "j_s1", "j_s2", "j_s5", "c1", "sigma_t", "mu"):
            object.__setattr__(self, name, _mass(name, getattr(self, name)))
        for name in ("m_n0", "c2", "g", "counterweight", "n1"):
            object.__setattr__(self, name, _mass(name, getattr(self, name)))
        if self.spring_zero not in ("paper", "outer"):
            raise MechanismError(
                f"spring_zero must be 'paper' or 'outer', got {self.spring_zero!r}"
            )

    @property
    def omega(self) -> float:
        """Crank angular velocity (rad/s): negative, the crank turns clockwise."""
        return -np.pi * self.n1 / 30.0

    # ------------------------------------------------------------------ kinematics
    def jets(self, phi):
        phi = as_angles(phi)
        a = crank(phi, self.l_oa)
        b, s, rod = dyad_rrp(a, self.l_ab, 0.0, 0.0, 0.0, branch=1, phi=phi)
        c = PointJet(b.x + self.x_bc, b.y + self.y_c, b.dx, b.dy, b.ddx, b.ddy)
        e = PointJet.fixed(self.x_e + 0.0 * a.x, self.y_e + 0.0 * a.x)
        th5, s5 = dyad_rpr(c, self.x_e, self.y_e, offset=self.l_de, branch=1, phi=phi)
        return a, b, s, rod, c, e, th5, s5

    @property
    def phi50(self):
        """Ejector angle (rad) at the outer dead centre (``spring_zero="outer"``)."""
        _, _, _, _, _, _, th5, _ = self.jets(np.array([0.0]))
        return float(th5.value[0])

    @property
    def phi50_paper(self):
        """Paper 003's phi_50 as printed (rad): ``pi/2 - arctg((l_AB - l_OA + x_BC - x_E) /
        (y_C - y_E)) - arcsin(l_DE / sqrt((l_AB - l_OA + x_BC - x_E)^2 + (y_C - y_E)^2))``, the
        ejector angle at the inner dead centre (``x_B = l_AB - l_OA``)."""
        x = self.l_ab - self.l_oa + self.x_bc - self.x_e
        y = self.y_c - self.y_e
        # arctg as printed (arctan(t) = arctan2(t, 1)), in ops so CasADi lengths work too
        value = np.pi / 2 - ops.arctan2(x / y, 1.0) - ops.arcsin(self.l_de / ops.hypot(x, y))
        return value if ops.is_symbolic(value) else float(value)

    def motion(self, phi, speed=None, epsilon=0.0) -> Motion:
        """Motion over crank angles ``phi`` (rad, ccw from +x); ``speed`` (rad/s) defaults to
        analogs; use ``self.omega`` for the machine's clockwise 600 rpm.

        Points ``O, A, B, C, E, D`` (D: foot of the slot normal through E); links ``crank``,
        ``rod``, ``ejector``; sliders ``B`` (x of B) and ``slot`` (C along the ejector).
        """
        omega, eps = speed_pair(speed, epsilon)
        phi = as_angles(phi)
        a, b, s, rod, c, e, th5, s5 = self.jets(phi)
        zero = 0.0 * a.x
        d = coupler_point(e, th5, 0.0, self.l_de)
        points = {"O": PointJet.fixed(zero, zero), "A": a, "B": b, "C": c, "E": e, "D": d}
        crank_jet = Jet(phi + zero, 1.0 + zero, zero)
        return Motion(
            phi=phi,
            omega=omega,
            epsilon=eps,
            points={k: PointTrack.from_jet(p, omega, eps) for k, p in points.items()},
            links={
                "crank": LinkTrack.from_jet(crank_jet, omega, eps),
                "rod": LinkTrack.from_jet(rod, omega, eps),
                "ejector": LinkTrack.from_jet(th5, omega, eps),
            },
            sliders={
                "B": SliderTrack.from_jet(s, omega, eps),
                "slot": SliderTrack.from_jet(s5, omega, eps),
            },
            pressure_angle=ops.arcsin(ops.fabs(a.y) / self.l_ab),
        )

    def sketch(self, phi):
        """Drawing description at crank angles ``phi`` (rad, ccw; the machine turns clockwise):
        crank OA, rod AB, the punch slider from B to C on its guide, the ejector E-D with the
        slot in which the block at C slides. The angle shown is the clockwise angle from the
        outer dead centre."""
        from ...kinematics.sketch import Bar, Sketch, Slider, as_frames

        phi = np.atleast_1d(as_angles(phi))
        m = self.motion(phi)
        points = as_frames(m.points)
        # the ejector's arm runs from its pivot E over D along the slot past C's travel
        th5 = np.asarray(m.links["ejector"].angle, dtype=float)
        dx, dy = points["D"]
        cx, cy = points["C"]
        along = (cx - dx) * np.cos(th5) + (cy - dy) * np.sin(th5)
        reach = float(along.max()) + 0.02
        points["S"] = (dx + reach * np.cos(th5), dy + reach * np.sin(th5))
        return Sketch(
            points=points,
            bars=(
                Bar("crank", ("O", "A")),
                Bar("rod", ("A", "B")),
                Bar("slider", ("B", "C")),
                Bar("ejector", ("E", "D", "S")),
            ),
            ground=("O", "E"),
            sliders=(Slider("B", 0.0), Slider("C", th5, through="D")),
            angles=-phi,
            angle_label="clockwise crank angle from the outer dead centre",
            name=self.describe(),
            labels=("O", "A", "B", "C", "E"),
            joints=("A", "B", "C"),
        )

    # ------------------------------------------------------------------ loads
    def stroke_from_outer(self, motion: Motion):
        """Punch distance ``s_B = l_OA + l_AB - x_B`` (m) from the outer dead centre."""
        return self.l_oa + self.l_ab - motion.points["B"].x

    def upsetting(self, motion: Motion):
        """Upsetting force (N, along +x magnitude) on the punch: ``F_e0 + c1 l_e^4`` while the
        punch is within ``h`` of the outer dead centre and advancing (or at rest), else 0.

        "Advancing" is judged on the machine's real motion: on an analog motion (no speed) the
        analogs are per counter-clockwise radian, and the machine turns clockwise, so the punch
        advances where the analog ``dx_B/dphi`` is negative."""
        s = self.stroke_from_outer(motion)
        f = upsetting_force(s, self.h, self.c1, self.sigma_t, self.mu, self.d, self.l_blank)
        vx = motion.points["B"].vx
        if motion.is_analog:
            vx = -vx  # velocity per unit clockwise crank speed
        scale = abs(self.l_oa * motion.omega) if not motion.is_analog else self.l_oa
        return ops.where(vx >= -1e-9 * scale, f, 0.0 * f)

    def spring(self) -> TorsionSpring:
        """Ejector spring ``M_n = M_n0 + c2 beta5`` (see ``spring_zero``, ``spring_sense``)."""
        zero = self.phi50_paper if self.spring_zero == "paper" else self.phi50
        return TorsionSpring(
            "ejector", "ejector", self.m_n0, self.c2, zero, sense=self.spring_sense
        )

    def force_model(self, gravity=True) -> ForceModel:
        """Bodies, joints and loads (gravity, upsetting force, ejector spring)."""
        m_cw = self.counterweight / self.cw_radius
        m_crank = self.m1 + m_cw
        moment = self.m1 * self.l_os1 + self.counterweight
        if ops.is_symbolic(m_crank) or np.all(np.asarray(m_crank) > 0):
            u1 = -moment / m_crank
        else:  # a massless crank: its centre of mass is irrelevant, put it at O
            positive = np.asarray(m_crank) > 0
            u1 = np.where(positive, -moment / np.where(positive, m_crank, 1.0), 0.0)
        # centroidal inertia of crank + counterweight (point mass at cw_radius opposite A)
        j1 = self.j_s1 + self.m1 * (self.l_os1 + u1) ** 2 + m_cw * (self.cw_radius + u1) ** 2
        bodies = {
            "crank": LinkInertia("crank", "O", m_crank, (u1, 0.0), j1),
            "rod": LinkInertia("rod", "A", self.m2, (self.l_as2, 0.0), self.j_s2),
            "slider": LinkInertia(None, "B", self.m3, (self.l_bs3, 0.0)),
            "block": LinkInertia(None, "C", 0.0),
            "ejector": LinkInertia("ejector", "E", self.m5, (self.l_es5, 0.0), self.j_s5),
        }
        joints = [
            Revolute("R10", "crank", FRAME, "O"),
            Revolute("R21", "rod", "crank", "A"),
            Revolute("R32", "slider", "rod", "B"),
            Prismatic("R30", "slider", FRAME, "B", 0.0),
            Revolute("R43", "block", "slider", "C"),
            Prismatic("R54", "block", "ejector", "C", "ejector"),
            Revolute("R50", "ejector", FRAME, "E"),
        ]
        loads = [
            PointForce(
                "slider", "B", lambda m: (-self.upsetting(m), 0.0 * self.upsetting(m)), "upsetting"
            ),
            self.spring(),
        ]
        if gravity:
            loads.append(Gravity(self.g))
        return ForceModel(bodies, tuple(joints), tuple(loads), "crank")

    def forces(self, phi, gravity=True) -> ForceResult:
        """Kinetostatics at crank angles ``phi`` (rad, ccw) at the machine's clockwise speed."""
        m = self.motion(phi, speed=self.omega)
        return kinetostatics(self.force_model(gravity), m)
