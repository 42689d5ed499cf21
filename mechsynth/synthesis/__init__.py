"""Optimization problems and solvers; sweeps and design charts (nomograms).

The charts, the convex minimax and the Pareto fronts load on first use of one of their names
(their imports -- file formats, json, tempfile -- are not needed by a solve).
"""

from __future__ import annotations

from ..lazy import lazy_names as _lazy_names
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


__getattr__, __dir__ = _lazy_names(globals(), _LAZY)
