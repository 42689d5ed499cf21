"""Motion generation: four-bars and slider-cranks that carry a coupler through given poses.

:func:`burmester` (from :mod:`.burmester`) gives the dyads of 2 to 5 poses; this module pairs
them into linkages (:func:`motion_generation`), checks each for the classical defects, ranks them,
draws them (:func:`plot_motion`) and hands a chosen one to the optimizer
(:func:`motion_problem`).

A pairing of two dyads, the *crank* (an RR dyad: fixed pivot O, moving pivot A) and the *driven*
dyad (RR: fixed pivot D, moving pivot B, a four-bar; PR: the slider B on a guide, a
slider-crank; RP: a block pinned at D through which the coupler slides, an inverted
slider-crank), is a :class:`~mechsynth.kinematics.Linkage` in the poses' frame (ground points
``O`` and ``D``, crank ``OA`` at the absolute crank angle, ``AB`` the coupler -- for an RP dyad
the RPR group ``coupler`` pinned at A, its slot through the block ``block`` at D --, the pose
point ``P`` and a point ``Q`` on the pose frame's x axis attached to the coupler) and, where its
crank turns fully, the same design as an :class:`~mechsynth.FourBar` or
:class:`~mechsynth.SliderCrank` in their standard frame (crank pivot at the origin, ground or
guide along +x) with the rigid transform between the frames (the inverted slider-crank has no
such class: its ``Linkage`` is the design).

Defects (``Candidate.defects``):

* ``"branch"`` -- the poses are not all reached on one assembly branch of the driven dyad (the
  sign of ``(D - A) x (B - A)``, or of the slider's side of the rod's foot, changes);
* ``"order"`` -- turning the crank one way, the poses do not come in their given order within
  one turn;
* ``"limit"`` -- between the first and the last pose the crank meets a limit position (it would
  have to reverse): a rocking crank's range does not cover the poses' span;
* ``"grashof"`` -- the crank cannot make full turns (the four-bar is not a crank-rocker or
  double-crank; the slider-crank's rod is too short; the inverted slider-crank's slot comes
  nearer its crank pin than ``|OD| - OA`` allows: ``| |OD| - OA | <= |offset|``).

Ranking: fewer defects first, then the larger minimum transmission angle (folded to
``[0, 90 deg]``) over the motion from the first to the last pose.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..errors import MechanismError
from .burmester import Burmester, Dyad, as_poses, burmester

__all__ = [
    "burmester",
    "motion_generation",
    "MotionGeneration",
    "Candidate",
    "pair",
    "pose_errors",
    "pose_error_measure",
    "motion_problem",
    "plot_motion",
]

#: crank-angle samples between the first and the last pose (transmission angle, limits)
SPAN_SAMPLES = 181
#: the kind of linkage of each kind of driven dyad
KINDS = {"RR": "four-bar", "PR": "slider-crank", "RP": "inverted slider-crank"}


def driven_key(kind: str) -> str:
    """The name under which a candidate linkage of ``kind`` reports the driven dyad's
    transmission angle (its point B, or the RPR group's link ``coupler``)."""
    return "coupler" if kind == KINDS["RP"] else "B"


@dataclass(frozen=True, eq=False)
class Candidate:
    """A four-bar or slider-crank from two dyads (see the module notes).

    Attributes
    ----------
    kind : ``"four-bar"``, ``"slider-crank"`` or ``"inverted slider-crank"``.
    crank, driven : the driving RR dyad and the driven dyad (RR, PR or RP).
    linkage : the design as a :class:`~mechsynth.kinematics.Linkage` in the poses' frame:
        ground points ``O`` (crank pivot) and ``D`` (rocker pivot; a slider-crank has its guide
        through the slider's first position; an inverted slider-crank's block pivot), points
        ``A``, ``B`` (not for an RP dyad: its coupler is the RPR link ``coupler``), the pose
        point ``P`` and ``Q`` (on the pose frame's x axis, a quarter of the coupler from P); its
        input is the absolute crank angle (``phase`` 0).
    crank_angles : the crank angle (rad, from +x) at each pose, unwrapped in the direction of
        rotation from the first pose.
    direction : +1 (counter-clockwise) or -1: the crank's turning direction through the poses.
    branch : the driven dyad's assembly branch at the poses (+1, -1; 0 when it changes).
    grashof : the four-bar's Grashof class (``"crank-rocker"``, ...); for a slider-crank and
        an inverted slider-crank ``"full-turn crank"`` or ``"rocking crank"``.
    defects : the defects found (module notes); empty for a usable linkage.
    min_transmission : the smallest transmission angle (rad, folded to [0, pi/2]) over the
        motion from the first to the last pose; 0 where the crank meets a limit position (a toggle)
        on the way.
    mechanism : the design as :class:`~mechsynth.FourBar` / :class:`~mechsynth.SliderCrank` in
        the standard frame, or None when its crank does not turn fully.
    origin, rotation : the standard frame: ``standard = R(-rotation) (user - origin)``.
    """

    kind: str
    crank: Dyad
    driven: Dyad
    linkage: object
    crank_angles: np.ndarray
    direction: int
    branch: int
    grashof: str
    defects: tuple[str, ...]
    min_transmission: float
    mechanism: object = None
    origin: tuple[float, float] = (0.0, 0.0)
    rotation: float = 0.0
    notes: tuple[str, ...] = field(default=())

    @property
    def defect_free(self) -> bool:
        return not self.defects

    @property
    def standard_angles(self) -> np.ndarray:
        """The crank angles at the poses in the standard frame (rad)."""
        return self.crank_angles - self.rotation

    def to_standard(self, xy) -> np.ndarray:
        """Points of the poses' frame in the standard frame."""
        c, s = np.cos(self.rotation), np.sin(self.rotation)
        rel = np.asarray(xy, float) - self.origin
        return np.stack([c * rel[..., 0] + s * rel[..., 1], -s * rel[..., 0] + c * rel[..., 1]], -1)

    def from_standard(self, xy) -> np.ndarray:
        """Points of the standard frame in the poses' frame."""
        c, s = np.cos(self.rotation), np.sin(self.rotation)
        p = np.asarray(xy, float)
        return np.stack(
            [c * p[..., 0] - s * p[..., 1] + self.origin[0],
             s * p[..., 0] + c * p[..., 1] + self.origin[1]], -1
        )  # fmt: skip

    def _rrr_branch(self) -> int:
        """The branch the linkage's RRR group was built on (its first pose's when the poses
        change branch)."""
        return int(next(g.branch for g in self.linkage.groups if getattr(g, "kind", "") == "RRR"))

    def linkage_data(self) -> dict:
        """The linkage as the tables of a linkage file (``[linkage]``, ``[ground]``,
        ``[[group]]``; SI numbers), as :func:`~mechsynth.synthesis.load_linkage` reads them."""
        p = {k: float(v) for k, v in self.linkage.parameters.items()}
        ground = {"O": [p["O_x"], p["O_y"]]}
        groups = [{"type": "crank", "point": "A", "about": "O", "length": p["OA"]}]
        on = ["A", "B"]
        if self.kind == "four-bar":
            ground["D"] = [p["D_x"], p["D_y"]]
            groups.append(
                {"type": "rrr", "point": "B", "first": ["A", p["AB"]], "second": ["D", p["DB"]],
                 "branch": self._rrr_branch()}
            )  # fmt: skip
        elif self.kind == KINDS["RP"]:
            ground["D"] = [p["D_x"], p["D_y"]]
            groups.append(
                {"type": "rpr", "link": "coupler", "about": "A", "through": "D",
                 "offset": p["coupler_offset"], "branch": 1, "block": "block"}
            )  # fmt: skip
            on = "coupler"
        else:
            guide = {"through": [p["B_guide_x"], p["B_guide_y"]], "angle": p["B_guide_angle"]}
            groups.append({"type": "rrp", "point": "B", "rod": ["A", p["AB"]], "guide": guide})
        for q in ("P", "Q"):
            groups.append(
                {"type": "attach", "point": q, "on": on, "along": p[f"{q}_along"],
                 "left": p[f"{q}_left"]}
            )  # fmt: skip
        return {"linkage": {"name": self.kind, "output": "P"}, "ground": ground, "group": groups}

    def summary(self) -> dict:
        p = self.linkage.parameters
        out = {
            "kind": self.kind,
            "defects": list(self.defects),
            "grashof": self.grashof,
            "branch": self.branch,
            "direction": self.direction,
            "min_transmission_deg": float(np.degrees(self.min_transmission)),
            "crank_angles_deg": np.degrees(self.crank_angles).tolist(),
            "crank": self.crank.as_dict(),
            "driven": self.driven.as_dict(),
            "parameters": {k: float(v) for k, v in p.items()},
        }
        return out


def _cross(a, b):
    """z of the cross product of plane vectors (``(..., 2)``)."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _rp_linkage(crank: Dyad, driven: Dyad, poses, u):
    """The Linkage of an RR crank and an RP dyad: the RPR group ``coupler`` pinned at A, its
    axis along ``u`` (the slot's direction in pose 1, taken so that the block lies ahead of A),
    the slot ``offset`` to the left of that axis through the block pivot D."""
    from ..kinematics.linkage import Linkage

    za, d = np.asarray(crank.circle), np.asarray(driven.centre)
    un = np.array([-u[1], u[0]])
    span = float(np.max(np.hypot(*(poses[:, :2] - poses[0, :2]).T)))
    p1 = poses[0, :2]
    q1 = p1 + 0.25 * max(float(np.hypot(*(d - za))), span) * np.array(
        [np.cos(poses[0, 2]), np.sin(poses[0, 2])]
    )
    lk = (
        Linkage(ground={"O": crank.centre, "D": driven.centre}, name=KINDS["RP"])
        .crank("A", about="O", length=crank.length)
        .rpr("coupler", about="A", through="D", offset=float((d - za) @ un), block="block")
    )
    for name, pt in (("P", p1), ("Q", q1)):
        lk = lk.attach(name, on="coupler", along=float((pt - za) @ u), left=float((pt - za) @ un))
    return lk.with_output("P")


def _linkage(kind, crank: Dyad, driven: Dyad, poses, branch):
    """The Linkage of a pairing, in the poses' frame."""
    from ..kinematics.linkage import Linkage

    za, zb = np.asarray(crank.circle), np.asarray(driven.circle)
    ab = float(np.hypot(*(zb - za)))
    if ab <= 1e-12 * max(float(np.abs(np.concatenate([za, zb])).max()), 1e-300):
        raise MechanismError("the two dyads share their moving pivot: no coupler between them")
    e = (zb - za) / ab
    en = np.array([-e[1], e[0]])
    p1 = poses[0, :2]
    q1 = p1 + 0.25 * ab * np.array([np.cos(poses[0, 2]), np.sin(poses[0, 2])])
    pa = (float((p1 - za) @ e), float((p1 - za) @ en))
    qa = (float((q1 - za) @ e), float((q1 - za) @ en))
    ground = {"O": crank.centre}
    if kind == "four-bar":
        ground["D"] = driven.centre
    lk = Linkage(ground=ground, name=kind).crank("A", about="O", length=crank.length)
    if kind == "four-bar":
        lk = lk.rrr("B", ("A", ab), ("D", driven.length), branch=branch)
    else:
        g = driven.guide_angle + (np.pi if branch < 0 else 0.0)
        lk = lk.rrp("B", ("A", ab), guide=(tuple(driven.circle), float(g)), branch=1)
    return (
        lk.attach("P", on=("A", "B"), along=pa[0], left=pa[1])
        .attach("Q", on=("A", "B"), along=qa[0], left=qa[1])
        .with_output("P")
    )


def pair(poses, crank: Dyad, driven: Dyad) -> Candidate:
    """The four-bar (``driven`` RR), slider-crank (``driven`` PR) or inverted slider-crank
    (``driven`` RP) of two dyads, checked for its defects (module notes)."""
    from ..kinematics.four_bar import FourBar, grashof

    poses = as_poses(poses, max_poses=None)
    if crank.kind != "RR":
        raise MechanismError("the crank must be an RR dyad (a fixed pivot), got a slider dyad")
    kind = KINDS[driven.kind]
    a_pos, b_pos = crank.positions(poses), driven.positions(poses)
    o = np.asarray(crank.centre)
    phi = np.arctan2(a_pos[:, 1] - o[1], a_pos[:, 0] - o[0])
    # the driven dyad's branch at each pose
    if kind == "four-bar":
        d = np.asarray(driven.centre)
        side = _cross(d - a_pos, b_pos - a_pos)
    elif kind == KINDS["RP"]:
        # the block's place along the slot from A (the slot's direction in each pose, taken
        # so that it is ahead of A in pose 1): through zero, the coupler meets a toggle
        d = np.asarray(driven.centre)
        g1 = driven.line_angle + poses[0, 2]
        ahead = float((d - a_pos[0]) @ np.array([np.cos(g1), np.sin(g1)]))
        ug = driven.line_angle + (np.pi if ahead < 0 else 0.0) + poses[:, 2]
        side = np.einsum("ij,ij->i", d - a_pos, np.column_stack([np.cos(ug), np.sin(ug)]))
    else:
        g = np.array([np.cos(driven.guide_angle), np.sin(driven.guide_angle)])
        side = (b_pos - a_pos) @ g
    signs = np.sign(side)
    branch = int(signs[0]) if np.all(signs == signs[0]) and signs[0] != 0 else 0
    defects = []
    if branch == 0:
        defects.append("branch")
    # order: one turning direction that meets the poses in order within one turn
    direction, span = 0, None
    for s in (1, -1):
        rel = np.mod(s * (phi - phi[0]), 2.0 * np.pi)
        if np.all(np.diff(rel) > 0):
            direction, span = s, rel
            break
    if direction == 0:
        defects.append("order")
        rel = np.mod(phi - phi[0], 2.0 * np.pi)
        direction, span = 1, rel
    unwrapped = phi[0] + direction * span
    la = crank.length
    if kind == "four-bar":
        lg = float(np.hypot(*(np.asarray(driven.centre) - o)))
        lc = float(np.hypot(*(np.asarray(driven.circle) - np.asarray(crank.circle))))
        gclass = grashof(la, lc, driven.length, lg).kind
        rotates = gclass in ("crank-rocker", "double-crank")
    elif kind == KINDS["RP"]:
        u1 = np.array([np.cos(ug[0]), np.sin(ug[0])])
        offset = float(_cross(u1, np.asarray(driven.centre) - a_pos[0]))
        lg = float(np.hypot(*(np.asarray(driven.centre) - o)))
        rotates = abs(lg - la) > abs(offset)
        gclass = "full-turn crank" if rotates else "rocking crank"
    else:
        g = np.array([np.cos(driven.guide_angle), np.sin(driven.guide_angle)])
        offset = float(_cross(g, o - np.asarray(driven.circle)))
        lc = float(np.hypot(*(np.asarray(driven.circle) - np.asarray(crank.circle))))
        rotates = lc > la + abs(offset)
        gclass = "full-turn crank" if rotates else "rocking crank"
    if not rotates:
        defects.append("grashof")
    if kind == KINDS["RP"]:
        lk = _rp_linkage(crank, driven, poses, u1)
    else:
        lk = _linkage(kind, crank, driven, poses, branch if branch else int(signs[0] or 1))
    # the motion from the first to the last pose: limits and transmission angle
    sweep = phi[0] + direction * np.linspace(0.0, span[-1], SPAN_SAMPLES)
    margins = lk.assembly_margins(sweep)
    cond = np.min(np.stack([np.asarray(v, float) for v in margins.values()]), axis=0)
    mu_min = 0.0  # a limit position is a toggle: transmission angle 0
    if np.any(cond <= 0.0):
        defects.append("limit")
    else:
        m = lk.motion(sweep)
        mu = np.asarray(m.transmission_angles[driven_key(kind)], float)
        mu_min = float(np.min(np.fmin(mu, np.pi - mu)))
    mech, origin, rot = None, (float(o[0]), float(o[1])), 0.0
    if rotates and branch != 0 and kind != KINDS["RP"]:
        if kind == "four-bar":
            rot = float(np.arctan2(*(np.asarray(driven.centre) - o)[::-1]))
            mech = FourBar(
                crank=float(la), coupler=lc, rocker=float(driven.length), ground=lg,
                branch="open" if branch > 0 else "crossed",
            )  # fmt: skip
        else:
            from ..kinematics.slider_crank import SliderCrank

            rot = float(driven.guide_angle + (np.pi if branch < 0 else 0.0))
            off = float(
                -np.sin(rot) * (driven.circle[0] - o[0]) + np.cos(rot) * (driven.circle[1] - o[1])
            )
            mech = SliderCrank(crank=float(la), rod=lc, offset=off)
    return Candidate(
        kind, crank, driven, lk, unwrapped, int(direction), branch, gclass, tuple(defects),
        mu_min, mech, origin, rot,
    )  # fmt: skip


def pose_errors(linkage, poses, crank_angles=None) -> tuple[np.ndarray, np.ndarray]:
    """How far a linkage of this module (points ``O``, ``A``, ``P``, ``Q``) misses the poses:
    ``(position error (m), angle error (rad))`` per pose, with the crank turned to
    ``crank_angles`` or, by default, to where the pose puts the moving pivot A (the angle of
    ``A - O`` with A placed by the pose). A linkage that cannot be assembled at one of these
    crank angles raises :class:`~mechsynth.MechanismError` (it cannot take that pose)."""
    poses = as_poses(poses, max_poses=None)
    if crank_angles is None:
        # A in the pose frame, from the coupler frame (origin A, x towards B) the points are
        # attached in: no motion needed (a rocking crank need not reach any given angle)
        o = {k: float(v) for k, v in linkage.parameters.items()}
        p = np.array([o["P_along"], o["P_left"]])
        f = np.array([o["Q_along"], o["Q_left"]]) - p
        f = f / np.hypot(*f)
        local = np.array([(-p) @ f, _cross(f, -p)])
        c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
        ax = poses[:, 0] + c * local[0] - s * local[1]
        ay = poses[:, 1] + s * local[0] + c * local[1]
        crank_angles = np.arctan2(ay - o["O_y"], ax - o["O_x"]) - o.get("phase", 0.0)
    m = linkage.motion(np.asarray(crank_angles, float))
    px, py = np.asarray(m.points["P"].x, float), np.asarray(m.points["P"].y, float)
    qx, qy = np.asarray(m.points["Q"].x, float), np.asarray(m.points["Q"].y, float)
    pos = np.hypot(px - poses[:, 0], py - poses[:, 1])
    ang = np.abs(np.angle(np.exp(1j * (np.arctan2(qy - py, qx - px) - poses[:, 2]))))
    return pos, ang


@dataclass(frozen=True, eq=False)
class MotionGeneration:
    """Result of :func:`motion_generation`.

    Attributes
    ----------
    burmester : the :class:`~mechsynth.synthesis.burmester.Burmester` theory of the poses.
    dyads : the dyads paired.
    candidates : every pairing, ranked (defect-free first, then by the larger minimum
        transmission angle).
    """

    burmester: Burmester
    dyads: tuple[Dyad, ...]
    candidates: tuple[Candidate, ...]

    @property
    def poses(self) -> np.ndarray:
        return self.burmester.poses

    @property
    def best(self) -> Candidate:
        """The first-ranked candidate."""
        if not self.candidates:
            raise MechanismError("no pairing of these dyads gives a linkage")
        return self.candidates[0]

    @property
    def defect_free(self) -> tuple[Candidate, ...]:
        return tuple(c for c in self.candidates if c.defect_free)

    def table(self) -> dict[str, list]:
        """Columns of the ranked candidates (SI: m, deg for the angles)."""
        cols: dict[str, list] = {
            k: []
            for k in (
                "rank", "kind", "defects", "grashof", "min transmission angle [deg]",
                "O x [m]", "O y [m]", "A x [m]", "A y [m]", "D x [m]", "D y [m]",
                "B x [m]", "B y [m]", "guide angle [deg]", "crank [m]", "coupler [m]",
                "rocker [m]",
            )
        }  # fmt: skip
        for i, c in enumerate(self.candidates, start=1):
            p = c.linkage.parameters
            cols["rank"].append(i)
            cols["kind"].append(c.kind)
            cols["defects"].append(" ".join(c.defects) or "none")
            cols["grashof"].append(c.grashof)
            cols["min transmission angle [deg]"].append(float(np.degrees(c.min_transmission)))
            cols["O x [m]"].append(c.crank.centre[0])
            cols["O y [m]"].append(c.crank.centre[1])
            cols["A x [m]"].append(c.crank.circle[0])
            cols["A y [m]"].append(c.crank.circle[1])
            dc = c.driven.centre or (float("nan"), float("nan"))
            cols["D x [m]"].append(dc[0])
            cols["D y [m]"].append(dc[1])
            cols["B x [m]"].append(c.driven.circle[0])
            cols["B y [m]"].append(c.driven.circle[1])
            ga = c.driven.guide_angle
            cols["guide angle [deg]"].append(float("nan") if ga is None else float(np.degrees(ga)))
            cols["crank [m]"].append(float(p["OA"]))
            cols["coupler [m]"].append(float(p["AB"]) if "AB" in p else float("nan"))
            cols["rocker [m]"].append(float(p["DB"]) if "DB" in p else float("nan"))
        return cols

    def plot(self, candidate: int | Candidate | None = 0, ax=None, **kwargs):
        """:func:`plot_motion` of the poses with candidate ``candidate`` (an index into the
        ranking, a :class:`Candidate`, or None for none)."""
        if isinstance(candidate, int):
            candidate = self.candidates[candidate] if self.candidates else None
        return plot_motion(self.burmester, candidate=candidate, ax=ax, **kwargs)

    def problem(self, candidate: int | Candidate = 0, **kwargs):
        """:func:`motion_problem` for a candidate (index into the ranking, or one)."""
        if isinstance(candidate, int):
            candidate = self.candidates[candidate]
        return motion_problem(candidate, self.poses, **kwargs)

    def as_dict(self) -> dict:
        return {
            "burmester": self.burmester.as_dict(),
            "dyads": [d.as_dict() for d in self.dyads],
            "candidates": [c.summary() for c in self.candidates],
        }


def _curve_samples(bm: Burmester, k: int) -> list[np.ndarray]:
    """``k`` centre points spread along the 4-pose centre-point curve (within a box three
    times the poses' span about them)."""
    pts = bm.centre_curve(1441)
    lo, hi = bm.poses[:, :2].min(0), bm.poses[:, :2].max(0)
    span = max(float(np.max(hi - lo)), bm._scale)
    inside = np.all((pts > lo - 1.5 * span) & (pts < hi + 1.5 * span), axis=1)
    pts = pts[inside]
    if len(pts) < k:
        return list(pts)
    step = np.hypot(*np.diff(pts, axis=0).T)
    step = np.where(step > 0.1 * span, 0.0, step)  # across a break
    s = np.concatenate([[0.0], np.cumsum(step)])
    targets = np.linspace(0.0, s[-1], k + 2)[1:-1]
    idx = np.unique(np.searchsorted(s, targets).clip(0, len(pts) - 1))
    return [pts[i] for i in idx]


def motion_generation(poses, centres=None, dyads=None, samples: int = 12) -> MotionGeneration:
    """Four-bars and slider-cranks that carry a coupler through 2 to 5 poses, ranked.

    Parameters
    ----------
    poses : rows ``(x, y, angle)`` (m, m, rad; see :func:`burmester`).
    centres : fixed pivots to use (3 poses: any points; 4 poses: points of the centre-point
        curve; 5 poses: Burmester points); their circle points follow from the theory.
    dyads : :class:`~mechsynth.synthesis.burmester.Dyad` objects to pair instead (2 poses: make
        them with ``Burmester.dyad(centre, circle)``).
    samples : 4 poses without ``centres``: how many centre points to take along the curve.

    Returns
    -------
    MotionGeneration : every pairing of two dyads (each RR dyad as the crank, the other RR,
        PR or RP as the driven dyad), checked for defects and ranked.
    """
    from .. import validate

    bm = burmester(poses)
    n = bm.n
    if dyads is not None and centres is not None:
        raise MechanismError("give centres or dyads, not both")
    if dyads is not None:
        ds = list(dyads)
        if not all(isinstance(d, Dyad) for d in ds):
            raise MechanismError("dyads must be Dyad objects (Burmester.circle_point, .dyad, ...)")
    elif centres is not None:
        cs = validate.real("centres", centres)
        cs = np.array(cs, dtype=float, ndmin=2)
        if cs.ndim != 2 or cs.shape[1] != 2:
            raise MechanismError(f"centres must be rows of (x, y); got shape {cs.shape}")
        ds = [bm.circle_point(c) for c in cs]
    elif n == 5:
        ds = list(bm.points)
    elif n == 4:
        samples = validate.integer("samples", samples, 2, 200)
        ds = []
        for c in _curve_samples(bm, samples):
            try:
                ds.append(bm.circle_point(c))
            except MechanismError:  # a sample at a pole
                continue
        ds += list(bm.sliders()) + list(bm.rp_dyads())
    else:
        raise MechanismError(
            f"with {n} poses every point is a centre point: choose the fixed pivots "
            "(centres=[(x1, y1), (x2, y2)]) or give dyads"
        )
    if sum(d.kind == "RR" for d in ds) < 1 or len(ds) < 2:
        raise MechanismError(
            f"{len(ds)} dyad(s) ({sum(d.kind == 'RR' for d in ds)} with a fixed pivot): a "
            "linkage needs two, one of them a crank"
            + (" -- these 5 poses have no real Burmester points" if n == 5 and not ds else "")
        )
    cands, errors = [], []
    for i, a in enumerate(ds):
        if a.kind != "RR":
            continue
        for j, b in enumerate(ds):
            if i == j:
                continue
            try:
                cands.append(pair(bm.poses, a, b))
            except MechanismError as exc:  # e.g. a length the linkage refuses
                errors.append(str(exc))
    if not cands:
        raise MechanismError(
            f"no pairing of the {len(ds)} dyads gives a linkage"
            + (f": {errors[0]}" if errors else "")
        )
    mu = [c.min_transmission for c in cands]
    order = sorted(
        range(len(cands)),
        key=lambda k: (len(cands[k].defects), -mu[k]),
    )
    return MotionGeneration(bm, tuple(ds), tuple(cands[k] for k in order))


# --------------------------------------------------------------------- exact to optimal
def pose_error_measure(poses, kind: str = "four-bar"):
    """A :class:`~mechsynth.objectives.ScalarMeasure` of a linkage of this module: the largest
    structural error (m) over the poses -- how far each moving pivot, placed by the pose, lies
    off its circle about its fixed pivot (or off the slider's guide; for an inverted
    slider-crank, how far the block pivot lies off the slot placed by the pose). Zero exactly
    when the linkage can take every pose. Written with ``ops``: CasADi parameters give exact
    derivatives; its branches ``(+e, -e)`` make ``<=`` and ``minimize`` smooth."""
    from ..kinematics import ops
    from ..objectives.base import ScalarMeasure

    poses = as_poses(poses, max_poses=None)
    cth, sth = np.cos(poses[:, 2]), np.sin(poses[:, 2])

    rp = kind == KINDS["RP"]

    def errors(lk):
        p = lk.parameters
        fx, fy = p["Q_along"] - p["P_along"], p["Q_left"] - p["P_left"]
        fn = ops.sqrt(fx * fx + fy * fy)
        fx, fy = fx / fn, fy / fn
        out = []
        if rp:  # the block pivot D in the coupler's frame (origin A, x along the slot)
            for j in range(len(poses)):
                dx, dy = p["D_x"] - poses[j, 0], p["D_y"] - poses[j, 1]
                lx, ly = cth[j] * dx + sth[j] * dy, -sth[j] * dx + cth[j] * dy
                out.append(lx * fy + ly * fx + p["P_left"] - p["coupler_offset"])
        pairs = ((-p["P_along"], -p["P_left"], "A"),)
        if not rp:
            pairs += ((p["AB"] - p["P_along"], -p["P_left"], "B"),)
        for vx, vy, which in pairs:
            lx, ly = vx * fx + vy * fy, -fy * vx + fx * vy  # in the pose frame
            for j in range(len(poses)):
                x = poses[j, 0] + cth[j] * lx - sth[j] * ly
                y = poses[j, 1] + sth[j] * lx + cth[j] * ly
                if which == "A":
                    dx, dy = x - p["O_x"], y - p["O_y"]
                    out.append(ops.sqrt(dx * dx + dy * dy) - p["OA"])
                elif kind == "four-bar":
                    dx, dy = x - p["D_x"], y - p["D_y"]
                    out.append(ops.sqrt(dx * dx + dy * dy) - p["DB"])
                else:
                    g = p["B_guide_angle"]
                    out.append(
                        -ops.sin(g) * (x - p["B_guide_x"]) + ops.cos(g) * (y - p["B_guide_y"])
                    )
        return out

    def fn(lk):
        e = errors(lk)
        worst = ops.fabs(e[0])
        for v in e[1:]:
            worst = ops.fmax(worst, ops.fabs(v))
        return worst

    def branches(lk):
        e = errors(lk)
        return tuple(e) + tuple(-v for v in e)

    return ScalarMeasure("pose_error", fn, "m", branches=branches)


def motion_problem(
    candidate: Candidate,
    poses,
    objective: str = "transmission",
    tol: float = 1e-4,
    span: float = 0.5,
    vary=None,
):
    """An :class:`~mechsynth.synthesis.Problem` that starts from an exact candidate.

    Parameters
    ----------
    candidate : a :class:`Candidate` whose crank turns fully (the problem certifies over the
        whole turn).
    poses : the poses to hold (more than five allowed).
    objective : ``"transmission"`` -- maximize the minimum transmission angle at B subject to the
        pose error (:func:`pose_error_measure`) ``<= tol``; ``"error"`` -- minimize the pose
        error (for more poses than the exact theory takes).
    tol : the pose error allowed (m), with ``"transmission"``.
    span : each varied dimension's bounds: its value -+ ``span`` times the poses' extent (m).
    vary : the parameters varied (default: the pivots, the lengths and the coupler points).

    Returns
    -------
    Problem : call ``.solve()``; its ``design`` is the refined Linkage.
    """
    from .. import validate
    from ..objectives import kinematic as ob
    from .problem import Problem

    poses = as_poses(poses, max_poses=None)
    validate.option("objective", objective, ("transmission", "error"))
    tol = validate.positive("tol", tol, "m")
    span = validate.positive("span", span)
    if "grashof" in candidate.defects:
        raise MechanismError(
            f"the candidate's crank does not turn fully ({candidate.grashof}): a Problem "
            "certifies its measures over the whole turn; choose a candidate without the "
            "grashof defect"
        )
    lk = candidate.linkage
    params = {k: float(v) for k, v in lk.parameters.items()}
    extent = float(np.max(np.ptp(poses[:, :2], axis=0)))
    extent = max(extent, 1e-9)
    if vary is None:
        vary = [k for k in params if k not in ("phase", "B_guide_angle")]
    variables = {}
    for k in vary:
        if k not in params:
            raise MechanismError(f"vary: the linkage has no parameter {k!r}; it has {list(params)}")
        lo, hi = params[k] - span * extent, params[k] + span * extent
        if lk.parameter_kinds.get(k) == "length":
            lo = max(lo, 0.05 * params[k])
        variables[k] = (lo, hi)
    fixed = {k: v for k, v in params.items() if k not in variables}
    prob = Problem(lk, variables=variables, fixed=fixed)
    err = pose_error_measure(poses, candidate.kind)
    if objective == "transmission":
        prob.maximize(ob.min_transmission_angle(driven_key(candidate.kind)))
        prob.subject_to(err <= tol)
    else:
        prob.minimize(err)
    return prob


# --------------------------------------------------------------------- figure
def plot_motion(bm: Burmester, candidate: Candidate | None = None, ax=None, title=None):
    """The poses (small frames numbered 1..n), the poles, the centre- and circle-point curves
    (4 poses) or the Burmester points (5 poses), and a candidate linkage drawn in each pose.
    Returns the figure."""
    import matplotlib.pyplot as plt

    from .. import display
    from ..kinematics.drawing import draw_sketch
    from ..plotting import PALETTE, style

    du = display.current()
    k = du.factor("m")
    unit = du.unit("m")
    poses = bm.poses
    with style():
        if ax is None:
            fig, ax = plt.subplots(figsize=(9.0, 6.0))
        else:
            fig = ax.figure
        pts = [poses[:, :2]]
        if candidate is not None:
            sk = candidate.linkage.sketch(candidate.crank_angles)
            for f in range(len(poses)):
                draw_sketch(sk, f, ax=ax, alpha=0.35 + 0.65 * (f == 0), labels=f == 0, title=False)
            pts += [candidate.crank.positions(poses), candidate.driven.positions(poses),
                    np.array([candidate.crank.centre])]  # fmt: skip
            if candidate.driven.centre is not None:
                pts.append(np.array([candidate.driven.centre]))
        span = float(np.max(np.ptp(poses[:, :2], axis=0)))
        ax.plot([], [], color=PALETTE[5], lw=1.4, marker=">", ms=5,
                label="poses (x axis, y axis)")  # fmt: skip
        poles = np.array([p for p in bm.poles.values() if p is not None])
        lo = np.min(np.concatenate(pts), axis=0)
        hi = np.max(np.concatenate(pts), axis=0)
        size = max(float(np.max(hi - lo)), span)
        view_lo, view_hi = lo - 0.35 * size, hi + 0.35 * size
        if len(poles):
            near = poles[np.all((poles > view_lo) & (poles < view_hi), axis=1)]
            if len(near):
                ax.plot(near[:, 0] / k, near[:, 1] / k, "x", color=PALETTE[0], ms=5,
                        label="poles")  # fmt: skip
                pts.append(near)
        if bm.n == 4:
            cc, kc = bm.centre_curve(1441), bm.circle_curve(1441)
            ax.plot(cc[:, 0] / k, cc[:, 1] / k, color=PALETTE[4], lw=1.2,
                    label="centre-point curve")  # fmt: skip
            ax.plot(kc[:, 0] / k, kc[:, 1] / k, color=PALETTE[1], lw=1.2, ls="--",
                    label="circle-point curve (pose 1)")  # fmt: skip
        if bm.n == 5 and bm.points:
            rr = [d for d in bm.points if d.kind == "RR"]
            if rr:
                c = np.array([d.centre for d in rr])
                z = np.array([d.circle for d in rr])
                ax.plot(c[:, 0] / k, c[:, 1] / k, "s", color=PALETTE[4], ms=6,
                        label="Burmester centre points")  # fmt: skip
                ax.plot(z[:, 0] / k, z[:, 1] / k, "o", mfc="none", color=PALETTE[1], ms=6,
                        label="circle points (pose 1)")  # fmt: skip
                both = np.concatenate([c, z])
                near = np.all((both > view_lo) & (both < view_hi), axis=1)
                pts.append(both[near])
        rp = np.array([d.centre for d in bm.rp_dyads()]).reshape(-1, 2)
        rp = rp[np.all((rp > view_lo) & (rp < view_hi), axis=1)]
        if len(rp):  # the block pivots in view (an RP dyad's pivot is often far away)
            ax.plot(rp[:, 0] / k, rp[:, 1] / k, "D", mfc="none", color=PALETTE[2], ms=7,
                    label="RP dyads' block pivots")  # fmt: skip
            pts.append(rp)
        lo = np.min(np.concatenate(pts), axis=0)
        hi = np.max(np.concatenate(pts), axis=0)
        size = max(float(np.max(hi - lo)), span)
        ax.set_xlim((lo[0] - 0.15 * size) / k, (hi[0] + 0.15 * size) / k)
        ax.set_ylim((lo[1] - 0.15 * size) / k, (hi[1] + 0.3 * size) / k)
        ax.set_aspect("equal", adjustable="box")
        arrow = 0.07 * size
        for j, (x, y, a) in enumerate(poses):
            ax.annotate(
                "", xy=((x + arrow * np.cos(a)) / k, (y + arrow * np.sin(a)) / k),
                xytext=(x / k, y / k),
                arrowprops={"arrowstyle": "-|>", "color": PALETTE[5], "lw": 1.6}, zorder=20,
            )  # fmt: skip
            ax.plot(
                [x / k, (x - 0.5 * arrow * np.sin(a)) / k],
                [y / k, (y + 0.5 * arrow * np.cos(a)) / k],
                color=PALETTE[5], lw=1.2, zorder=20,
            )  # fmt: skip
            ax.annotate(
                str(j + 1),
                ((x - 0.35 * arrow * np.cos(a)) / k, (y - 0.35 * arrow * np.sin(a)) / k),
                ha="center", va="center", fontsize=8, color=PALETTE[5], zorder=21,
                bbox={"boxstyle": "round,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.8},
            )  # fmt: skip
        ax.set_xlabel(f"x, {unit}")
        ax.set_ylabel(f"y, {unit}")
        if title is None:
            title = f"Motion generation: {bm.n} poses"
            if candidate is not None:
                mu = np.degrees(candidate.min_transmission)
                title += (f"\n{candidate.kind}, min transmission angle {mu:.1f} deg, defects: "
                          f"{', '.join(candidate.defects) or 'none'}")  # fmt: skip
        if title:
            ax.set_title(title, fontsize=10)
        ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=7, framealpha=0.9)
    return fig
