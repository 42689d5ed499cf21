"""The beam pumping unit, in one place.

* :mod:`.beam_unit` — :class:`BeamPumpingUnit` (API 11E geometry, conventional and Mark II),
  its exact motion (:class:`PumpMotion`), torque factor and drawing (paper 000).
* :mod:`.torque` — dynamometer cards, gearbox torque, counterbalance (LP and scan),
  permissible load.
* :mod:`.measures` — the torque-factor measure for synthesis problems.
* :mod:`.analysis` — ``mechsynth pump analyze``: one unit from a TOML file and a card.

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
from .measures import PUMPING_MEASURES, peak_torque_factor
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
]

register_mechanism("beam-pump", BeamPumpingUnit)
for _name, _factory in PUMPING_MEASURES.items():
    register_measure(_name, _factory)
