"""mechsynth: optimization-based mechanism synthesis.

Kinematic and force models of linkages, written once, serve numpy analysis (vectorized over crank
angles and designs), CasADi exact derivatives for IPOPT, and cvxpy convex subproblems.

>>> import mechsynth as ms
>>> sc = ms.SliderCrank(crank=0.07, rod=0.24, offset=0.0)
>>> m = sc.motion(ms.cycle(720), speed=ms.rpm(600))
"""

from . import display, kinematics, objectives, progress
from .display import display_units
from .errors import MechanismError, SolverError
from .kinematics import FourBar, Linkage, Motion, Param, SliderCrank
from .machines.dwell import DwellSliderCrank
from .machines.impact import crank_rocker, five_link, six_link
from .machines.nail_header import NailHeader
from .machines.pumping_unit import BeamPumpingUnit, SpatialPumpingUnit
from .synthesis import Problem, Result
from .units import cycle, deg, dms, inch, rpm, spm, to_deg, to_inch, to_rpm

__version__ = "0.1.0"

__all__ = [
    "display",
    "display_units",
    "progress",
    "kinematics",
    "objectives",
    "Problem",
    "Result",
    "MechanismError",
    "SolverError",
    "SliderCrank",
    "FourBar",
    "Linkage",
    "Param",
    "BeamPumpingUnit",
    "SpatialPumpingUnit",
    "NailHeader",
    "DwellSliderCrank",
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
