"""Dwell metrics of a coupler curve: Chebyshev (minimax) straight-line fits and dwell windows.

Construction
------------
*Minimax line fit.* For points ``p_i`` and a unit normal ``n(theta)``, every line with that normal
has the largest perpendicular deviation ``>= (max_i p_i.n - min_i p_i.n) / 2``, with equality for
the mid line. So the Chebyshev fit minimizes the *width* ``w(theta) = max - min`` of the
projections over the direction only. The minimum width of a point set is attained with one edge of
its convex hull flush with the band (rotating-calipers theorem), hence

    2E = min over hull edges of (max distance of the hull vertices from that edge's line),

which is exact; rotating calipers find it in O(h) for a hull of h vertices. ``E`` is the
half-width of the band (the deviation of the fitted line), ``2E`` its width (the residual motion
of link 5 during the dwell).

*Dwell window.* Given a tolerance E, the dwell is the longest cyclic run of consecutive crank-angle
samples whose minimax fit has half-width <= E. Feasibility is monotone under inclusion (a subset
never needs a wider band), so a two-pointer sweep over the doubled cycle finds the longest run with
O(N) exact fits. The dwell duration is ``alpha_Sigma = (L - 1) * dphi`` for a run of L samples on a
uniform grid of step dphi; it starts at ``phi_L`` (C at K_L) and the fitted line has slope ``xi``.

*Stroke.* With the slot of link 5 laid along the fitted line (angle xi) link 5 moves by
``s5 = C . (-sin xi, cos xi)``; its relative stroke ``S_max`` is (max s5 - min s5) / rod.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np
from scipy.spatial import ConvexHull, QhullError

from ...errors import MechanismError
from ...objectives.base import Measure

__all__ = [
    "LineFit",
    "minimax_line_fit",
    "DwellWindow",
    "dwell_window",
    "window_deviation",
    "relative_stroke",
    "dwell_windows",
    "dwell_metrics",
    "best_window_width",
    "DwellDuration",
    "DwellDeviation",
    "DwellStroke",
]


@dataclass(frozen=True)
class LineFit:
    """Chebyshev line fit: the line ``x*(-sin xi) + y*cos xi = c`` with half-width ``E``.

    Attributes
    ----------
    deviation : half-width E of the band (largest perpendicular distance to the line), m.
    width : 2E, m.
    xi : direction of the line (rad, in [0, pi)).
    c : signed distance of the line from the origin along ``(-sin xi, cos xi)``, m.
    """

    deviation: float
    xi: float
    c: float

    @property
    def width(self) -> float:
        return 2.0 * self.deviation


@numba.njit(cache=True, nogil=True)
def _hull_width(px, py):
    """Minimum width (2E) of a point set (see :func:`_hull_band`)."""
    return _hull_band(px, py)[0]


@numba.njit(cache=True, nogil=True)
def _hull_band(px, py):
    """Minimum width (2E) of a point set and the direction ``(ex, ey)`` of the hull edge the
    band lies along: monotone-chain hull, then rotating calipers. ``(0, 0)`` as the direction
    when the hull has fewer than three vertices (collinear or coincident points)."""
    n = px.size
    if n <= 2:
        return 0.0, 0.0, 0.0
    o1 = np.argsort(py, kind="mergesort")
    o2 = np.argsort(px[o1], kind="mergesort")
    order = o1[o2]
    hx = np.empty(2 * n)
    hy = np.empty(2 * n)
    lower = 0
    m = 0
    for t in range(2 * n - 1):  # lower hull (t < n), then upper hull back to the start
        i = order[t] if t < n else order[2 * n - 2 - t]
        lim = 2 if t < n else lower + 1
        while (
            m >= lim
            and (
                (hx[m - 1] - hx[m - 2]) * (py[i] - hy[m - 2])
                - (hy[m - 1] - hy[m - 2]) * (px[i] - hx[m - 2])
            )
            <= 0.0
        ):
            m -= 1
        hx[m] = px[i]
        hy[m] = py[i]
        m += 1
        if t == n - 1:
            lower = m
    m -= 1  # last point repeats the first
    if m < 3:
        return 0.0, 0.0, 0.0
    # rotating calipers: the hull is counter-clockwise without collinear vertices, so the
    # distance of the vertices from an edge rises to one maximum and falls; its farthest vertex
    # only moves forward as the edge turns (O(m) in all)
    best, bex, bey = np.inf, 0.0, 0.0
    c = 1
    for a in range(m):
        b = a + 1 if a + 1 < m else 0
        ex, ey = hx[b] - hx[a], hy[b] - hy[a]
        ln = np.sqrt(ex * ex + ey * ey)
        if ln == 0.0:
            continue
        far = ex * (hy[c] - hy[a]) - ey * (hx[c] - hx[a])
        for _ in range(m):
            nc = c + 1 if c + 1 < m else 0
            d = ex * (hy[nc] - hy[a]) - ey * (hx[nc] - hx[a])
            if d <= far:
                break
            c, far = nc, d
        if far / ln < best:
            best, bex, bey = far / ln, ex, ey
    if best == np.inf:
        return 0.0, 0.0, 0.0
    return best, bex, bey


@numba.njit(cache=True, nogil=True)
def _window_ok(px, py, i, j, width):
    """True if samples i .. j-1 of the doubled curve fit a band of ``width``."""
    if j - i <= 2:
        return True
    ex, ey = px[j - 1] - px[i], py[j - 1] - py[i]
    ln = np.sqrt(ex * ex + ey * ey)
    if ln > 0.0:  # quick accept: the band along the chord bounds the minimax width from above
        lo, hi = np.inf, -np.inf
        tlo, thi = i, i
        for t in range(i, j):
            d = (ex * (py[t] - py[i]) - ey * (px[t] - px[i])) / ln
            if d < lo:
                lo, tlo = d, t
            if d > hi:
                hi, thi = d, t
        if hi - lo <= width:
            return True
        # quick reject: a sub-triangle (chord ends + farthest point) needs a band of width
        # 2 area / longest side, a lower bound of the minimax width of the whole set
        t = thi if hi > -lo else tlo
        far = max(hi, -lo)
        a2 = far * ln  # twice the triangle area
        s1 = np.hypot(px[t] - px[i], py[t] - py[i])
        s2 = np.hypot(px[j - 1] - px[t], py[j - 1] - py[t])
        if a2 / max(ln, s1, s2) > width:
            return False
    return _hull_width(px[i:j], py[i:j]) <= width


@numba.njit(cache=True, nogil=True, parallel=True)
def _longest_windows(x, y, width):
    """Two-pointer sweep per design (rows of x, y): (start, count) of the longest cyclic run."""
    nd, n = x.shape
    start = np.zeros(nd, dtype=np.int64)
    count = np.ones(nd, dtype=np.int64)
    for d in numba.prange(nd):
        px = np.concatenate((x[d], x[d]))
        py = np.concatenate((y[d], y[d]))
        j = 1
        for i in range(n):
            if j < i + 1:
                j = i + 1
            while j < i + n and _window_ok(px, py, i, j + 1, width):
                j += 1
            if j - i > count[d]:
                start[d] = i
                count[d] = j - i
            if count[d] == n:
                break
    return start, count


@numba.njit(cache=True, nogil=True, parallel=True)
def _window_bands(x, y, start, count):
    """Per design: minimum width (2E) of the cyclic window ``start .. start+count-1`` and the
    direction of its band (see :func:`_hull_band`)."""
    nd, n = x.shape
    width = np.empty(nd)
    ex = np.empty(nd)
    ey = np.empty(nd)
    for d in numba.prange(nd):
        idx = (start[d] + np.arange(count[d])) % n
        width[d], ex[d], ey[d] = _hull_band(x[d][idx], y[d][idx])
    return width, ex, ey


@numba.njit(cache=True, nogil=True, parallel=True)
def _best_fixed_windows(x, y, count):
    """Per design: the smallest minimax width (2E) over all cyclic windows of ``count`` samples,
    and the start index where it is attained."""
    nd, n = x.shape
    best = np.empty(nd)
    where = np.zeros(nd, dtype=np.int64)
    for d in numba.prange(nd):
        px = np.concatenate((x[d], x[d, :count]))
        py = np.concatenate((y[d], y[d, :count]))
        b = np.inf
        for i in range(n):
            w = _hull_width(px[i : i + count], py[i : i + count])
            if w < b:
                b = w
                where[d] = i
        best[d] = b
    return best, where


def _fit_direction(points, xi):
    xi = float(np.mod(xi, np.pi))
    nx, ny = -np.sin(xi), np.cos(xi)
    proj = points[:, 0] * nx + points[:, 1] * ny
    hi, lo = proj.max(), proj.min()
    return LineFit(0.5 * (hi - lo), xi, 0.5 * (hi + lo))


def minimax_line_fit(points) -> LineFit:
    """Exact Chebyshev (minimax perpendicular deviation) straight-line fit of 2-D points.

    Parameters
    ----------
    points : array (N, 2), N >= 2, finite.

    Returns
    -------
    LineFit with the half-width E, the direction xi and the offset c of the best line.
    """
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 2 or p.shape[0] < 2:
        raise MechanismError(f"points must be an (N, 2) array with N >= 2, got shape {p.shape}")
    if not np.all(np.isfinite(p)):
        raise MechanismError("points must be finite")
    try:
        hull = p[ConvexHull(p).vertices]
    except QhullError:
        # (nearly) collinear or too few points: the band is along the principal direction
        q = p - p.mean(axis=0)
        _, _, vt = np.linalg.svd(q, full_matrices=False)
        return _fit_direction(p, np.arctan2(vt[0, 1], vt[0, 0]))
    edges = np.roll(hull, -1, axis=0) - hull
    lengths = np.hypot(edges[:, 0], edges[:, 1])
    keep = lengths > 0
    edges, base, lengths = edges[keep], hull[keep], lengths[keep]
    # distances of all hull vertices from each edge line (hull is convex: all on one side)
    rel_x = hull[None, :, 0] - base[:, None, 0]
    rel_y = hull[None, :, 1] - base[:, None, 1]
    dist = np.abs(edges[:, None, 0] * rel_y - edges[:, None, 1] * rel_x) / lengths[:, None]
    widths = dist.max(axis=1)
    best = int(np.argmin(widths))
    return _fit_direction(p, np.arctan2(edges[best, 1], edges[best, 0]))


def window_deviation(x, y, start, stop) -> LineFit:
    """Minimax fit of the samples ``start .. stop-1`` (indices taken cyclically) of a curve."""
    n = len(x)
    idx = np.arange(start, stop) % n
    return minimax_line_fit(np.column_stack([np.asarray(x)[idx], np.asarray(y)[idx]]))


@dataclass(frozen=True)
class DwellWindow:
    """Longest crank-angle window whose coupler-curve section fits a line within ``tolerance``.

    Attributes
    ----------
    tolerance : E, the admitted half-width (m).
    dwell : alpha_Sigma, crank angle of the window (rad).
    phi_L : crank angle at the start of the window (rad, in [0, 2 pi)).
    start, count : first sample index and number of samples in the window.
    fit : the minimax fit of the window (deviation <= tolerance).
    """

    tolerance: float
    dwell: float
    phi_L: float
    start: int
    count: int
    fit: LineFit

    @property
    def xi(self) -> float:
        return self.fit.xi

    @property
    def deviation(self) -> float:
        return self.fit.deviation


def _check_grid(phi):
    phi = np.asarray(phi, dtype=float)
    n = phi.size
    if phi.ndim != 1 or n < 4:
        raise MechanismError(
            f"phi must be a 1-D grid of at least 4 crank angles, got shape {phi.shape}"
        )
    step = 2.0 * np.pi / n
    if not np.allclose(np.diff(phi), step, rtol=1e-9, atol=1e-12):
        raise MechanismError(
            f"phi must cover one cycle in {n} equal steps of {step:.6g} rad (e.g. ms.cycle({n}))"
        )
    return phi, step


def dwell_window(phi, x, y, tolerance) -> DwellWindow:
    """Longest cyclic window of a closed curve sampled at ``phi`` with minimax half-width <= E.

    Parameters
    ----------
    phi : crank angles (rad), one full cycle in equal steps (``ms.cycle(N)``).
    x, y : coordinates (m) of the curve at ``phi``.
    tolerance : E (m), the admitted half-width of the band (> 0).
    """
    phi, step = _check_grid(phi)
    if not np.isfinite(tolerance) or tolerance <= 0:
        raise MechanismError(f"tolerance (half-width E) must be positive, got {tolerance}")
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    n = phi.size
    if x.shape != (n,) or y.shape != (n,):
        raise MechanismError(f"x and y must have the shape of phi {(n,)}, got {x.shape}, {y.shape}")
    st, ct = _longest_windows(x[None, :], y[None, :], 2.0 * float(tolerance))
    best_i, best_len = int(st[0]), int(ct[0])
    fit = window_deviation(x, y, best_i, best_i + best_len)
    dwell = 2.0 * np.pi if best_len == n else (best_len - 1) * step
    return DwellWindow(
        float(tolerance), float(dwell), float(np.mod(phi[best_i], 2 * np.pi)), best_i, best_len, fit
    )


def dwell_windows(phi, x, y, tolerance):
    """Batch version of :func:`dwell_window` for curves in the rows of ``x``, ``y`` (..., N).

    Returns a dict of arrays over the leading axes: ``dwell`` (rad), ``phi_L`` (rad), ``deviation``
    (E, m), ``xi`` (rad), ``start``, ``count``. The windows come from the compiled two-pointer
    sweep; each window's line is then fitted exactly.
    """
    phi, step = _check_grid(phi)
    if not np.isfinite(tolerance) or tolerance <= 0:
        raise MechanismError(f"tolerance (half-width E) must be positive, got {tolerance}")
    x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    n = phi.size
    if x.shape[-1] != n:
        raise MechanismError(f"the last axis of x, y must match phi ({n}), got {x.shape}")
    lead = x.shape[:-1]
    fx = np.ascontiguousarray(x.reshape(-1, n))
    fy = np.ascontiguousarray(y.reshape(-1, n))
    with numba.parallel_chunksize(8):  # designs differ in cost: hand them out in small chunks
        st, ct = _longest_windows(fx, fy, 2.0 * float(tolerance))
        width, ex, ey = _window_bands(fx, fy, st, ct)
    dev = 0.5 * width
    xi = np.mod(np.arctan2(ey, ex), np.pi)
    # (nearly) collinear windows have no hull edge to align with: the exact fit takes the
    # principal direction
    for d in np.flatnonzero((ex == 0.0) & (ey == 0.0)):
        f = window_deviation(fx[d], fy[d], st[d], st[d] + ct[d])
        dev[d], xi[d] = f.deviation, f.xi
    dwell = np.where(ct == n, 2.0 * np.pi, (ct - 1) * step)
    return {
        "dwell": dwell.reshape(lead),
        "phi_L": np.mod(phi[st], 2.0 * np.pi).reshape(lead),
        "deviation": dev.reshape(lead),
        "xi": xi.reshape(lead),
        "start": st.reshape(lead),
        "count": ct.reshape(lead),
    }


def dwell_metrics(phi, x, y, tolerance, rod=1.0):
    """:func:`dwell_windows` plus ``S_max``: the relative stroke of link 5 with its slot along
    each window's fitted line (see :func:`relative_stroke`)."""
    win = dwell_windows(phi, x, y, tolerance)
    win["S_max"] = relative_stroke(x, y, win["xi"][..., None], rod)
    return win


