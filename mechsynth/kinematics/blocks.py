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
import math
from typing import NamedTuple

import numpy as np

from ..errors import MechanismError
from . import ops
from .tracks import Jet, PointJet

__all__ = [
    "crank",
    "crank_pin",
    "dyad_rrr",
    "rrr_apart",
    "dyad_rrp",
    "dyad_rrp_on",
    "dyad_rpr",
    "dyad_rpr_on",
    "coupler_point",
    "link_angle",
    "cam_contact",
    "ContactJets",
]

# Relative round-off allowed in an assembly condition before it counts as violated.
_ASSEMBLY_RTOL = 1e-12

#: numpy >= 2, whose ``errstate`` used as a decorator keeps its state per call (numpy 1 keeps it
#: on the one ``errstate`` object, which a nested or concurrent call would overwrite)
_NUMPY_2 = int(np.__version__.split(".")[0]) >= 2


def _with_angles(exc, phi, bad, value=None, limit=8):
    """Attach to ``exc`` where it failed: ``exc.angles``, the crank angles (rad) where ``bad``
    holds -- the first one (the message's) first, then the most negative ``value`` first, at
    most ``limit`` -- and ``exc.design``, the failing design's index in a batch (or None). A
    solver that meets the failure between its grid angles adds these angles to its grid."""
    exc.angles, exc.design = (), None
    if phi is None or ops.is_symbolic(phi):
        return exc
    idx = np.unravel_index(int(np.argmax(bad)), bad.shape)
    lead = bad.ndim - np.ndim(phi)
    if lead > 0 and bad.size > np.size(phi):
        exc.design = tuple(int(i) for i in idx[:lead])
    phb = np.broadcast_to(np.asarray(phi, dtype=float), bad.shape)
    ph = phb[bad]
    if value is not None:
        ph = ph[np.argsort(np.broadcast_to(value, bad.shape)[bad], kind="stable")]
    ph = np.concatenate([[phb[idx]], ph])
    _, first = np.unique(np.round(ph, 12), return_index=True)
    exc.angles = tuple(float(a) for a in ph[np.sort(first)][:limit])
    return exc


def _where(phi, bad, idx) -> str:
    """`` at crank angle X deg`` (and the design's index in a batch) of the entry ``idx``."""
    if phi is None or ops.is_symbolic(phi):
        return ""
    ph = np.broadcast_to(np.asarray(phi, dtype=float), bad.shape)[idx]
    text = f" at crank angle {np.rad2deg(ph):.6g} deg"
    lead = bad.ndim - np.ndim(phi)
    if lead > 0 and bad.size > np.size(phi):
        text += f" (design index {tuple(int(i) for i in idx[:lead])})"
    return text


def _check_nonnegative(value, scale, what, phi=None):
    """Raise MechanismError where ``value`` < 0 beyond round-off relative to ``scale``."""
    if ops.is_symbolic(value):
        return value
    value = np.asarray(value, dtype=float)
    if value.min(initial=np.inf) >= 0.0:  # assembles everywhere (nan fails this and is checked)
        return value
    bad = value < -_ASSEMBLY_RTOL * np.maximum(np.asarray(scale, dtype=float), 1e-300)
    if np.any(bad):
        idx = np.unravel_index(int(np.argmax(bad)), bad.shape)
        raise _with_angles(
            MechanismError(
                f"{what}{_where(phi, bad, idx)}: the dyad cannot be assembled "
                f"(deficit {value[idx]:.6g})"
            ),
            phi,
            bad,
            value,
        )
    return np.maximum(value, 0.0)


def _root(value, scale, what, phi):
    """``sqrt(value)`` of a dyad's assembly condition ``value >= 0``. Given the crank angles
    ``phi`` (numeric), a negative ``value`` is left to give NaN here: the dyad's last test,
    :func:`_failed`, finds it in the analogs and :func:`_check_nonnegative` then names it (one
    pass over the analogs serves both checks). Without ``phi``, checked here."""
    if phi is None:
        return ops.sqrt(_check_nonnegative(value, scale, what, phi))
    return ops.sqrt(value)


