"""A proved lower bound on the error of prescribed-timing four-bar path generation.

With prescribed timing the crank pin at target ``i`` is ``A_i = O1 + R(d_i) W`` (``O1`` the
crank pivot, ``W`` the crank vector at the first target, ``d_i`` the given turn from the first
target). The rocker pivot ``O2`` and the lengths ``coupler`` (r3) and ``rocker`` (r4) then place
the coupler pin ``B_i`` (the dyad's closed form on the chosen branch), so the coupler's frame at
each target is known, and the coupler point ``(u, v)`` in that frame enters linearly: written in
the coupler's frame each target is ``q_i = R(-psi_i) (T_i - A_i)`` (``psi_i`` the direction
A -> B), and the best coupler point is their mean, the error ``sum |q_i - mean q|^2`` exactly.
So the error is a function of eight numbers ``x = (O1, W, O2, r3, r4)``, and

* **branch and bound** over boxes of those eight: on a box, interval arithmetic encloses each
  ``q_i`` in a rectangle (``A_i`` within a disk of radius ``|half-diagonal of O1| + |half-
  diagonal of W|`` around its value at the centre, the directions by ``asin`` of radius over
  distance, the dyad's angle by interval arithmetic on the law of cosines), and the smallest of
  ``sum_i dist(m, rectangle_i)^2`` over the coupler point ``m`` (separable in x and y, each a
  convex piecewise quadratic minimized exactly over its pieces) is a lower bound of the error
  of every design in the box (first order); the linear model of ``q`` with a remainder proved
  by an interval Jacobian (:mod:`.path_bound_linear`, second order) gives another; the larger
  counts, a child box inherits its parent's, and a box is split where its share of the
  remainder is largest. A box where some target cannot be assembled anywhere is dropped;
  each box's centre, evaluated exactly, is a design whose error bounds the minimum from above.
* The bound is on a **relaxation**: the full turn (Grashof), the smallest transmission angle,
  the bounds on ``u``, ``v`` and the ground's direction are dropped (only assembly at the targets
  is kept), so it holds for the four-bar problem with any of those constraints. The lower bound
  reported is the smallest box bound over the leaves of the search tree: a valid bound at any
  moment, rising as the boxes are refined (it tends to the relaxed minimum: the enclosures
  shrink to points).

The interval arithmetic is ordinary floating point (no outward rounding); every enclosure is
widened by ``1e-12`` in units of the targets' rms radius, far above the round-off of these few
operations.

Its reach (measured, ``docs/path_generation.md``): with the pivots given (four effective
dimensions) the gap closes in seconds over lengths free by tens of per cent; with all eight free
a region of a few centimetres comes within some 15 % in a minute; over the default bounds of
:func:`~mechsynth.path_generation` (lengths up to ten times the targets' extent) the tree does
not close in any reasonable number of boxes, and the result says so (``useful`` False).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from .. import validate
from ..errors import MechanismError

__all__ = ["PathBound", "path_bound", "bound_region", "region_around", "relaxed_error",
           "enclosures", "COORDS"]

#: the box coordinates, in this order (m): crank pivot, crank vector at the first target,
#: rocker pivot, coupler and rocker lengths
COORDS = ("x0", "y0", "crank_x", "crank_y", "x2", "y2", "coupler", "rocker")

METHOD = (
    "branch and bound over (crank pivot, crank vector at the first target, rocker pivot, "
    "coupler, rocker); per box, interval enclosures of the targets in the coupler's frame and "
    "the exact least distance of a coupler point to them; relaxation: assembly at the targets "
    "only (full turn, transmission angle, u, v and ground-direction bounds dropped)"
)

# floating-point slack added to every enclosure (normalized units, the targets' rms radius 1)
_SLACK = 1e-12


@dataclass(frozen=True)
class PathBound:
    """A lower bound on the global minimum of prescribed-timing path generation.

    Attributes
    ----------
    lower : proved lower bound on the sum of squared distances (m^2) of every four-bar in the
        region (either branch unless one is named), whatever its other constraints.
    best : the best error known (m^2): the design's given (``best=``), else the best box
        centre's (a four-bar assembled at every target; its full turn not checked); ``inf`` if
        none. When a box centre does better than the design given, the message says so.
    gap : ``best - lower`` (m^2); ``relative_gap``: ``gap / best`` (0 when both are 0).
    closed : the gap is within the tolerance (``rtol * best`` or ``atol``).
    useful : the bound says something: closed, or ``lower >= best / 2`` (the best is then
        within a factor 2 of the global optimum). False says plainly: no useful bound.
    method : how the bound was found (words); ``boxes``: boxes evaluated; ``open``: boxes
        left unresolved; ``seconds``: wall time.
    region : the searched box ``{coordinate: (lower, upper)}`` (m) of :data:`COORDS`;
        ``branches``: the assembly branches searched.
    best_design : the best box centre's design ``{name: value}`` (the four-bar's variables,
        :data:`~mechsynth.synthesis.path_result.NAMES`, m and rad, ``phi1`` the crank angle at
        the first target, ``branch`` and ``error``), or None.
    message : why the search stopped, and whether the bound is useful.
    history : ``(boxes, lower bound, best)`` (m^2) after each step of the tree (the best: of the
        design given or the tree's centres).
    """

    lower: float
    best: float
    gap: float
    relative_gap: float
    closed: bool
    useful: bool
    method: str
    boxes: int
    open: int
    seconds: float
    region: dict
    branches: tuple[str, ...]
    best_design: dict | None = None
    message: str = ""
    history: tuple = field(default=(), repr=False)

    def summary(self) -> str:
        return (
            f"lower bound {self.lower:.6g} m^2, best {self.best:.6g} m^2, gap {self.gap:.4g} "
            f"m^2" + ("" if self.closed else f" ({100 * self.relative_gap:.3g} % of the best)")
            + f", {self.boxes} boxes, {self.seconds:.2f} s: {self.message}"
        )

    def figure(self, title: str | None = None):
        """The lower bound and the best error against the boxes evaluated (a matplotlib
        figure; :func:`~mechsynth.synthesis.path_figures.bound_figure`)."""
        from .path_figures import bound_figure

        return bound_figure([self], [title or "prescribed-timing path generation"])

    def as_dict(self) -> dict:
        return {
            "lower": self.lower,
            "best": self.best,
            "gap": self.gap,
            "relative_gap": self.relative_gap,
            "closed": self.closed,
            "useful": self.useful,
            "method": self.method,
            "boxes": self.boxes,
            "open": self.open,
            "seconds": self.seconds,
            "region": {k: list(v) for k, v in self.region.items()},
            "branches": list(self.branches),
            "best_design": self.best_design,
            "message": self.message,
        }


# ------------------------------------------------------------------------------ geometry
def _angle_half(r, d):
    """Half-width of the directions of a vector within a disk of radius ``r`` around one of
    length ``d`` (pi when the disk holds the origin)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(r < d, np.arcsin(np.clip(r / np.where(d > 0, d, 1.0), 0.0, 1.0)), np.pi)


def _cos_interval(lo, hi):
    """Enclosure of ``cos`` over ``[lo, hi]`` (elementwise)."""
    wide = hi - lo >= 2.0 * np.pi
    a, b = np.cos(lo), np.cos(hi)
    cmin, cmax = np.minimum(a, b), np.maximum(a, b)
    k = np.ceil(lo / (2.0 * np.pi))  # a multiple of 2 pi inside: cos reaches 1
    cmax = np.where(wide | (2.0 * np.pi * k <= hi), 1.0, cmax)
    k = np.ceil((lo - np.pi) / (2.0 * np.pi))  # an odd multiple of pi inside: -1
    cmin = np.where(wide | (np.pi + 2.0 * np.pi * k <= hi), -1.0, cmin)
    return cmin, cmax


def _times(rlo, rhi, clo, chi):
    """Enclosure of ``r c`` with ``0 <= rlo <= r <= rhi`` and ``clo <= c <= chi``."""
    lo = np.where(clo >= 0, rlo * clo, rhi * clo)
    hi = np.where(chi >= 0, rhi * chi, rlo * chi)
    return lo, hi


def _rot(d, v):
    """``R(d) v`` for angles ``d (n,)`` and vectors ``v (..., 2)`` -> ``(..., n, 2)``."""
    c, s = np.cos(d), np.sin(d)
    x, y = v[..., None, 0], v[..., None, 1]
    return np.stack([c * x - s * y, s * x + c * y], axis=-1)


def _kappa_range(r3lo, r3hi, r4lo, r4hi, dlo, dhi):
    """The exact range of ``kappa = (r3^2 + d^2 - r4^2) / (2 r3 d)`` (the cosine of the dyad's
    angle at A) over the box of ``r3, r4, d > 0``: it falls with ``r4``; it has no stationary
    point inside (that needs ``r4 = 0``), so its extremes lie at the corners or where an edge
    meets ``d^2 = r3^2 - r4^2`` (along d) or ``r3^2 = d^2 - r4^2`` (along r3)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        dl = np.where(dlo > 0, dlo, 1.0)

        def k(r3, r4, d):
            return (r3 * r3 + d * d - r4 * r4) / (2.0 * r3 * d)

        vals = []
        for r4 in (r4lo, r4hi):
            for r3 in (r3lo, r3hi):
                for d in (dl, dhi):
                    vals.append(k(r3, r4, d))
                dc = np.sqrt(np.maximum(r3 * r3 - r4 * r4, 0.0))
                vals.append(np.where((dc > dl) & (dc < dhi), k(r3, r4, np.clip(dc, dl, dhi)),
                                     np.nan))  # fmt: skip
            for d in (dl, dhi):
                rc = np.sqrt(np.maximum(d * d - r4 * r4, 0.0))
                vals.append(np.where((rc > r3lo) & (rc < r3hi),
                                     k(np.clip(rc, r3lo, r3hi), r4, d), np.nan))  # fmt: skip
        v = np.stack(vals)
        lo, hi = np.nanmin(v, axis=0), np.nanmax(v, axis=0)
    # round-off: widen by a few units in the last place
    return lo - 1e-12 * (1.0 + np.abs(lo)), hi + 1e-12 * (1.0 + np.abs(hi))


def enclosures(lo, hi, sigma, turns, targets, full=False):
    """Rectangles that hold the targets in the coupler's frame for every design in a box.

    Parameters
    ----------
    lo, hi : ``(K, 8)`` boxes over :data:`COORDS` (normalized units).
    sigma : ``(K,)`` branch of each box (+1: B left of A -> O2, the four-bar's ``open``).
    turns : ``(n,)`` crank turns from the first target (rad); ``targets``: ``(n, 2)``.

    Returns
    -------
    qlo, qhi : ``(K, n, 2)`` corners of the rectangles.
    feasible : ``(K,)`` False where some target cannot be assembled by any design of the box.
    parts : with ``full``, a dict of the intermediate enclosures (``kappa``: the cosine of the
        dyad's angle at A; ``psi``: the direction A -> B; ``d``: ``|A O2|``; each a
        ``(lower, upper)`` pair of ``(K, n)`` arrays).
    """
    c, h = 0.5 * (lo + hi), 0.5 * (hi - lo)
    r_a = np.hypot(h[:, 0], h[:, 1]) + np.hypot(h[:, 2], h[:, 3])  # |A_i - A_i(centre)|
    r_o2 = np.hypot(h[:, 4], h[:, 5])
    a = c[:, None, 0:2] + _rot(turns, c[:, 2:4])  # (K, n, 2) crank pins at the centre
    dv = c[:, None, 4:6] - a  # A -> O2
    dc = np.hypot(dv[..., 0], dv[..., 1])
    rd = (r_a + r_o2)[:, None]
    dlo, dhi = np.maximum(dc - rd, 0.0), dc + rd
    ang_d, hw_d = np.arctan2(dv[..., 1], dv[..., 0]), _angle_half(rd, dc)
    r3lo, r3hi = lo[:, None, 6], hi[:, None, 6]
    r4lo, r4hi = lo[:, None, 7], hi[:, None, 7]
    klo, khi = _kappa_range(r3lo, r3hi, r4lo, r4hi, dlo, dhi)
    unbounded = dlo <= 0.0
    klo = np.where(unbounded, -np.inf, klo)
    khi = np.where(unbounded, np.inf, khi)
    feasible = ~np.any((klo > 1.0) | (khi < -1.0), axis=1)
    alo = np.arccos(np.clip(khi, -1.0, 1.0))
    ahi = np.arccos(np.clip(klo, -1.0, 1.0))
    s = sigma[:, None]
    psi_lo = ang_d - hw_d + np.where(s > 0, alo, -ahi)
    psi_hi = ang_d + hw_d + np.where(s > 0, ahi, -alo)
    v = targets[None] - a  # A -> T
    vc = np.hypot(v[..., 0], v[..., 1])
    ra = r_a[:, None]
    ang_v, hw_v = np.arctan2(v[..., 1], v[..., 0]), _angle_half(ra, vc)
    th_lo = ang_v - hw_v - psi_hi
    th_hi = ang_v + hw_v - psi_lo
    mlo, mhi = np.maximum(vc - ra, 0.0), vc + ra
    clo, chi = _cos_interval(th_lo, th_hi)
    slo, shi = _cos_interval(th_lo - 0.5 * np.pi, th_hi - 0.5 * np.pi)
    xlo, xhi = _times(mlo, mhi, clo, chi)
    ylo, yhi = _times(mlo, mhi, slo, shi)
    qlo = np.stack([xlo, ylo], axis=-1) - _SLACK
    qhi = np.stack([xhi, yhi], axis=-1) + _SLACK
    if full:
        parts = {"kappa": (klo, khi), "psi": (psi_lo, psi_hi), "d": (dlo, dhi)}
        return qlo, qhi, feasible, parts
    return qlo, qhi, feasible


def _least_spread(lo, hi):
    """``min over m of sum_i dist(m, [lo_i, hi_i])^2`` exactly, for each row ``(K, n)``: the
    function is a convex quadratic between the sorted ends; each piece's stationary point,
    clipped to the piece, is evaluated and the least kept."""
    k, n = lo.shape
    ends = np.sort(np.concatenate([lo, hi], axis=1), axis=1)  # (K, 2n)
    left = np.concatenate([ends[:, :1] - 1.0, ends], axis=1)  # piece j: [left_j, right_j]
    right = np.concatenate([ends, ends[:, -1:] + 1.0], axis=1)
    mid = 0.5 * (left + right)
    below = hi[:, None, :] < mid[:, :, None]  # interval i left of the piece: (m - hi_i)^2
    above = lo[:, None, :] > mid[:, :, None]  # right of it: (lo_i - m)^2
    num = np.sum(np.where(below, hi[:, None, :], 0.0) + np.where(above, lo[:, None, :], 0.0), 2)
    cnt = np.sum(below | above, axis=2)
    m = np.where(cnt > 0, num / np.maximum(cnt, 1), mid)
    m = np.clip(m, np.where(np.arange(2 * n + 1) == 0, -np.inf, left),
                np.where(np.arange(2 * n + 1) == 2 * n, np.inf, right))  # fmt: skip
    d = np.maximum(lo[:, None, :] - m[:, :, None], 0.0) + np.maximum(
        m[:, :, None] - hi[:, None, :], 0.0
    )
    return np.min(np.sum(d * d, axis=2), axis=1)


def _box_bounds(lo, hi, sigma, turns, targets, linear=True, split=False):
    """Each box's lower bound: the larger of the rectangles' (first order) and, with
    ``linear``, the linear model's (second order, :mod:`.path_bound_linear`); with ``split``
    also where to split each box (the coordinate of the largest share of the remainder)."""
    qlo, qhi, ok = enclosures(lo, hi, sigma, turns, targets)
    lb = _least_spread(qlo[..., 0], qhi[..., 0]) + _least_spread(qlo[..., 1], qhi[..., 1])
    where = np.argmax(hi - lo, axis=1)
    if linear and lb.size:
        from .path_bound_linear import linear_bound

        lin, share = linear_bound(lo, hi, sigma, turns, targets, split=True)
        lb = np.maximum(lb, lin)
        where = np.argmax(share, axis=1)
    lb = np.where(ok, lb, np.inf)
    return (lb, where) if split else lb


def coupler_frame(x, sigma, turns, targets):
    """The targets in the coupler's frame ``(K, n, 2)`` (``u`` along A -> B, ``v`` to its
    left) for the designs ``x (K, 8)`` (:data:`COORDS`) on branches ``sigma``, and whether every
    target can be assembled ``(K,)``."""
    a = x[:, None, 0:2] + _rot(turns, x[:, 2:4])
    dv = x[:, None, 4:6] - a
    d = np.hypot(dv[..., 0], dv[..., 1])
    r3, r4 = x[:, None, 6], x[:, None, 7]
    with np.errstate(divide="ignore", invalid="ignore"):
        k = (r3**2 + d**2 - r4**2) / (2.0 * r3 * d)
    ok = np.all(np.abs(k) <= 1.0, axis=1)
    psi = np.arctan2(dv[..., 1], dv[..., 0]) + sigma[:, None] * np.arccos(np.clip(k, -1, 1))
    v = targets[None] - a
    c, s = np.cos(psi), np.sin(psi)
    return np.stack([c * v[..., 0] + s * v[..., 1], -s * v[..., 0] + c * v[..., 1]], -1), ok


def relaxed_error(x, sigma, turns, targets):
    """Exact error ``(K,)`` of the designs ``x (K, 8)`` (:data:`COORDS`) on branches ``sigma``
    with the best coupler point, and that point ``(K, 2)`` (``u`` along A -> B, ``v`` to its
    left); ``inf`` where some target cannot be assembled."""
    q, ok = coupler_frame(x, sigma, turns, targets)
    m = q.mean(axis=1)
    err = np.sum((q - m[:, None, :]) ** 2, axis=(1, 2))
    return np.where(ok, err, np.inf), m


def _design(x, sigma, m, centre, scale):
    """The four-bar's variables (NAMES, SI) of a normalized box point."""
    o1 = centre + scale * x[0:2]
    o2 = centre + scale * x[4:6]
    g = o2 - o1
    angle = float(np.arctan2(g[1], g[0]))
    return {
        "crank": float(scale * np.hypot(*x[2:4])),
        "coupler": float(scale * x[6]),
        "rocker": float(scale * x[7]),
        "ground": float(np.hypot(*g)),
        "u": float(scale * m[0]),
        "v": float(scale * m[1]),
        "x0": float(o1[0]),
        "y0": float(o1[1]),
        "angle": angle,
        "phi1": float(np.arctan2(x[3], x[2]) - angle),
        "branch": "open" if sigma > 0 else "crossed",
    }


def bound_region(targets, bounds=None) -> dict:
    """The box of :data:`COORDS` (m) that holds every four-bar within ``bounds`` (the
    :func:`~mechsynth.path_generation` bounds, its defaults for the names not given): the crank
    pivot's box, the crank vector within ``+-crank`` upper bound, the rocker pivot the crank
    pivot's box plus the ground vector over its length and direction bounds (interval
    arithmetic), the coupler and rocker bounds."""
    from .path_generation import _check_bounds

    t = np.asarray(targets, dtype=float)
    b = _check_bounds(bounds, t)
    c = b["crank"][1]
    # the rocker pivot O1 + ground (cos angle, sin angle): interval arithmetic on the bounds
    g = (np.array(b["ground"][0]), np.array(b["ground"][1]))
    a0, a1 = np.array(b["angle"][0]), np.array(b["angle"][1])
    cx = _times(*g, *_cos_interval(a0, a1))
    sy = _times(*g, *_cos_interval(a0 - 0.5 * np.pi, a1 - 0.5 * np.pi))
    return {
        "x0": b["x0"],
        "y0": b["y0"],
        "crank_x": (-c, c),
        "crank_y": (-c, c),
        "x2": (b["x0"][0] + float(cx[0]), b["x0"][1] + float(cx[1])),
        "y2": (b["y0"][0] + float(sy[0]), b["y0"][1] + float(sy[1])),
        "coupler": b["coupler"],
        "rocker": b["rocker"],
        "_crank": b["crank"],
        "_ground": b["ground"],
    }


def box_point(design, phi1) -> np.ndarray:
    """The point of :data:`COORDS` (m) of a four-bar ``design`` (``{name: value}`` of the
    four-bar's variables) whose crank angle at the first target is ``phi1`` (rad)."""
    th = design["angle"] + phi1
    o1 = np.array([design["x0"], design["y0"]], dtype=float)
    w = design["crank"] * np.array([np.cos(th), np.sin(th)])
    o2 = o1 + design["ground"] * np.array([np.cos(design["angle"]), np.sin(design["angle"])])
    return np.array([*o1, *w, *o2, design["coupler"], design["rocker"]], dtype=float)


def region_around(design, phi1, size) -> dict:
    """The box of :data:`COORDS` within ``size`` (m) of a design's point (:func:`box_point`)
    in every coordinate (the lengths kept above ``size / 100``)."""
    x = box_point(design, phi1)
    out = {k: (float(v - size), float(v + size)) for k, v in zip(COORDS, x)}
    for k in ("coupler", "rocker"):
        lo, hi = out[k]
        out[k] = (max(lo, 0.01 * size), max(hi, 0.02 * size))
    return out


def _length_prune(lo, hi, crank, ground):
    """False where no point of the box has ``|W|`` within ``crank`` or ``|O2 - O1|`` within
    ``ground`` (both are bounds of the four-bar problem)."""

    def dist_range(alo, ahi):  # |v| over the box [alo, ahi] of 2-vectors
        near = np.clip(0.0, alo, ahi)
        far = np.maximum(np.abs(alo), np.abs(ahi))
        return np.hypot(near[:, 0], near[:, 1]), np.hypot(far[:, 0], far[:, 1])

    wlo, whi = dist_range(lo[:, 2:4], hi[:, 2:4])
    glo, ghi = dist_range(lo[:, 4:6] - hi[:, 0:2], hi[:, 4:6] - lo[:, 0:2])
    return (wlo <= crank[1]) & (whi >= crank[0]) & (glo <= ground[1]) & (ghi >= ground[0])


def path_bound(
    targets,
    angles,
    *,
    bounds: dict | None = None,
    region: dict | None = None,
    branch: str = "either",
    best: float | None = None,
    max_boxes: int = 200_000,
    time_limit: float = 30.0,
    rtol: float = 1e-3,
    atol: float | None = None,
    batch: int = 2048,
) -> PathBound:
    """A proved lower bound on the smallest error of any four-bar tracing ``targets`` at the
    prescribed crank ``angles`` (see the module's text for the method).

    Parameters
    ----------
    targets : ``(N, 2)`` points (m) or a CSV file (:func:`~mechsynth.read_targets`).
    angles : crank angle at each target (rad; only the turns from the first one count, the
        crank turning counter-clockwise, as :func:`~mechsynth.path_generation`'s
        ``timing="prescribed"``).
    bounds : the four-bar's bounds (:func:`~mechsynth.path_generation`'s ``bounds``; its
        defaults for the others), turned into the searched box by :func:`bound_region`.
    region : the searched box itself, ``{coordinate: (lower, upper)}`` (m) for all of
        :data:`COORDS` (instead of ``bounds``).
    branch : ``"open"``, ``"crossed"`` or ``"either"`` (both searched).
    best : the error of a design known to lie in the region (e.g. ``path_generation``'s),
        the upper end of the gap.
    max_boxes, time_limit : budget (boxes evaluated, seconds); the bound holds whenever the
        search stops.
    rtol, atol : the gap at which the search stops (``atol`` default ``1e-12`` times the
        targets' mean squared radius times N).
    batch : boxes split per step (vectorized).

    Returns
    -------
    PathBound
    """
    t0 = time.perf_counter()
    from .path_targets import read_targets

    t = read_targets(targets, closed=False)
    n = len(t)
    given = np.asarray(validate.real("angles", angles, "rad"), dtype=float).ravel()
    if given.size != n:
        raise MechanismError(f"angles: need one per target ({n}), got {given.size}")
    validate.option("branch", branch, ("open", "crossed", "either"))
    max_boxes = validate.integer("max_boxes", max_boxes, lo=1, hi=10**9)
    batch = validate.integer("batch", batch, lo=1, hi=10**7)
    time_limit = validate.number("time_limit", time_limit, "s")
    if not time_limit > 0:
        raise MechanismError(f"time_limit must be positive (s), got {time_limit:.6g}")
    rtol = validate.number("rtol", rtol)
    if not 0 <= rtol < 1:
        raise MechanismError(f"rtol must be in [0, 1), got {rtol:.6g}")
    if best is not None:
        best = validate.number("best", best, "m^2")
        if best < 0:
            raise MechanismError(f"best is an error (a sum of squares): need >= 0, got {best}")
    if region is not None and bounds is not None:
        raise MechanismError("give bounds or region, not both")
    if region is None:
        reg = bound_region(t, bounds)
        crank, ground = reg.pop("_crank"), reg.pop("_ground")
    else:
        if not isinstance(region, dict) or set(region) != set(COORDS):
            raise MechanismError(f"region must give (lower, upper) for each of {', '.join(COORDS)}")
        reg = {}
        for k in COORDS:
            lo = validate.number(f"region[{k!r}] lower", region[k][0], "m")
            hi = validate.number(f"region[{k!r}] upper", region[k][1], "m")
            if not lo < hi:
                raise MechanismError(f"region[{k!r}]: need lower < upper, got ({lo}, {hi})")
            reg[k] = (lo, hi)
        for k in ("coupler", "rocker"):
            if reg[k][0] <= 0:
                raise MechanismError(f"region[{k!r}]: a length's lower bound must be > 0, got "
                                     f"{reg[k][0]}")  # fmt: skip
        crank, ground = (0.0, np.inf), (0.0, np.inf)
    centre = t.mean(axis=0)
    scale = float(np.sqrt(np.mean(np.sum((t - centre) ** 2, axis=1))))
    tn = (t - centre) / scale
    turns = given - given[0]
    shift = np.array([*centre, 0, 0, *centre, 0, 0])
    rlo = (np.array([reg[k][0] for k in COORDS]) - shift) / scale
    rhi = (np.array([reg[k][1] for k in COORDS]) - shift) / scale
    cn, gn = np.asarray(crank) / scale, np.asarray(ground) / scale
    a_tol = (1e-12 * n if atol is None else validate.number("atol", atol, "m^2") / scale**2)
    sig = {"open": [1.0], "crossed": [-1.0], "either": [1.0, -1.0]}[branch]

    lo = np.repeat(rlo[None], len(sig), axis=0)
    hi = np.repeat(rhi[None], len(sig), axis=0)
    sg = np.array(sig)
    lb, cut = _box_bounds(lo, hi, sg, turns, tn, split=True)
    ub_given = np.inf if best is None else best / scale**2
    ub, inc = ub_given, None
    boxes, floor = len(sig), np.inf  # floor: least bound of the boxes dropped
    history = []
    stop = "the gap closed"
    while True:
        keep = np.isfinite(lb)
        lo, hi, sg, lb, cut = lo[keep], hi[keep], sg[keep], lb[keep], cut[keep]
        target = ub - max(rtol * ub, a_tol)
        drop = lb >= target
        if np.any(drop):
            floor = min(floor, float(lb[drop].min()))
            lo, hi, sg, lb, cut = lo[~drop], hi[~drop], sg[~drop], lb[~drop], cut[~drop]
        lower = min(floor, float(lb.min(initial=np.inf)), ub)
        history.append((boxes, lower * scale**2, ub * scale**2))
        if lb.size == 0:
            break
        if boxes >= max_boxes:
            stop = f"the box budget ({max_boxes}) ran out"
            break
        if time.perf_counter() - t0 > time_limit:
            stop = f"the time limit ({time_limit:.3g} s) ran out"
            break
        k = min(batch, lb.size)
        pick = np.argpartition(lb, k - 1)[:k] if k < lb.size else np.arange(lb.size)
        rest = np.ones(lb.size, dtype=bool)
        rest[pick] = False
        plo, phi_, psg = lo[pick], hi[pick], sg[pick]
        j = cut[pick]
        mid = 0.5 * (plo[np.arange(k), j] + phi_[np.arange(k), j])
        alo, ahi = plo.copy(), phi_.copy()
        ahi[np.arange(k), j] = mid
        blo, bhi = plo.copy(), phi_.copy()
        blo[np.arange(k), j] = mid
        clo, chi = np.vstack([alo, blo]), np.vstack([ahi, bhi])
        csg = np.concatenate([psg, psg])
        ok = _length_prune(clo, chi, cn, gn)
        clo, chi, csg = clo[ok], chi[ok], csg[ok]
        # a child lies in its parent: the parent's bound holds for it too
        clb, ccut = _box_bounds(clo, chi, csg, turns, tn, split=True)
        clb = np.maximum(clb, np.tile(lb[pick], 2)[ok])
        x = 0.5 * (clo + chi)
        err, m = relaxed_error(x, csg, turns, tn)
        # a centre counts as an upper bound only inside the problem's length bounds
        w, g = np.hypot(x[:, 2], x[:, 3]), np.hypot(x[:, 4] - x[:, 0], x[:, 5] - x[:, 1])
        inside = (w >= cn[0]) & (w <= cn[1]) & (g >= gn[0]) & (g <= gn[1])
        err = np.where(inside, err, np.inf)
        i = int(np.argmin(err)) if err.size else 0
        if err.size and err[i] < ub:
            ub, inc = float(err[i]), (x[i].copy(), float(csg[i]), m[i].copy())
        boxes += 2 * k
        lo = np.vstack([lo[rest], clo])
        hi = np.vstack([hi[rest], chi])
        sg = np.concatenate([sg[rest], csg])
        lb = np.concatenate([lb[rest], clb])
        cut = np.concatenate([cut[rest], ccut])
    lower = max(0.0, lower) * scale**2
    relaxed = ub * scale**2  # the tree's best centre (or the design given)
    best_v = relaxed if best is None else float(best)
    gap = best_v - lower
    rel = 0.0 if gap <= 0 or best_v == 0 else gap / best_v
    closed = bool(gap <= max(rtol * best_v, a_tol * scale**2))
    useful = bool(closed or (np.isfinite(best_v) and lower >= 0.5 * best_v))
    if lb.size == 0:
        stop = "every box resolved"
    what = (
        "the bound proves the best within the tolerance of the global optimum" if closed
        else "useful: the best is within a factor 2 of the global optimum" if useful
        else "no useful bound: the lower bound is below half the best (refine the region or "
        "give more boxes)"
    )  # fmt: skip
    if best is not None and relaxed < best_v * (1 - rtol) - a_tol * scale**2:
        what += (
            f"; a four-bar of the region assembled at the targets reaches {relaxed:.6g} m^2 "
            "(best_design: its full turn, transmission angle and other constraints are not "
            "checked)"
        )
    design = None
    if inc is not None:
        design = _design(inc[0], inc[1], inc[2], centre, scale)
        design["error"] = relaxed
    return PathBound(
        lower=float(lower),
        best=float(best_v),
        gap=float(gap),
        relative_gap=float(rel),
        closed=closed,
        useful=useful,
        method=METHOD,
        boxes=int(boxes),
        open=int(lb.size),
        seconds=time.perf_counter() - t0,
        region={k: (float(v[0]), float(v[1])) for k, v in reg.items()},
        branches=tuple("open" if s > 0 else "crossed" for s in sig),
        best_design=design,
        message=f"{stop}; {what}",
        history=tuple(history),
    )
