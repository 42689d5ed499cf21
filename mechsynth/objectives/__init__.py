"""Measures that reduce a mechanism's cycle to a number: objectives and constraints."""

from .base import Combination, Constraint, CycleMeasure, Measure, ScalarMeasure, reduce_cycle

__all__ = ["Measure", "CycleMeasure", "ScalarMeasure", "Combination", "Constraint", "reduce_cycle"]
