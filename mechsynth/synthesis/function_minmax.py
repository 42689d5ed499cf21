"""The min-max stage of function generation: the worst true output error over the whole input
range, minimized by the certified :class:`~mechsynth.synthesis.Problem` machinery.

A function generator runs its input over part of a turn only, and the phases (where the input
and output ranges start) are design variables. :class:`FourBarGenerator` and
:class:`SliderCrankGenerator` express that as mechanisms of their own: the input is the rotation
``t`` from the start of the range (``t`` in ``[0, span]``, not a whole turn), the motion is the
four-bar's (slider-crank's) own at crank angle ``phi0 + t`` -- no second model --, and their
``input_range`` tells the certifier to look for true peaks over the range, ends included, and
nowhere else. The structural error is a :class:`~mechsynth.objectives.CycleMeasure` whose
smooth branches are ``+e`` and ``-e`` (its peak is ``max |e|``), so its minimum is certified
like any peak: grid angles are added where the solver's grid missed the true worst error.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace
from typing import Any, ClassVar

import numpy as np

from ..errors import UsageError
from ..kinematics import ops
from ..kinematics.four_bar import FourBar
from ..kinematics.mechanism import Mechanism
from ..kinematics.slider_crank import SliderCrank
from ..objectives.base import CycleMeasure
from ..objectives.kinematic import min_transmission_angle

__all__ = [
    "FourBarGenerator",
    "CrankFourBarGenerator",
    "SliderCrankGenerator",
    "minmax",
    "structural_error",
    "file_structural_error",
]


class _Ranged:
    """The input is the rotation ``t`` (rad) from the start of the range, over ``[0, span]``."""

    span: float

    @property
    def input_range(self) -> tuple[float, float]:
        s = float(self.span)
        return (min(0.0, s), max(0.0, s))

    @property
    def periodic(self) -> bool:
        return False

    @property
    def input_unit(self) -> str:
        """The input is a rotation (rad), though not periodic."""
        return "rad"

    def turn(self, n: int = 48):
        lo, hi = self.input_range
        return np.linspace(lo, hi, int(n))

    def as_dict(self) -> dict:
        """The design's fields as plain values; a problem file's target function is not one
        (it is the file's ``[function]`` table)."""
        out = super().as_dict()
        out.pop("target", None)
        return out


@dataclass(frozen=True)
class FourBarGenerator(_Ranged, Mechanism):
    """A four-bar as a function generator: crank angle ``phi0 + t``, ``t`` over
    ``[0, span]`` (rad); ``psi0`` is the rocker angle where the output range starts. The
    crank need not turn fully (:class:`CrankFourBarGenerator` requires it)."""

    crank: float
    coupler: float
    rocker: float
    ground: float
    phi0: float
    psi0: float
    span: float
    branch: str = "open"
    target: Any = field(default=None, compare=False, repr=False)

    parameters: ClassVar[tuple[str, ...]] = (
        "crank", "coupler", "rocker", "ground", "phi0", "psi0",
    )  # fmt: skip
    length_parameters: ClassVar[tuple[str, ...]] = ("crank", "coupler", "rocker", "ground")
    parameter_units: ClassVar[dict[str, str]] = {"phi0": "rad", "psi0": "rad"}
    default_output: ClassVar[str] = "B"
    full_turn: ClassVar[bool] = False

    def four_bar(self) -> FourBar:
        return FourBar(
            self.crank, self.coupler, self.rocker, self.ground, self.branch, self.full_turn
        )

    @classmethod
    def feasibility_constraints(cls, params, margin=1e-3):
        return FourBar.feasibility_constraints({**params, "full_turn": cls.full_turn}, margin)

    def motion(self, phi, speed=None, epsilon=0.0, **kwargs):
        m = self.four_bar().motion(ops.plus(self.phi0, phi), speed, epsilon, **kwargs)
        return replace(m, phi=phi)

    def output(self, motion):
        """The output's travel from the start of the range (rad): rocker angle - psi0."""
        return motion.links["rocker"].angle - self.psi0


@dataclass(frozen=True)
class CrankFourBarGenerator(FourBarGenerator):
    """:class:`FourBarGenerator` whose crank makes full turns (a crank-rocker or double-crank)."""

    full_turn: ClassVar[bool] = True


@dataclass(frozen=True)
class SliderCrankGenerator(_Ranged, Mechanism):
    """A slider-crank as a function generator: crank angle ``phi0 + t``, ``t`` over
    ``[0, span]`` (rad); ``s0`` (m) is the slider position where the output range starts."""

    crank: float
    rod: float
    offset: float
    phi0: float
    s0: float
    span: float
    target: Any = field(default=None, compare=False, repr=False)

    parameters: ClassVar[tuple[str, ...]] = ("crank", "rod", "offset", "phi0", "s0")
    length_parameters: ClassVar[tuple[str, ...]] = ("crank", "rod")
    parameter_units: ClassVar[dict[str, str]] = {"phi0": "rad"}
    default_output: ClassVar[str] = "slider"

    def slider_crank(self) -> SliderCrank:
        return SliderCrank(self.crank, self.rod, self.offset)

    @classmethod
    def feasibility_constraints(cls, params, margin=1e-3):
        return SliderCrank.feasibility_constraints(params, margin)

    def motion(self, phi, speed=None, epsilon=0.0, **kwargs):
        m = self.slider_crank().motion(ops.plus(self.phi0, phi), speed, epsilon, **kwargs)
        return replace(m, phi=phi)

    def output(self, motion):
        """The output's travel from the start of the range (m): slider position - s0."""
        return motion.slider.position - self.s0


def structural_error(target, angular: bool) -> CycleMeasure:
    """``max |e(t)|`` with ``e`` the generator's output travel minus ``target(t)`` (wrapped
    into (-pi, pi] for an angle), branches ``+e`` and ``-e``. ``target`` must take numpy
    arrays and CasADi symbols (the functions of :mod:`.function_expr` do)."""

    def e(mechanism, motion):
        t = motion.phi
        if ops.is_symbolic(t):
            with warnings.catch_warnings():  # numpy ufuncs on CasADi symbols (supported)
                warnings.simplefilter("ignore", FutureWarning)
                ideal = target(t)
        else:
            ideal = target(t)
        d = mechanism.output(motion) - ideal
        return ops.arctan2(ops.sin(d), ops.cos(d)) if angular else d

    return CycleMeasure(
        "structural_error",
        lambda mech, m: ops.fabs(e(mech, m)),
        "max",
        "rad" if angular else "m",
        branches=lambda mech, m: (e(mech, m), -e(mech, m)),
    )


def file_structural_error(angular: bool) -> CycleMeasure:
    """:func:`structural_error` against the generator's own ``target`` (``t -> ideal output
    travel``, set by the problem files of :mod:`.function_problem`): the measure a problem file
    names ``structural_error``."""

    def target_of(mechanism):
        target = getattr(mechanism, "target", None)
        if target is None:
            raise UsageError(
                f"structural_error measures a function generator with a target function "
                f"(mechanism = 'function-generator' in a problem file); {type(mechanism).__name__}"
                " has none"
            )
        return target

    def e(mechanism, motion):
        return structural_error(target_of(mechanism), angular).samples(mechanism, motion)

    def branches(mechanism, motion):
        return structural_error(target_of(mechanism), angular).branches(mechanism, motion)

    return CycleMeasure("structural_error", e, "max", "rad" if angular else "m", branches=branches)


def minmax(
    start,
    target,
    *,
    bounds: dict | None = None,
    min_transmission: float | None = None,
    angles: int = 33,
    starts: int = 1,
    seed: int | None = 0,
    progress: bool | None = False,
):
    """Minimize the certified worst structural error from the generator ``start``.

    Parameters
    ----------
    start : a :class:`FourBarGenerator` (or crank variant) or :class:`SliderCrankGenerator`:
        the start design, also tried first; its ground (crank) stays fixed (the scale).
    target : ``t -> ideal output travel`` (rad or m) over the input rotation ``t``.
    bounds : ``{name: (lo, hi)}`` overriding the default boxes (lengths within a factor 4 of
        the start's, phases within 60 deg, ``s0`` within the start's crank length).
    min_transmission : lower bound of the transmission angle over the range (rad), or None.
    angles : the solver's base grid over the range (the certifier adds more as needed).
    starts, seed, progress : of :meth:`Problem.solve` (the start design is tried first).

    Returns
    -------
    :class:`~mechsynth.synthesis.Result` of the problem (its ``design`` a generator).
    """
    from .problem import Problem

    cls = type(start)
    four_bar = isinstance(start, FourBarGenerator)
    names = ("crank", "coupler", "rocker") if four_bar else ("rod", "offset")
    box = {}
    for k in names:
        v = float(getattr(start, k))
        box[k] = (v / 4.0, v * 4.0) if k != "offset" else (v - 2 * start.crank, v + 2 * start.crank)
    phases = ("phi0", "psi0") if four_bar else ("phi0", "s0")
    for k in phases:
        v = float(getattr(start, k))
        w = np.pi / 3.0 if k != "s0" else float(start.crank)
        box[k] = (v - w, v + w)
    box.update(bounds or {})
    fixed = {"span": float(start.span)}
    if four_bar:
        fixed.update(ground=float(start.ground), branch=start.branch)
    else:
        fixed.update(crank=float(start.crank))
    lo, hi = start.input_range
    prob = Problem(cls, variables=box, fixed=fixed, angles=np.linspace(lo, hi, int(angles)))
    prob.minimize(structural_error(target, four_bar))
    if min_transmission is not None:
        prob.subject_to(min_transmission_angle() >= float(min_transmission))
    x0 = {k: float(getattr(start, k)) for k in box}
    return prob.solve(starts=starts, seed=seed, x0=x0, progress=progress)
