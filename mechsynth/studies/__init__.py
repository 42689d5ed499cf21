"""Reproducible studies of the source papers, each comparing with the published values.

A study is a module with a ``run(out=None, **options) -> StudyResult`` function, registered in
:data:`STUDIES` by name. ``mechsynth study run NAME --out DIR`` runs it from the command line.
"""

from __future__ import annotations

import importlib

from ..errors import MechanismError
from ..fileio import output_dir
from ..report import StudyResult

__all__ = ["StudyResult", "STUDIES", "get_study", "run_study"]

#: name -> (module, one-line description)
STUDIES: dict[str, tuple[str, str]] = {
    "extreme-velocity": (
        "mechsynth.studies.extreme_velocity",
        "Paper 004: extreme slider velocities of the slider-crank (Table 1, errata in lambda_s)",
    ),
    "dwell": (
        "mechsynth.studies.dwell",
        "Paper 003b: longest-dwell coupler-curve dwell linkage on a central slider-crank",
    ),
    "beam-pump": (
        "mechsynth.studies.beam_pump",
        "Paper 000: axial vs desaxial Mark II-type pumping units; synthesis and Pareto front",
    ),
    "nail-header": (
        "mechsynth.studies.nail_header",
        "Paper 003a: AB4115 nail-header reactions (Table 1) and the optimal slider mass",
    ),
    "impact": (
        "mechsynth.studies.impact",
        "Paper 001: six-link and five-link percussive machines, the blow, motor drive, forces",
    ),
    "spatial-pump": (
        "mechsynth.studies.spatial_pump",
        "Paper 002: spatial pumping-unit drive, redundant vs rational; pitman split tolerances",
    ),
}


def get_study(name: str):
    """The study module registered as ``name``."""
    if name not in STUDIES:
        known = ", ".join(sorted(STUDIES))
        raise MechanismError(f"unknown study {name!r}; known studies: {known}")
    return importlib.import_module(STUDIES[name][0])


def run_study(name: str, out=None, **options) -> StudyResult:
    """Run the study ``name``, writing figures and tables into ``out`` (a directory) if given."""
    out_dir = output_dir(out)
    return get_study(name).run(out=out_dir, **options)
