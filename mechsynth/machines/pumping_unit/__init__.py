"""The beam pumping unit, in one place.

* :mod:`.beam_unit` — :class:`BeamPumpingUnit` (API 11E geometry, conventional and Mark II),
  its exact motion (:class:`PumpMotion`), torque factor and drawing (paper 000).
* :mod:`.torque` — dynamometer cards, gearbox torque, counterbalance (LP and scan),
  permissible load.
* :mod:`.measures` — the torque-factor measure for synthesis problems.
* :mod:`.analysis` — ``mechsynth pump analyze``: one unit from a TOML file and a card.
* :mod:`.spatial_unit`, :mod:`.spatial_forces`, :mod:`.spatial_design` — the spatial
  double-crank drive of paper 002 (:class:`SpatialPumpingUnit`): 3-D kinematics, kinetostatics
  with redundant constraints closed by the pitmans' elasticity, tolerances, counterbalance;
  :mod:`.spatial_drawing` — its 3-D animation (:func:`animate_drive`).
* :mod:`.paper002` — paper 002's printed equations as residuals, and their errata.
* :mod:`.rod_string` — a predicted dynamometer card from the wave equation of the rod string.

``ms.BeamPumpingUnit`` is the public name of the unit; ``mechanism = "beam-pump"`` names it in
problem files.
"""

from ...synthesis.problem_file import register_measure, register_mechanism
from .beam_unit import (
    ROTATIONS,
    UNIT_CLASSES,
    BeamPumpingUnit,
    PumpMotion,
    crank_speed,
    harmonic_approximation,
    paper_crank_and_pitman,
)
from .measures import PUMPING_MEASURES, peak_torque_factor, rod_clearance
from .rod_string import RodString, wave_equation_card
from .spatial_design import (
    CounterbalanceSizing,
    limit_contour,
    size_counterbalance,
    split_curve,
    split_map,
    tolerance,
    tolerance_design_chart,
)
from .spatial_drawing import animate_drive
from .spatial_forces import (
    SpatialForces,
    SpatialMasses,
    planar_torque,
    power_balance,
    spatial_forces,
)
from .spatial_unit import DEVIATIONS, SpatialPumpingUnit, SpatialPumpMotion
from .torque import (
    Counterbalance,
    DynamometerCard,
    TorqueCurve,
    net_torque,
    optimal_counterbalance,
    permissible_load,
    scan_counterbalance,
    torque_curve,
    torque_factor_table,
)

__all__ = [
    "BeamPumpingUnit",
    "PumpMotion",
    "UNIT_CLASSES",
    "ROTATIONS",
    "crank_speed",
    "harmonic_approximation",
    "paper_crank_and_pitman",
    "peak_torque_factor",
    "rod_clearance",
    "PUMPING_MEASURES",
    "DynamometerCard",
    "TorqueCurve",
    "Counterbalance",
    "net_torque",
    "torque_curve",
    "optimal_counterbalance",
    "scan_counterbalance",
    "permissible_load",
    "torque_factor_table",
    "SpatialPumpingUnit",
    "SpatialPumpMotion",
    "SpatialMasses",
    "SpatialForces",
    "DEVIATIONS",
    "spatial_forces",
    "planar_torque",
    "power_balance",
    "split_curve",
    "split_map",
    "limit_contour",
    "animate_drive",
    "tolerance",
    "tolerance_design_chart",
    "size_counterbalance",
    "CounterbalanceSizing",
    "RodString",
    "wave_equation_card",
]

register_mechanism("beam-pump", BeamPumpingUnit)
for _name, _factory in PUMPING_MEASURES.items():
    register_measure(_name, _factory)
