"""Optimization problems and solvers; sweeps and design charts (nomograms)."""

from .problem import Problem
from .result import STATUSES, Certification, ConstraintValue, Result

__all__ = ["Problem", "Result", "ConstraintValue", "Certification", "STATUSES"]
