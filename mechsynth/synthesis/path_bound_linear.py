"""The second-order box bound of :mod:`.path_bound`: the targets in the coupler's frame as a
linear function of the box's coordinates plus a proved remainder.

On a box with centre ``c`` and half-widths ``h``, the mean value theorem gives, for each
component of ``q`` (the targets in the coupler's frame, ``2n`` numbers) and each design ``x = c
+ delta`` of the box, ``q(x) = q(c) + J(xi) delta`` with ``xi`` in the box. With ``[J]`` an
interval enclosure of the Jacobian over the box (interval arithmetic on the derivative chain:
crank pin, ``|A O2|`` and its direction, the law of cosines, ``acos``, the rotation into the
coupler's frame) and ``M`` its midpoint, ``|q(x) - q(c) - M delta| <= rad([J]) |delta| =: E``
componentwise. The error with the best coupler point is ``|P q(x)|^2`` (``P`` removes the mean
over the targets), so ``sqrt(error) >= |P (q(c) + M delta)| - |E|``, and the smallest value
of the convex quadratic ``|P (q(c) + M delta)|^2`` over the box is bounded from below by the
Frank-Wolfe gap at any point of the box (here: the unconstrained least-squares point clipped
to the box, then a few sweeps of exact coordinate descent). The remainder shrinks with the
square of the box, so near a minimum this bound approaches the error while the rectangles of
:func:`~mechsynth.synthesis.path_bound.enclosures` (which let every target move on its own)
stay first-order. A box where the dyad may reach a toggle (``|kappa|`` up to 1: the
derivative of ``acos`` unbounded) gets no bound from here.
"""

from __future__ import annotations

import numpy as np

__all__ = ["linear_bound", "jacobian_enclosure"]


# -------------------------------------------------------------- interval arithmetic (lo, hi)
def _add(a, b):
    return a[0] + b[0], a[1] + b[1]


def _neg(a):
    return -a[1], -a[0]


def _mul(a, b):
    p = np.stack([a[0] * b[0], a[0] * b[1], a[1] * b[0], a[1] * b[1]])
    return p.min(axis=0), p.max(axis=0)


def _scale(a, k):
    """``k a`` for exact numbers ``k`` (any sign)."""
    x, y = k * a[0], k * a[1]
    return np.minimum(x, y), np.maximum(x, y)


def _sq(a):
    lo2, hi2 = a[0] * a[0], a[1] * a[1]
    top = np.maximum(lo2, hi2)
    low = np.where((a[0] <= 0) & (a[1] >= 0), 0.0, np.minimum(lo2, hi2))
    return low, top


def _inv_pos(a):
    """``1 / a`` for ``a > 0``."""
    return 1.0 / a[1], 1.0 / a[0]


def _cos(a):
    from .path_bound import _cos_interval

    return _cos_interval(a[0], a[1])


def _sin(a):
    from .path_bound import _cos_interval

    return _cos_interval(a[0] - 0.5 * np.pi, a[1] - 0.5 * np.pi)


def _point(x):
    return x, x