def best_window_width(phi, x, y, span):
    """Smallest minimax band width 2E (m) over all crank windows of length ``span`` (rad), for
    curves in the rows of ``x``, ``y``; returns ``(width, phi_start)`` arrays over designs."""
    phi, step = _check_grid(phi)
    count = int(np.floor(span / step + 1e-9)) + 1
    if not 2 <= count <= phi.size:
        raise MechanismError(f"span ({span} rad) must cover 1 .. {phi.size - 1} grid steps")
    x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    n = phi.size
    lead = x.shape[:-1]
    with numba.parallel_chunksize(8):
        w, st = _best_fixed_windows(
            np.ascontiguousarray(x.reshape(-1, n)), np.ascontiguousarray(y.reshape(-1, n)), count
        )
    return w.reshape(lead), np.mod(phi[st], 2 * np.pi).reshape(lead)


def relative_stroke(x, y, xi, rod=1.0):
    """Relative stroke S_max of link 5 with its slot at angle ``xi``: range of C . n over rod."""
    s5 = -np.asarray(x) * np.sin(xi) + np.asarray(y) * np.cos(xi)
    return (s5.max(axis=-1) - s5.min(axis=-1)) / rod


def _curve(motion):
    c = motion.points["C"]
    return np.asarray(c.x, dtype=float), np.asarray(c.y, dtype=float)


