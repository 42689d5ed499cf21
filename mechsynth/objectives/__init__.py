"""Measures that reduce a mechanism's cycle to a number: objectives and constraints."""

from .base import Combination, Constraint, CycleMeasure, Measure, ScalarMeasure, reduce_cycle
from .forces import (
    peak_driving_force,
    peak_reaction,
    peak_torque,
    reaction_affine_map,
    rms_torque,
)
from .kinematic import (
    KINEMATIC_MEASURES,
    assembly_margin,
    grashof_margin,
    max_pressure_angle,
    min_transmission_angle,
    peak_acceleration,
    peak_angular_acceleration,
    peak_angular_velocity,
    peak_velocity,
    stroke,
    swing_angle,
    time_ratio,
)

__all__ = ["Measure", "CycleMeasure", "ScalarMeasure", "Combination", "Constraint", "reduce_cycle"]
__all__ += [
    "peak_velocity",
    "peak_acceleration",
    "max_pressure_angle",
    "min_transmission_angle",
    "stroke",
    "swing_angle",
    "time_ratio",
    "grashof_margin",
    "peak_angular_velocity",
    "peak_angular_acceleration",
    "assembly_margin",
    "KINEMATIC_MEASURES",
]
__all__ += [
    "peak_reaction",
    "peak_torque",
    "peak_driving_force",
    "rms_torque",
    "reaction_affine_map",
]
