"""mechsynth: optimization-based mechanism synthesis.

Kinematic and force models of linkages, written once, serve numpy analysis (vectorized over crank
angles and designs), CasADi exact derivatives for IPOPT, and cvxpy convex subproblems.

>>> import mechsynth as ms
>>> sc = ms.SliderCrank(crank=0.07, rod=0.24, offset=0.0)
>>> m = sc.motion(ms.cycle(720), speed=ms.rpm(600))

``import mechsynth`` is light (numpy and the units): the layers load on first use of a name
(``ms.SliderCrank`` loads the kinematics), and the heavy libraries (scipy's integrators and
optimizers, cvxpy, CasADi, numba, matplotlib) only where a call needs them.
"""

from __future__ import annotations

import importlib

from .errors import MechanismError, SolverError, UnknownNameError
from .lazy import lazy_names as _lazy_names
from .units import cycle, deg, dms, inch, rpm, spm, to_deg, to_inch, to_rpm

__version__ = "0.1.0"

#: public name -> module that defines it (imported on first access)
_LAZY = {
    "display_units": "display",
    "FourBar": "kinematics",
    "Linkage": "kinematics",
    "Motion": "kinematics",
    "Param": "kinematics",
    "SliderCrank": "kinematics",
    "DwellSliderCrank": "machines.dwell",
    "NailHeader": "machines.nail_header",
    "BeamPumpingUnit": "machines.pumping_unit",
    "SpatialPumpingUnit": "machines.pumping_unit",
    "ImpactMachine": "machines.impact",
    "crank_rocker": "machines.impact",
    "five_link": "machines.impact",
    "six_link": "machines.impact",
    "Problem": "synthesis",
    "Result": "synthesis",
    "function_generation": "synthesis.function_generation",
    "burmester": "synthesis.motion_generation",
    "motion_generation": "synthesis.motion_generation",
    "path_generation": "synthesis.path_generation",
    "path_bound": "synthesis.path_bound",
    "nomogram": "nomograms",
}
_SUBPACKAGES = (
    "display",
    "progress",
    "kinematics",
    "dynamics",
    "objectives",
    "synthesis",
    "machines",
    "nomograms",
    "studies",
)

#: modules that register something with a lower layer when imported (the force model of a
#: Linkage, the machines' mechanisms and measures for problem and design files); loaded by
#: :func:`load_registrations` when a registry is asked for a name it does not hold.
_REGISTRARS = (
    "dynamics.linkage_forces",
    "synthesis.linkage_file",
    "synthesis.function_problem",
    "machines.pumping_unit",
    "machines.nail_header",
    "machines.dwell",
    "machines.impact",
)


def load_registrations() -> None:
    """Import the modules that fill the registries (idempotent; cheap after the first call)."""
    for name in _REGISTRARS:
        importlib.import_module(f"{__name__}.{name}")


__getattr__, __dir__ = _lazy_names(globals(), _LAZY, _SUBPACKAGES)


__all__ = [
    "display",
    "display_units",
    "progress",
    "kinematics",
    "objectives",
    "Problem",
    "Result",
    "function_generation",
    "burmester",
    "motion_generation",
    "path_generation",
    "path_bound",
    "nomogram",
    "MechanismError",
    "SolverError",
    "UnknownNameError",
    "SliderCrank",
    "FourBar",
    "Linkage",
    "Param",
    "BeamPumpingUnit",
    "SpatialPumpingUnit",
    "NailHeader",
    "DwellSliderCrank",
    "ImpactMachine",
    "crank_rocker",
    "six_link",
    "five_link",
    "Motion",
    "cycle",
    "deg",
    "dms",
    "inch",
    "rpm",
    "spm",
    "to_deg",
    "to_inch",
    "to_rpm",
]