def _failed(phi, *analogs):
    """True where a dyad's checks must look closer: an analog not finite (a toggle position,
    or NaN from a dyad that cannot be assembled), for numeric input with the crank angles
    given. One pass: the sum of the analogs is finite when they all are."""
    if phi is None:
        return False
    # symbolic input is not checked (a numpy array never is: the type test alone passes it)
    if type(phi) is not np.ndarray and ops.is_symbolic(phi):
        return False
    for x in analogs:
        if type(x) is not np.ndarray and ops.is_symbolic(x):
            return False
    if len(analogs) == 2:  # one pass over both: their dot product is finite when they are
        a, b = analogs
        if (
            type(a) is np.ndarray
            and type(b) is np.ndarray
            and a.shape == b.shape
            and a.size <= _PAIR_MAX
            and a.dtype is _FLOAT64
            and b.dtype is _FLOAT64
        ):
            return not math.isfinite(_vdot(a, b))
    for x in analogs:
        if not ops.finite(x):
            return True
    return False


#: numpy's float64 and its dot product (as :func:`mechsynth.validate.finite` calls it), for
#: up to ``_PAIR_MAX`` entries (one design's grid of angles): BLAS threads a longer dot product,
#: which costs a batch of 100 designs twice its CPU time
_FLOAT64 = np.dtype(np.float64)
_vdot = getattr(np.vdot, "__wrapped__", np.vdot)
_PAIR_MAX = 8192


def _check_toggle(what, phi, *analogs):
    """Raise MechanismError where an analog is not finite: the dyad is at a toggle position (its
    links in line), where the velocity analogs are infinite or 0/0. Checked only for numeric
    input with the crank angles given."""
    if not _failed(phi, *analogs):  # every analog finite (or not checked here)
        return
    bad = ~np.isfinite(analogs[0])
    for x in analogs[1:]:
        bad = bad | ~np.isfinite(x)
    if np.any(bad):
        idx = np.unravel_index(int(np.argmax(bad)), bad.shape)
        raise _with_angles(
            MechanismError(f"{what}{_where(phi, bad, idx)}: the velocity analogs are infinite"),
            phi,
            bad,
        )


#: numpy's 0/0 and x/0 warnings off (numpy >= 2 sets them per call, in the calling context)
_QUIET = np.errstate(divide="ignore", invalid="ignore")


try:  # numpy >= 2 keeps its floating-point error handling in a context variable
    from numpy._core.umath import _extobj_contextvar as _ERRSTATE
    from numpy._core.umath import _make_extobj
except ImportError:  # pragma: no cover - numpy's errstate decorator instead
    _ERRSTATE = _make_extobj = None

#: the error handling a dyad last met and the same with 0/0 and x/0 ignored, in one tuple
_QUIET_OF: list = [(None, None)]


def _toggles_raise(fn):
    """Run a dyad with numpy's 0/0 and x/0 warnings off: at a toggle position its analogs are
    inf or nan, and the dyad raises MechanismError for them instead. The undecorated function
    (``__wrapped__``) is what the compiled kernels are built from.

    With numpy >= 2 this is ``np.errstate(divide="ignore", invalid="ignore")`` without its
    cost per call: the quiet state is set in numpy's context variable itself and made again
    only when the caller's error handling is another (numpy's states are immutable objects,
    so the one met last is recognised by identity)."""
    if _ERRSTATE is not None:
        get, put, reset = _ERRSTATE.get, _ERRSTATE.set, _ERRSTATE.reset

        @functools.wraps(fn)
        def quiet(*args, **kwargs):
            state = get()
            last = _QUIET_OF[0]
            if last[0] is not state:
                last = _QUIET_OF[0] = (state, _make_extobj(divide="ignore", invalid="ignore"))
            token = put(last[1])
            try:
                return fn(*args, **kwargs)
            finally:
                reset(token)

        return quiet
    if _NUMPY_2:  # numpy's own decorator: no context manager object made per call
        return _QUIET(fn)

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
    x, y = length * c, length * s
    # x is also the pin's dx: its position is a copy; y is held by the position alone
    return PointJet(ops.plus(x0, x), ops.shifted(y, -y0), -y, x, -x, -y)


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


_RRR_APART = "RRR dyad: distance between its pivots outside [|l1 - l2|, l1 + l2]"
_RRP_FAR = "RRP dyad: the point is farther from the guide than the link length"


def rrr_apart(p1: PointJet, p2: PointJet):
    """``(dx, dy, d2)``: the vector p1 -> p2 and its length squared (m, m^2), as
    :func:`dyad_rrr` computes them (``dx`` is ``-p1.x`` where ``p2.x`` is the number 0)."""
    dx, dy = ops.minus(p2.x, p1.x), ops.minus(p2.y, p1.y)
    return dx, dy, dx * dx + dy * dy


