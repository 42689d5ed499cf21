"""Forces: mass properties, loads, kinetostatics, reduced dynamics and motors."""

from .equation_of_motion import (
    CycleResult,
    energy_method_flywheel,
    energy_stepping,
    quartic_coefficients,
    run_up,
    size_flywheel,
    steady_cycle,
)
from .inertia import LinkInertia, com_track, kinetic_energy, reduced_inertia
from .kinetostatics import (
    Contact,
    DrivingForce,
    ForceModel,
    ForceResult,
    Prismatic,
    Revolute,
    four_bar_model,
    kinetostatics,
    slider_crank_model,
)
from .linkage_forces import linkage_force_model
from .loads import Gravity, PointForce, TabulatedLoad, Torque, TorsionSpring, upsetting_force
from .motor import InductionMotor, LinearDrive
from .reduced import ReducedModel, gravity_moment, point_force_moment, reduced_model

__all__ = ["LinkInertia", "com_track", "kinetic_energy", "reduced_inertia"]
__all__ += ["InductionMotor", "LinearDrive", "ReducedModel", "gravity_moment"]
__all__ += ["point_force_moment", "reduced_model", "CycleResult", "energy_method_flywheel"]
__all__ += ["energy_stepping", "quartic_coefficients", "size_flywheel", "steady_cycle", "run_up"]
__all__ += ["ForceModel", "ForceResult", "Prismatic", "Revolute", "Contact", "four_bar_model"]
__all__ += ["linkage_force_model", "DrivingForce"]
__all__ += ["kinetostatics", "slider_crank_model", "Gravity", "PointForce", "TabulatedLoad"]
__all__ += ["Torque", "TorsionSpring", "upsetting_force"]
