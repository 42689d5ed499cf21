"""Optimization problems and solvers; sweeps and design charts (nomograms).

The charts, the convex minimax and the Pareto fronts load on first use of one of their names
(their imports -- file formats, json, tempfile -- are not needed by a solve).
"""

from __future__ import annotations

import importlib

from .problem import Problem
from .result import STATUSES, Certification, ConstraintValue, Result

__all__ = ["Problem", "Result", "ConstraintValue", "Certification", "STATUSES"]

#: public name -> submodule that defines it (imported on first access)
_LAZY = {
    "Chart": "charts",
    "sweep": "charts",
    "AffineMap": "convex",
    "ConvexResult": "convex",
    "affine_map": "convex",
    "minimax_affine": "convex",
    "minimax_cycle": "convex",
    "ParetoFront": "pareto",
    "pareto_front": "pareto",
    "load_linkage": "linkage_file",
}
__all__ += list(_LAZY)


def __getattr__(name: str):
    if name not in _LAZY:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{_LAZY[name]}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
