"""Geometry and motion: building blocks (crank, dyads) and the named mechanisms built from them."""

from . import four_bar_formulas, ops
from .blocks import (
    cam_contact,
    coupler_point,
    crank,
    dyad_rpr,
    dyad_rpr_on,
    dyad_rrp,
    dyad_rrp_on,
    dyad_rrr,
    link_angle,
)
from .compiled import FourBarBatch, SliderCrankBatch, four_bar_batch, slider_crank_batch
from .curves import Circle, Curve, Involute, ParametricCurve
from .four_bar import FourBar, Grashof, grashof
from .linkage import Linkage, Param, Topology
from .mechanism import Mechanism
from .slider_crank import SliderCrank
from .tracks import Jet, LinkTrack, Motion, PointJet, PointTrack, SliderTrack

__all__ = [
    "ops",
    "crank",
    "dyad_rrr",
    "dyad_rrp",
    "dyad_rpr",
    "dyad_rrp_on",
    "dyad_rpr_on",
    "cam_contact",
    "Curve",
    "Circle",
    "Involute",
    "ParametricCurve",
    "Linkage",
    "Param",
    "Topology",
    "coupler_point",
    "link_angle",
    "Mechanism",
    "SliderCrank",
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
