"""Measures that reduce a mechanism's cycle to a number: objectives and constraints.

The force measures load on first use of one of their names (they import the dynamics layer,
which a kinematic problem does not need).
"""

from __future__ import annotations

from ..lazy import lazy_names as _lazy_names
from .base import Combination, Constraint, CycleMeasure, Measure, ScalarMeasure, reduce_cycle
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

#: public name -> submodule that defines it (imported on first access)
_LAZY = {
    "peak_reaction": "forces",
    "peak_torque": "forces",
    "peak_driving_force": "forces",
    "rms_torque": "forces",
    "reaction_affine_map": "forces",
    "clearance": "clearances",
    "link_separation": "clearances",
}
__all__ += list(_LAZY)


__getattr__, __dir__ = _lazy_names(globals(), _LAZY)