@_toggles_raise
def dyad_rrr(p1: PointJet, p2: PointJet, l1, l2, branch=1, phi=None, apart=None):
    """RRR dyad: joint C at distance ``l1`` from ``p1`` and ``l2`` from ``p2``.

    ``branch=+1`` puts C to the left of the directed line p1 -> p2, ``-1`` to the right.
    ``apart``: :func:`rrr_apart` of ``p1, p2`` when the caller has it (a linkage's group
    computes it for its assembly margin), not computed again.

    Returns
    -------
    c : PointJet of the middle joint.
    theta1 : Jet of the angle of link p1 -> C.
    theta2 : Jet of the angle of link p2 -> C.
    """
    dx, dy, d2 = rrr_apart(p1, p2) if apart is None else apart
    a = (l1 * l1 - l2 * l2 + d2) / (2.0 * d2)  # fraction of p1->p2 to the foot of C
    q = l1 * l1 / d2
    h2 = q - a * a  # (height of C above the line / d)^2
    h = _root(h2, q, _RRR_APART, phi)
    if branch < 0:
        h = -h
    ex, ey = a * dx - h * dy, a * dy + h * dx  # p1 -> C
    cx, cy = p1.x + ex, p1.y + ey
    fx, fy = ops.shifted(cx, p2.x), ops.shifted(cy, p2.y)  # p2 -> C
    # The links turn C about p1 and p2: w1 J e - w2 J f = p2' - p1' = r (J a quarter turn);
    # dotted with f and e, with the cross product cr = e x f = l1 l2 sin(theta2 - theta1):
    # w1 = r . f / cr, w2 = r . e / cr. The second order is the same system with
    # r2 = p2'' - p1'' + w1^2 e - w2^2 f.
    cr = ex * fy - ey * fx
    rx, ry = ops.minus(p2.dx, p1.dx), ops.minus(p2.dy, p1.dy)
    w1 = (rx * fx + ry * fy) / cr
    w2 = (rx * ex + ry * ey) / cr
    q1, q2 = w1 * w1, w2 * w2
    m1x, m1y = q1 * ex, q1 * ey  # C's centripetal acceleration about p1, negated
    rx2 = ops.minus(p2.ddx, p1.ddx) + m1x - q2 * fx
    ry2 = ops.minus(p2.ddy, p1.ddy) + m1y - q2 * fy
    e1 = (rx2 * fx + ry2 * fy) / cr
    e2 = (rx2 * ex + ry2 * ey) / cr
    # the second analogs hold the first squared: they are not finite wherever those are not
    if _failed(phi, e1, e2):
        _check_nonnegative(h2, q, _RRR_APART, phi)
        _check_toggle("RRR dyad: links in line (toggle position)", phi, e1, e2)
    c = PointJet(
        cx,
        cy,
        p1.dx - w1 * ey,
        p1.dy + w1 * ex,
        p1.ddx - e1 * ey - m1x,
        p1.ddy + e1 * ex - m1y,
    )
    t1 = ops.arctan2(ey, ex)
    t2 = ops.arctan2(fy, fx)
    return c, Jet(t1, w1, e1), Jet(t2, w2, e2)


def _rrp_slide(t, hgt, t1, h1, t2, h2, length, branch, phi):
    """The slider's jet along its guide from the jets of the foot ``t`` and the height ``hgt`` of
    the link's moving end over the guide, with the assembly and toggle checks. Shared by the
    fixed and the moving guide.

    The link runs ``w = branch sqrt(length^2 - hgt^2)`` along the guide, ``s = t + w``, at the
    angle ``a`` from the guide with ``length (cos a, sin a) = (w, -hgt)``. Differentiating the
    second, ``a' = -h1 / w`` and ``a'' = -(h2 + hgt a'^2) / w``; from ``w w' = -hgt h1`` and its
    derivative, ``w' = hgt a'`` and ``w'' = -(length^2 a'^2 + hgt h2) / w``. Returns the
    slider's jet, ``w``, ``-w``, ``a'`` and ``a'^2``.
    """
    ll = length * length
    w2 = ll - hgt * hgt
    w = _root(w2, ll, _RRP_FAR, phi)
    if branch < 0:
        w = -w
    nw = -w
    a1 = h1 / nw
    aa = a1 * a1
    w_1 = hgt * a1
    w_2 = (ll * aa + hgt * h2) / nw
    # w'' holds a'^2: it is not finite wherever a' or w' is not, so it alone is checked
    if _failed(phi, w_2):
        _check_nonnegative(w2, ll, _RRP_FAR, phi)
        _check_toggle("RRP dyad: link perpendicular to the guide (toggle position)", phi, w_2)
    return Jet(t + w, t1 + w_1, t2 + w_2), w, nw, a1, aa


