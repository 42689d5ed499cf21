"""Path generation's trade-off: error against the smallest transmission angle.

An epsilon-constraint sweep: :func:`~mechsynth.synthesis.path_generation.path_generation` with
``min_transmission`` at each of the given angles; the non-dominated points (the library's
Pareto filter, :func:`mechsynth.synthesis.pareto._dominance`) form the front. A published
design drawn against it shows what it traded away.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["TransmissionFront", "transmission_front"]


@dataclass(frozen=True)
class TransmissionFront:
    """``asked`` (rad): the sweep's smallest transmission angles; ``mu`` (rad): the designs'
    achieved smallest angle; ``error`` (m^2); ``nondominated`` mask; ``results``: the
    :class:`~mechsynth.synthesis.path_generation.PathResult` of each point."""

    asked: np.ndarray
    mu: np.ndarray
    error: np.ndarray
    nondominated: np.ndarray
    results: tuple

    def error_at(self, mu_min: float) -> float:
        """Smallest error on the front with a transmission angle of at least ``mu_min``."""
        ok = self.nondominated & (self.mu >= mu_min - 1e-9)
        return float(self.error[ok].min()) if ok.any() else float("nan")

    def figure(self, published=None, title="error versus smallest transmission angle"):
        from .path_figures import pareto_figure

        pts = [(m, e) for m, e, k in zip(self.mu, self.error, self.nondominated) if k]
        return pareto_figure(sorted(pts), published=published, title=title)


def transmission_front(targets, angles, **options) -> TransmissionFront:
    """The error-versus-transmission-angle front of path generation on ``targets``: one solve
    per smallest transmission angle in ``angles`` (rad); ``options`` go to
    :func:`path_generation`."""
    from .pareto import _dominance
    from .path_generation import path_generation

    asked = np.asarray(angles, dtype=float).ravel()
    results = tuple(path_generation(targets, min_transmission=a, **options) for a in asked)
    ok = np.array([r.best is not None for r in results])
    mu = np.array([r.best.transmission[0] if r.best else np.nan for r in results])
    err = np.array([r.best.error if r.best else np.nan for r in results])
    nd = _dominance(err, mu, ok, ("min", "max"))
    return TransmissionFront(asked, mu, err, nd, results)
