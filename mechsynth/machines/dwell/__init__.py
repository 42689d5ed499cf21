"""Dwell linkages on the coupler curve of a central slider-crank (paper 003, second part), in one
place.

* :mod:`.linkage` -- :class:`DwellSliderCrank`: the bent-rod slider-crank and its translating
  slotted output link.
* :mod:`.metrics` -- the dwell metrics: exact minimax line fits of coupler-curve sections,
  compiled window sweeps parallel over designs (numeric only; imported on use: it compiles).
* :mod:`.charts` -- the dwell charts of ``mechsynth chart dwell``.

The synthesis study is ``mechsynth study run dwell`` (:mod:`mechsynth.studies.dwell`).
"""

from ...synthesis.design_file import register_design
from ...synthesis.problem_file import register_mechanism
from .linkage import DwellSliderCrank

__all__ = ["DwellSliderCrank"]

register_design("dwell", DwellSliderCrank)
# problem files over its kinematic measures (the dwell metrics are numeric: see the study)
register_mechanism("dwell", DwellSliderCrank)