@_toggles_raise
def dyad_rrp(
    p: PointJet,
    length,
    guide_x=0.0,
    guide_y=0.0,
    guide_angle=0.0,
    branch=1,
    phi=None,
    height=None,
):
    """RRP dyad: a link of ``length`` from the moving point ``p`` to a slider B on a fixed straight
    guide through (guide_x, guide_y) with direction ``guide_angle`` (rad from +x).

    ``branch=+1`` puts B ahead of the foot of ``p`` along the guide direction, ``-1`` behind it.
    (:func:`dyad_rrp_on` is the same dyad on a guide carried by a moving link.) ``height``: the
    signed height of ``p`` over the guide, ``(p - G) . n`` with ``n`` the guide's left normal
    (equal to this function's bit for bit), when the caller has it (a linkage's group, for
    its assembly margin): not computed again; a guide along +x (``guide_angle`` the number 0)
    takes ``p.y - guide_y`` itself.

    Returns
    -------
    b : PointJet of the slider joint.
    s : Jet of the slider position along the guide, measured from (guide_x, guide_y).
    theta : Jet of the angle of the link p -> B.

    Notes
    -----
    In the guide's frame the link is ``length (cos a, sin a) = (w, -hgt)`` (see
    :func:`_rrp_slide`), so its angle's analogs are ``a' = -h1 / w`` and
    ``a'' = -(h2 + hgt a'^2) / w``, and the fixed guide adds nothing to them.
    """
    rx, ry = ops.shifted(p.x, guide_x), ops.shifted(p.y, guide_y)
    along_x = ops.is_zero(guide_angle)  # a guide along +x: its frame is the plane's
    if along_x:
        ux, uy = 1.0, 0.0
        t, hgt, t1, h1, t2, h2 = rx, ry, p.dx, p.dy, p.ddx, p.ddy
    else:
        ux, uy = ops.cos(guide_angle), ops.sin(guide_angle)
        t = rx * ux + ry * uy  # foot along the guide
        hgt = ry * ux - rx * uy if height is None else height  # signed height
        t1, h1 = p.dx * ux + p.dy * uy, p.dy * ux - p.dx * uy
        t2, h2 = p.ddx * ux + p.ddy * uy, p.ddy * ux - p.ddx * uy
    s, w, nw, a1, aa = _rrp_slide(t, hgt, t1, h1, t2, h2, length, branch, phi)
    if along_x:
        b = PointJet(  # copies: B's track and the slider's are separate arrays
            ops.plus(guide_x, s.value),
            ops.full_like(s.value, guide_y),
            ops.plus(0.0, s.d1),
            ops.zeros_like(s.d1),
            ops.plus(0.0, s.d2),
            ops.zeros_like(s.d2),
        )
        angle = ops.arctan2(-hgt, w)
    else:
        b = PointJet(
            guide_x + s.value * ux,
            guide_y + s.value * uy,
            s.d1 * ux,
            s.d1 * uy,
            s.d2 * ux,
            s.d2 * uy,
        )
        angle = ops.arctan2(w * uy - hgt * ux, w * ux + hgt * uy)
    return b, s, Jet(angle, a1, (h2 + hgt * aa) / nw)


