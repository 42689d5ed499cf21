"""The planar four-bar: crank O1A, coupler AB, rocker O2B, ground O1O2.

Conventions
-----------
* Crank pivot O1 at the origin, rocker pivot O2 at (ground, 0).
* Crank angle ``phi`` from +x, counter-clockwise; link angles from +x: crank O1 -> A, coupler
  A -> B, rocker O2 -> B.
* ``branch="open"`` puts B to the left of the directed line A -> O2 (for a crank-rocker drawn with
  the coupler above the ground: the uncrossed quadrilateral); ``"crossed"`` to the right.
* Transmission angle: between the coupler and the rocker (in [0, pi]); pressure angle: between the
  coupler's force on B and B's velocity, ``|pi/2 - transmission angle|``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .. import validate
from ..errors import MechanismError
from ..validate import MAX_LENGTH
from . import ops
from .blocks import coupler_point, crank_pin, dyad_rrr
from .mechanism import (
    Mechanism,
    as_angles,
    check_length,
    fail_where,
    guard_motion,
    speed_pair,
)
from .tracks import LinkTrack, Motion, PointJet, PointTrack

__all__ = ["FourBar", "Grashof", "grashof", "four_bar_chain"]

_BRANCHES = {"open": 1, "crossed": -1}


def four_bar_chain(c, s, crank, coupler, rocker, ground, sigma, phi=None):
    """The four-bar as a chain of blocks: crank pin A, then the RRR dyad A-B-O2.

    ``c, s`` are the crank's direction cosines (cos and sin of the crank angle), ``sigma`` the
    branch (+1 open, -1 crossed); ``phi`` (the angles themselves) only locates assembly errors.
    Returns the jets of A and B and the angle jets of coupler and rocker. This one function is
    what :meth:`FourBar.jets` evaluates and what the compiled batch kernels are built from.
    """
    a = crank_pin(c, s, crank)
    o2 = PointJet(ground, 0.0, 0.0, 0.0, 0.0, 0.0)  # the frame pivot (broadcast by the dyad)
    b, cpl, rck = dyad_rrr(a, o2, coupler, rocker, sigma, phi=phi)
    return a, b, cpl, rck


@dataclass(frozen=True)
class Grashof:
    """Grashof classification of a four-bar.

    Attributes
    ----------
    kind : "crank-rocker", "double-crank", "rocker-crank", "double-rocker" (Grashof, coupler
        shortest), "triple-rocker" (non-Grashof) or "change-point".
    margin : ``(p + q) - (s + l)`` in m: positive for Grashof linkages, zero at a change point.
    shortest : name of the shortest link.
    """

    kind: str
    margin: float
    shortest: str

    @property
    def is_grashof(self) -> bool:
        return self.margin >= 0.0

    @property
    def crank_rotates(self) -> bool:
        """True when the input crank can make full turns."""
        return self.kind in ("crank-rocker", "double-crank")

    def __str__(self) -> str:
        return f"{self.kind} (Grashof margin {self.margin:.6g} m, shortest link: {self.shortest})"


def grashof(crank: float, coupler: float, rocker: float, ground: float, rtol: float = 1e-12):
    """Classify a four-bar by Grashof's criterion ``s + l <= p + q``."""
    lengths = {"crank": crank, "coupler": coupler, "rocker": rocker, "ground": ground}
    values = sorted(lengths.values())
    margin = float(values[1] + values[2] - values[0] - values[3])
    shortest = min(lengths, key=lengths.get)
    if abs(margin) <= rtol * values[3]:
        return Grashof("change-point", margin, shortest)
    if margin < 0:
        return Grashof("triple-rocker", margin, shortest)
    kind = {
        "crank": "crank-rocker",
        "ground": "double-crank",
        "rocker": "rocker-crank",
        "coupler": "double-rocker",
    }[shortest]
    return Grashof(kind, margin, shortest)


