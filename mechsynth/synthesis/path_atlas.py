"""An atlas of normalized four-bar coupler curves, to seed path generation by shape.

Each entry is a four-bar whose crank turns fully (ground 1, the other lengths and the coupler
point drawn at random, both assembly branches) and the elliptic Fourier descriptors of its
coupler curve (Kuhl and Giardina, *Elliptic Fourier features of a closed contour*, Computer
Graphics and Image Processing 18 (1982) 236-258), normalized for position, size, orientation
and starting point. Two curves of the same shape have nearly the same descriptors whatever
their placement, size and parametrization, so the nearest entries to a target's descriptors
are the four-bars whose curves look most like it; :func:`seed` maps one onto the targets (a
similarity fitted to corresponding points), giving a design and a crank angle per target from
which a local solver starts.

The atlas is built on first use from a fixed random seed (about a second) and kept for the
process: nothing is shipped.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

__all__ = ["efd", "normalized_efd", "Atlas", "atlas", "seed", "Seed"]

#: harmonics kept in the descriptors
HARMONICS = 8
#: crank angles per curve in the atlas
SAMPLES = 96


def efd(points, harmonics: int = HARMONICS):
    """Elliptic Fourier coefficients of closed polygons.

    Parameters
    ----------
    points : array (..., M, 2) of the polygons' vertices in order (the last joins the first).
    harmonics : number of harmonics.

    Returns
    -------
    coeffs : array (..., harmonics, 4) of ``(a_n, b_n, c_n, d_n)`` (x = sum a cos + b sin,
        y = sum c cos + d sin over the arc-length parameter ``2 pi n t / T``).
    centre : array (..., 2), the polygon's centroid along its arc (``A0, C0``).
    """
    p = np.asarray(points, dtype=float)
    d = np.roll(p, -1, axis=-2) - p  # segment k: vertex k -> k+1
    dt = np.hypot(d[..., 0], d[..., 1])
    t = np.cumsum(dt, axis=-1)
    total = t[..., -1:]
    t0 = t - dt  # start of each segment
    safe = np.where(dt > 0, dt, 1.0)
    slope = np.where((dt > 0)[..., None], d / safe[..., None], 0.0)  # (..., M, 2)
    n = np.arange(1, harmonics + 1)
    phase1 = 2.0 * np.pi * n[:, None] * (t / total)[..., None, :]  # (..., H, M)
    phase0 = 2.0 * np.pi * n[:, None] * (t0 / total)[..., None, :]
    dcos = np.cos(phase1) - np.cos(phase0)
    dsin = np.sin(phase1) - np.sin(phase0)
    k = total / (2.0 * n**2 * np.pi**2)  # (..., H)
    a = k * np.einsum("...hm,...m->...h", dcos, slope[..., 0])
    b = k * np.einsum("...hm,...m->...h", dsin, slope[..., 0])
    c = k * np.einsum("...hm,...m->...h", dcos, slope[..., 1])
    dd = k * np.einsum("...hm,...m->...h", dsin, slope[..., 1])
    # the zeroth harmonic: the mean of the curve over its arc (trapezoidal per segment)
    mid = 0.5 * (p + np.roll(p, -1, axis=-2))
    centre = np.einsum("...m,...mk->...k", dt, mid) / total
    return np.stack([a, b, c, dd], axis=-1), centre


@dataclass(frozen=True)
class Normalized:
    """Normalized descriptors and the transformation that normalized them: a curve point at
    arc fraction ``s`` maps to ``rotation(-psi) (p - centre) / scale`` at fraction
    ``s - start`` (``start`` in turns)."""

    descriptors: np.ndarray  # (..., H, 4)
    centre: np.ndarray  # (..., 2)
    scale: np.ndarray  # (...)
    psi: np.ndarray  # (...) rad
    start: np.ndarray  # (...) turns


def normalized_efd(points, harmonics: int = HARMONICS, flip: bool = False) -> Normalized:
    """Descriptors normalized for position, size, orientation and starting point (Kuhl and
    Giardina's first-harmonic normalization). The major axis of the first ellipse has two ends;
    ``flip`` starts at the other one (the even harmonics change sign)."""
    coeffs, centre = efd(points, harmonics)
    a1, b1, c1, d1 = (coeffs[..., 0, i] for i in range(4))
    theta = 0.5 * np.arctan2(2.0 * (a1 * b1 + c1 * d1), a1**2 + c1**2 - b1**2 - d1**2)
    if flip:
        theta = theta + np.pi
    n = np.arange(1, harmonics + 1)
    ct, st = np.cos(n * theta[..., None]), np.sin(n * theta[..., None])
    a, b, c, d = (coeffs[..., i] for i in range(4))
    # [a b; c d] @ [[cos, -sin], [sin, cos]]
    a2, b2 = a * ct + b * st, -a * st + b * ct
    c2, d2 = c * ct + d * st, -c * st + d * ct
    psi = np.arctan2(c2[..., 0], a2[..., 0])
    scale = np.hypot(a2[..., 0], c2[..., 0])
    cp, sp = np.cos(psi)[..., None], np.sin(psi)[..., None]
    inv = 1.0 / np.where(scale > 0, scale, 1.0)[..., None]
    out = np.stack(
        [
            (cp * a2 + sp * c2) * inv,
            (cp * b2 + sp * d2) * inv,
            (-sp * a2 + cp * c2) * inv,
            (-sp * b2 + cp * d2) * inv,
        ],
        axis=-1,
    )
    return Normalized(out, centre, scale, psi, theta / (2.0 * np.pi))


def _features(desc: np.ndarray) -> np.ndarray:
    """The descriptors as flat feature vectors (the first harmonic's fixed 1 and 0 dropped;
    higher harmonics weighted by n so the fine shape counts without dominating)."""
    n = np.arange(1, desc.shape[-2] + 1, dtype=float)
    w = np.sqrt(n)[:, None] * np.ones(4)
    flat = (desc * w).reshape(*desc.shape[:-2], -1)
    return np.concatenate([flat[..., 1:2], flat[..., 3:4], flat[..., 4:]], axis=-1)


@dataclass(frozen=True)
class Atlas:
    """Four-bars (ground 1) with their curves' normalized descriptors.

    Attributes
    ----------
    designs : array (n, 6) of ``crank, coupler, rocker, ground, u, v`` (ground = 1).
    branch : array (n,) of +1 (open) / -1 (crossed).
    mu_min : array (n,) of the smallest transmission angle over the turn (rad).
    features : array (n, f) of the curves' shape features.
    arc : array (n, SAMPLES + 1): the arc fraction (turns, from crank angle 0) at each atlas
        crank angle, closing with 1, to turn a curve's arc fraction into a crank angle.
    start : array (n,) of the normalization's starting arc fraction (turns).
    """

    designs: np.ndarray
    branch: np.ndarray
    mu_min: np.ndarray
    features: np.ndarray
    arc: np.ndarray
    start: np.ndarray

    def __len__(self) -> int:
        return len(self.branch)


def coupler_curves(designs, branch, phi):
    """Coupler-point positions ``(n, len(phi), 2)`` of four-bars ``designs`` (n, 6) =
    ``crank, coupler, rocker, ground, u, v`` in their own frame (crank pivot at the origin,
    rocker pivot on +x) by the library's four-bar model."""
    from ..kinematics import ops
    from ..kinematics.blocks import coupler_point
    from ..kinematics.four_bar import four_bar_chain

    d = np.asarray(designs, dtype=float)
    col = [d[:, i : i + 1] for i in range(6)]
    phi = np.asarray(phi, dtype=float)
    sig = np.asarray(branch, dtype=float)[:, None]
    out = np.empty((len(d), phi.size, 2))
    for s in (1, -1):  # the branch is a block argument: one pass per branch
        rows = np.flatnonzero(sig[:, 0] == s)
        if rows.size == 0:
            continue
        a, _, cpl, _ = four_bar_chain(
            ops.cos(phi), ops.sin(phi), *(c[rows] for c in col[:4]), s, phi
        )
        p = coupler_point(a, cpl, col[4][rows], col[5][rows])
        out[rows, :, 0], out[rows, :, 1] = p.x, p.y
    return out


def _transmission_extremes(a, b, c, d):
    """Cosines of the transmission angle at crank angles 0 and pi, its two extremes over a
    full turn (law of cosines on the diagonal A-O2, from ``|d - a|`` to ``d + a``)."""
    c0 = (b * b + c * c - (d - a) ** 2) / (2.0 * b * c)
    c1 = (b * b + c * c - (d + a) ** 2) / (2.0 * b * c)
    return c0, c1


def min_transmission(a, b, c, d):
    """Smallest transmission angle over a full crank turn (rad; an obtuse angle counted as
    pi minus it) of four-bars whose crank turns fully: exact, from the two extremes."""
    c0, c1 = _transmission_extremes(a, b, c, d)
    worst = np.maximum(np.abs(c0), np.abs(c1))
    return np.arccos(np.clip(worst, -1.0, 1.0))


@functools.lru_cache(maxsize=2)
def atlas(size: int = 12000, seed: int = 2026) -> Atlas:
    """The atlas of ``size`` four-bars (built once per process; deterministic)."""
    rng = np.random.default_rng(seed)
    m = 4 * size
    crank = np.exp(rng.uniform(np.log(0.05), np.log(1.2), m))
    coupler = np.exp(rng.uniform(np.log(0.15), np.log(4.0), m))
    rocker = np.exp(rng.uniform(np.log(0.15), np.log(4.0), m))
    ground = np.ones(m)
    ok = (crank + ground < coupler + rocker) & (np.abs(ground - crank) > np.abs(coupler - rocker))
    mu = min_transmission(crank, coupler, rocker, ground)
    ok &= mu > np.deg2rad(8.0)
    idx = np.flatnonzero(ok)[:size]
    n = idx.size
    r = coupler[idx] * np.sqrt(rng.uniform(0.0, 1.0, n)) * 1.6
    ang = rng.uniform(-np.pi, np.pi, n)
    u = 0.5 * coupler[idx] + r * np.cos(ang)
    v = r * np.sin(ang)
    designs = np.column_stack([crank[idx], coupler[idx], rocker[idx], ground[idx], u, v])
    branch = np.where(rng.uniform(size=n) < 0.5, 1, -1)
    phi = np.linspace(0.0, 2.0 * np.pi, SAMPLES, endpoint=False)
    pts = coupler_curves(designs, branch, phi)
    norm = normalized_efd(pts)
    seg = np.hypot(*np.moveaxis(np.diff(np.concatenate([pts, pts[:, :1]], axis=1), axis=1), -1, 0))
    arc = np.concatenate([np.zeros((n, 1)), np.cumsum(seg, axis=1)], axis=1)
    arc /= arc[:, -1:]
    keep = norm.scale > 1e-3
    return Atlas(
        designs[keep],
        branch[keep],
        mu[idx][keep],
        _features(norm.descriptors[keep]),
        arc[keep],
        np.mod(norm.start[keep], 1.0),
    )


@dataclass(frozen=True)
class Seed:
    """A start for the local solver: a four-bar (``crank, coupler, rocker, ground, u, v``),
    its branch, its placement (crank pivot ``x0, y0`` and ground angle ``angle``) and crank
    angles at the targets (rad, increasing), with the atlas distance and the fit's squared
    error."""

    design: np.ndarray
    branch: int
    x0: float
    y0: float
    angle: float
    angles: np.ndarray
    distance: float
    fit: float


def _similarity(src, dst):
    """Least-squares rotation, scale and translation (no reflection) taking ``src`` points to
    ``dst`` (Umeyama). Returns ``scale, angle, shift`` and the squared residual."""
    ms_, md = src.mean(axis=0), dst.mean(axis=0)
    s, d = src - ms_, dst - md
    zs = s[:, 0] + 1j * s[:, 1]
    zd = d[:, 0] + 1j * d[:, 1]
    k = np.vdot(zs, zd) / max(np.vdot(zs, zs).real, 1e-300)
    scale, angle = abs(k), float(np.angle(k))
    rot = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    shift = md - scale * rot @ ms_
    res = float(np.sum((scale * s @ rot.T - d) ** 2))
    return scale, angle, shift, res


def seed(targets, count: int = 16, min_mu: float = 0.0, pool: int | None = None) -> list[Seed]:
    """Starts for the targets (a closed path, ``(N, 2)`` in order): the ``count`` best of the
    atlas's nearest ``pool`` curves by shape, each placed by the similarity that best fits its
    points at the targets' arc fractions, ranked by that fit. Entries whose smallest
    transmission angle is below ``min_mu`` (rad) are skipped."""
    at = atlas()
    t = np.asarray(targets, dtype=float)
    pool = pool or 6 * count
    rows = np.flatnonzero(at.mu_min >= min_mu) if min_mu > 0 else np.arange(len(at))
    if rows.size == 0:
        return []
    seg = np.hypot(*np.diff(np.vstack([t, t[:1]]), axis=0).T)
    frac = np.concatenate([[0.0], np.cumsum(seg)[:-1]]) / seg.sum()
    out = []
    for flip in (False, True):
        nt = normalized_efd(t, flip=flip)
        ft = _features(nt.descriptors)
        dist = np.linalg.norm(at.features[rows] - ft, axis=1)
        best = rows[np.argsort(dist)[:pool]]
        for i in best:
            # the target at arc fraction s matches the atlas curve at s - start_t + start_a
            s_atlas = np.mod(frac - nt.start + at.start[i], 1.0)
            phi = np.interp(s_atlas, at.arc[i], np.linspace(0, 2 * np.pi, SAMPLES + 1))
            phi = phi[0] + np.mod(phi - phi[0], 2.0 * np.pi)
            if np.any(np.diff(phi) < -1e-9):  # the curve doubles back on itself here: skip
                phi = phi[0] + np.maximum.accumulate(phi - phi[0])
            pts = coupler_curves(at.designs[i : i + 1], at.branch[i : i + 1], phi)[0]
            scale, angle, shift, res = _similarity(pts, t)
            out.append(
                Seed(
                    at.designs[i] * scale,
                    int(at.branch[i]),
                    float(shift[0]),
                    float(shift[1]),
                    angle,
                    phi,
                    float(np.linalg.norm(at.features[i] - ft)),
                    res,
                )
            )
    out.sort(key=lambda s: s.fit)
    return out[:count]


def seed_timed(targets, given, count: int = 16, min_mu: float = 0.0, phases: int = 24,
               block: int = 2000) -> list[Seed]:
    """Starts for prescribed timing: the targets ``(N, 2)`` reached at crank angles
    ``phi0 + given`` (rad). Every atlas curve is sampled at those angles for ``phases`` values
    of ``phi0`` over a turn; the similarity (rotation, scale, shift) that best maps each sample
    set onto the targets is solved in closed form (complex least squares), and the ``count``
    curves with the smallest residual, each at its best ``phi0``, are placed by it. Unlike
    :func:`seed`, which matches shapes at the points' arc fractions, this keeps the timing the
    solver must keep. Entries whose smallest transmission angle is below ``min_mu`` are
    skipped."""
    at = atlas()
    t = np.asarray(targets, dtype=float)
    zt = t[:, 0] + 1j * t[:, 1]
    zt = zt - zt.mean()
    tt = float(np.sum(np.abs(zt) ** 2))
    d = np.asarray(given, dtype=float) - float(given[0])
    phi0 = np.linspace(0.0, 2.0 * np.pi, int(phases), endpoint=False)
    ang = (phi0[:, None] + d[None, :]).ravel()  # (phases * N,)
    rows = np.flatnonzero(at.mu_min >= min_mu) if min_mu > 0 else np.arange(len(at))
    best_res = np.empty(rows.size)
    best_p = np.empty(rows.size, dtype=int)
    for s in range(0, rows.size, block):
        r = rows[s : s + block]
        c = coupler_curves(at.designs[r], at.branch[r], ang).reshape(len(r), phases, len(t), 2)
        zc = c[..., 0] + 1j * c[..., 1]
        zc = zc - zc.mean(axis=-1, keepdims=True)
        num = np.sum(np.conj(zc) * zt, axis=-1)
        den = np.maximum(np.sum(np.abs(zc) ** 2, axis=-1), 1e-300)
        res = tt - np.abs(num) ** 2 / den  # (designs, phases)
        res = np.where(np.isfinite(res), res, np.inf)
        p = np.argmin(res, axis=1)
        i = np.arange(len(r))
        best_res[s : s + block], best_p[s : s + block] = res[i, p], p
    out = []
    for j in np.argsort(best_res)[:count]:
        if not np.isfinite(best_res[j]):
            break
        i = rows[j]
        angles = phi0[best_p[j]] + d
        pts = coupler_curves(at.designs[i : i + 1], at.branch[i : i + 1], angles)[0]
        scale, angle, shift, res = _similarity(pts, t)
        out.append(Seed(at.designs[i] * scale, int(at.branch[i]), float(shift[0]),
                        float(shift[1]), angle, angles, 0.0, res))  # fmt: skip
    return out
