"""Reference problems: natural synthesis problems with known optima, posed as a user poses them.

Each entry builds its :class:`~mechsynth.synthesis.Problem` (bounds as posed, wide ones
included) and states the optimum with its source, so that tests can require the default solve
to reach it:

>>> from mechsynth.synthesis.reference import REFERENCE_PROBLEMS
>>> ref = REFERENCE_PROBLEMS["four-bar-max-swing"]
>>> round(ref.value_deg, 6)
99.511197

``four-bar-max-swing``
    A four-bar with ground 1 and crank, coupler and rocker in 0.1..3: maximize the rocker's
    swing angle with a minimum transmission angle of 40 deg. Most of this box is not a
    crank-rocker (double-cranks, rocker-cranks, linkages that do not turn), so most start points
    are invalid: the solver must discard them, not die on them. The optimum has the crank at its
    lower bound ``a = 0.1`` and the transmission angle at its limit at both dead centres
    (``mu = 40 deg`` at crank angle 0, ``180 - 40 deg`` at 180 deg), which gives closed forms:
    ``b^2 + c^2 = a^2 + d^2`` and ``b c = a d / cos(40 deg)`` (law of cosines at the two
    positions), so ``b, c = (sqrt(s + 2p) +- sqrt(s - 2p)) / 2`` with ``s = a^2 + d^2``,
    ``p = a d / cos 40 deg``; the swing is the difference of the rocker angles at the folded
    and extended dead centres: 99.5111971 deg (b = 0.9964116414, c = 0.1310108428).
    (The issue that posed it quoted 99.5111983 deg, a differential-evolution value 1.2e-6 deg
    above the closed form's, within its constraint tolerance.)

``slider-crank-min-acceleration``
    Offset slider-crank, crank 0.01..0.2, rod 0.05..0.2, offset -0.1..0.1 m at 600 rpm:
    minimize the peak slider acceleration at a stroke of 0.1 m. Several local optima (one per
    guide side, one with the rod at its bound); the least is 231.387 m/s^2 by a brute-force scan
    over (rod, offset) with the crank from the stroke equation (``tests/
    test_solver_regressions.py``, to 1e-4).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

__all__ = ["ReferenceProblem", "REFERENCE_PROBLEMS", "four_bar_max_swing_optimum"]


@dataclass(frozen=True)
class ReferenceProblem:
    """A problem with its known optimum.

    Attributes
    ----------
    name : catalogue key.
    build : ``() -> Problem``, the problem as posed.
    value : the optimal objective value (SI units: rad, m/s^2).
    design : the optimal variable values ``{name: value}`` (SI), where known.
    rtol : relative tolerance to which the source knows the value.
    source : where the value comes from.
    """

    name: str
    build: Callable
    value: float
    design: dict = field(default_factory=dict)
    rtol: float = 1e-7
    source: str = ""

    @property
    def value_deg(self) -> float:
        """The value in degrees (angle objectives)."""
        return math.degrees(self.value)


def four_bar_max_swing_optimum(crank=0.1, ground=1.0, mu_min_deg=40.0):
    """Closed-form optimum of ``four-bar-max-swing``: ``(swing in rad, coupler, rocker)`` with
    the transmission angle at ``mu_min_deg`` at both dead centres (see the module docstring)."""
    a, d = crank, ground
    cm = math.cos(math.radians(mu_min_deg))
    s, p = a * a + d * d, a * d / cm
    b = (math.sqrt(s + 2 * p) + math.sqrt(s - 2 * p)) / 2
    c = (math.sqrt(s + 2 * p) - math.sqrt(s - 2 * p)) / 2
    rocker_extended = math.acos((c * c + d * d - (b + a) ** 2) / (2 * c * d))
    rocker_folded = math.acos((c * c + d * d - (b - a) ** 2) / (2 * c * d))
    return rocker_extended - rocker_folded, b, c


def _four_bar_max_swing():
    from .. import objectives as ob
    from ..kinematics import FourBar
    from .problem import Problem

    prob = Problem(
        FourBar,
        variables={"crank": (0.1, 3.0), "coupler": (0.1, 3.0), "rocker": (0.1, 3.0)},
        fixed={"ground": 1.0},
    )
    prob.maximize(ob.swing_angle())
    prob.subject_to(ob.min_transmission_angle() >= math.radians(40.0))
    return prob


def _slider_crank_min_acceleration():
    from .. import objectives as ob
    from ..kinematics import SliderCrank
    from ..units import rpm
    from .problem import Problem

    prob = Problem(
        SliderCrank,
        variables={"crank": (0.01, 0.2), "rod": (0.05, 0.2), "offset": (-0.1, 0.1)},
        speed=rpm(600),
    )
    prob.minimize(ob.peak_acceleration("slider"))
    prob.subject_to(ob.stroke("slider") == 0.1)
    return prob


_swing, _b, _c = four_bar_max_swing_optimum()

REFERENCE_PROBLEMS: dict[str, ReferenceProblem] = {
    "four-bar-max-swing": ReferenceProblem(
        "four-bar-max-swing",
        _four_bar_max_swing,
        _swing,
        {"crank": 0.1, "coupler": _b, "rocker": _c},
        rtol=1e-12,
        source="closed form (transmission angle at its limit at both dead centres)",
    ),
    "slider-crank-min-acceleration": ReferenceProblem(
        "slider-crank-min-acceleration",
        _slider_crank_min_acceleration,
        231.387,
        rtol=1e-4,
        source="brute-force scan over (rod, offset), tests/test_solver_regressions.py",
    ),
}
