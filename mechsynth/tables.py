"""Tables of results: unit-labelled columns in display units, as CSV text or files and as dicts.

Every ``to_csv`` / ``to_dict`` of mechsynth's results (motions, force results, charts) builds its
columns with :func:`table`: each column is named ``"name [unit]"`` with the unit shown in the
display units (:mod:`mechsynth.display`; SI inside is unchanged), and names are never repeated.
"""

from __future__ import annotations

import csv
import io

import numpy as np

from . import display
from .errors import MechanismError
from .fileio import write_text

__all__ = ["table", "write_csv", "as_lists", "per_angle"]


def per_angle(values, phi) -> np.ndarray:
    """``values`` as one number per crank angle of ``phi`` (1-D); ValueError for a batch."""
    shape = np.shape(phi)
    a = np.asarray(values, dtype=float)
    if len(shape) != 1 or a.ndim > 1 or (a.ndim == 1 and a.shape != shape):
        raise MechanismError(
            f"a table holds one design over a 1-D set of crank angles; this result has shape "
            f"{a.shape} over angles {shape}: select one design first"
        )
    return np.broadcast_to(a, shape)


def table(columns) -> dict[str, np.ndarray]:
    """``[(name, si_unit, values), ...]`` -> ``{"name [unit]": values}`` in display units.

    ``values`` are 1-D (masked arrays keep their mask); a unit ``""`` gives the bare name.
    Raises ValueError on a repeated column name or columns of different lengths.
    """
    out: dict[str, np.ndarray] = {}
    size = None
    for name, unit, values in columns:
        v, shown = display.convert(values, unit) if unit else (values, "")
        if isinstance(v, np.ma.MaskedArray):
            arr = v
        else:
            arr = np.asarray(v)
            if arr.dtype.kind in "fiu":
                arr = arr.astype(float)
        if arr.ndim != 1:
            raise MechanismError(
                f"column {name!r} has shape {arr.shape}: tables hold one design per row set "
                "(select one design of a batch first)"
            )
        size = arr.size if size is None else size
        if arr.size != size:
            raise MechanismError(f"column {name!r} has {arr.size} rows, the others {size}")
        head = f"{name} [{shown}]" if shown else name
        if head in out:
            raise MechanismError(f"column {head!r} appears twice")
        out[head] = arr
    return out


def _cell(value, masked: bool) -> str:
    if masked:
        return ""
    if isinstance(value, (bool, np.bool_)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.10g}" if np.isfinite(value) else ""
    return str(value)


def write_csv(columns: dict[str, np.ndarray], path=None):
    """Write ``columns`` as CSV (one row per index; masked or non-finite cells empty). Returns
    the path, or the CSV text when ``path`` is None."""
    names = list(columns)
    data = [np.ma.asarray(columns[n]) for n in names]
    masks = [np.ma.getmaskarray(d) for d in data]
    rows = data[0].size if data else 0
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(names)
    for i in range(rows):
        w.writerow([_cell(d.data[i], m[i]) for d, m in zip(data, masks)])
    if path is None:
        return buf.getvalue()
    return write_text(path, buf.getvalue())


def as_lists(columns: dict[str, np.ndarray]) -> dict[str, list]:
    """``{name: list}`` with masked or non-finite entries as None (JSON-ready)."""
    out = {}
    for name, values in columns.items():
        v = np.ma.asarray(values)
        mask = np.ma.getmaskarray(v)
        items = []
        for x, m in zip(v.data.tolist(), mask):
            if m or (isinstance(x, float) and not np.isfinite(x)):
                items.append(None)
            else:
                items.append(x)
        out[name] = items
    return out
