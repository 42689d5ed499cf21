"""Geometry and motion: building blocks (crank, dyads) and the named mechanisms built from them."""

from . import four_bar_formulas, ops
from .blocks import coupler_point, crank, dyad_rpr, dyad_rrp, dyad_rrr, link_angle
from .compiled import FourBarBatch, SliderCrankBatch, four_bar_batch, slider_crank_batch
from .dwell import DwellSliderCrank
from .four_bar import FourBar, Grashof, grashof
from .mechanism import Mechanism
from .slider_crank import SliderCrank
from .tracks import Jet, LinkTrack, Motion, PointJet, PointTrack, SliderTrack

__all__ = [
    "ops",
    "crank",
    "dyad_rrr",
    "dyad_rrp",
    "dyad_rpr",
    "coupler_point",
    "link_angle",
    "Mechanism",
    "SliderCrank",
    "DwellSliderCrank",
    "FourBar",
    "Grashof",
    "grashof",
    "Jet",
    "PointJet",
    "PointTrack",
    "LinkTrack",
    "SliderTrack",
    "Motion",
    "four_bar_formulas",
    "four_bar_batch",
    "slider_crank_batch",
    "FourBarBatch",
    "SliderCrankBatch",
]
