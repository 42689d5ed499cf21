"""The sucker-rod beam pumping unit: a crank-rocker four-bar whose walking beam carries a horsehead.

Geometry and frame
------------------
* Origin at the crankshaft O1; +x horizontal **toward the well**, +y up (the well is on the
  right of every drawing, as in the industry's forms).
* The beam pivots at the centre (saddle) bearing O2 = (``pivot_x``, ``pivot_y``), ``pivot_y > 0``.
  A conventional (Class I) unit has its crankshaft behind the centre bearing (``pivot_x = +I``),
  a Mark II (Class III) unit in front of it (``pivot_x = -I``).
* Links: crank O1A (``crank``, API R), pitman AB (``pitman``, API P), rear arm O2B from the centre
  bearing to the equalizer bearing (``rear_arm``, API C), front arm from the centre bearing to
  the horsehead arc (``front_arm``, API A).
* Class I (``unit_class="conventional"``): the equalizer B is behind the centre bearing and the
  horsehead is on the other side (a lever of the first class). Class III (``"mark-ii"``): B and
  the horsehead are both in front of the centre bearing.

Crank angle
-----------
``theta`` is the industry's crank angle: measured from 12 o'clock **in the direction of
rotation**, with the well to the right. ``rotation="cw"`` turns the crank clockwise in that view,
``"ccw"`` counter-clockwise. All analogs (velocity analogs, the torque factor) are derivatives with
respect to ``theta``, so they are positive when the polished rod rises as the crank turns
forwards, whatever the rotation.

Polished rod
------------
The bridle leaves the horsehead arc (radius A about O2) tangentially and hangs vertically, so the
polished-rod position is exactly the arc length ``A * (psi - psi_bottom)`` with ``psi`` the angle
of the horsehead direction from +x: measured **up from the bottom of the stroke**. Its analog is
the torque factor ``TF = d(PR)/d(theta)`` (m/rad): crank torque = TF x polished-rod load by
virtual work. The harmonic and Mills approximations are offered only as labelled comparisons
(:func:`harmonic_approximation`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ...errors import MechanismError
from ...kinematics import ops
from ...kinematics.blocks import crank as crank_block
from ...kinematics.blocks import dyad_rrr, link_angle
from ...kinematics.four_bar import FourBar
from ...kinematics.mechanism import (
    Mechanism,
    as_angles,
    check_finite,
    check_length,
    fail_where,
    speed_pair,
)
from ...kinematics.tracks import Jet, LinkTrack, Motion, PointJet, PointTrack, SliderTrack

__all__ = [
    "BeamPumpingUnit",
    "PumpMotion",
    "UNIT_CLASSES",
    "ROTATIONS",
    "crank_speed",
    "harmonic_approximation",
    "paper_crank_and_pitman",
]

#: unit class -> (assembly branch of the RRR dyad, horsehead on B's side?)
UNIT_CLASSES = {"conventional": (1, False), "mark-ii": (-1, True)}
#: rotation (well on the right) -> sign of the physical (counter-clockwise) crank angle per theta
ROTATIONS = {"ccw": 1, "cw": -1}
_ALIASES = {"class-i": "conventional", "class-iii": "mark-ii", "markii": "mark-ii"}


def _unit_class(value: str) -> str:
    v = _ALIASES.get(str(value).lower(), str(value).lower())
    if v not in UNIT_CLASSES:
        raise MechanismError(f"unit_class must be 'conventional' or 'mark-ii', got {value!r}")
    return v


def _rotation(value: str) -> str:
    v = str(value).lower()
    if v not in ROTATIONS:
        raise MechanismError(f"rotation must be 'cw' or 'ccw' (well to the right), got {value!r}")
    return v


@dataclass(frozen=True)
class PumpMotion(Motion):
    """:class:`~mechsynth.kinematics.Motion` of a pumping unit with named accessors.

    ``polished_rod`` (position up from the bottom of stroke, velocity, acceleration), ``beam``
    (horsehead direction angle, its rate and acceleration), ``torque_factor`` (m/rad; always the
    crank-angle analog, also when the motion has a speed).
    """

    extra_units: ClassVar[dict[str, str]] = {
        "torque_factor": "m/rad",
        "acceleration_analog": "m/rad^2",
    }

    @property
    def polished_rod(self) -> SliderTrack:
        return self.sliders["polished_rod"]

    @property
    def beam(self) -> LinkTrack:
        return self.links["beam"]

    @property
    def torque_factor(self):
        return self.extra["torque_factor"]


def crank_speed(theta, mean, fluctuation=0.0, phase=0.0):
    """A crank speed that varies over the cycle: ``omega = mean * (1 + fluctuation/2 *
    cos(theta - phase))`` (rad/s), and the crank angular acceleration ``epsilon = omega *
    d(omega)/d(theta)`` (rad/s^2) that goes with it.

    ``fluctuation`` is the coefficient of speed fluctuation ``(max - min)/mean``. Returns
    ``(omega, epsilon)`` to pass as ``unit.motion(theta, speed=omega, epsilon=epsilon)``.
    """
    mean = check_finite("mean", mean)
    fluctuation = check_finite("fluctuation", fluctuation)
    if not 0.0 <= fluctuation < 2.0:
        raise MechanismError(f"fluctuation must be in [0, 2), got {fluctuation}")
    theta = np.asarray(theta, dtype=float)
    omega = mean * (1.0 + 0.5 * fluctuation * np.cos(theta - phase))
    domega = -mean * 0.5 * fluctuation * np.sin(theta - phase)
    return omega, omega * domega


def paper_crank_and_pitman(stroke, front_arm, rear_arm, pivot_x, pivot_y, unit_class="mark-ii"):
    """Crank and pitman lengths from the required stroke by paper 000, eqs. (2)-(3).

    The beam swings symmetrically about the horizontal through the centre bearing, so B's chord
    is vertical at ``x_B = pivot_x -+ rear_arm * cos(swing/2)`` (B behind the centre bearing for a
    conventional unit, in front for a Mark II) with ``swing = stroke / front_arm``; the dead
    centres put B at the chord's ends, ``|O1B0| = pitman + crank`` (upper end) and ``|O1B'| =
    pitman - crank`` (lower end).

    Returns ``(crank, pitman, x_B, h1)`` in m (h1 = chord travelled by B).
    """
    _, in_front = UNIT_CLASSES[_unit_class(unit_class)]
    half = stroke / (2.0 * front_arm)
    h1 = 2.0 * rear_arm * ops.sin(half)
    x_b = pivot_x + (1.0 if in_front else -1.0) * rear_arm * ops.cos(half)
    o1b0 = ops.sqrt(x_b * x_b + (pivot_y + h1 / 2.0) ** 2)
    o1b1 = ops.sqrt(x_b * x_b + (pivot_y - h1 / 2.0) ** 2)
    return (o1b0 - o1b1) / 2.0, (o1b0 + o1b1) / 2.0, x_b, h1


@dataclass(frozen=True)
class BeamPumpingUnit(Mechanism):
    """Beam pumping unit (see the module notes for the frame and the crank-angle convention).

    Parameters
    ----------
    crank : crank radius R (m), crank pin to crankshaft.
    pitman : pitman length P (m), crank pin to equalizer bearing.
    rear_arm : C (m), centre bearing to equalizer bearing.
    front_arm : A (m), centre bearing to the polished rod (horsehead arc radius).
    pivot_x : horizontal position of the centre bearing from the crankshaft (m), + toward the
        well: ``+I`` for a conventional unit, ``-I`` for a Mark II.
    pivot_y : height of the centre bearing above the crankshaft (m), ``H - G``; > 0.
    unit_class : ``"conventional"`` (Class I) or ``"mark-ii"`` (Class III).
    rotation : ``"cw"`` or ``"ccw"`` with the well to the right.

    Examples
    --------
    >>> import mechsynth as ms
    >>> u = ms.BeamPumpingUnit.from_api(A=155.0, C=111.06, I=111.02, P=132.01, R=42.01,
    ...                                 H=231.97, G=95.98, units="in")
    >>> round(ms.to_inch(u.stroke), 2)
    121.05
    """

    crank: float
    pitman: float
    rear_arm: float
    front_arm: float
    pivot_x: float
    pivot_y: float
    unit_class: str = "conventional"
    rotation: str = "cw"

    parameters: ClassVar[tuple[str, ...]] = (
        "crank",
        "pitman",
        "rear_arm",
        "front_arm",
        "pivot_x",
        "pivot_y",
    )
    default_output: ClassVar[str] = "slider"
    output_label: ClassVar[str] = "polished rod"

    def __post_init__(self):
        for name in ("crank", "pitman", "rear_arm", "front_arm", "pivot_y"):
            object.__setattr__(self, name, check_length(name, getattr(self, name)))
        object.__setattr__(self, "pivot_x", check_finite("pivot_x", self.pivot_x))
        object.__setattr__(self, "unit_class", _unit_class(self.unit_class))
        object.__setattr__(self, "rotation", _rotation(self.rotation))
        a, b, c, d = self.crank, self.pitman, self.rear_arm, self.ground
        if ops.is_symbolic(a, b, c, d):
            return
        fail_where(
            np.asarray(a + d) >= b + c,
            "crank + centre-bearing distance ({s} m) not less than pitman + rear arm ({t} m){at}: "
            "the crank cannot make a full turn",
            s=a + d,
            t=b + c,
        )
        fail_where(
            np.abs(d - a) <= np.abs(b - c),
            "|centre-bearing distance - crank| ({s} m) not greater than |pitman - rear arm| "
            "({t} m){at}: the crank cannot make a full turn",
            s=np.abs(d - a),
            t=np.abs(b - c),
        )

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_api(
        cls,
        A,
        C,
        I,  # noqa: E741 - the API 11E name
        P,
        R,
        K=None,
        H=None,
        G=None,
        unit_class="conventional",
        rotation="cw",
        units=None,
    ):
        """A unit from its API Spec 11E geometry.

        Parameters
        ----------
        A : centre bearing to polished rod (horsehead arc radius).
        C : centre bearing to equalizer bearing.
        I : horizontal distance between centre bearing and crankshaft.
        P : pitman, crank pin to equalizer bearing.
        R : crank radius (the crank-pin hole in use).
        K : distance centre bearing to crankshaft; or give the heights ``H`` (centre bearing) and
            ``G`` (crankshaft) above the base instead.
        unit_class : ``"conventional"`` (crankshaft behind the centre bearing) or ``"mark-ii"``
            (crankshaft in front of it, toward the well).
        rotation : ``"cw"`` or ``"ccw"``, seen with the well to the right.
        units : ``"m"`` or ``"in"``, the unit of all lengths; required: API 11E tables give
            inches, and a default would read them as metres (a unit 39 times too large).

        Raises
        ------
        MechanismError
            ``units`` missing or not ``"m"``/``"in"``; a length not positive; neither ``K``
            nor both heights; a crankshaft not below the centre bearing.
        """
        if units is None:
            raise MechanismError(
                "from_api: units is required, 'in' (the inches of API Spec 11E tables) or 'm': "
                "the unit of A, C, I, P, R, K, H and G"
            )
        scale = {"m": 1.0, "in": 0.0254}.get(units) if isinstance(units, str) else None
        if scale is None:
            raise MechanismError(f"units must be 'm' or 'in', got {units!r}")
        A, C, I, P, R = (check_length(n, v) for n, v in zip("ACIPR", (A, C, I, P, R)))  # noqa: E741
        if K is not None:
            if H is not None or G is not None:
                raise MechanismError("give either K or the heights H and G, not both")
            K = check_length("K", K)
            if not K > I:
                raise MechanismError(f"K ({K}) must exceed I ({I}): K is the hypotenuse over I")
            height = float(np.sqrt(K * K - I * I))
        else:
            if H is None or G is None:
                raise MechanismError("give K, or both heights H and G")
            H, G = check_finite("H", H), check_finite("G", G)
            height = H - G
            if not height > 0:
                raise MechanismError(
                    f"H ({H}) must exceed G ({G}): centre bearing above crankshaft"
                )
        uc = _unit_class(unit_class)
        sign = 1.0 if uc == "conventional" else -1.0
        return cls(
            crank=R * scale,
            pitman=P * scale,
            rear_arm=C * scale,
            front_arm=A * scale,
            pivot_x=sign * I * scale,
            pivot_y=height * scale,
            unit_class=uc,
            rotation=rotation,
        )

    @classmethod
    def from_stroke(
        cls,
        stroke,
        front_arm,
        rear_arm,
        pivot_x,
        pivot_y,
        unit_class="mark-ii",
        rotation="ccw",
        rtol=1e-9,
    ):
        """Synthesis of paper 000 (eqs. 2-3): crank and pitman for the required ``stroke`` (m)
        with the given beam arms and centre-bearing position (see
        :func:`paper_crank_and_pitman`). The stroke of the result is verified by the exact
        position analysis to ``rtol`` (MechanismError otherwise)."""
        from ...errors import MechanismError

        stroke = check_length("stroke", stroke)
        front_arm = check_length("front_arm", front_arm)
        if stroke / front_arm >= np.pi:
            raise MechanismError(
                f"stroke ({stroke} m) needs a beam swing of {stroke / front_arm:.4g} rad >= pi "
                f"with front_arm {front_arm} m"
            )
        r, l, _, _ = paper_crank_and_pitman(
            stroke, front_arm, rear_arm, pivot_x, pivot_y, unit_class
        )
        unit = cls(r, l, rear_arm, front_arm, pivot_x, pivot_y, unit_class, rotation)
        err = abs(unit.stroke - stroke) / stroke
        if not err <= rtol:
            raise MechanismError(
                f"eqs. (2)-(3) gave crank {r:.6g} m, pitman {l:.6g} m whose analysed stroke "
                f"{unit.stroke:.9g} m differs from the required {stroke:.9g} m (rel. {err:.3g})"
            )
        return unit

    # ------------------------------------------------------------------ optimizer hooks
    @classmethod
    def feasibility_constraints(cls, params, margin=1e-3):
        """Smooth ``g >= 0`` conditions for a crank that makes full turns (the four-bar's
        Grashof conditions with ground = |O1 O2|). ``params`` may hold CasADi symbols."""
        ground = ops.sqrt(params["pivot_x"] ** 2 + params["pivot_y"] ** 2)
        fb = {
            "crank": params["crank"],
            "coupler": params["pitman"],
            "rocker": params["rear_arm"],
            "ground": ground,
        }
        return FourBar.feasibility_constraints(fb, margin=margin)

    # ------------------------------------------------------------------ geometry
    @property
    def ground(self):
        """Distance K between crankshaft and centre bearing (m)."""
        return ops.sqrt(self.pivot_x * self.pivot_x + self.pivot_y * self.pivot_y)

    @property
    def sense(self) -> int:
        """+1 if the crank turns counter-clockwise (well on the right), -1 if clockwise."""
        return ROTATIONS[self.rotation]

    @property
    def branch(self) -> int:
        return UNIT_CLASSES[self.unit_class][0]

    @property
    def four_bar(self) -> FourBar:
        """The equivalent :class:`FourBar` (crank, pitman, rear arm, ground K)."""
        return FourBar(self.crank, self.pitman, self.rear_arm, self.ground)

    @property
    def grashof_margin(self):
        """``(p + q) - (s + l)`` of the four-bar (m); positive for a Grashof linkage."""
        a, b, c, d = self.crank, self.pitman, self.rear_arm, self.ground
        s = ops.fmin(ops.fmin(a, b), ops.fmin(c, d))
        lg = ops.fmax(ops.fmax(a, b), ops.fmax(c, d))
        return (a + b + c + d) - 2.0 * (s + lg)

    def mirrored(self) -> BeamPumpingUnit:
        """The same unit turning the other way."""
        return self.replace(rotation="ccw" if self.rotation == "cw" else "cw")

    def _theta_of_phi(self, phi):
        """Industry crank angle (rad, in [0, 2 pi)) of a physical crank angle (from +x, ccw)."""
        t = self.sense * (phi - np.pi / 2.0)
        t = ops.arctan2(ops.sin(t), ops.cos(t))
        return ops.where(t < 0, t + 2.0 * np.pi, t)

    def _head_angle(self, b: PointJet, o2: PointJet) -> Jet:
        """Direction of the horsehead from the centre bearing (near 0 rad: no wrap)."""
        if UNIT_CLASSES[self.unit_class][1]:
            return link_angle(o2, b)
        return link_angle(b, o2)

    def _dead_centres(self):
        """(theta, psi) at the extended and folded dead centres."""
        zero = 0.0 * self.ground
        o1 = PointJet.fixed(zero, zero)
        o2 = PointJet.fixed(self.pivot_x + zero, self.pivot_y + zero)
        b_ext, _, _ = dyad_rrr(o1, o2, self.pitman + self.crank, self.rear_arm, self.branch)
        b_fold, _, _ = dyad_rrr(o1, o2, self.pitman - self.crank, self.rear_arm, self.branch)
        th_ext = self._theta_of_phi(ops.arctan2(b_ext.y, b_ext.x))
        th_fold = self._theta_of_phi(ops.arctan2(-b_fold.y, -b_fold.x))
        psi_ext = self._head_angle(b_ext, o2).value
        psi_fold = self._head_angle(b_fold, o2).value
        return (th_ext, psi_ext), (th_fold, psi_fold)

    @property
    def dead_centres(self):
        """Crank angles (rad, industry convention, in [0, 2 pi)) of the bottom and the top of the
        stroke, ``(theta_bottom, theta_top)``: crank and pitman in line, exact."""
        (th_e, psi_e), (th_f, psi_f) = self._dead_centres()
        bottom = ops.where(psi_e < psi_f, th_e, th_f)
        top = ops.where(psi_e < psi_f, th_f, th_e)
        return bottom, top

    @property
    def beam_limits(self):
        """Horsehead direction angles (rad from +x) at the bottom and top of the stroke."""
        (_, psi_e), (_, psi_f) = self._dead_centres()
        return ops.fmin(psi_e, psi_f), ops.fmax(psi_e, psi_f)

    @property
    def swing_angle(self):
        """Beam swing between the dead centres (rad)."""
        (_, psi_e), (_, psi_f) = self._dead_centres()
        return ops.fabs(psi_e - psi_f)

    @property
    def stroke(self):
        """Polished-rod stroke (m): ``front_arm * swing_angle``, exact."""
        return self.front_arm * self.swing_angle

    @property
    def upstroke_span(self):
        """Crank rotation (rad) from the bottom to the top of the stroke."""
        bottom, top = self.dead_centres
        d = top - bottom
        return ops.where(d < 0, d + 2.0 * np.pi, d)

    @property
    def downstroke_span(self):
        """Crank rotation (rad) from the top back to the bottom of the stroke."""
        return 2.0 * np.pi - self.upstroke_span

    @property
    def crank_spans(self):
        """``(upstroke_span, downstroke_span)`` (rad); used by the time-ratio measure."""
        up = self.upstroke_span
        return up, 2.0 * np.pi - up

    @property
    def time_ratio(self):
        """Slower stroke / quicker stroke at constant crank speed (>= 1)."""
        up, down = self.crank_spans
        return ops.fmax(up, down) / ops.fmin(up, down)

    # ------------------------------------------------------------------ kinematics
    def jets(self, theta):
        """Jets (analogs per rad of ``theta``) of A, B, the pitman angle, the rear-arm angle and
        the horsehead direction angle."""
        s = self.sense
        theta = as_angles(theta)
        pin = crank_block(s * theta + np.pi / 2.0, self.crank)
        a = PointJet(pin.x, pin.y, s * pin.dx, s * pin.dy, pin.ddx, pin.ddy)
        zero = 0.0 * a.x
        o2 = PointJet.fixed(self.pivot_x + zero, self.pivot_y + zero)
        b, pitman, rear = dyad_rrr(a, o2, self.pitman, self.rear_arm, self.branch, phi=theta)
        head = self._head_angle(b, o2)
        return a, b, pitman, rear, head

    def motion(self, theta, speed=None, epsilon=0.0) -> PumpMotion:
        """Motion over crank angles ``theta`` (rad, industry convention).

        Parameters
        ----------
        theta : crank angles from 12 o'clock in the direction of rotation, any shape.
        speed : crank speed (rad/s, > 0 in the direction of rotation; ``ms.spm(8)``), a number or
            an array over ``theta`` (a speed that varies over the cycle, see
            :func:`crank_speed`); None gives analogs (m/rad, m/rad^2).
        epsilon : crank angular acceleration (rad/s^2), number or array, with a speed.

        Returns
        -------
        PumpMotion with ``polished_rod`` (position up from the bottom of stroke, m; velocity;
        acceleration), ``torque_factor`` (m/rad), ``beam``, points ``O1, A, B, O2, PR`` (PR: the
        polished rod's clamp point, x = pivot_x + front_arm), links ``crank, pitman, rear_arm,
        beam``, ``transmission_angle`` (pitman to rear arm) and ``pressure_angle`` (between the
        pitman force on B and B's velocity, ``|pi/2 - transmission|``).
        """
        omega, eps = speed_pair(speed, epsilon)
        theta = as_angles(theta)
        a, b, pitman, rear, head = self.jets(theta)
        psi_bottom, _ = self.beam_limits
        pr = Jet(
            self.front_arm * (head.value - psi_bottom),
            self.front_arm * head.d1,
            self.front_arm * head.d2,
        )
        zero = 0.0 * a.x
        s = self.sense
        crank_jet = Jet(s * theta + np.pi / 2.0 + zero, s + zero, zero)
        o1 = PointJet.fixed(zero, zero)
        o2 = PointJet.fixed(self.pivot_x + zero, self.pivot_y + zero)
        rod_point = PointJet(
            self.pivot_x + self.front_arm + zero, self.pivot_y + pr.value, zero, pr.d1, zero, pr.d2
        )
        points = {"O1": o1, "A": a, "B": b, "O2": o2, "PR": rod_point}
        mu = ops.arccos(ops.cos(pitman.value - rear.value))
        return PumpMotion(
            phi=theta,
            omega=omega,
            epsilon=eps,
            points={k: PointTrack.from_jet(p, omega, eps) for k, p in points.items()},
            links={
                "crank": LinkTrack.from_jet(crank_jet, omega, eps),
                "pitman": LinkTrack.from_jet(pitman, omega, eps),
                "rear_arm": LinkTrack.from_jet(rear, omega, eps),
                "beam": LinkTrack.from_jet(head, omega, eps),
            },
            sliders={"polished_rod": SliderTrack.from_jet(pr, omega, eps)},
            pressure_angle=ops.fabs(np.pi / 2.0 - mu),
            raw_transmission_angle=mu,
            extra={"torque_factor": pr.d1, "acceleration_analog": pr.d2},
        )

    def torque_factor(self, theta):
        """Torque factor TF = d(PR)/d(theta) (m/rad) at crank angles ``theta``."""
        return self.front_arm * self.jets(theta)[4].d1

    def position(self, theta):
        """Polished-rod position (m) up from the bottom of the stroke."""
        psi_bottom, _ = self.beam_limits
        return self.front_arm * (self.jets(theta)[4].value - psi_bottom)

    def sketch(self, theta, arc_deg: float = 60.0):
        """Drawing description at crank angles ``theta`` (rad, industry convention): crank,
        pitman, the beam from the equalizer bearing over the centre bearing to the horsehead,
        the horsehead face (``arc_deg`` wide), the bridle and polished rod, the Samson post."""
        from ...kinematics.sketch import Bar, Outline, Sketch, as_frames

        theta = np.atleast_1d(as_angles(theta))
        m = self.motion(theta)
        points = as_frames(m.points, ["O1", "A", "B", "O2"])
        ox, oy, a_len = float(self.pivot_x), float(self.pivot_y), float(self.front_arm)
        psi = np.asarray(m.beam.angle, dtype=float)
        points["H"] = (ox + a_len * np.cos(psi), oy + a_len * np.sin(psi))
        arc = psi[:, None] + np.deg2rad(np.linspace(-arc_deg / 2, arc_deg / 2, 31))[None, :]
        ground_y = -1.2 * float(self.crank)
        # the bridle leaves the horsehead where the face is vertical, level with the centre
        # bearing; the carrier bar rises with the polished rod
        rod_x = ox + a_len
        carrier = ground_y + 0.12 * a_len + np.asarray(m.polished_rod.position, dtype=float)
        rod = np.full_like(carrier, rod_x)

        def vertical(top, bottom):
            return np.stack([rod, rod], 1), np.stack(np.broadcast_arrays(top, bottom), 1)

        post = 0.3 * oy
        # the circle the crank (and its counterweights' pin radius) sweeps: the polished rod
        # must clear it (``studies.beam_pump.rod_clearance``)
        ring = np.linspace(0.0, 2.0 * np.pi, 73)
        r = float(self.crank)
        outlines = (
            Outline("crank circle", r * np.cos(ring), r * np.sin(ring), "thin"),
            Outline("horsehead", ox + a_len * np.cos(arc), oy + a_len * np.sin(arc)),
            Outline("bridle", *vertical(oy, carrier), "thin"),
            Outline(
                "carrier bar",
                rod[:, None] + 0.06 * a_len * np.array([-1.0, 1.0]),
                np.stack([carrier, carrier], 1),
            ),
            Outline("polished rod", *vertical(carrier, ground_y), "thin"),
            Outline(
                "Samson post",
                np.array([ox - post, ox, ox + post]),
                np.array([ground_y, oy, ground_y]),
                "frame",
            ),
            Outline(
                "base",
                np.array([min(0.0, ox) - post, max(rod_x, ox) + post]),
                np.array([ground_y, ground_y]),
                "frame",
            ),
        )
        return Sketch(
            points=points,
            bars=(
                Bar("crank", ("O1", "A")),
                Bar("pitman", ("A", "B")),
                Bar("beam", ("B", "O2", "H")),
            ),
            ground=("O1", "O2"),
            outlines=outlines,
            angles=theta,
            angle_label="crank angle θ from 12 o'clock in the direction of rotation",
            angle_symbol="θ",
            name=self.describe(),
            xlabel="x toward the well",
            labels=("O1", "A", "B", "O2"),
            joints=("A", "B"),
        )

    def describe(self) -> str:
        return f"{super().describe()} ({self.unit_class}, {self.rotation})"

    def draw(self, theta=0.0, ax=None, arc_deg=60.0, color=None, alpha=1.0, **kwargs):
        """Draw the unit at crank angle ``theta`` (rad): crank, pitman, beam with its horsehead
        face (``arc_deg`` wide), bridle and polished rod, Samson post (see
        :meth:`Mechanism.draw <mechsynth.kinematics.Mechanism.draw>` for ``trace``, ``labels``
        and ``title``). Returns the matplotlib axes."""
        return super().draw(theta, ax, color=color, alpha=alpha, arc_deg=arc_deg, **kwargs)

    def __repr__(self) -> str:
        if self.is_symbolic or np.ndim(self.crank):
            return f"BeamPumpingUnit({self.unit_class}, {self.rotation}, symbolic/batch)"
        return (
            f"BeamPumpingUnit({self.unit_class}, {self.rotation}: R={self.crank:.4g} m, "
            f"P={self.pitman:.4g} m, C={self.rear_arm:.4g} m, A={self.front_arm:.4g} m, "
            f"O2=({self.pivot_x:.4g}, {self.pivot_y:.4g}) m)"
        )


def harmonic_approximation(unit: BeamPumpingUnit, theta, speed):
    """APPROXIMATIONS, for comparison only: the simple harmonic motion of the polished rod and
    Mills' formula for its peak acceleration.

    Returns a dict: ``position`` (m, up from the bottom: ``S/2 (1 - cos(theta - theta_bottom))``),
    ``velocity``, ``acceleration`` (harmonic, m/s, m/s^2), ``mills_peak_acceleration``
    (``S omega^2 / 2 * (1 + R/P)``, m/s^2) and ``label``. Neither is the unit's exact kinematics
    (``unit.motion``)."""
    theta = np.asarray(theta, dtype=float)
    s = float(unit.stroke)
    bottom, _ = unit.dead_centres
    x = theta - float(bottom)
    omega = float(speed)
    return {
        "label": "harmonic approximation / Mills' peak acceleration (approximate, not exact)",
        "position": 0.5 * s * (1.0 - np.cos(x)),
        "velocity": 0.5 * s * omega * np.sin(x),
        "acceleration": 0.5 * s * omega**2 * np.cos(x),
        "mills_peak_acceleration": 0.5 * s * omega**2 * (1.0 + unit.crank / unit.pitman),
    }
