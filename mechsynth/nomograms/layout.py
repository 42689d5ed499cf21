"""Paper and the projective transform that puts a nomogram's scales on it.

Any projective transform of the plane keeps three points collinear when they were, so it turns
a valid nomogram into a valid nomogram: the determinant form fixes *which* points align, the
transform decides how the chart looks. :func:`fit_page` chooses it: a start (the four ends of
the two outer scales sent to the corners of the drawing area, where the form names them), then a
search over the two projective parameters for the layout whose most crowded stretch of every
scale is as long as possible, each candidate fitted to the drawing area by an affine map. All
lengths on the page are millimetres, origin at the paper's lower left corner.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import MechanismError

__all__ = ["Paper", "PAPERS", "paper", "apply", "homography", "fit_page"]


@dataclass(frozen=True)
class Paper:
    """A sheet: ``name``, ``width`` and ``height`` in mm (portrait), and the drawing area
    ``box = (x0, y0, x1, y1)`` in mm left for the scales (margins for the title above and the
    accuracy notes below)."""

    name: str
    width: float
    height: float
    margins: tuple[float, float, float, float] = (30.0, 62.0, 30.0, 34.0)  # left bottom right top

    @property
    def box(self) -> tuple[float, float, float, float]:
        left, bottom, right, top = self.margins
        return (left, bottom, self.width - right, self.height - top)

    @property
    def size_text(self) -> str:
        if self.name == "letter":
            return "Letter (8.5 x 11 in, 216 x 279 mm)"
        return f"{self.name.upper()} ({self.width:g} x {self.height:g} mm)"


PAPERS = {"a4": Paper("a4", 210.0, 297.0), "letter": Paper("letter", 215.9, 279.4)}


def paper(name) -> Paper:
    """The :class:`Paper` named ``name`` (``"a4"`` or ``"letter"``), or ``name`` itself."""
    if isinstance(name, Paper):
        return name
    key = str(name).strip().lower()
    if key not in PAPERS:
        raise MechanismError(f"paper must be one of {', '.join(PAPERS)}, got {name!r}")
    return PAPERS[key]


def apply(T, xyz) -> np.ndarray:
    """Points ``(..., 2)`` of homogeneous rows ``xyz (..., 3)`` through the 3x3 transform."""
    p = np.asarray(xyz, dtype=float) @ np.asarray(T, dtype=float).T
    return p[..., :2] / p[..., 2:3]


def homography(src, dst) -> np.ndarray:
    """The 3x3 projective map sending four points ``src`` (4, 2) to ``dst`` (4, 2)."""
    src, dst = np.asarray(src, dtype=float), np.asarray(dst, dtype=float)
    rows = []
    for (x, y), (u, v) in zip(src, dst, strict=True):
        rows.append([x, y, 1, 0, 0, 0, -u * x, -u * y, -u])
        rows.append([0, 0, 0, x, y, 1, -v * x, -v * y, -v])
    _, s, vt = np.linalg.svd(np.asarray(rows))
    if s[-2] < 1e-12 * s[0]:
        raise MechanismError("the four corner points of the layout are degenerate (collinear)")
    return vt[-1].reshape(3, 3) / vt[-1, -1]


def _affine_to_box(points_list, box, T):
    """``A @ T`` where A maps the bounding box of the points into ``box`` (both axes
    stretched); the points are those of ``T``."""
    allp = np.concatenate(points_list)
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    span = np.where(hi - lo > 1e-12 * (1 + np.abs(hi)), hi - lo, 1.0)
    x0, y0, x1, y1 = box
    sx, sy = (x1 - x0) / span[0], (y1 - y0) / span[1]
    A = np.array([[sx, 0, x0 - sx * lo[0]], [0, sy, y0 - sy * lo[1]], [0, 0, 1.0]])
    return A @ T


def _score(pages) -> float:
    """Sum over the labelled scales of log(shortest step between samples, mm): the most
    crowded stretch of each scale, which decides how many ticks it can carry."""
    total = 0.0
    for p in pages:
        steps = np.hypot(*np.diff(p, axis=0).T)
        total += np.log(max(float(steps.min()), 1e-9))
    return total


def fit_page(scales, box, corners=None, search="full", samples: int = 64) -> np.ndarray:
    """The transform (3x3) from base coordinates to the page (mm) for ``scales``.

    Parameters
    ----------
    scales : the nomogram's :class:`~mechsynth.nomograms.scales.Scale` objects.
    box : drawing area ``(x0, y0, x1, y1)`` in mm.
    corners : optional four ``(scale, value)`` pairs sent to the lower left, upper left, upper
        right and lower right corners of the box (the ends of the outer scales).
    search : ``"full"``: try projective changes (a 13 x 13 grid of the transform's last row
        ``(p, q, 1)``) and keep the best by :func:`_score` when it gains over 10 % in the
        product of the shortest steps; ``"moduli"``: only ``q = 0`` (vertical supports stay
        vertical and straight scales keep their graduation: the moduli change); False: none.
    """
    from .scales import base_curves

    base, labelled = [], []
    for s in scales:
        curves = base_curves(s, samples)
        h = np.concatenate([c[:, 2] for c in curves])
        xyz = np.concatenate(curves)
        where = f"scale {s.name}" + (f" inside its domain {s.domain}" if hasattr(s, "domain")
                                     else " inside its domains")
        if not np.all(np.isfinite(xyz)) or np.any(np.abs(h) < 1e-12 * np.abs(xyz).max()):
            raise MechanismError(f"{where.replace(' inside', ' goes to infinity inside')}")
        if np.any(h > 0) and np.any(h < 0):
            raise MechanismError(
                f"{where.replace(' inside', ' passes through infinity inside')}"
            )
        if not s.turning:
            labelled += range(len(base), len(base) + len(curves))
        base += curves
    T0 = np.eye(3)
    if corners is not None:
        by_name = {s.name: s for s in scales}
        src = [apply(np.eye(3), by_name[n].base([v]))[0] for n, v in corners]
        x0, y0, x1, y1 = box
        T0 = homography(src, [(x0, y0), (x0, y1), (x1, y1), (x1, y0)])
    pts = [apply(T0, b) for b in base]
    # normalize to the unit square so the search grid means the same for every chart
    T0 = _affine_to_box(pts, (0.0, 0.0, 1.0, 1.0), T0)
    best_T = _affine_to_box([apply(T0, b) for b in base], box, T0)
    best = _score([apply(best_T, base[i]) for i in labelled])
    if not search:
        return best_T
    found, found_score = best_T, best
    if search not in ("full", "moduli"):
        raise MechanismError(f"layout search must be 'full', 'moduli' or False, got {search!r}")
    grid = np.linspace(-0.6, 0.6, 13)
    for p in grid:
        for q in grid if search == "full" else (0.0,):
            if p == 0.0 and q == 0.0:
                continue
            P = np.array([[1.0, 0, 0], [0, 1.0, 0], [p, q, 1.0]])
            T = P @ T0
            w = [b @ T[2] for b in base]
            if any(np.any(wi <= 0.25 * np.abs(wi).max()) for wi in w):
                continue  # keep well away from the line sent to infinity
            Tb = _affine_to_box([apply(T, b) for b in base], box, T)
            sc = _score([apply(Tb, base[i]) for i in labelled])
            if sc > found_score:
                found, found_score = Tb, sc
    if found_score > best + np.log(1.1):
        return found
    return best_T