@_toggles_raise
def dyad_rrp_on(p: PointJet, length, g: PointJet, theta: Jet, branch=1, phi=None):
    """RRP dyad on a guide carried by a moving link: a link of ``length`` from the moving point
    ``p`` to a slider B on the straight line through the moving point ``g`` with the direction
    angle ``theta`` (a jet: the guide turns with the link that carries it).

    ``branch=+1`` puts B ahead of the foot of ``p`` along the guide direction, ``-1`` behind it.

    Returns
    -------
    b : PointJet of the slider joint.
    s : Jet of the slider position along the guide measured from ``g``: the sliding of B on the
        guide, relative to the link that carries it.
    theta_link : Jet of the angle of the link p -> B.

    Notes
    -----
    With ``r = p - g``, ``u`` the guide direction, ``n`` its left normal and ``w = theta'``, the
    foot ``t = r . u`` and the height ``h = r . n`` have ``t' = r' . u + w h`` and
    ``h' = r' . n - w t``; the slider is then :func:`dyad_rrp`'s, and
    ``B'' = g'' + (s'' - s w^2) u + (2 s' w + s theta'') n``. With ``w = 0`` and a fixed ``g``
    every term is :func:`dyad_rrp`'s.
    """
    ux, uy = ops.cos(theta.value), ops.sin(theta.value)
    nx, ny = -uy, ux
    w, e = theta.d1, theta.d2
    rx, ry = p.x - g.x, p.y - g.y
    rx1, ry1 = p.dx - g.dx, p.dy - g.dy
    rx2, ry2 = p.ddx - g.ddx, p.ddy - g.ddy
    t = rx * ux + ry * uy
    hgt = rx * nx + ry * ny
    r1u = rx1 * ux + ry1 * uy
    r1n = rx1 * nx + ry1 * ny
    s, _, _, _, _ = _rrp_slide(
        t,
        hgt,
        r1u + w * hgt,
        r1n - w * t,
        rx2 * ux + ry2 * uy + 2.0 * w * r1n + e * hgt - w * w * t,
        rx2 * nx + ry2 * ny - 2.0 * w * r1u - e * t - w * w * hgt,
        length,
        branch,
        phi,
    )
    sw = s.value * w
    a_u = s.d2 - sw * w
    a_n = 2.0 * s.d1 * w + s.value * e
    b = PointJet(
        g.x + s.value * ux,
        g.y + s.value * uy,
        g.dx + s.d1 * ux + sw * nx,
        g.dy + s.d1 * uy + sw * ny,
        g.ddx + a_u * ux + a_n * nx,
        g.ddy + a_u * uy + a_n * ny,
    )
    return b, s, link_angle(p, b)


@_toggles_raise
def dyad_rpr_on(p: PointJet, q: PointJet, offset=0.0, branch=1, phi=None):
    """RPR dyad with a pivot that may move: a slider block at the moving point ``p`` slides in a
    lever that turns about the point ``q`` (a fixed frame pivot or a moving joint); the slot line
    lies at perpendicular distance ``offset`` to the left of the lever's axis through ``q``.

    ``branch=+1`` takes the slider on the lever's positive axis (s > 0), ``-1`` the negative one.

    Returns
    -------
    theta : Jet of the lever angle (its axis direction from +x).
    s : Jet of the slider position along the lever's axis from ``q``.
    """
    rx, ry = p.x - q.x, p.y - q.y
    rho2 = rx * rx + ry * ry
    s2 = _check_nonnegative(
        rho2 - offset * offset,
        offset * offset,
        "RPR dyad: the point is closer to the lever pivot than the slot offset",
        phi,
    )
    s = branch * ops.sqrt(s2)
    # p - q = s u + offset n, u = (cos th, sin th), n = (-sin th, cos th)
    th = ops.arctan2(ry, rx) - ops.arctan2(offset, s)
    c, sn = ops.cos(th), ops.sin(th)
    rx1, ry1 = p.dx - q.dx, p.dy - q.dy
    rx2, ry2 = p.ddx - q.ddx, p.ddy - q.ddy
    pu1 = rx1 * c + ry1 * sn
    pn1 = -rx1 * sn + ry1 * c
    w = pn1 / s
    s_1 = pu1 + offset * w
    pu2 = rx2 * c + ry2 * sn
    pn2 = -rx2 * sn + ry2 * c
    eps = (pn2 - 2.0 * s_1 * w + offset * w * w) / s
    s_2 = pu2 + offset * eps + s * w * w
    _check_toggle("RPR dyad: slider at the foot of the lever pivot (s = 0)", phi, w, eps)
    return Jet(th, w, eps), Jet(s, s_1, s_2)


def dyad_rpr(p: PointJet, pivot_x, pivot_y, offset=0.0, branch=1, phi=None):
    """RPR dyad (oscillating slotted lever): a slider at the moving point ``p`` slides in a lever
    that turns about the fixed pivot (pivot_x, pivot_y); the slot line lies at perpendicular
    distance ``offset`` to the left of the lever's axis through the pivot. The fixed-pivot case
    of :func:`dyad_rpr_on`.

    ``branch=+1`` takes the slider on the lever's positive axis (s > 0), ``-1`` the negative one.

    Returns
    -------
    theta : Jet of the lever angle (its axis direction from +x).
    s : Jet of the slider position along the lever's axis from the pivot.
    """
    return dyad_rpr_on(p, PointJet(pivot_x, pivot_y, 0.0, 0.0, 0.0, 0.0), offset, branch, phi)


