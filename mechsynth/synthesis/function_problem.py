"""Problem files for function generators: ``mechanism = "function-generator"``.

A function generator's min-max problem needs what a crank-driven linkage cannot say in a
problem file: its input runs over part of a turn, from a phase that is itself a variable, and
its objective compares the output with a function. The file says it in a ``[function]`` table;
the mechanism is the generator of :mod:`.function_minmax` (input: the rotation ``t`` from the
start of the range, over ``[0, input_range]``), so ``angles = N`` grids the range, not a turn,
and the certifier looks for the worst error over the range, ends included::

    mechanism = "function-generator"
    minimize = "structural_error"          # the worst |output - ideal| over the range
    constraints = ["min_transmission_angle >= 30 deg"]
    angles = 33

    [function]
    y = "log10(x)"                         # an expression in x (read by function_expr)
    x = [1, 10]
    input_range = "60 deg"
    output_range = "90 deg"                # a length ("500 mm") for a slider-crank
    mechanism = "four-bar"                 # "crank four-bar" (full turns), "slider-crank"
    branch = "open"                        # four-bars

    [variables]                            # the generator's parameters: crank, coupler,
    crank = [0.05, 0.8]                    # rocker, ground, phi0, psi0 (a slider-crank:
    phi0 = ["90 deg", "150 deg"]           # crank, rod, offset, phi0, s0)

    [fixed]
    ground = 1.0

``structural_error`` is in rad (``structural_error(slider)`` in m for a slider-crank). The
parameters are those of :class:`~.function_minmax.FourBarGenerator` and
:class:`~.function_minmax.SliderCrankGenerator`; each must be a variable or fixed.
:meth:`FunctionGeneration.problem_toml <.function_generation.FunctionGeneration>` writes such a
file around a design (``mechsynth synthesize function --out`` writes ``problem.toml``).
"""

from __future__ import annotations

import numpy as np

from ..errors import MechanismError
from ..objectives.base import CycleMeasure
from .function_minmax import (
    CrankFourBarGenerator,
    FourBarGenerator,
    SliderCrankGenerator,
    file_structural_error,
)
from .problem_file import parse_quantity, register_measure, register_mechanism

__all__ = ["GeneratorFamily", "function_target", "problem_data", "FUNCTION_KEYS"]

#: the keys of a problem file's ``[function]`` table
FUNCTION_KEYS = ("y", "x", "input_range", "output_range", "mechanism", "branch")
_CLASSES = {
    "four-bar": FourBarGenerator,
    "crank four-bar": CrankFourBarGenerator,
    "slider-crank": SliderCrankGenerator,
}


def function_target(y, x, input_range: float, output_range: float):
    """``t -> ideal output travel`` of ``y = f(x)`` (an expression text or a callable taking
    numpy arrays and CasADi symbols): ``x`` on ``[x0, x1]`` over ``t`` in ``[0,
    input_range]``, ``f(x0) .. f(x1)`` onto ``0 .. output_range``."""
    from .function_generation import _function

    f, _ = _function(y)
    x0, x1 = (float(v) for v in x)
    with np.errstate(all="ignore"):  # a function not finite at an end is named below
        y0, y1 = (float(np.asarray(f(np.array([v])), float)[0]) for v in (x0, x1))
    if not (np.isfinite(y0) and np.isfinite(y1)) or y0 == y1:
        raise MechanismError(
            f"function: f(x0) = {y0:.6g} and f(x1) = {y1:.6g} must be finite and differ"
        )
    scale = output_range / (y1 - y0)

    def target(t):
        return (f(x0 + t / input_range * (x1 - x0)) - y0) * scale

    return target


