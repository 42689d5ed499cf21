"""Burmester theory: the dyads that carry a moving plane through 2 to 5 given poses.

Conventions
-----------
* A pose is ``(x, y, angle)``: the origin of the moving plane's frame (a point of the coupler,
  m) and the angle of its x axis from +x, counter-clockwise (rad). Pose 1 is the first row.
* A point of the moving plane with frame coordinates ``m`` is at ``R(angle_j) m + p_j`` in pose
  ``j``. The displacement from pose 1 to pose ``j`` maps a point ``z`` (where it is in pose 1)
  to ``A_j (z - p_1) + p_j`` with ``A_j`` the rotation by ``angle_j - angle_1``.
* An RR dyad (a crank or rocker) is a *centre point* ``c`` (the fixed pivot) and a *circle
  point* (the moving pivot), reported where it lies in pose 1 (global coordinates, ``circle``)
  and in the moving frame (``local``); its positions in all poses lie on one circle about ``c``.
  A PR dyad (a slider: its centre point at infinity) has a circle point whose positions lie on
  one straight line, the guide. An RP dyad (a block pinned at a fixed pivot, the coupler sliding
  through it: its circle point at infinity) has a line fixed in the moving plane, the slot,
  that passes through its fixed pivot in every pose.

Equations
---------
With ``u = z - p_1``, ``w = c - p_1``, ``d_j = p_j - p_1``, the condition
``|A_j u + d_j - w|^2 = |u - w|^2`` is bilinear:

    E_j(w, u) = |d_j|^2 / 2 - d_j.w + (A_j^T d_j).u - w.(A_j - I) u = (w, 1)^T Q_j (u, 1) = 0,

linear in the circle point for a given centre point and in the centre point for a given circle
point. Three poses give two equations (one circle point per centre point and the reverse); four
give three, whose compatibility ``det[Q_j^T (w, 1)] = 0`` is the centre-point curve, a circular
cubic through the six poles (the circle-point curve likewise with ``Q_j``); five give four
equations with at most four real solutions, the Burmester points. They are found as the real
roots of a quartic: two centre-point cubics (poses 1234 and 1235) both pass through the pole
P12; on a line through P12 in the direction ``e1 + t e2`` each meets its other two points where
a quadratic in the distance vanishes, and the resultant of the two quadratics is a polynomial of
degree 8 in ``t`` whose factors ``1 + t^2`` (the circular points) and the directions of the
common poles P13 and P23 are divided out. Each real root is refined by Newton's method on the
four equations to round-off.

RP dyads are the PR dyads of the inverse motion (the fixed plane seen from the moving one: pose
``j`` inverted is ``(-R(-angle_j) p_j, -angle_j)``): a point of the fixed plane whose positions
in the moving frame lie on one line is a fixed pivot through which that line, fixed in the
moving plane, passes in every pose.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from itertools import permutations

import numpy as np

from .. import validate
from ..errors import MechanismError

__all__ = ["Burmester", "Dyad", "burmester", "as_poses", "displace"]

#: Burmester theory's limits: 2 poses at least, 5 at most (exact synthesis)
MIN_POSES, MAX_POSES = 2, 5
#: the largest pose angle accepted (rad): beyond it a difference of angles loses its digits
MAX_POSE_ANGLE = 1e6


def as_poses(poses, name: str = "poses", max_poses: int | None = MAX_POSES) -> np.ndarray:
    """``poses`` as an ``(n, 3)`` float array of ``(x, y, angle)`` rows, checked: finite, two
    poses at least (at most ``max_poses``), no two alike, not all at one point."""
    arr = validate.real(name, poses)
    arr = np.array(arr, dtype=float, ndmin=2)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise MechanismError(
            f"{name} must be rows of (x, y, angle), an (n, 3) array; got shape {arr.shape}"
        )
    n = arr.shape[0]
    big = np.abs(arr[:, :2]) > validate.MAX_LENGTH
    if big.any():
        i, k = np.argwhere(big)[0]
        raise MechanismError(
            f"{name}: pose {i + 1}'s {'xy'[k]} ({arr[i, k]:.6g} m) beyond "
            f"{validate.MAX_LENGTH:.0e} m"
        )
    if np.any(np.abs(arr[:, 2]) > MAX_POSE_ANGLE):
        i = int(np.argmax(np.abs(arr[:, 2])))
        raise MechanismError(
            f"{name}: pose {i + 1}'s angle ({arr[i, 2]:.6g} rad) beyond {MAX_POSE_ANGLE:.0e} "
            "rad (give angles within a few turns)"
        )
    if n < MIN_POSES or (max_poses is not None and n > max_poses):
        top = f" and at most {max_poses}" if max_poses is not None else ""
        raise MechanismError(
            f"{name}: exact motion generation takes at least {MIN_POSES}{top} poses, got {n}"
        )
    span = float(np.max(np.hypot(*(arr[:, :2] - arr[0, :2]).T)))
    scale = max(span, float(np.max(np.abs(arr[:, :2]))), 1e-300)
    for i in range(n):
        for j in range(i + 1, n):
            dp = float(np.hypot(*(arr[j, :2] - arr[i, :2])))
            turn = abs(np.angle(np.exp(1j * (arr[j, 2] - arr[i, 2]))))
            if dp <= 1e-9 * scale and turn <= 1e-9:
                raise MechanismError(
                    f"{name} {i + 1} and {j + 1} coincide ({_fmt(arr[i])}): every pose must "
                    "differ from the others in position or angle"
                )
    if span <= 1e-9 * scale:
        raise MechanismError(
            f"{name}: all poses share the point ({arr[0, 0]:.6g}, {arr[0, 1]:.6g}); the plane "
            "only turns about it, which a crank pinned there does: no dyad to synthesize"
        )
    return arr


def _fmt(row) -> str:
    return f"x {row[0]:.6g} m, y {row[1]:.6g} m, angle {np.degrees(row[2]):.6g} deg"


def _rot(angle):
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s], [s, c]])


def displace(poses: np.ndarray, z) -> np.ndarray:
    """Where the point of the moving plane at ``z`` in pose 1 lies in every pose: ``(n, 2)``
    (``z`` may be ``(..., 2)``: the result is ``(..., n, 2)``)."""
    z = np.asarray(z, dtype=float)
    beta = poses[:, 2] - poses[0, 2]
    rel = z[..., None, :] - poses[0, :2]
    c, s = np.cos(beta), np.sin(beta)
    x = c * rel[..., 0] - s * rel[..., 1] + poses[:, 0]
    y = s * rel[..., 0] + c * rel[..., 1] + poses[:, 1]
    return np.stack([x, y], axis=-1)


@dataclass(frozen=True)
class Dyad:
    """One dyad that carries the moving plane through the poses.

    Attributes
    ----------
    centre : ``(x, y)`` of the fixed pivot (m); None for a slider (PR) dyad.
    circle : ``(x, y)`` of the moving pivot in pose 1 (m, global coordinates).
    local : the moving pivot in the moving frame (m): ``circle = R(angle_1) local + p_1``.
    length : the crank's length ``|circle - centre|`` (m); for a slider the distance of its
        guide from the origin is not a length: None.
    guide_angle : a slider's guide direction from +x (rad, in ``[0, pi)``); None for RR.
    residual : the largest deviation over all poses from an exact dyad (m): of the moving
        pivot's distance from the centre from ``length`` (RR), of its positions from the
        guide line (PR), or of the fixed pivot from the slot line (RP).
    line_angle : an RP dyad's slot direction in the moving frame (rad from the frame's x axis,
        in ``[0, pi)``; in pose ``j`` the slot runs at ``angle_j + line_angle`` from +x); its
        ``centre`` is the fixed pivot the slot passes through and ``circle`` (``local``) the
        point of the slot at that pivot in pose 1. None for RR and PR.
    """

    centre: tuple[float, float] | None
    circle: tuple[float, float]
    local: tuple[float, float]
    length: float | None
    guide_angle: float | None = None
    residual: float = 0.0
    line_angle: float | None = None

    @property
    def kind(self) -> str:
        """``"RR"`` (a crank pinned at ``centre``), ``"PR"`` (a slider on a guide) or ``"RP"``
        (a slot of the moving plane through a block pinned at ``centre``)."""
        if self.line_angle is not None:
            return "RP"
        return "RR" if self.centre is not None else "PR"

    def positions(self, poses) -> np.ndarray:
        """The moving pivot in every pose, ``(n, 2)`` (m)."""
        return displace(np.asarray(poses, dtype=float), self.circle)

    def as_dict(self) -> dict:
        return {
            "kind": self.kind,
            "centre": None if self.centre is None else list(self.centre),
            "circle": list(self.circle),
            "local": list(self.local),
            "length": self.length,
            "guide_angle": self.guide_angle,
            "residual": self.residual,
            "line_angle": self.line_angle,
        }


def _dyad(poses, w, u, scale, origin) -> Dyad:
    """A Dyad from normalized ``w``, ``u`` (relative to pose 1's point, divided by ``scale``)."""
    c = origin + scale * np.asarray(w, float)
    z = origin + scale * np.asarray(u, float)
    local = _rot(-poses[0, 2]) @ (z - poses[0, :2])
    pos = displace(poses, z)
    radii = np.hypot(*(pos - c).T)
    length = float(np.hypot(*(z - c)))
    return Dyad(
        (float(c[0]), float(c[1])),
        (float(z[0]), float(z[1])),
        (float(local[0]), float(local[1])),
        length,
        None,
        float(np.max(np.abs(radii - length))),
    )


def _slider(poses, u, normal, scale, origin) -> Dyad:
    z = origin + scale * np.asarray(u, float)
    local = _rot(-poses[0, 2]) @ (z - poses[0, :2])
    n = np.asarray(normal, float) / np.hypot(*normal)
    pos = displace(poses, z)
    off = (pos - z) @ n
    angle = float(np.mod(np.arctan2(n[0], -n[1]), np.pi))  # the guide is normal to n
    return Dyad(
        None,
        (float(z[0]), float(z[1])),
        (float(local[0]), float(local[1])),
        None,
        angle,
        float(np.max(np.abs(off))),
    )


@dataclass(frozen=True, eq=False)
class Burmester:
    """Burmester theory of 2 to 5 poses (see the module notes); made by :func:`burmester`.

    Attributes
    ----------
    poses : ``(n, 3)`` array of ``(x, y, angle)`` rows (m, rad).
    poles : ``{(i, j): (x, y)}`` the displacement poles of poses ``i < j`` (1-based), the
        fixed point of the displacement from pose i to pose j; None where the two poses differ
        by a translation only (the pole at infinity).
    points : the Burmester dyads (five poses: RR dyads, 0, 2 or 4; plus a PR slider where a
        centre point lies at infinity, an RP dyad where a circle point does); empty for fewer
        poses.
    """

    poses: np.ndarray
    poles: dict = field(repr=False)
    points: tuple[Dyad, ...] = ()
    _scale: float = field(default=1.0, repr=False)

    @property
    def n(self) -> int:
        return int(self.poses.shape[0])

    # -------------------------------------------------------------- normalized equations
    def _q(self) -> np.ndarray:
        """``Q_j`` (j = 2..n) of the bilinear equations in normalized coordinates."""
        return _q_matrices(self.poses, self._scale)

    def _norm(self, point):
        return (np.asarray(point, dtype=float) - self.poses[0, :2]) / self._scale

    def _check_point(self, point, name):
        p = validate.real(name, point)
        p = np.asarray(p, dtype=float)
        if p.shape != (2,):
            raise MechanismError(f"{name} must be a point (x, y), got shape {p.shape}")
        return p

    # -------------------------------------------------------------- 3 and 4 poses: maps
    def circle_point(self, centre) -> Dyad:
        """The dyad with the fixed pivot ``centre`` (3 poses: any point; 4 poses: a point of the
        centre-point curve; 5 poses: a Burmester point)."""
        c = self._check_point(centre, "centre")
        if self.n < 3:
            raise MechanismError(
                "with 2 poses every point of the perpendicular bisector of a circle point's two "
                "positions is a centre point: give both (Burmester.dyad(centre, circle))"
            )
        rows = np.einsum("i,jik->jk", np.append(self._norm(c), 1.0), self._q())
        u = _solve_rows(rows, "centre", c, "centre-point curve", self.n, self._scale)
        return _dyad(self.poses, self._norm(c), u, self._scale, self.poses[0, :2])

    def centre_point(self, circle) -> Dyad:
        """The dyad whose moving pivot is at ``circle`` in pose 1 (the reverse of
        :meth:`circle_point`)."""
        z = self._check_point(circle, "circle")
        if self.n < 3:
            raise MechanismError(
                "with 2 poses the centre point is any point of the perpendicular bisector of the "
                "circle point's two positions: give both (Burmester.dyad(centre, circle))"
            )
        rows = np.einsum("jik,k->ji", self._q(), np.append(self._norm(z), 1.0))
        w = _solve_rows(rows, "circle", z, "circle-point curve", self.n, self._scale)
        return _dyad(self.poses, w, self._norm(z), self._scale, self.poses[0, :2])

    def dyad(self, centre, circle, tol: float = 1e-9) -> Dyad:
        """The dyad of a given fixed and moving pivot, checked: the moving pivot's positions
        must lie on one circle about ``centre`` to ``tol`` times the poses' span."""
        c = self._check_point(centre, "centre")
        z = self._check_point(circle, "circle")
        d = _dyad(self.poses, self._norm(c), self._norm(z), self._scale, self.poses[0, :2])
        if d.residual > tol * self._scale:
            raise MechanismError(
                f"circle point ({z[0]:.6g}, {z[1]:.6g}) does not stay on a circle about centre "
                f"({c[0]:.6g}, {c[1]:.6g}) through the poses: its distance varies by "
                f"{d.residual:.3g} m (> {tol * self._scale:.3g} m)"
            )
        return d

    def slider_point(self, guide_angle) -> Dyad:
        """3 poses: the slider (PR) dyad whose guide runs at ``guide_angle`` (rad from +x): the
        one point of the moving plane whose three positions lie on a line of that direction."""
        if self.n != 3:
            raise MechanismError(
                f"slider_point(guide_angle) takes 3 poses (got {self.n}); with 4 poses the "
                "slider dyad is Burmester.sliders(), with 5 it exists only where a Burmester "
                "point lies at infinity"
            )
        g = validate.angle("guide_angle", guide_angle)
        n = np.array([-np.sin(g), np.cos(g)])
        rows, rhs = _slider_rows(self.poses, self._scale, n)
        if abs(np.linalg.det(rows)) < 1e-12:
            raise MechanismError(
                f"no single slider point for a guide at {np.degrees(g):.6g} deg: every "
                "point's positions or none lie on such lines"
            )
        u = np.linalg.solve(rows, -rhs)
        return _slider(self.poses, u, n, self._scale, self.poses[0, :2])

    def rp_point(self, line_angle) -> Dyad:
        """3 poses: the RP dyad whose slot runs at ``line_angle`` in the moving frame (rad from
        its x axis): the one fixed point that the line of that direction, fixed in the moving
        plane, passes through in all three poses."""
        if self.n != 3:
            raise MechanismError(
                f"rp_point(line_angle) takes 3 poses (got {self.n}); with 4 poses the RP dyad "
                "is Burmester.rp_dyads(), with 5 it exists only where a circle point lies at "
                "infinity"
            )
        g = validate.angle("line_angle", line_angle)
        d = _rp_dyad(self.poses, self._scale, np.array([-np.sin(g), np.cos(g)]))
        if d is None:
            raise MechanismError(
                f"no single fixed pivot for a slot at {np.degrees(g):.6g} deg in the moving "
                "frame: every point's positions or none lie on such lines"
            )
        return d

    def rp_dyads(self) -> tuple[Dyad, ...]:
        """4 poses: the RP dyad (the circle-point curve's real point at infinity: one, as the
        PR dyad of the inverse motion); 5 poses: the RP dyads among :attr:`points`; ()
        otherwise."""
        if self.n == 5:
            return tuple(d for d in self.points if d.kind == "RP")
        if self.n != 4:
            return ()
        d = _rp_dyad(self.poses, self._scale)
        return (d,) if d is not None and d.residual <= 1e-7 * self._scale else ()

    def sliders(self) -> tuple[Dyad, ...]:
        """4 poses: the slider (PR) dyad, the circle point of the centre-point curve's real point
        at infinity (one); 5 poses: the slider dyads among :attr:`points`; () otherwise."""
        if self.n == 5:
            return tuple(d for d in self.points if d.kind == "PR")
        if self.n != 4:
            return ()
        n = _slider_normal(self.poses, self._scale, 3)
        rows, rhs = _slider_rows(self.poses, self._scale, n)
        u, *_ = np.linalg.lstsq(rows, -rhs, rcond=None)
        d = _slider(self.poses, u, n, self._scale, self.poses[0, :2])
        return (d,) if d.residual <= 1e-7 * self._scale else ()

    # -------------------------------------------------------------- 4 poses: curves
    def centre_curve(self, n: int = 721) -> np.ndarray:
        """4 poses: the centre-point curve sampled, ``(k, 2)`` (m) in polylines separated by rows
        of NaN (its branches and its asymptote); each point exact to round-off."""
        return self._curve(n, transpose=False)

    def circle_curve(self, n: int = 721) -> np.ndarray:
        """4 poses: the circle-point curve (moving pivots in pose 1) sampled like
        :meth:`centre_curve`."""
        return self._curve(n, transpose=True)

    def _curve(self, n, transpose):
        if self.n != 4:
            raise MechanismError(
                f"the centre- and circle-point curves are those of 4 poses (got {self.n})"
            )
        n = validate.integer("n", n, 16, 100_000)
        q = self._q()
        q = np.swapaxes(q, 1, 2) if transpose else q
        # a point on the cubic to sample it from: a finite pole (the centre-point curve passes
        # all six, the circle-point curve P12, P13, P14)
        pairs = [(1, 2), (1, 3), (1, 4)] + ([] if transpose else [(2, 3), (2, 4), (3, 4)])
        finite = [self.poles[k] for k in pairs if self.poles[k] is not None]
        if not finite:
            raise MechanismError(
                "the four poses differ by translations only (one angle): no centre- or "
                "circle-point curve (a parallel-motion linkage carries such poses)"
            )
        base = self._norm(finite[0])
        pts = _sample_cubic(q, base, n)
        return self.poses[0, :2] + self._scale * pts

    def centre_residual(self, centre) -> float:
        """4 poses: the centre-point curve's equation at ``centre`` (0 on the curve), scaled to
        an approximate distance (m) from the curve."""
        c = self._norm(self._check_point(centre, "centre"))
        return self._scale * _cubic_distance(self._q(), c)

    # -------------------------------------------------------------- output
    def as_dict(self) -> dict:
        return {
            "poses": self.poses.tolist(),
            "poles": {
                f"P{i}{j}": (None if p is None else list(p)) for (i, j), p in self.poles.items()
            },
            "burmester_points": [d.as_dict() for d in self.points],
            "sliders": [d.as_dict() for d in self.sliders()],
            "rp_dyads": [d.as_dict() for d in self.rp_dyads()],
        }

    def plot(self, candidate=None, ax=None, **kwargs):
        """The poses, the poles, the curves (4 poses) or the Burmester points (5 poses) and,
        given a :class:`~mechsynth.synthesis.motion_generation.Candidate`, its linkage drawn in
        the poses; see :func:`mechsynth.synthesis.motion_generation.plot_motion`."""
        from .motion_generation import plot_motion

        return plot_motion(self, candidate=candidate, ax=ax, **kwargs)


def _q_matrices(poses, scale) -> np.ndarray:
    beta = poses[1:, 2] - poses[0, 2]
    d = (poses[1:, :2] - poses[0, :2]) / scale
    c, s = np.cos(beta), np.sin(beta)
    k = len(beta)
    q = np.zeros((k, 3, 3))
    # -(A_j - I)
    q[:, 0, 0] = 1.0 - c
    q[:, 0, 1] = s
    q[:, 1, 0] = -s
    q[:, 1, 1] = 1.0 - c
    q[:, 0:2, 2] = -d
    # (A_j^T d_j)^T
    q[:, 2, 0] = c * d[:, 0] + s * d[:, 1]
    q[:, 2, 1] = -s * d[:, 0] + c * d[:, 1]
    q[:, 2, 2] = 0.5 * (d[:, 0] ** 2 + d[:, 1] ** 2)
    return q


def _solve_rows(rows, name, point, curve, n, scale):
    """The unknown ``v`` of ``rows[:, :2] v + rows[:, 2] = 0`` (2 or more rows), or a clear
    error when the point is off the curve (too many rows) or makes the system singular."""
    a, b = rows[:, :2], -rows[:, 2]
    sv = np.linalg.svd(a, compute_uv=False)
    if sv[-1] <= 1e-10 * max(sv[0], 1.0):
        raise MechanismError(
            f"{name} ({point[0]:.6g}, {point[1]:.6g}) is a pole or makes the poses' conditions "
            "dependent: a whole line of partner points fits (choose another point)"
        )
    v, *_ = np.linalg.lstsq(a, b, rcond=None)
    if rows.shape[0] > 2:
        res = float(np.max(np.abs(a @ v - b)))
        if res > 1e-8 * max(1.0, float(np.max(np.abs(rows)))):
            where = "a Burmester point" if n == 5 else f"on the {curve}"
            raise MechanismError(
                f"{name} ({point[0]:.6g}, {point[1]:.6g}) is not {where} of these {n} poses "
                f"(equation residual {res * scale**2:.3g} m^2)"
            )
    return v


def _slider_rows(poses, scale, normal):
    """Rows of ``n . ((A_j - I) u + d_j) = 0`` (j = 2..n): ``(rows, rhs)`` with
    ``rows u + rhs = 0``."""
    beta = poses[1:, 2] - poses[0, 2]
    d = (poses[1:, :2] - poses[0, :2]) / scale
    c, s = np.cos(beta), np.sin(beta)
    nx, ny = normal
    # n^T (A - I) = (nx (c - 1) + ny s, -nx s + ny (c - 1))
    rows = np.stack([nx * (c - 1.0) + ny * s, -nx * s + ny * (c - 1.0)], axis=1)
    return rows, d @ np.asarray(normal, float)


def _slider_normal(poses, scale, k):
    """The guide normal of the 4-pose slider point: the compatibility determinant of the slider
    rows is ``(nx^2 + ny^2)(a nx + b ny)`` (the isotropic directions make the rows' first two
    columns proportional), so its real root is ``n`` normal to ``(a, b)``."""

    def det(nv):
        rows, rhs = _slider_rows(poses[: k + 1], scale, nv)
        return np.linalg.det(np.column_stack([rows, rhs]))

    a, b = det((1.0, 0.0)), det((0.0, 1.0))
    return np.array([-b, a]) / np.hypot(a, b)


def _inverse_poses(poses) -> np.ndarray:
    """The fixed plane's poses seen from the moving frame (pose 1's point moved to the origin
    first, for the digits): ``(-R(-angle_j) (p_j - p_1), -angle_j)``."""
    rel = poses[:, :2] - poses[0, :2]
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    x = -(c * rel[:, 0] + s * rel[:, 1])
    y = -(-s * rel[:, 0] + c * rel[:, 1])
    return np.column_stack([x, y, -poses[:, 2]])


def _rp_dyad(poses, scale, normal=None) -> Dyad | None:
    """The RP dyad as the PR dyad of the inverse motion (module notes): for the slot normal
    ``normal`` in the moving frame (3 poses), or the one of 4 or 5 poses (its normal from the
    first four). None where the equations leave it undetermined."""
    inv = _inverse_poses(poses)
    if normal is None:
        normal = _slider_normal(inv, scale, 3)
    if not np.all(np.isfinite(normal)):
        return None
    rows, rhs = _slider_rows(inv, scale, normal)
    if rows.shape[0] == 2:
        if abs(np.linalg.det(rows)) < 1e-12:
            return None
        u = np.linalg.solve(rows, -rhs)
    else:
        u, *_ = np.linalg.lstsq(rows, -rhs, rcond=None)
    s = _slider(inv, u, normal, scale, inv[0, :2])
    centre = poses[0, :2] + np.asarray(s.local)
    local = np.asarray(s.circle)  # the pivot's place in the moving frame in pose 1
    z = _rot(poses[0, 2]) @ local + poses[0, :2]
    return Dyad(
        (float(centre[0]), float(centre[1])),
        (float(z[0]), float(z[1])),
        (float(local[0]), float(local[1])),
        None,
        None,
        s.residual,
        s.guide_angle,
    )


def _det_rows(r1, r2, r3):
    """Row-wise 3x3 determinants of stacked rows (``(..., 3)`` each)."""
    return np.einsum("...i,...i->...", r1, np.cross(r2, r3))


def _cubic_coefficients(q, base, v):
    """``c1, c2, c3`` of ``det[Q_k^T ((base + r v), 1)] = c1 r + c2 r^2 + c3 r^3`` for
    directions ``v`` (``(m, 2)``), ``base`` on the cubic (so the constant term vanishes)."""
    a = np.einsum("i,kij->kj", np.append(base, 1.0), q)  # (3, 3): rows at the base point
    b = np.einsum("mi,kij->mkj", v, q[:, :2, :])  # (m, 3, 3): rows' change per unit r
    a1, a2, a3 = a
    b1, b2, b3 = b[:, 0], b[:, 1], b[:, 2]
    c1 = _det_rows(b1, a2, a3) + _det_rows(a1, b2, a3) + _det_rows(a1, a2, b3)
    c2 = _det_rows(a1, b2, b3) + _det_rows(b1, a2, b3) + _det_rows(b1, b2, a3)
    c3 = _det_rows(b1, b2, b3)
    return c1, c2, c3


def _sample_cubic(q, base, n):
    """Points of the cubic ``det[Q_k^T (x, 1)] = 0`` through ``base``: on each ray from
    ``base`` at angles ``0 .. 2 pi`` the positive roots of ``c3 r^2 + c2 r + c1``, ordered into
    two polylines (smaller and larger root) broken where a root is missing or leaps."""
    psi = np.linspace(0.0, 2.0 * np.pi, n)
    v = np.stack([np.cos(psi), np.sin(psi)], axis=1)
    c1, c2, c3 = _cubic_coefficients(q, base, v)
    disc = c2 * c2 - 4.0 * c1 * c3
    with np.errstate(invalid="ignore", divide="ignore"):
        sq = np.sqrt(disc)
        qq = -0.5 * (c2 + np.copysign(sq, c2))  # the stable pair of roots
        r1, r2 = qq / c3, c1 / qq
    lo, hi = np.fmin(r1, r2), np.fmax(r1, r2)
    out = []
    for r in (lo, hi):
        ok = np.isfinite(r) & (r > 0) & (disc >= 0)
        pts = base + r[:, None] * v
        pts[~ok] = np.nan
        # a leap (an asymptote between two samples): break the line
        step = np.hypot(*np.diff(pts, axis=0).T)
        typical = np.nanmedian(step) if np.any(np.isfinite(step)) else 0.0
        jump = np.zeros(len(pts), bool)
        jump[1:] = step > 50.0 * max(typical, 1e-12)
        pts[jump] = np.nan
        out += [pts, np.full((1, 2), np.nan)]
    return np.concatenate(out)


def _cubic_distance(q, x):
    """``|F(x)| / |grad F(x)|`` for the cubic ``F = det[Q_k^T (x, 1)]`` (normalized)."""
    rows = np.einsum("i,kij->kj", np.append(x, 1.0), q)
    f = np.linalg.det(rows)
    g = []
    for axis in range(2):
        drows = q[:, axis, :]
        g.append(
            _det_rows(drows[0], rows[1], rows[2])
            + _det_rows(rows[0], drows[1], rows[2])
            + _det_rows(rows[0], rows[1], drows[2])
        )
    return float(abs(f) / max(np.hypot(*g), 1e-300))


# ------------------------------------------------------------------ five poses
_P = np.polynomial.polynomial


def _poly_det(m):
    """Determinant of a 3x3 matrix of polynomials (coefficient arrays, increasing powers)."""
    total = np.zeros(1)
    for perm in permutations(range(3)):
        sign = np.linalg.det(np.eye(3)[list(perm)])
        term = _P.polymul(_P.polymul(m[0][perm[0]], m[1][perm[1]]), m[2][perm[2]])
        total = _P.polyadd(total, sign * term)
    return total


def _line_cubic(q, base, e1, e2):
    """Polynomials ``c1(t), c2(t), c3(t)`` of the cubic along ``base + r (e1 + t e2)``."""
    a = np.einsum("i,kij->kj", np.append(base, 1.0), q)
    b0 = np.einsum("i,kij->kj", e1, q[:, :2, :])
    b1 = np.einsum("i,kij->kj", e2, q[:, :2, :])
    rows_a = [[np.array([a[k, j]]) for j in range(3)] for k in range(3)]
    rows_b = [[np.array([b0[k, j], b1[k, j]]) for j in range(3)] for k in range(3)]
    coeffs = [np.zeros(1) for _ in range(4)]
    for mask in range(8):  # multilinear: each row from a (constant) or b (times r)
        m = [rows_b[k] if mask >> k & 1 else rows_a[k] for k in range(3)]
        deg = bin(mask).count("1")
        coeffs[deg] = _P.polyadd(coeffs[deg], _poly_det(m))
    return coeffs[1], coeffs[2], coeffs[3]


def _burmester_points(poses, scale):
    """Normalized ``(w, u)`` of the real Burmester points of 5 poses (poses 1, 2 differing by a
    rotation) and the number of real roots of the quartic."""
    q = _q_matrices(poses, scale)
    qa, qb = q[[0, 1, 2]], q[[0, 1, 3]]  # poses 1234 and 1235
    p12 = _pole_norm(poses, 0, 1, scale)
    p13 = _pole_norm(poses, 0, 2, scale)
    p23 = _pole_norm(poses, 1, 2, scale)
    known = [p - p12 for p in (p13, p23) if p is not None]
    # e1 along the bisector of the known directions: their t stay in [-1, 1]
    if known:
        ang = [np.arctan2(k[1], k[0]) for k in known if np.hypot(*k) > 1e-9]
        if len(ang) == 2:
            gam = 0.5 * (ang[0] + ang[1])
            if abs(np.angle(np.exp(1j * (ang[0] - ang[1])))) > np.pi / 2:
                gam += np.pi / 2
        else:
            gam = ang[0] if ang else 0.3
    else:
        gam = 0.3
    for attempt in range(3):
        g = gam + 0.37 * attempt
        e1, e2 = np.array([np.cos(g), np.sin(g)]), np.array([-np.sin(g), np.cos(g)])
        a1, a2, a3 = _line_cubic(qa, p12, e1, e2)
        b1, b2, b3 = _line_cubic(qb, p12, e1, e2)
        x = _P.polysub(_P.polymul(a3, b1), _P.polymul(a1, b3))
        y = _P.polysub(_P.polymul(a3, b2), _P.polymul(a2, b3))
        z = _P.polysub(_P.polymul(a2, b1), _P.polymul(a1, b2))
        res = _P.polysub(_P.polymul(x, x), _P.polymul(y, z))
        known_t = []
        for k in known:
            if np.hypot(*k) > 1e-9:
                known_t.append((k @ e2) / (k @ e1))
        div = _P.polyfromroots(known_t) if known_t else np.ones(1)
        div = _P.polymul(div, [1.0, 0.0, 1.0])
        quartic, rem = _P.polydiv(res, div)
        top = np.max(np.abs(res))
        if abs(quartic[-1]) > 1e-9 * np.max(np.abs(quartic)) and top > 0:
            break
    roots = _P.polyroots(quartic) if len(quartic) > 1 else np.array([])
    found = []
    for t in roots:
        if abs(t.imag) > 1e-6 * (1.0 + abs(t.real)):
            continue
        t = t.real
        xv, yv = _P.polyval(t, x), _P.polyval(t, y)
        if abs(yv) < 1e-300:
            continue
        r = -xv / yv
        w = p12 + r * (e1 + t * e2)
        rows = np.einsum("i,jik->jk", np.append(w, 1.0), q)
        u, *_ = np.linalg.lstsq(rows[:, :2], -rows[:, 2], rcond=None)
        sol = _newton(q, w, u)
        if sol is None:
            continue
        if not any(np.allclose(sol, f, atol=1e-8 * (1 + np.abs(f).max())) for f in found):
            found.append(sol)
    return found


def residual_jacobian(q, x):
    """``E_j(w, u)`` (j = 2..) at ``x = (w, u)`` stacked and their exact Jacobian
    ``dE/d(w, u)``, ``(k, 4)`` (normalized coordinates)."""
    wh, uh = np.append(x[:2], 1.0), np.append(x[2:], 1.0)
    e = np.einsum("i,jik,k->j", wh, q, uh)
    jw = np.einsum("jik,k->ji", q, uh)[:, :2]
    ju = np.einsum("i,jik->jk", wh, q)[:, :2]
    return e, np.concatenate([jw, ju], axis=1)


def _newton(q, w, u, iters: int = 30):
    """Newton's method on ``E_j(w, u) = 0`` (j = 2..5); ``(w, u)`` stacked, or None."""
    x = np.concatenate([w, u])
    for _ in range(iters):
        e, jac = residual_jacobian(q, x)
        try:
            dx = np.linalg.solve(jac, -e)
        except np.linalg.LinAlgError:
            return None
        x = x + dx
        if np.max(np.abs(dx)) <= 1e-15 * (1.0 + np.max(np.abs(x))):
            break
    e, _ = residual_jacobian(q, x)
    if not np.all(np.isfinite(x)) or np.max(np.abs(e)) > 1e-10 * (1.0 + np.max(np.abs(x))) ** 2:
        return None
    return x


def _pole_norm(poses, i, j, scale):
    """The pole of poses i, j (0-based) in normalized coordinates, or None (translation)."""
    beta = poses[j, 2] - poses[i, 2]
    if abs(np.sin(beta / 2.0)) < 1e-12:
        return None
    # fixed point of z -> R(beta) (z - p_i) + p_j
    a = _rot(beta)
    pi, pj = (poses[i, :2] - poses[0, :2]) / scale, (poses[j, :2] - poses[0, :2]) / scale
    return np.linalg.solve(np.eye(2) - a, pj - a @ pi)


def burmester(poses) -> Burmester:
    """Burmester theory of 2 to 5 poses of a moving plane.

    Parameters
    ----------
    poses : rows ``(x, y, angle)`` (m, m, rad): the origin of the moving frame and the angle of
        its x axis from +x, counter-clockwise.

    Returns
    -------
    Burmester : the poles; 3 poses: :meth:`~Burmester.circle_point` for any centre point and
        :meth:`~Burmester.centre_point` for any circle point, :meth:`~Burmester.slider_point`;
        4 poses: :meth:`~Burmester.centre_curve`, :meth:`~Burmester.circle_curve`, the same maps
        on the curves, :meth:`~Burmester.sliders`; 5 poses: the Burmester points
        (:attr:`~Burmester.points`, all real solutions, each refined to round-off).

    Examples
    --------
    >>> import numpy as np, mechsynth as ms
    >>> bm = ms.burmester([(0, 0, 0), (1, 0.5, np.radians(30)), (1.5, 1.5, np.radians(75))])
    >>> d = bm.circle_point((0.0, 2.0))
    >>> round(d.residual, 12)
    0.0
    """
    arr = as_poses(poses)
    n = arr.shape[0]
    scale = float(np.max(np.hypot(*(arr[:, :2] - arr[0, :2]).T)))
    poles = {}
    for i in range(n):
        for j in range(i + 1, n):
            p = _pole_norm(arr, i, j, scale)
            poles[(i + 1, j + 1)] = (
                None if p is None else tuple(float(v) for v in arr[0, :2] + scale * p)
            )
    points: tuple[Dyad, ...] = ()
    if n == 5:
        points = _five(arr, scale)
    return Burmester(arr, poles, points, scale)


def _five(arr, scale) -> tuple[Dyad, ...]:
    # the elimination needs a finite pole P12: put first a pair of poses that differ in angle
    order = None
    for i in range(5):
        for j in range(5):
            if i != j and abs(np.sin((arr[j, 2] - arr[i, 2]) / 2.0)) > 1e-6:
                order = [i, j] + [k for k in range(5) if k not in (i, j)]
                break
        if order:
            break
    if order is None:
        return ()  # pure translations: only sliders, handled below
    re = arr[order]
    sols = _burmester_points(re, scale)
    origin = re[0, :2]
    dyads = []
    for x in sols:
        c = origin + scale * x[:2]
        z_re = origin + scale * x[2:]
        # the moving pivot where it lies in the original pose 1
        beta = arr[0, 2] - re[0, 2]
        z = _rot(beta) @ (z_re - re[0, :2]) + arr[0, :2]
        d = _dyad(arr, (c - arr[0, :2]) / scale, (z - arr[0, :2]) / scale, scale, arr[0, :2])
        dyads.append(d)
    dyads.sort(key=lambda d: (d.centre[0], d.centre[1]))
    n = _slider_normal(arr, scale, 3)
    rows, rhs = _slider_rows(arr, scale, n)
    u, *_ = np.linalg.lstsq(rows, -rhs, rcond=None)
    s = _slider(arr, u, n, scale, arr[0, :2])
    if s.residual <= 1e-9 * scale:
        dyads.append(s)
    rp = _rp_dyad(arr, scale)
    if rp is not None and rp.residual <= 1e-9 * scale:
        dyads.append(rp)
    if any(d.kind != "RR" for d in dyads):
        # the quartic's root of a dyad at infinity comes back as an RR dyad of a huge length
        # (its far pivot in floating point): the PR or RP dyad is that dyad, exactly
        dyads = [d for d in dyads if d.kind != "RR" or d.length <= 1e6 * scale]
    return tuple(dyads)
