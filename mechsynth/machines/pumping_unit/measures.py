"""Measures of beam pumping units (:class:`~mechsynth.machines.pumping_unit.BeamPumpingUnit`).

The polished rod is the unit's main slider (``"slider"`` / ``"polished_rod"``), so the kinematic
measures apply directly (``peak_acceleration("slider")``, ``stroke("slider")``,
``max_pressure_angle()``, ``time_ratio()``). This module adds the torque factor and the
polished rod's clearance from the crank circle (a unit whose crank sweeps through its own rod
cannot be built: bound it from below in every synthesis).
"""

from __future__ import annotations

from ...errors import MechanismError
from ...objectives.base import CycleMeasure

__all__ = ["peak_torque_factor", "rod_clearance", "PUMPING_MEASURES"]


def _tf(mechanism, motion):
    tf = motion.extra.get("torque_factor") if motion.extra else None
    if tf is None:
        raise MechanismError(
            f"{type(mechanism).__name__} has no torque factor (not a pumping unit)"
        )
    return tf


def peak_torque_factor() -> CycleMeasure:
    """Largest |torque factor| over the cycle (m/rad; crank torque per unit polished-rod load),
    whatever the crank speed of the motion. Smooth branches ``(TF, -TF)``."""
    from ...kinematics import ops

    return CycleMeasure(
        "peak_torque_factor",
        lambda mech, motion: ops.fabs(_tf(mech, motion)),
        "max",
        "m/rad",
        branches=lambda mech, motion: (_tf(mech, motion), -_tf(mech, motion)),
    )


def rod_clearance() -> CycleMeasure:
    """Smallest distance (m) between the polished rod's vertical line and the circle of the
    crank's radius about the crankshaft over the cycle (negative: the crank sweeps through the
    rod). Bound it by the room the counterweights and the rod clamp need, e.g.
    ``rod_clearance() >= 0.3``."""
    import numpy as np

    from ...objectives.clearances import clearance

    return clearance("PR", circle=("O1", "crank"), direction=np.pi / 2, name="rod_clearance")


#: name -> factory, for problem files
PUMPING_MEASURES = {"peak_torque_factor": peak_torque_factor, "rod_clearance": rod_clearance}
