"""Shape-only path generation: the coupler curve's shape against the targets' polygon.

Position, orientation, size and timing are all free: the error is the squared distance between
the normalized elliptic Fourier descriptors (:mod:`~mechsynth.synthesis.path_atlas`) of the
coupler curve (``SAMPLES`` crank angles over the turn) and of the closed polygon of the targets,
minimized over the four-bar's shape (ground 1; crank, coupler, rocker, coupler point; the
branch of the start) by Nelder-Mead from the atlas's nearest curves, the full turn and the
smallest transmission angle as constraints (a start that leaves them is pulled back by a
penalty; the result is checked). The design is then placed on the targets by the similarity
that best fits its points at the targets' arc fractions, which also gives a crank angle per
target and the point error.
"""

from __future__ import annotations

import numpy as np

__all__ = ["shape_path_generation", "SHAPE_ERROR"]

SHAPE_ERROR = (
    "squared distance between the normalized elliptic Fourier descriptors (8 harmonics, "
    "weighted by sqrt(n)) of the coupler curve and of the targets' closed polygon "
    "(dimensionless; position, orientation, size and timing free)"
)


def _design(x):
    """Four-bar ``crank, coupler, rocker, ground, u, v`` (ground 1) from the search vector
    ``log crank, log coupler, log rocker, u, v``."""
    return np.array([np.exp(x[0]), np.exp(x[1]), np.exp(x[2]), 1.0, x[3], x[4]])


def shape_path_generation(targets, starts=8, min_mu=0.0, margin=1e-3, time_limit=None,
                          t_start=None):  # fmt: skip
    """Shape-only path generation on closed ``targets`` (N, 2). Returns ``(solutions, starts
    run, distinct, status, why)``; each solution's ``error`` is the shape error
    (:data:`SHAPE_ERROR`), ``sum_squares`` the point error once placed."""
    import time

    from scipy.optimize import minimize

    from .path_atlas import (
        SAMPLES,
        _features,
        _similarity,
        atlas,
        coupler_curves,
        min_transmission,
        normalized_efd,
    )
    from .path_generation import _same, evaluated

    t = np.asarray(targets, dtype=float)
    at = atlas()
    feats = [_features(normalized_efd(t, flip=f).descriptors) for f in (False, True)]
    rows = np.flatnonzero(at.mu_min >= min_mu - np.deg2rad(10.0)) if min_mu > 0 else None
    rows = np.arange(len(at)) if rows is None or rows.size == 0 else rows
    dist = np.minimum(*(np.linalg.norm(at.features[rows] - f, axis=1) for f in feats))
    pick = rows[np.argsort(dist)[:starts]]
    phi = np.linspace(0.0, 2.0 * np.pi, SAMPLES, endpoint=False)
    seg = np.hypot(*np.diff(np.vstack([t, t[:1]]), axis=0).T)
    frac = np.concatenate([[0.0], np.cumsum(seg)[:-1]]) / seg.sum()

    def shape_error(x, branch):
        d = _design(x)
        a, b, c, g = d[:4]
        ok = (a + g < b + c) and (abs(g - a) > abs(b - c))
        total = a + b + c + g
        rel = min((b + c - a - g) / total, ((g - a) ** 2 - (b - c) ** 2) / total**2)
        mu = float(min_transmission(a, b, c, g)) if ok else 0.0
        pen = 1e3 * (max(0.0, margin - rel) + max(0.0, min_mu - mu))
        if not ok or rel < margin * 0.5:
            return 10.0 + pen
        pts = coupler_curves(d[None], np.array([branch]), phi)[0]
        f = _features(normalized_efd(pts).descriptors)
        return float(min(np.sum((f - ft) ** 2) for ft in feats)) + pen

    found, ran, why = [], 0, ""
    for i in pick:
        if time_limit is not None and time.perf_counter() - t_start > time_limit:
            break
        d0 = at.designs[i]
        x0 = np.array([np.log(d0[0]), np.log(d0[1]), np.log(d0[2]), d0[4], d0[5]])
        br = int(at.branch[i])
        res = minimize(shape_error, x0, args=(br,), method="Nelder-Mead",
                       options={"xatol": 1e-10, "fatol": 1e-16, "maxiter": 3000,
                                "maxfev": 6000})  # fmt: skip
        ran += 1
        d = _design(res.x)
        sol = _place(d, br, t, frac, phi, feats, evaluated, _similarity, coupler_curves,
                     normalized_efd, res.fun)  # fmt: skip
        if sol is None:
            why = "no start ended on a four-bar whose crank turns fully"
            continue
        if sol.transmission[0] < min_mu - 1e-6:
            why = f"transmission angle {np.rad2deg(sol.transmission[0]):.4f} deg below the bound"
            continue
        found.append(sol)
    found.sort(key=lambda s: s.error)
    distinct = []
    for s in found:
        if not any(_same(s, d_, rtol=1e-3) for d_ in distinct):
            distinct.append(s)
    return distinct, ran, len(distinct), "optimal" if distinct else "infeasible", why


def _place(d, branch, t, frac, phi, feats, evaluated, similarity, curves, nefd, shape):
    """The design ``d`` placed on the targets: each target's arc fraction matched on the curve
    (the normalizations' starting points), then the best similarity; a PathSolution."""
    pts = curves(d[None], np.array([branch]), phi)[0]
    seg = np.hypot(*np.diff(np.vstack([pts, pts[:1]]), axis=0).T)
    arc = np.concatenate([[0.0], np.cumsum(seg)]) / seg.sum()
    na = nefd(pts)
    best = None
    for flip in (False, True):
        nt = nefd(t, flip=flip)
        s_curve = np.mod(frac - nt.start + na.start, 1.0)
        ang = np.interp(s_curve, arc, np.linspace(0.0, 2.0 * np.pi, len(phi) + 1))
        ang = ang[0] + np.mod(ang - ang[0], 2.0 * np.pi)
        ang = ang[0] + np.maximum.accumulate(ang - ang[0])
        p = curves(d[None], np.array([branch]), ang)[0]
        scale, rot, shift, res = similarity(p, t)
        if best is None or res < best[0]:
            best = (res, scale, rot, shift, ang)
    _, scale, rot, shift, ang = best
    vals = dict(zip(("crank", "coupler", "rocker", "ground", "u", "v"), d * scale))
    vals.update(x0=shift[0], y0=shift[1], angle=rot)
    ang = ang - 2.0 * np.pi * np.floor(ang[0] / (2.0 * np.pi))
    sol = evaluated(vals, "open" if branch > 0 else "crossed", ang, t)
    if sol is None:
        return None
    from dataclasses import replace

    return replace(sol, error=float(shape))