class GeneratorFamily:
    """A function generator as a design family of a :class:`~mechsynth.synthesis.Problem`
    (like a :class:`~mechsynth.kinematics.Linkage`): called with parameter values it gives the
    generator, with the family's range, branch and target; ``input_range`` is ``[0,
    input_range]`` (not periodic), so a grid of ``N`` angles covers the range."""

    def __init__(self, cls, values: dict, span: float, target, branch: str = "open"):
        self.cls = cls
        self.values = dict(values)
        self.span = float(span)
        self.target = target
        self.branch = branch
        self.__name__ = cls.__name__

    # -- what Problem reads of a design family
    @property
    def parameters(self) -> dict:
        return dict(self.values)

    @property
    def parameter_kinds(self) -> dict:
        kinds = {k: "length" for k in self.cls.length_parameters}
        kinds.update(phi0="angle", psi0="angle", s0="offset", offset="offset")
        return {k: kinds[k] for k in self.values}

    @property
    def length_parameters(self) -> tuple[str, ...]:
        return self.cls.length_parameters

    @property
    def default_output(self) -> str:
        return self.cls.default_output

    @property
    def input_range(self) -> tuple[float, float]:
        return (min(0.0, self.span), max(0.0, self.span))

    @property
    def periodic(self) -> bool:
        return False

    def unit_of(self, name: str) -> str:
        return self.cls.unit_of(name)

    def __call__(self, **values):
        unknown = set(values) - set(self.values)
        if unknown:
            raise MechanismError(
                f"{self.__name__} has no parameter {sorted(unknown)[0]!r}; its parameters: "
                f"{', '.join(self.values)}"
            )
        extra = {"branch": self.branch} if self.cls is not SliderCrankGenerator else {}
        return self.cls(**{**self.values, **values}, span=self.span, target=self.target, **extra)

    def feasibility_constraints(self, params, margin=1e-3):
        return self.cls.feasibility_constraints({**self.values, **params}, margin)


class _FunctionGeneratorFile:
    """``mechanism = "function-generator"``: the generator read from the file's tables."""

    __name__ = "FunctionGenerator"
    file_keys = ("function",)

    @staticmethod
    def from_problem_data(data: dict, path=None) -> GeneratorFamily:
        return family_from_data(data)


def family_from_data(data: dict) -> GeneratorFamily:
    """The :class:`GeneratorFamily` of a problem file's tables (``[function]``, with every
    parameter in ``[variables]`` or ``[fixed]``; see the module notes)."""
    fn = data.get("function")
    if not isinstance(fn, dict):
        raise MechanismError(
            "mechanism = 'function-generator' needs a [function] table (y, x, input_range, "
            "output_range, mechanism, branch)"
        )
    unknown = set(fn) - set(FUNCTION_KEYS)
    missing = {"y", "x", "input_range", "output_range"} - set(fn)
    if unknown or missing:
        what = f"unknown keys {sorted(unknown)}" if unknown else f"missing {sorted(missing)}"
        raise MechanismError(f"[function]: {what}; its keys: {', '.join(FUNCTION_KEYS)}")
    kind = fn.get("mechanism", "four-bar")
    if not isinstance(kind, str) or kind not in _CLASSES:
        raise MechanismError(
            f"[function] mechanism must be one of {', '.join(_CLASSES)}, got {kind!r}"
        )
    cls = _CLASSES[kind]
    x = fn["x"]
    if not isinstance(x, list) or len(x) != 2:
        raise MechanismError(f"[function] x: expected [x0, x1], got {x!r}")
    x0, x1 = (parse_quantity(v, "[function] x", "") for v in x)
    if not x0 < x1:
        raise MechanismError(f"[function] x: need x0 < x1, got {x0:g} and {x1:g}")
    span = parse_quantity(fn["input_range"], "[function] input_range", "rad")
    out_unit = "m" if cls is SliderCrankGenerator else "rad"
    out = parse_quantity(fn["output_range"], "[function] output_range", out_unit)
    for name, v in (("input_range", span), ("output_range", out)):
        if v == 0.0 or (name == "input_range" or out_unit == "rad") and abs(v) >= 2 * np.pi:
            raise MechanismError(
                f"[function] {name}: {v:g} {out_unit if name != 'input_range' else 'rad'}: "
                "need a non-zero range of less than a turn"
            )
    branch = fn.get("branch", "open")
    if not isinstance(branch, str) or branch not in ("open", "crossed"):
        raise MechanismError(f"[function] branch must be 'open' or 'crossed', got {branch!r}")
    values = {}
    variables, fixed = data.get("variables", {}), data.get("fixed", {})
    for name in cls.parameters:
        unit = cls.unit_of(name)
        if name in fixed:
            values[name] = parse_quantity(fixed[name], f"fixed {name!r}", unit)
        elif name in variables and isinstance(variables[name], list) and variables[name]:
            lo = parse_quantity(variables[name][0], f"variable {name!r}", unit)
            hi = parse_quantity(variables[name][-1], f"variable {name!r}", unit)
            values[name] = 0.5 * (lo + hi)  # a default only: the variable sets it
        else:
            raise MechanismError(
                f"{cls.__name__}: give {name} as a variable or fixed (its parameters: "
                f"{', '.join(cls.parameters)})"
            )
    return GeneratorFamily(cls, values, span, function_target(fn["y"], (x0, x1), span, out),
                           branch)  # fmt: skip