def jacobian_enclosure(lo, hi, sigma, turns, targets):
    """Interval enclosure of the Jacobian of ``q`` (the targets in the coupler's frame) over
    each box: ``(Jlo, Jhi)``, each ``(K, n, 2, 8)``, and ``ok`` ``(K,)`` (False where the
    derivative is unbounded in the box: a toggle, or ``A`` and ``O2`` may meet)."""
    from .path_bound import enclosures

    qlo, qhi, feas, parts = enclosures(lo, hi, sigma, turns, targets, full=True)
    K, n = lo.shape[0], len(turns)
    c, s = np.cos(turns)[None, :], np.sin(turns)[None, :]

    def iv(j):
        return lo[:, None, j] + 0.0 * c, hi[:, None, j] + 0.0 * c  # (K, n)

    o1x, o1y, wx, wy, o2x, o2y, r3, r4 = (iv(j) for j in range(8))
    ax = _add(o1x, _add(_scale(wx, c), _scale(wy, -s)))
    ay = _add(o1y, _add(_scale(wx, s), _scale(wy, c)))
    dx, dy = _add(o2x, _neg(ax)), _add(o2y, _neg(ay))
    d = parts["d"]
    ok = feas & np.all(d[0] > 0, axis=1)
    dpos = (np.where(d[0] > 0, d[0], 1.0), d[1])
    inv_d = _inv_pos(dpos)
    inv_d2 = _inv_pos(_mul(dpos, dpos))
    ex, ey = _mul(dx, inv_d), _mul(dy, inv_d)  # D / d
    fx, fy = _neg(_mul(dy, inv_d2)), _mul(dx, inv_d2)  # (-Dy, Dx) / d^2: d(angle D)/dD
    kap = parts["kappa"]
    one = 1.0 - np.maximum(kap[0] ** 2, kap[1] ** 2)
    ok &= np.all(one > 0, axis=1) & np.all((kap[0] > -1) & (kap[1] < 1), axis=1)
    low2 = np.where((kap[0] <= 0) & (kap[1] >= 0), 0.0, np.minimum(kap[0] ** 2, kap[1] ** 2))
    root = (np.sqrt(np.where(one > 0, one, 1.0)), np.sqrt(np.clip(1.0 - low2, 0.0, 1.0)))
    dalpha = _neg(_inv_pos(root))  # d acos(kappa) / d kappa = -1 / sqrt(1 - kappa^2)
    d2 = _sq(dpos)
    r3s, r4s = _sq(r3), _sq(r4)
    kd = _mul(_add(d2, _add(r4s, _neg(r3s))), _inv_pos(_scale(_mul(r3, d2), 2.0)))
    k3 = _mul(_add(r3s, _add(r4s, _neg(d2))), _inv_pos(_scale(_mul(r3s, dpos), 2.0)))
    k4 = _neg(_mul(r4, _inv_pos(_mul(r3, dpos))))
    # derivatives of D = O2 - A by the eight coordinates, as exact (dDx, dDy) per column
    zero = np.zeros_like(c)
    dD = [(-1 + zero, zero), (zero, -1 + zero), (-c, -s), (s, -c), (1 + zero, zero),
          (zero, 1 + zero), (zero, zero), (zero, zero)]  # fmt: skip
    dV = [(-1 + zero, zero), (zero, -1 + zero), (-c, -s), (s, -c)] + [(zero, zero)] * 4
    psi = parts["psi"]
    cp, sp = _cos(psi), _sin(psi)
    qx, qy = (qlo[..., 0], qhi[..., 0]), (qlo[..., 1], qhi[..., 1])
    sg = sigma[:, None] + 0.0 * c
    Jlo = np.empty((K, n, 2, 8))
    Jhi = np.empty((K, n, 2, 8))
    for j in range(8):
        gx, gy = dD[j]
        dd = _add(_scale(ex, gx), _scale(ey, gy))  # d|D| / dx_j
        dang = _add(_scale(fx, gx), _scale(fy, gy))
        dk = _mul(kd, dd)
        if j == 6:
            dk = _add(dk, k3)
        if j == 7:
            dk = _add(dk, k4)
        dpsi = _add(dang, _scale(_mul(dalpha, dk), sg))
        vx, vy = dV[j]
        rx = _add(_scale(cp, vx), _scale(sp, vy))  # R(-psi) dV
        ry = _add(_scale(sp, -vx), _scale(cp, vy))
        jx = _add(rx, _mul(qy, dpsi))
        jy = _add(ry, _neg(_mul(qx, dpsi)))
        Jlo[..., 0, j], Jhi[..., 0, j] = jx
        Jlo[..., 1, j], Jhi[..., 1, j] = jy
    bad = ~np.all(np.isfinite(Jlo) & np.isfinite(Jhi), axis=(1, 2, 3))
    return Jlo, Jhi, ok & ~bad


