"""Target points of path generation: from an array or a CSV file, checked."""

from __future__ import annotations

import numpy as np

from ..errors import MechanismError

__all__ = ["read_targets"]


def read_targets(source, closed: bool = True) -> np.ndarray:
    """Target points as an ``(N, 2)`` array (m) from an array-like of ``(x, y)`` rows or a CSV
    file (two numeric columns ``x, y``; a header row of names is skipped).

    Raises :class:`MechanismError` for fewer than 3 points, non-finite values, a wrong number
    of columns, consecutive duplicates (and, for a closed path, the last equal to the first).
    """
    from pathlib import Path

    if isinstance(source, (str, Path)):
        pts = _read_csv(source)
    else:
        try:
            pts = np.asarray(source, dtype=float)
        except (TypeError, ValueError):
            raise MechanismError(
                f"targets must be (x, y) rows of numbers, got {source!r}"
            ) from None
        if pts.ndim != 2 or pts.shape[1] != 2:
            raise MechanismError(
                f"targets must be an (N, 2) array of (x, y) rows, got shape {pts.shape}"
            )
    bad = ~np.isfinite(pts)
    if bad.any():
        i = int(np.argwhere(bad)[0, 0])
        raise MechanismError(f"target {i + 1} is not finite: {tuple(pts[i])}")
    if len(pts) < 3:
        raise MechanismError(f"path generation needs at least 3 targets, got {len(pts)}")
    step = np.hypot(*np.diff(pts, axis=0).T)
    scale = max(float(np.ptp(pts, axis=0).max()), 1e-300)
    same = np.flatnonzero(step <= 1e-12 * scale)
    if same.size:
        i = int(same[0])
        raise MechanismError(
            f"targets {i + 1} and {i + 2} are the same point {tuple(pts[i])}: consecutive "
            "targets must differ"
        )
    if closed and np.hypot(*(pts[-1] - pts[0])) <= 1e-12 * scale:
        raise MechanismError(
            f"the last target repeats the first {tuple(pts[0])}: a closed path joins them "
            "itself (drop the last row)"
        )
    return pts


def _read_csv(path) -> np.ndarray:
    from ..fileio import read_text

    text, p = read_text(path, "targets file")
    rows, header = [], False
    for k, line in enumerate(text.splitlines(), start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        cells = [c.strip() for c in line.replace(";", ",").split(",")]
        if len(cells) != 2:
            raise MechanismError(
                f"{p}: line {k}: expected 2 columns x, y, got {len(cells)}: {line!r}"
            )
        try:
            rows.append((float(cells[0]), float(cells[1])))
        except ValueError:
            if rows or header:  # only the first line may be a header
                raise MechanismError(f"{p}: line {k}: not two numbers: {line!r}") from None
            header = True
    if not rows:
        raise MechanismError(f"{p}: no target rows (x, y)")
    return np.asarray(rows, dtype=float)
