"""Optimization problems and solvers; sweeps and design charts (nomograms)."""

from .problem import Problem
from .result import STATUSES, Certification, ConstraintValue, Result

__all__ = ["Problem", "Result", "ConstraintValue", "Certification", "STATUSES"]

from .charts import Chart, sweep  # noqa: E402
from .convex import AffineMap, ConvexResult, affine_map, minimax_affine, minimax_cycle  # noqa: E402

__all__ += ["Chart", "sweep", "AffineMap", "ConvexResult", "affine_map", "minimax_affine"]
__all__ += ["minimax_cycle"]

from .pareto import ParetoFront, pareto_front  # noqa: E402

__all__ += ["ParetoFront", "pareto_front"]

from . import linkage_file  # noqa: E402,F401  (registers mechanism = "linkage" for problem files)
from .linkage_file import load_linkage  # noqa: E402

__all__ += ["load_linkage"]
