"""Nomograms (alignment charts): the engine and the built-in charts of the library's models.

The engine knows nothing of mechanisms: scales as value -> position maps
(:mod:`~mechsynth.nomograms.scales`), the forms of the determinant theory
(:mod:`~mechsynth.nomograms.forms`), fitted charts for relations with no exact form
(:mod:`~mechsynth.nomograms.fitting`), the projective layout on paper
(:mod:`~mechsynth.nomograms.layout`), ticks by value density
(:mod:`~mechsynth.nomograms.ticks`), reading and the accuracy report
(:mod:`~mechsynth.nomograms.nomogram`), and the renderer (:mod:`~mechsynth.nomograms.render`,
the only module that imports matplotlib). The built-in charts of the library's models live in
:mod:`~mechsynth.nomograms.library`; ``ms.nomogram(f, u=..., v=...)`` makes one of a user's own
relation (:mod:`~mechsynth.nomograms.user`). See ``docs/nomograms.md``.
"""

from .forms import Var, determinant, parallel, proportional, z_chart
from .layout import PAPERS, Paper
from .nomogram import Accuracy, Nomogram, PlacedScale
from .scales import Grid, Scale
from .user import Product, Sum, nomogram

__all__ = [
    "nomogram",
    "Sum",
    "Product",
    "Nomogram",
    "PlacedScale",
    "Accuracy",
    "Scale",
    "Grid",
    "Var",
    "Paper",
    "PAPERS",
    "parallel",
    "z_chart",
    "proportional",
    "determinant",
    "fitted",
    "fitted_chain",
    "build",
    "NOMOGRAMS",
]


def __getattr__(name):  # the fitted forms and the library load scipy and the models on use
    if name in ("fitted", "fitted_chain"):
        from . import fitting

        return getattr(fitting, name)
    if name in ("build", "NOMOGRAMS"):
        from . import library

        return getattr(library, name)
    raise AttributeError(f"module 'mechsynth.nomograms' has no attribute {name!r}")
