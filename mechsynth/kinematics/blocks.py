"""Building blocks of planar linkages: the crank driver and the Assur dyads RRR, RRP and RPR.

Every block takes the jets (position and crank-angle analogs) of the points it is attached to and
returns the jets of what it moves, in closed form:

* position from the triangle/line intersection, with an assembly ``branch`` (+1 or -1) where two
  assemblies exist;
* first and second analogs by differentiating the loop-closure equation, which is linear in the
  unknown derivatives with the same 2x2 matrix at both orders.

All arguments broadcast: crank angles of any shape, parameters as scalars or arrays (batches of
designs), or CasADi symbols. Assembly is checked for numpy input: where the dyad cannot close,
:class:`~mechsynth.errors.MechanismError` names the violated condition and the first offending
crank angle. Symbolic input is not checked (the optimizer's constraints keep it assemblable).
"""

from __future__ import annotations

import functools

import numpy as np

from ..errors import MechanismError
from . import ops
from .tracks import Jet, PointJet

__all__ = ["crank", "crank_pin", "dyad_rrr", "dyad_rrp", "dyad_rpr", "coupler_point", "link_angle"]

# Relative round-off allowed in an assembly condition before it counts as violated.
_ASSEMBLY_RTOL = 1e-12


def _check_nonnegative(value, scale, what, phi=None):
    """Raise MechanismError where ``value`` < 0 beyond round-off relative to ``scale``."""
    if ops.is_symbolic(value):
        return value
    value = np.asarray(value, dtype=float)
    bad = value < -_ASSEMBLY_RTOL * np.maximum(np.asarray(scale, dtype=float), 1e-300)
    if np.any(bad):
        idx = np.unravel_index(int(np.argmax(bad)), bad.shape)
        where = ""
        if phi is not None and not ops.is_symbolic(phi):
            ph = np.broadcast_to(np.asarray(phi, dtype=float), bad.shape)[idx]
            where = f" at crank angle {np.rad2deg(ph):.6g} deg"
        raise MechanismError(
            f"{what}{where}: the dyad cannot be assembled (deficit {value[idx]:.6g})"
        )
    return np.maximum(value, 0.0)


def _check_toggle(what, phi, *analogs):
    """Raise MechanismError where an analog is not finite: the dyad is at a toggle position (its
    links in line), where the velocity analogs are infinite or 0/0. Checked only for numeric
    input with the crank angles given."""
    if phi is None or ops.is_symbolic(phi, *analogs):
        return
    bad = ~np.isfinite(analogs[0])
    for x in analogs[1:]:
        bad = bad | ~np.isfinite(x)
    if np.any(bad):
        idx = np.unravel_index(int(np.argmax(bad)), bad.shape)
        ph = np.broadcast_to(np.asarray(phi, dtype=float), bad.shape)[idx]
        raise MechanismError(
            f"{what} at crank angle {np.rad2deg(ph):.6g} deg: the velocity analogs are infinite"
        )


def _toggles_raise(fn):
    """Run a dyad with numpy's 0/0 and x/0 warnings off: at a toggle position its analogs are
    inf or nan, and the dyad raises MechanismError for them instead. The undecorated function
    (``__wrapped__``) is what the compiled kernels are built from."""

    @functools.wraps(fn)
    def quiet(*args, **kwargs):
        with np.errstate(divide="ignore", invalid="ignore"):
            return fn(*args, **kwargs)

    return quiet


def crank(phi, length, x0=0.0, y0=0.0, phase=0.0) -> PointJet:
    """Crank pin A of a crank of ``length`` (m) pivoted at (x0, y0), angle ``phi + phase`` from +x.

    ``phi`` is the driving (generalized) coordinate: analogs are derivatives with respect to it.
    """
    return crank_pin(ops.cos(phi + phase), ops.sin(phi + phase), length, x0, y0)


def crank_pin(c, s, length, x0=0.0, y0=0.0) -> PointJet:
    """Crank pin A from the crank's direction cosines ``c, s`` (cos and sin of its angle).

    The form the batch kernels use: the sines and cosines of a crank-angle grid are computed once
    for all designs.
    """
    return PointJet(
        x0 + length * c, y0 + length * s, -length * s, length * c, -length * c, -length * s
    )


