"""Certification of a peak over the cycle: the true continuous maximum of a per-angle quantity.

A solver sees a peak only at its grid angles. :func:`true_peak` finds the true maximum over the
continuous crank angle for one design: a dense uniform evaluation (vectorized) picks the local
maxima near the top, and a bounded 1-D search (``scipy.optimize.minimize_scalar``) around each
refines it to ``xatol`` in angle. :func:`check_peak` compares it with the grid maximum and returns
the angles to add to the grid when the grid missed the peak (DESIGN principle 3).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..kinematics.mechanism import input_domain, input_grid

__all__ = ["PeakCheck", "true_peak", "check_peak"]


@dataclass(frozen=True)
class PeakCheck:
    """A peak measure at one design: the solver grid's value against the true one.

    Attributes
    ----------
    name : the measure.
    grid_value : the measure's value from the solver's grid angles.
    true_value : the value at the true continuous extremum (dense grid + 1-D local search).
    angle : crank angle (rad, in [0, 2 pi)) of the true extremum.
    gap : ``|true - grid| / max(|true|, 1e-300)``.
    """

    name: str
    grid_value: float
    true_value: float
    angle: float
    gap: float


def _q(atom, mechanism, speed, phi):
    motion = mechanism.motion(np.asarray(phi, dtype=float), speed=speed)
    return np.asarray(atom.q(mechanism, motion), dtype=float)


_GOLDEN = 0.5 * (3.0 - math.sqrt(5.0))
_SQRT_EPS = math.sqrt(2.2e-16)  # scipy's constant (not quite sqrt(machine epsilon))


def _local_min(f, a, b, xatol=1e-11, maxfun=500):
    """A local minimum of ``f`` on ``[a, b]``: Brent's method (golden sections and parabolic
    steps), ended when the bracket is within ``xatol`` (plus ``sqrt(eps) |x|``) of its best
    point or after ``maxfun`` evaluations. Returns ``(x, f(x))``.

    Step for step ``scipy.optimize.minimize_scalar(f, bounds=(a, b), method="bounded",
    options={"xatol": xatol})`` (the same points, bit for bit; tested), whose import costs more
    than a whole certified solve.
    """
    x = w = v = a + _GOLDEN * (b - a)  # x best, w second best, v the one before
    fx = fw = fv = f(x)
    d = e = 0.0
    num = 1
    m = 0.5 * (a + b)
    tol = _SQRT_EPS * abs(x) + xatol / 3.0
    while abs(x - m) > 2.0 * tol - 0.5 * (b - a):
        golden = True
        if abs(e) > tol:  # the parabola through x, w, v
            golden = False
            r = (x - w) * (fx - fv)
            q = (x - v) * (fx - fw)
            p = (x - v) * q - (x - w) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            q = abs(q)
            r, e = e, d
            if abs(p) < abs(0.5 * q * r) and p > q * (a - x) and p < q * (b - x):
                d = (p + 0.0) / q
                u = x + d
                if (u - a) < 2.0 * tol or (b - u) < 2.0 * tol:
                    d = tol if m >= x else -tol
            else:
                golden = True
        if golden:  # a golden section of the larger part
            e = (a - x) if x >= m else (b - x)
            d = _GOLDEN * e
        u = x + (-1.0 if d < 0 else 1.0) * max(abs(d), tol)
        fu = f(u)
        num += 1
        if fu <= fx:
            if u >= x:
                a = x
            else:
                b = x
            v, fv, w, fw, x, fx = w, fw, x, fx, u, fu
        else:
            if u < x:
                a = u
            else:
                b = u
            if fu <= fw or w == x:
                v, fv, w, fw = w, fw, u, fu
            elif fu <= fv or v == x or v == w:
                v, fv = u, fu
        m = 0.5 * (a + b)
        tol = _SQRT_EPS * abs(x) + xatol / 3.0
        if num >= maxfun:
            break
    return x, fx


def true_peak(atom, mechanism, speed=None, n_dense=2048, window=1e-2, max_candidates=6):
    """True maximum of ``q`` (the atom's stacked branches) over the crank angle (over the travel
    of a linkage driven by a slider, ends included: its input does not wrap around).

    Returns
    -------
    peak : max q over [0, 2 pi).
    angle : where it is attained (rad).
    candidates : list of ``(angle, q)`` of every refined local maximum near the top (within
        ``window`` times the range of q of the global maximum, at most ``max_candidates`` per
        branch), each a candidate for the solver grid.
    """
    lo, hi, periodic = input_domain(mechanism)
    phi = input_grid(mechanism, n_dense)
    h = (hi - lo) / (n_dense if periodic else n_dense - 1)
    q = _q(atom, mechanism, speed, phi)
    top = float(q.max())
    spread = max(float(q.max() - q.min()), abs(top), 1e-300)
    candidates = []
    for j, qj in enumerate(q):
        before, after = np.roll(qj, 1), np.roll(qj, -1)
        if not periodic:  # the ends of a travel have one neighbour each
            before[0], after[-1] = -np.inf, -np.inf
        is_local = (qj >= before) & (qj >= after) & (qj >= top - window * spread)
        idx = np.flatnonzero(is_local)
        if idx.size > max_candidates:
            idx = idx[np.argsort(qj[idx])[-max_candidates:]]
        for i in idx:

            def neg(t, j=j):
                return -_q(atom, mechanism, speed, np.array([t]))[j, 0]

            a, b = phi[i] - h, phi[i] + h
            if not periodic:
                a, b = max(a, lo), min(b, hi)
            x, fx = _local_min(neg, a, b, xatol=1e-11)
            angle, value = (float(x), -float(fx)) if -fx >= qj[i] else (phi[i], qj[i])
            if periodic:
                angle = float(np.mod(angle - lo, hi - lo) + lo)
            candidates.append((float(angle), float(value)))
    best = max(candidates, key=lambda c: c[1])
    return best[1], best[0], candidates


def check_peak(atom, mechanism, grid, speed=None, rtol=1e-9, n_dense=2048):
    """Compare the grid maximum of ``atom`` with the true one at ``mechanism``.

    Returns
    -------
    check : :class:`PeakCheck` (in the measure's units).
    new_angles : angles to add to the grid (empty when the grid peak is the true peak within
        ``rtol``).
    true_q : the true ``max q`` (for evaluating the measure at its true value).
    """
    grid_q = float(_q(atom, mechanism, speed, grid).max())
    peak, angle, candidates = true_peak(atom, mechanism, speed, n_dense=n_dense)
    tol = rtol * max(abs(peak), 1e-300)
    new = [a for a, v in candidates if v > grid_q + tol] if peak > grid_q + tol else []
    true_v = float(atom.from_peak(peak))
    grid_v = float(atom.from_peak(grid_q))
    gap = abs(true_v - grid_v) / max(abs(true_v), 1e-300)
    return PeakCheck(atom.measure.name, grid_v, true_v, angle, gap), new, peak