# ------------------------------------------------------------------------------ higher pair
class ContactJets(NamedTuple):
    """What :func:`cam_contact` moves and measures.

    Attributes
    ----------
    follower : PointJet of the follower's reference point on its guide (a roller's centre, or
        the point of a flat face on the guide line).
    s : Jet of the follower's position along the guide from the guide point.
    point : PointJet of the geometric contact point on the profile (it slides along the profile:
        not a material point of either body).
    normal : angle (rad) of the common normal at the contact, pointing from the profile into the
        follower (the direction of the force the profile exerts).
    sigma : the curve parameter at the contact.
    pressure : pressure angle (rad, in [0, pi/2]): between the common normal and the guide.
    residual : the contact equation's residual after the iterations (m, numeric check).
    found : True where the guide line meets the profile (a sign change was bracketed).
    """

    follower: PointJet
    s: Jet
    point: PointJet
    normal: object
    sigma: object
    pressure: object
    residual: object
    found: object


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


def cam_contact(
    base: PointJet,
    angle: Jet,
    curve,
    p,
    guide_x,
    guide_y,
    guide_angle,
    radius=0.0,
    face=None,
    branch=1,
    side=1,
    phi=None,
    samples=24,
    iterations=8,
):
    """Higher pair: a translating follower on a fixed guide in contact with a profile curve
    carried by a moving link (a cam).

    Parameters
    ----------
    base, angle : the jets of the carrying link's frame (origin and x-axis angle).
    curve : a :class:`~mechsynth.kinematics.curves.Curve` in that frame; ``p`` its role values.
    guide_x, guide_y, guide_angle : the follower's straight guide (through the point, at the
        angle, rad from +x).
    radius : roller radius (m; 0 for a point follower), when ``face`` is None.
    face : angle (rad) of a flat face's normal from the guide direction (0: the face is
        perpendicular to the guide), or None for a roller.
    branch : +1 the follower rests on the profile's outermost contact ahead along the guide
        direction (the largest position), -1 the hindmost.
    side : +1 the roller runs on the right of the curve's direction of travel (outside a
        counter-clockwise closed profile), -1 on its left.
    phi : crank angles, for the numeric checks' messages.
    samples, iterations : the contact is found by sampling the contact equation at ``samples``
        curve parameters, taking the bracket of the outermost sign change (``branch``) and a
        fixed count of safeguarded Newton steps inside it; all written with ``ops``, so the
        same code runs with numpy and CasADi.

    Returns
    -------
    ContactJets

    Notes
    -----
    Roller: the centre curve ``k(sigma) = c(sigma) + radius nu(sigma)`` (``nu`` the unit normal on
    the roller's side) crosses the guide line: ``(B + R k - G) . n = 0``. Flat face with normal
    ``m``: the profile's tangent is perpendicular to ``m``, ``(R c') . m = 0``. The analogs of
    ``s`` and ``sigma`` come from the differentiated contact conditions, linear in them with the
    same matrix at both orders.
    """
    ux, uy = ops.cos(guide_angle), ops.sin(guide_angle)
    nx, ny = -uy, ux
    th, w, e = angle.value, angle.d1, angle.d2
    cth, sth = ops.cos(th), ops.sin(th)
    lo, hi = curve.domain
    flat = face is not None
    if flat:
        mx, my = ops.cos(guide_angle + face), ops.sin(guide_angle + face)
        um = ux * mx + uy * my

    def rot(x, y):
        return cth * x - sth * y, sth * x + cth * y

    def offset_curve(c):
        """The roller centre curve k and its first two derivatives (link frame)."""
        x, y, x1, y1, x2, y2, x3, y3 = c
        g = ops.sqrt(x1 * x1 + y1 * y1)
        g1 = (x1 * x2 + y1 * y2) / g
        g2 = (x2 * x2 + y2 * y2 + x1 * x3 + y1 * y3) / g - g1 * g1 / g
        k = side * radius
        nu = (y1 / g, -x1 / g)
        nu1 = (y2 / g - y1 * g1 / (g * g), -x2 / g + x1 * g1 / (g * g))
        q = g2 / (g * g) - 2.0 * g1 * g1 / (g * g * g)
        nu2 = (
            y3 / g - 2.0 * y2 * g1 / (g * g) - y1 * q,
            -x3 / g + 2.0 * x2 * g1 / (g * g) + x1 * q,
        )
        return (
            (x + k * nu[0], y + k * nu[1]),
            (x1 + k * nu1[0], y1 + k * nu1[1]),
            (x2 + k * nu2[0], y2 + k * nu2[1]),
            (side * nu[0], side * nu[1]),
        )

    def equation(sigma):
        """Residual f, its derivative in sigma and the follower position s at ``sigma``."""
        c = curve.jet(sigma, p)
        if flat:
            t1 = rot(c[2], c[3])
            t2 = rot(c[4], c[5])
            xx, xy = rot(c[0], c[1])
            s = ((base.x + xx - guide_x) * mx + (base.y + xy - guide_y) * my) / um
            return t1[0] * mx + t1[1] * my, t2[0] * mx + t2[1] * my, s
        k, k1, _, _ = offset_curve(c)
        qx, qy = rot(*k)
        q1x, q1y = rot(*k1)
        dx, dy = base.x + qx - guide_x, base.y + qy - guide_y
        return dx * nx + dy * ny, q1x * nx + q1y * ny, dx * ux + dy * uy

    # ---- bracket of the outermost sign change
    n = int(samples)
    span = hi - lo
    sig = [lo + span * k / n for k in range(n + 1)]
    vals = [equation(sg) for sg in (sig if not curve.closed else sig[:-1])]
    if curve.closed:
        vals.append(vals[0])
    big = 1e300
    best = None
    for k in range(n):
        f0, _, s0 = vals[k]
        f1, _, s1 = vals[k + 1]
        crossing = f0 * f1 <= 0.0
        den = f1 - f0
        den = ops.where(den == 0.0, 1.0 + 0.0 * den, den)
        frac = ops.fmin(ops.fmax(-f0 / den, 0.0 * den), 1.0 + 0.0 * den)
        score = ops.where(crossing, branch * (s0 + frac * (s1 - s0)), -big + 0.0 * den)
        start = sig[k] + frac * (sig[k + 1] - sig[k])
        if best is None:
            best = [score, start, sig[k] + 0.0 * den, sig[k + 1] + 0.0 * den, f0]
            continue
        better = score > best[0]
        best = [
            ops.where(better, score, best[0]),
            ops.where(better, start, best[1]),
            ops.where(better, sig[k] + 0.0 * den, best[2]),
            ops.where(better, sig[k + 1] + 0.0 * den, best[3]),
            ops.where(better, f0, best[4]),
        ]
    found, sigma, a, b, fa = best
    if not ops.is_symbolic(found) and phi is not None:
        _fail_where(
            np.asarray(found) <= -0.5 * big,
            "higher pair: the follower's guide line misses the profile (no contact)",
            phi,
        )
    # ---- safeguarded Newton inside the bracket
    for _ in range(int(iterations)):
        f, fs, _ = equation(sigma)
        right = f * fa > 0.0  # the root lies beyond sigma
        a = ops.where(right, sigma, a)
        fa = ops.where(right, f, fa)
        b = ops.where(right, b, sigma)
        step = sigma - f / ops.where(fs == 0.0, 1.0 + 0.0 * fs, fs)
        inside = (step - a) * (b - step) >= 0.0
        sigma = ops.where(inside, step, 0.5 * (a + b))

    # ---- the contact at sigma and its analogs
    c = curve.jet(sigma, p)
    cx, cy = rot(c[0], c[1])
    c1x, c1y = rot(c[2], c[3])
    c2x, c2y = rot(c[4], c[5])
    if flat:
        c3x, c3y = rot(c[6], c[7])
        fs = c2x * mx + c2y * my
        residual = c1x * mx + c1y * my
        jc1m = -c1y * mx + c1x * my  # (J R c') . m
        sigma_1 = -w * jc1m / fs
        sigma_2 = (
            -(
                e * jc1m
                - w * w * residual
                + 2.0 * w * sigma_1 * (-c2y * mx + c2x * my)
                + sigma_1 * sigma_1 * (c3x * mx + c3y * my)
            )
            / fs
        )
        _check_toggle(
            "higher pair: flat face at an inflection of the profile (contact jumps)",
            phi,
            sigma_1,
            sigma_2,
        )
        dx, dy = base.x + cx - guide_x, base.y + cy - guide_y
        s0 = (dx * mx + dy * my) / um
        v1x = base.dx - w * cy + c1x * sigma_1
        v1y = base.dy + w * cx + c1y * sigma_1
        s1 = (v1x * mx + v1y * my) / um
        a2x = base.ddx - e * cy - w * w * cx - 2.0 * w * sigma_1 * c1y
        a2y = base.ddy + e * cx - w * w * cy + 2.0 * w * sigma_1 * c1x
        a2x = a2x + sigma_1 * sigma_1 * c2x + sigma_2 * c1x
        a2y = a2y + sigma_1 * sigma_1 * c2y + sigma_2 * c1y
        s2 = (a2x * mx + a2y * my) / um
        normal = ops.arctan2(branch * my + 0.0 * th, branch * mx + 0.0 * th)
        scale = ops.sqrt(c1x * c1x + c1y * c1y)
    else:
        k, k1, k2, nu = offset_curve(c)
        qx, qy = rot(*k)
        q1x, q1y = rot(*k1)
        q2x, q2y = rot(*k2)
        dx, dy = base.x + qx - guide_x, base.y + qy - guide_y
        residual = dx * nx + dy * ny
        s0 = dx * ux + dy * uy
        det = -_cross(ux, uy, q1x, q1y)  # u x (-q')
        r1x, r1y = base.dx - w * qy, base.dy + w * qx
        s1 = _cross(r1x, r1y, -q1x, -q1y) / det
        sigma_1 = _cross(ux, uy, r1x, r1y) / det
        r2x = base.ddx - e * qy - w * w * qx - 2.0 * w * sigma_1 * q1y + sigma_1 * sigma_1 * q2x
        r2y = base.ddy + e * qx - w * w * qy + 2.0 * w * sigma_1 * q1x + sigma_1 * sigma_1 * q2y
        s2 = _cross(r2x, r2y, -q1x, -q1y) / det
        sigma_2 = _cross(ux, uy, r2x, r2y) / det
        _check_toggle(
            "higher pair: the follower's guide is tangent to the roller's path (contact jumps)",
            phi,
            s1,
            s2,
        )
        nwx, nwy = rot(nu[0], nu[1])
        normal = ops.arctan2(nwy, nwx)
        scale = ops.sqrt(q1x * q1x + q1y * q1y)
    s = Jet(s0, s1, s2)
    follower = PointJet(guide_x + s0 * ux, guide_y + s0 * uy, s1 * ux, s1 * uy, s2 * ux, s2 * uy)
    # the geometric contact point on the profile: B + R c(sigma(phi))
    point = PointJet(
        base.x + cx,
        base.y + cy,
        base.dx - w * cy + c1x * sigma_1,
        base.dy + w * cx + c1y * sigma_1,
        base.ddx
        - e * cy
        - w * w * cx
        - 2.0 * w * sigma_1 * c1y
        + sigma_1 * sigma_1 * c2x
        + sigma_2 * c1x,
        base.ddy
        + e * cx
        - w * w * cy
        + 2.0 * w * sigma_1 * c1x
        + sigma_1 * sigma_1 * c2y
        + sigma_2 * c1y,
    )
    cn, sn = ops.cos(normal), ops.sin(normal)
    pressure = ops.arctan2(ops.fabs(_cross(cn, sn, ux, uy)), ops.fabs(cn * ux + sn * uy))
    if not ops.is_symbolic(residual) and phi is not None:
        tol = 1e-10 * (np.abs(s0) + np.abs(scale) + np.abs(radius) + 1e-300)
        _fail_where(
            ~(np.abs(residual) <= tol),
            "higher pair: the contact iteration did not converge",
            phi,
        )
    return ContactJets(follower, s, point, normal, sigma, pressure, residual, found > -0.5 * big)


def _fail_where(bad, what, phi):
    """Raise MechanismError naming the first crank angle where ``bad`` holds (numeric only)."""
    bad = np.asarray(bad)
    if not np.any(bad):
        return
    idx = np.unravel_index(int(np.argmax(bad)), bad.shape)
    raise _with_angles(MechanismError(f"{what}{_where(phi, bad, idx)}"), phi, bad)