def linear_bound(lo, hi, sigma, turns, targets, sweeps: int = 4, split: bool = False):
    """A lower bound ``(K,)`` on the error (normalized units) of every design in each box by the
    linear model and its remainder (see the module's text); 0 where none is found. With
    ``split``, also each coordinate's share ``(K, 8)`` of the remainder (``sum E_ik rad(J)_ikj
    h_j``; the half-widths ``h`` where the box has no linear bound): the box is best split
    where it is largest."""
    with np.errstate(all="ignore"):
        out, share = _linear_bound(lo, hi, sigma, turns, targets, sweeps)
    return (out, share) if split else out


def _linear_bound(lo, hi, sigma, turns, targets, sweeps):
    """:func:`linear_bound` (floating-point warnings of the boxes it gives no bound off)."""
    from .path_bound import _SLACK, relaxed_error

    K, n = lo.shape[0], len(turns)
    c, h = 0.5 * (lo + hi), 0.5 * (hi - lo)
    Jlo, Jhi, ok = jacobian_enclosure(lo, hi, sigma, turns, targets)
    Jlo = np.where(ok[:, None, None, None], Jlo, 0.0)
    Jhi = np.where(ok[:, None, None, None], Jhi, 0.0)
    M = 0.5 * (Jlo + Jhi)
    E = np.einsum("kiaj,kj->kia", 0.5 * (Jhi - Jlo), h) + _SLACK  # (K, n, 2)
    err_c, _ = relaxed_error(c, sigma, turns, targets)
    ok &= np.isfinite(err_c)
    q0 = _q_at(c, sigma, turns, targets)  # (K, n, 2)
    g0 = (q0 - q0.mean(axis=1, keepdims=True)).reshape(K, 2 * n)
    g0 = np.where(ok[:, None] & np.isfinite(g0), g0, 0.0)
    G = (M - M.mean(axis=1, keepdims=True)).reshape(K, 2 * n, 8)
    A = np.einsum("kpi,kpj->kij", G, G)
    b = np.einsum("kpi,kp->ki", G, g0)
    reg = 1e-12 * (np.trace(A, axis1=1, axis2=2)[:, None, None] + 1e-300) * np.eye(8)
    try:
        delta = -np.linalg.solve(A + reg, b[..., None])[..., 0]
    except np.linalg.LinAlgError:
        delta = np.zeros((K, 8))
    delta = np.where(np.isfinite(delta), delta, 0.0)
    delta = np.clip(delta, -h, h)
    diag = np.einsum("kii->ki", A)
    for _ in range(sweeps):  # exact coordinate descent on the box
        for j in range(8):
            grad = np.einsum("ki,ki->k", A[:, j, :], delta) + b[:, j]
            step = np.where(diag[:, j] > 0, -grad / np.where(diag[:, j] > 0, diag[:, j], 1), 0)
            delta[:, j] = np.clip(delta[:, j] + step, -h[:, j], h[:, j])
    r = g0 + np.einsum("kpi,ki->kp", G, delta)
    f = np.sum(r * r, axis=1)
    grad = 2.0 * np.einsum("kpi,kp->ki", G, r)
    fw = f + np.sum(np.minimum(grad * (-h - delta), grad * (h - delta)), axis=1)
    root = np.sqrt(np.maximum(fw, 0.0)) - np.sqrt(np.sum(E * E, axis=(1, 2)))
    out = np.where(ok & (root > 0), root * root, 0.0)
    share = np.einsum("kia,kiaj,kj->kj", E, 0.5 * (Jhi - Jlo), h)
    share = np.where(ok[:, None] & np.all(np.isfinite(share), axis=1, keepdims=True), share, h)
    return np.where(np.isfinite(out), out, 0.0), share


def _q_at(x, sigma, turns, targets):
    """The targets in the coupler's frame ``(K, n, 2)`` for the designs ``x``."""
    from .path_bound import coupler_frame

    return coupler_frame(x, sigma, turns, targets)[0]