@dataclass(frozen=True)
class FourBar(Mechanism):
    """Planar four-bar driven by its crank O1A.

    Parameters
    ----------
    crank, coupler, rocker, ground : link lengths (m), > 0.
    branch : ``"open"`` or ``"crossed"`` assembly (see the module conventions).
    full_turn : when True (default) the crank must make full turns: the design is checked on
        construction (``crank + ground < coupler + rocker`` and
        ``|ground - crank| > |coupler - rocker|``). With False, ``motion`` checks the angles asked.

    Examples
    --------
    >>> import mechsynth as ms
    >>> fb = ms.FourBar(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2)
    >>> fb.grashof.kind
    'crank-rocker'
    """

    crank: float
    coupler: float
    rocker: float
    ground: float
    branch: str = "open"
    full_turn: bool = True

    parameters: ClassVar[tuple[str, ...]] = ("crank", "coupler", "rocker", "ground")
    length_parameters: ClassVar[tuple[str, ...]] = ("crank", "coupler", "rocker", "ground")
    default_output: ClassVar[str] = "B"

    def __post_init__(self):
        a, b, c, d = self.crank, self.coupler, self.rocker, self.ground
        if (  # one design: lengths in (0, MAX_LENGTH] (NaN fails), a crank that turns fully
            type(a) is float and type(b) is float and type(c) is float and type(d) is float
            and 0.0 < a <= MAX_LENGTH and 0.0 < b <= MAX_LENGTH
            and 0.0 < c <= MAX_LENGTH and 0.0 < d <= MAX_LENGTH
            and self.full_turn is True and type(self.branch) is str and self.branch in _BRANCHES
            and a + d < b + c and abs(d - a) > abs(b - c)
        ):  # fmt: skip
            return
        for name in self.parameters:
            object.__setattr__(self, name, check_length(name, getattr(self, name)))
        if not isinstance(self.full_turn, (bool, np.bool_)):
            raise MechanismError(f"full_turn must be True or False, got {self.full_turn!r}")
        if type(self.branch) is not str or self.branch not in _BRANCHES:
            validate.option("branch", self.branch, tuple(_BRANCHES))
        a, b, c, d = self.crank, self.coupler, self.rocker, self.ground
        if ops.is_symbolic(a, b, c, d):
            return
        if not (type(a) is float and type(b) is float and type(c) is float and type(d) is float):
            validate.broadcast(crank=a, coupler=b, rocker=c, ground=d)
        if self.full_turn:
            fail_where(
                np.asarray(a + d) >= b + c,
                "crank + ground ({s} m) not less than coupler + rocker ({t} m){at}: "
                "the crank cannot make a full turn",
                s=a + d,
                t=b + c,
            )
            fail_where(
                np.abs(d - a) <= np.abs(b - c),
                "|ground - crank| ({s} m) not greater than |coupler - rocker| ({t} m){at}: "
                "the crank cannot make a full turn",
                s=np.abs(d - a),
                t=np.abs(b - c),
            )
        else:
            longest = np.maximum(np.maximum(a, b), np.maximum(c, d))
            fail_where(
                2 * longest >= a + b + c + d,
                "longest link ({l} m) not shorter than the sum of the other three ({o} m){at}: "
                "the four-bar cannot be assembled",
                l=longest,
                o=a + b + c + d - longest,
            )

    @classmethod
    def feasibility_constraints(cls, params, margin=1e-3):
        """Smooth conditions ``g >= 0`` (dimensionless) for a crank that makes full turns (when
        ``full_turn`` is True, the default), else for assembly: ``coupler + rocker - crank -
        ground >= margin * sum`` and ``(ground - crank)^2 - (coupler - rocker)^2 >= margin *
        sum^2``. Written with ``ops``, so ``params`` may hold CasADi symbols."""
        a, b, c, d = (params[k] for k in ("crank", "coupler", "rocker", "ground"))
        total = a + b + c + d
        if not params.get("full_turn", True):
            return [
                (f"{k} shorter than the other three links", (total - 2.0 * x) / total - margin)
                for k, x in (("crank", a), ("coupler", b), ("rocker", c), ("ground", d))
            ]
        return [
            ("crank + ground < coupler + rocker (full turn)", (b + c - a - d) / total - margin),
            (
                "|ground - crank| > |coupler - rocker| (full turn)",
                ((d - a) ** 2 - (b - c) ** 2) / total**2 - margin,
            ),
        ]

    @property
    def sigma(self) -> int:
        return _BRANCHES[self.branch]

    @property
    def grashof(self) -> Grashof:
        """Grashof classification with its margin (single designs only)."""
        if np.ndim(self.crank) or ops.is_symbolic(self.crank):
            raise MechanismError(
                "grashof classifies one numeric design; use grashof_margin for batches"
            )
        return grashof(self.crank, self.coupler, self.rocker, self.ground)

    @property
    def grashof_margin(self):
        """``(p + q) - (s + l)`` (m), vectorized over designs."""
        ls = np.sort(
            np.stack(np.broadcast_arrays(self.crank, self.coupler, self.rocker, self.ground)),
            axis=0,
        )
        return ls[1] + ls[2] - ls[0] - ls[3]

    # ---------------------------------------------------------------- kinematics
    def jets(self, phi):
        """Jets of A and B and angle jets of coupler and rocker."""
        phi = as_angles(phi)
        return four_bar_chain(
            ops.cos(phi),
            ops.sin(phi),
            self.crank,
            self.coupler,
            self.rocker,
            self.ground,
            self.sigma,
            phi,
        )

    def motion(self, phi, speed=None, epsilon=0.0, coupler_points=None) -> Motion:
        """Motion over crank angles ``phi`` (rad).

        Parameters
        ----------
        phi : crank angles, any shape (broadcast against array parameters).
        speed : crank angular velocity (rad/s); None gives analogs.
        epsilon : crank angular acceleration (rad/s^2), with a speed.
        coupler_points : ``{name: (u, v)}`` points fixed on the coupler, ``u`` (m) along A -> B from
            A and ``v`` (m) to its left.

        Returns
        -------
        Motion with points ``"O1"``, ``"A"``, ``"B"``, ``"O2"`` (and coupler points), links
        ``"crank"``, ``"coupler"``, ``"rocker"``, and the transmission and pressure angles.
        """
        omega, eps = speed_pair(speed, epsilon)
        phi = as_angles(phi)
        l1, l2, l3, l0 = self.crank, self.coupler, self.rocker, self.ground
        if not (  # one design at one speed: nothing to broadcast
            type(l1) is float and type(l2) is float and type(l3) is float and type(l0) is float
            and type(omega) is float and type(eps) is float
        ):  # fmt: skip
            guard_motion({"crank": l1, "coupler": l2, "rocker": l3, "ground": l0}, phi, omega, eps)
        a, b, coupler, rocker = four_bar_chain(
            *ops.cos_sin(phi),
            self.crank,
            self.coupler,
            self.rocker,
            self.ground,
            _BRANCHES[self.branch],
            phi,
        )
        # the frame pivots' and the crank's tracks are constants: made, not computed (the
        # zeros in one allocation: the pivots' eleven and, without a crank acceleration, the
        # crank's)
        z = ops.zero_rows(a.x, 12)
        crank = LinkTrack.of(
            ops.plus(0.0 * self.crank, phi),
            ops.full_like(a.x, omega),
            z[11] if type(eps) is float and eps == 0.0 else ops.full_like(a.x, eps),
        )
        o1 = PointTrack.of(z[0], z[1], z[2], z[3], z[4], z[5])
        o2 = PointTrack.of(ops.full_like(a.x, self.ground), z[6], z[7], z[8], z[9], z[10])
        points = {"O1": o1, "A": a, "B": b, "O2": o2}
        if coupler_points:
            for name, (u, v) in coupler_points.items():
                points[name] = coupler_point(a, coupler, u, v)
        # the angle between coupler and rocker, in [0, pi]: arccos(cos(difference)) without
        # its two transcendental passes (and exact where that loses digits, near 0 and pi)
        turn = ops.fabs(coupler.value - rocker.value)  # in [0, 2 pi)
        mu = ops.fmin(turn, 2.0 * np.pi - turn)
        return Motion.from_jets(
            phi,
            omega,
            eps,
            points,
            {"crank": crank, "coupler": coupler, "rocker": rocker},
            {},
            ops.fabs(np.pi / 2 - mu),
            mu,
        )

    def sketch(self, phi, coupler_points=None):
        """Drawing description at crank angles ``phi``: crank O1A, coupler AB (a plate with its
        coupler points), rocker O2B, pivots O1 and O2."""
        from .sketch import Bar, Sketch, as_frames

        m = self.motion(phi, coupler_points=coupler_points)
        extra = tuple(coupler_points or ())
        return Sketch(
            points=as_frames(m.points),
            bars=(
                Bar("crank", ("O1", "A")),
                Bar("coupler", ("A", "B", *extra), closed=bool(extra)),
                Bar("rocker", ("O2", "B")),
            ),
            ground=("O1", "O2"),
            angles=phi,
            angle_label="crank angle φ",
            name=self.describe(),
        )

    def coupler_jet(self, phi, u, v) -> PointJet:
        """Jet of a point fixed on the coupler (see ``motion``'s ``coupler_points``)."""
        a, _, coupler, _ = self.jets(phi)
        return coupler_point(a, coupler, u, v)

    # ---------------------------------------------------------------- cycle properties
    def _require_crank_rocker(self, what: str):
        if ops.is_symbolic(self.crank, self.coupler, self.rocker, self.ground):
            return
        a, b, c, d = (
            np.asarray(x, dtype=float) for x in (self.crank, self.coupler, self.rocker, self.ground)
        )
        shortest = np.minimum(np.minimum(b, c), d)
        fail_where(
            (a >= shortest) | ~self._rotates(a, b, c, d),
            f"{what} needs a crank-rocker (crank shortest, crank turns fully); crank {{a}} m, "
            "coupler {b} m, rocker {c} m, ground {d} m{at}",
            a=a,
            b=b,
            c=c,
            d=d,
        )

    @staticmethod
    def _rotates(a, b, c, d):
        return (a + d < b + c) & (np.abs(d - a) > np.abs(b - c))

    @property
    def dead_centres(self):
        """Crank angles (rad) of the two rocker limit positions, ``(phi_extended, phi_folded)``:
        crank and coupler in line, extended and folded. Crank-rockers only."""
        self._require_crank_rocker("dead_centres")
        return self._limit_positions()[0]

    def _limit_positions(self):
        a, b, c, d = self.crank, self.coupler, self.rocker, self.ground
        o1 = PointJet.fixed(0.0 * d, 0.0 * d)
        o2 = PointJet.fixed(d + 0.0 * a, 0.0 * d)
        b_ext, _, rocker_ext = dyad_rrr(o1, o2, b + a, c, self.sigma)
        b_fold, _, rocker_fold = dyad_rrr(o1, o2, b - a, c, self.sigma)
        phi_ext = ops.arctan2(b_ext.y, b_ext.x)
        phi_fold = ops.arctan2(-b_fold.y, -b_fold.x)
        return (phi_ext, phi_fold), (rocker_ext.value, rocker_fold.value)

    @property
    def rocker_limits(self):
        """Rocker angles (rad) at the extended and folded dead centres."""
        self._require_crank_rocker("rocker_limits")
        return self._limit_positions()[1]

    @property
    def swing_angle(self):
        """Rocker swing angle (rad) between its limit positions. Crank-rockers only."""
        ext, fold = self.rocker_limits
        delta = ext - fold
        return ops.fabs(ops.arctan2(ops.sin(delta), ops.cos(delta)))

    @property
    def crank_spans(self):
        """Crank rotation (rad, counter-clockwise) from the extended to the folded dead centre and
        back; they add up to 2 pi. Crank-rockers only."""
        ext, fold = self.dead_centres
        diff = fold - ext
        first = ops.where(diff < 0, diff + 2.0 * np.pi, diff)
        return first, 2.0 * np.pi - first

    @property
    def time_ratio(self):
        """Time ratio (slower swing / quicker swing, >= 1) at constant crank speed."""
        first, second = self.crank_spans
        return ops.fmax(first, second) / ops.fmin(first, second)