def _structural_error(output=None) -> CycleMeasure:
    """The problem files' ``structural_error``: rad, or m with ``(slider)``."""
    if output not in (None, "rocker", "slider"):
        raise MechanismError(
            f"structural_error takes no argument, 'rocker' or 'slider' (m), got {output!r}"
        )
    return file_structural_error(angular=output != "slider")


def problem_data(fg, *, bounds: dict | None = None, min_transmission=None, angles: int = 33):
    """The tables of a problem file (``mechanism = "function-generator"``) for the min-max
    stage from the design of ``fg`` (a :class:`~.function_generation.FunctionGeneration` from
    a function): the boxes of :func:`~.function_minmax.minmax` around it (or ``bounds``), its
    ground (crank) fixed, and ``min_transmission`` (rad) as a constraint when given."""
    if fg.function is None or fg.domain is None:
        raise MechanismError(
            "a problem file needs the function: this design is from precision pairs"
        )
    g = fg.generator()
    four_bar = isinstance(g, FourBarGenerator)
    names = ("crank", "coupler", "rocker") if four_bar else ("rod", "offset")
    box = {}
    for k in names:
        v = float(getattr(g, k))
        box[k] = [v / 4.0, v * 4.0] if k != "offset" else [v - 2 * g.crank, v + 2 * g.crank]
    for k in ("phi0", "psi0") if four_bar else ("phi0", "s0"):
        v = float(getattr(g, k))
        w = np.pi / 3.0 if k != "s0" else float(g.crank)
        box[k] = [v - w, v + w]
    for k, (lo, hi) in (bounds or {}).items():
        box[k] = [float(lo), float(hi)]
    fixed = {"ground": float(g.ground)} if four_bar else {"crank": float(g.crank)}
    kind = ("crank four-bar" if g.full_turn else "four-bar") if four_bar else "slider-crank"
    function = {
        "y": fg.function,
        "x": [float(v) for v in fg.domain],
        "input_range": float(fg.spans[0]),
        "output_range": float(fg.spans[1]),
        "mechanism": kind,
    }
    if four_bar:
        function["branch"] = g.branch
    data = {
        "mechanism": "function-generator",
        "minimize": "structural_error" if four_bar else "structural_error(slider)",
        "angles": int(angles),
        "function": function,
        "variables": box,
        "fixed": fixed,
    }
    if min_transmission is not None:
        data["constraints"] = [f"min_transmission_angle >= {float(min_transmission)!r} rad"]
    return data


register_mechanism("function-generator", _FunctionGeneratorFile())
register_measure("structural_error", _structural_error)