def link_angle(p: PointJet, q: PointJet) -> Jet:
    """Angle (from +x) of the segment p -> q and its analogs, for any two moving points."""
    ux, uy = q.x - p.x, q.y - p.y
    dux, duy = q.dx - p.dx, q.dy - p.dy
    ddux, dduy = q.ddx - p.ddx, q.ddy - p.ddy
    r2 = ux * ux + uy * uy
    cross1 = ux * duy - uy * dux
    d1 = cross1 / r2
    # d/dphi (cross1 / r2) with cross1' = ux*dduy - uy*ddux and r2' = 2 (u . u')
    d2 = (ux * dduy - uy * ddux) / r2 - cross1 * 2.0 * (ux * dux + uy * duy) / (r2 * r2)
    return Jet(ops.arctan2(uy, ux), d1, d2)


def coupler_point(base: PointJet, angle: Jet, u, v) -> PointJet:
    """Point fixed on a link: ``u`` along the link's direction ``angle`` from ``base``, ``v`` to its
    left (m). Returns its jet."""
    c, s = ops.cos(angle.value), ops.sin(angle.value)
    # position offset in the frame: R(theta) @ (u, v)
    ox = u * c - v * s
    oy = u * s + v * c
    w, w2 = angle.d1, angle.d2
    return PointJet(
        base.x + ox,
        base.y + oy,
        base.dx - oy * w,
        base.dy + ox * w,
        base.ddx - oy * w2 - ox * w * w,
        base.ddy + ox * w2 - oy * w * w,
    )


@_toggles_raise
def dyad_rrr(p1: PointJet, p2: PointJet, l1, l2, branch=1, phi=None):
    """RRR dyad: joint C at distance ``l1`` from ``p1`` and ``l2`` from ``p2``.

    ``branch=+1`` puts C to the left of the directed line p1 -> p2, ``-1`` to the right.

    Returns
    -------
    c : PointJet of the middle joint.
    theta1 : Jet of the angle of link p1 -> C.
    theta2 : Jet of the angle of link p2 -> C.
    """
    dx, dy = p2.x - p1.x, p2.y - p1.y
    d2 = dx * dx + dy * dy
    a = (l1 * l1 - l2 * l2 + d2) / (2.0 * d2)  # fraction of p1->p2 to the foot of C
    h2 = l1 * l1 / d2 - a * a  # (height of C above the line / d)^2
    h2 = _check_nonnegative(
        h2,
        l1 * l1 / d2,
        "RRR dyad: distance between its pivots outside [|l1 - l2|, l1 + l2]",
        phi,
    )
    h = branch * ops.sqrt(h2)
    cx = p1.x + a * dx - h * dy
    cy = p1.y + a * dy + h * dx
    # direction cosines of the links p1 -> C and p2 -> C, and sin(theta2 - theta1)
    c1, s1 = (cx - p1.x) / l1, (cy - p1.y) / l1
    c2, s2 = (cx - p2.x) / l2, (cy - p2.y) / l2
    sin21 = s2 * c1 - c2 * s1
    # l1 w1 e1perp - l2 w2 e2perp = p2' - p1' (rhs); dot with e2 and e1 to separate.
    rx, ry = p2.dx - p1.dx, p2.dy - p1.dy
    w1 = (rx * c2 + ry * s2) / (l1 * sin21)
    w2 = (rx * c1 + ry * s1) / (l2 * sin21)
    rx2 = p2.ddx - p1.ddx + l1 * w1 * w1 * c1 - l2 * w2 * w2 * c2
    ry2 = p2.ddy - p1.ddy + l1 * w1 * w1 * s1 - l2 * w2 * w2 * s2
    e1 = (rx2 * c2 + ry2 * s2) / (l1 * sin21)
    e2 = (rx2 * c1 + ry2 * s1) / (l2 * sin21)
    _check_toggle("RRR dyad: links in line (toggle position)", phi, w1, w2, e1, e2)
    c = PointJet(
        cx,
        cy,
        p1.dx - l1 * w1 * s1,
        p1.dy + l1 * w1 * c1,
        p1.ddx - l1 * e1 * s1 - l1 * w1 * w1 * c1,
        p1.ddy + l1 * e1 * c1 - l1 * w1 * w1 * s1,
    )
    t1 = ops.arctan2(cy - p1.y, cx - p1.x)
    t2 = ops.arctan2(cy - p2.y, cx - p2.x)
    return c, Jet(t1, w1, e1), Jet(t2, w2, e2)


