"""Percussive machines of variable structure (paper 001), in one place.

* :mod:`.model` -- the base crank-rocker whose rocker carries the striker
  (:func:`crank_rocker`), the six-link (:func:`six_link`: extra rod K-N and the striker N on a
  straight guide at the angle rho) and the five-link (:func:`five_link`: an involute or
  circular-arc profile on the rocker pushing the striker), all :class:`~mechsynth.Linkage`
  values; the representative machine's numbers; the special position.
* :mod:`.paper001` -- the paper's formulas (1)-(12), (20)-(21) as printed, checked against the
  exact model, and the errata.
* :mod:`.impact` -- the blow (:class:`Tool`, Newton's law, the crank's speed jump, joint
  impulses); :mod:`.drive` -- :class:`ImpactMachine` driven by an induction motor (steady state,
  start-up, flywheel); :mod:`.forces`; :mod:`.design` (the representative machine and its
  sources); :mod:`.synthesis` (certified blow-energy problem, Pareto front).

``ms.six_link``, ``ms.five_link``, ``ms.crank_rocker``, ``ms.ImpactMachine`` are the public
names; the study is
``mechsynth study run impact``.
"""

from .drive import ImpactMachine
from .impact import Tool
from .model import REPRESENTATIVE, crank_rocker, five_link, six_link, special_angles

__all__ = [
    "REPRESENTATIVE",
    "ImpactMachine",
    "Tool",
    "crank_rocker",
    "six_link",
    "five_link",
    "special_angles",
]