def _phi(motion):
    return np.asarray(motion.phi, dtype=float).reshape(-1)


def _per_design(motion, fn):
    x, y = _curve(motion)
    phi = _phi(motion)
    x, y = np.broadcast_arrays(x, y)
    if x.ndim == 1:
        return fn(phi, x, y)
    flat_x = x.reshape(-1, x.shape[-1])
    flat_y = y.reshape(-1, y.shape[-1])
    out = np.array([fn(phi, a, b) for a, b in zip(flat_x, flat_y)])
    return out.reshape(x.shape[:-1])


class DwellDuration(Measure):
    """alpha_Sigma (rad): longest crank-angle window whose coupler section of C fits a straight
    line within half-width ``tolerance`` (relative to the rod). Not smooth: use with "de" or a
    grid search."""

    unit = "rad"

    def __init__(self, tolerance: float, name: str = "dwell"):
        self.tolerance, self.name = float(tolerance), name

    def from_motion(self, mechanism, motion):
        tol = self.tolerance * float(mechanism.rod)
        x, y = _curve(motion)
        return dwell_windows(_phi(motion), x, y, tol)["dwell"]


class DwellStroke(Measure):
    """S_max: relative stroke of link 5 with its slot along the line fitted to the dwell window
    found for ``tolerance``."""

    def __init__(self, tolerance: float, name: str = "S_max"):
        self.tolerance, self.name = float(tolerance), name

    def from_motion(self, mechanism, motion):
        rod = float(mechanism.rod)
        x, y = _curve(motion)
        return dwell_metrics(_phi(motion), x, y, self.tolerance * rod, rod)["S_max"]


class DwellDeviation(Measure):
    """E (relative to the rod): minimax half-width of the coupler section of C over the crank
    window [phi_start, phi_start + span] (rad). 2E is the band width."""

    def __init__(self, phi_start: float, span: float, name: str = "E"):
        self.phi_start, self.span, self.name = float(phi_start), float(span), name

    def from_motion(self, mechanism, motion):
        rod = float(mechanism.rod)

        def fn(p, x, y):
            n = p.size
            step = 2 * np.pi / n
            i0 = int(np.ceil(np.mod(self.phi_start - p[0], 2 * np.pi) / step - 1e-9))
            count = int(np.floor(self.span / step + 1e-9)) + 1
            return window_deviation(x, y, i0, i0 + count).deviation / rod

        return _per_design(motion, fn)