@_toggles_raise
def dyad_rrp(p: PointJet, length, guide_x=0.0, guide_y=0.0, guide_angle=0.0, branch=1, phi=None):
    """RRP dyad: a link of ``length`` from the moving point ``p`` to a slider B on a fixed straight
    guide through (guide_x, guide_y) with direction ``guide_angle`` (rad from +x).

    ``branch=+1`` puts B ahead of the foot of ``p`` along the guide direction, ``-1`` behind it.

    Returns
    -------
    b : PointJet of the slider joint.
    s : Jet of the slider position along the guide, measured from (guide_x, guide_y).
    theta : Jet of the angle of the link p -> B.
    """
    ux, uy = ops.cos(guide_angle), ops.sin(guide_angle)
    nx, ny = -uy, ux
    rx, ry = p.x - guide_x, p.y - guide_y
    t = rx * ux + ry * uy  # foot of p along the guide
    hgt = rx * nx + ry * ny  # signed height of p above the guide
    w2 = _check_nonnegative(
        length * length - hgt * hgt,
        length * length,
        "RRP dyad: the point is farther from the guide than the link length",
        phi,
    )
    w = ops.sqrt(w2)
    t1 = p.dx * ux + p.dy * uy
    h1 = p.dx * nx + p.dy * ny
    t2 = p.ddx * ux + p.ddy * uy
    h2 = p.ddx * nx + p.ddy * ny
    w_1 = -hgt * h1 / w
    w_2 = -(h1 * h1 + hgt * h2) / w - (hgt * h1) ** 2 / (w * w2)
    _check_toggle("RRP dyad: link perpendicular to the guide (toggle position)", phi, w_1, w_2)
    s = Jet(t + branch * w, t1 + branch * w_1, t2 + branch * w_2)
    b = PointJet(
        guide_x + s.value * ux,
        guide_y + s.value * uy,
        s.d1 * ux,
        s.d1 * uy,
        s.d2 * ux,
        s.d2 * uy,
    )
    return b, s, link_angle(p, b)


@_toggles_raise
def dyad_rpr(p: PointJet, pivot_x, pivot_y, offset=0.0, branch=1, phi=None):
    """RPR dyad (oscillating slotted lever): a slider at the moving point ``p`` slides in a lever
    that turns about the fixed pivot (pivot_x, pivot_y); the slot line lies at perpendicular
    distance ``offset`` to the left of the lever's axis through the pivot.

    ``branch=+1`` takes the slider on the lever's positive axis (s > 0), ``-1`` the negative one.

    Returns
    -------
    theta : Jet of the lever angle (its axis direction from +x).
    s : Jet of the slider position along the lever's axis from the pivot.
    """
    rx, ry = p.x - pivot_x, p.y - pivot_y
    rho2 = rx * rx + ry * ry
    s2 = _check_nonnegative(
        rho2 - offset * offset,
        offset * offset,
        "RPR dyad: the point is closer to the lever pivot than the slot offset",
        phi,
    )
    s = branch * ops.sqrt(s2)
    # p - pivot = s u + offset n, u = (cos th, sin th), n = (-sin th, cos th)
    th = ops.arctan2(ry, rx) - ops.arctan2(offset, s)
    c, sn = ops.cos(th), ops.sin(th)
    pu1 = p.dx * c + p.dy * sn
    pn1 = -p.dx * sn + p.dy * c
    w = pn1 / s
    s_1 = pu1 + offset * w
    pu2 = p.ddx * c + p.ddy * sn
    pn2 = -p.ddx * sn + p.ddy * c
    eps = (pn2 - 2.0 * s_1 * w + offset * w * w) / s
    s_2 = pu2 + offset * eps + s * w * w
    _check_toggle("RPR dyad: slider at the foot of the lever pivot (s = 0)", phi, w, eps)
    return Jet(th, w, eps), Jet(s, s_1, s_2)
