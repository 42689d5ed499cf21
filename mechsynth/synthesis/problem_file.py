"""Problem files: a synthesis problem in TOML, as read by ``mechsynth optimize problem.toml``.

Format
------
Top-level keys come first (TOML puts every key after a ``[table]`` header into that table)::

    mechanism = "slider-crank"          # a name in MECHANISMS
    minimize = "peak_acceleration(slider)"     # or maximize = "..."
    constraints = [
        "stroke(slider) == 0.1 m",
        "max_pressure_angle <= 30 deg",
    ]
    speed = "600 rpm"                   # crank speed; a number is rad/s; omit for analogs
    method = "ipopt"                    # "ipopt" (default), "slsqp" or "de"
    starts = 8                          # multi-start count (local methods)
    seed = 0
    angles = 64                         # base crank-angle grid

    [variables]                         # name = [lower, upper]; numbers are SI (m, rad)
    crank = [0.01, 0.2]
    rod = ["50 mm", "200 mm"]           # or strings with a unit
    offset = [-0.1, 0.1]

    [fixed]                             # other parameters
    # branch = "open"

A measure is ``name`` or ``name(arg, ..., key=value)`` with a name from :data:`MEASURES`
(``peak_velocity``, ``peak_acceleration``, ``max_pressure_angle``, ``min_transmission_angle``,
``stroke``, ``swing_angle``, ``time_ratio``, ``grashof_margin``, ``peak_angular_velocity``,
``peak_angular_acceleration``); arguments are output/link names or numbers with units
(``peak_velocity(C, direction=90 deg)``). A constraint is ``measure <op> number [unit]`` with
``<=``, ``>=`` or ``==``. Constraints may also be tables::

    [[constraints]]
    measure = "stroke"
    args = ["slider"]
    op = "=="
    value = 100
    unit = "mm"

Units: m, mm, cm, in; rad, deg; m/s, m/s^2, rad/s, rad/s^2; rpm (speed). Values are converted to
SI; a unit that is not listed is an error, and so is a unit of the wrong dimension: ``speed`` is
an angular velocity (a linear one for a slider-driven linkage), a bound has its parameter's unit,
a constraint's value its measure's (no stroke in degrees, no pressure angle in mm). A bare number
is SI. Every key has a type and a range (``starts`` a whole number 1..10,000, ``angles``
8..1,000,000, ``seed`` >= 0, ``method`` ipopt/slsqp/de); unknown keys are refused with the valid
ones listed.
"""

from __future__ import annotations

import re
from typing import Any

import numpy as np

from .. import load_registrations, validate
from ..errors import MechanismError
from ..fileio import read_toml
from ..kinematics import FourBar, SliderCrank
from ..objectives.base import Constraint, Measure
from ..objectives.kinematic import KINEMATIC_MEASURES
from .problem import Problem

__all__ = [
    "MECHANISMS",
    "MEASURES",
    "UNITS",
    "register_mechanism",
    "register_measure",
    "parse_measure",
    "parse_constraint",
    "parse_quantity",
    "load_problem",
    "ProblemSpec",
]

#: mechanism name in problem files -> class
MECHANISMS: dict[str, type] = {"slider-crank": SliderCrank, "four-bar": FourBar}

#: measure name in problem files -> factory returning a Measure
MEASURES: dict[str, Any] = dict(KINEMATIC_MEASURES)

#: unit -> factor to SI
UNITS: dict[str, float] = {
    "": 1.0,
    "m": 1.0,
    "mm": 1e-3,
    "cm": 1e-2,
    "in": 0.0254,
    "inch": 0.0254,
    "rad": 1.0,
    "deg": np.pi / 180.0,
    "m/s": 1.0,
    "m/s^2": 1.0,
    "m/s2": 1.0,
    "rad/s": 1.0,
    "rad/s^2": 1.0,
    "rad/s2": 1.0,
    "rpm": 2.0 * np.pi / 60.0,
    "spm": 2.0 * np.pi / 60.0,  # strokes per minute of a pumping unit: one crank turn each
    "1": 1.0,
}


#: unit -> the SI unit it converts to (its dimension); a bare number is SI of whatever is asked
UNIT_SI: dict[str, str] = {
    "": "",
    "m": "m",
    "mm": "m",
    "cm": "m",
    "in": "m",
    "inch": "m",
    "rad": "rad",
    "deg": "rad",
    "m/s": "m/s",
    "m/s^2": "m/s^2",
    "m/s2": "m/s^2",
    "rad/s": "rad/s",
    "rad/s^2": "rad/s^2",
    "rad/s2": "rad/s^2",
    "rpm": "rad/s",
    "spm": "rad/s",
    "1": "1",
}

_DIMENSION = {
    "m": "a length",
    "rad": "an angle",
    "m/s": "a velocity",
    "m/s^2": "an acceleration",
    "rad/s": "an angular velocity",
    "rad/s^2": "an angular acceleration",
    "1": "a pure number",
}


def _units_for(si: str) -> str:
    return ", ".join(u for u, v in UNIT_SI.items() if u and v == si) or "none"


def register_mechanism(name: str, cls) -> None:
    """Make ``cls`` available as ``mechanism = "name"`` in problem files. An object with
    ``from_problem_data(data, path)`` instead builds the mechanism from the file's own tables
    (named in its ``file_keys``), as ``"linkage"`` does."""
    MECHANISMS[name] = cls


def register_measure(name: str, factory) -> None:
    """Make ``factory(*args, **kwargs) -> Measure`` available by ``name`` in problem files."""
    MEASURES[name] = factory


_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def parse_quantity(text, what: str = "value", unit: str | None = None) -> float:
    """A number (SI) or a string ``"<number> <unit>"`` -> float in SI units.

    ``unit``: the SI unit the value must have (``"m"``, ``"rad"``, ``"rad/s"``, ``""`` for a
    pure number, None for any): a unit of another dimension (``speed = "600 m"``, a stroke in
    degrees) is an error naming the units that fit. Non-finite values are refused.
    """
    if isinstance(text, bool) or not isinstance(text, (int, float, str)):
        raise MechanismError(f"{what}: expected a number or '<number> <unit>', got {text!r}")
    if isinstance(text, (int, float)):
        v = validate.real(what, text)
        if unit == "rad":
            validate.radians_meant(what, v)
        return v
    m = re.fullmatch(rf"\s*({_NUMBER})\s*([A-Za-z/^0-9]*)\s*", text)
    if not m:
        raise MechanismError(f"{what}: expected '<number> [unit]', got {text!r}")
    given = m.group(2)
    if given not in UNITS:
        raise MechanismError(
            f"{what}: unknown unit {given!r} in {text!r}; known: {', '.join(u for u in UNITS if u)}"
        )
    si = UNIT_SI.get(given, "")
    if unit is not None and given and si != (unit or "1") and not (si == "1" and unit == ""):
        expected = _DIMENSION.get(unit or "1", unit)
        raise MechanismError(
            f"{what}: {text!r} is {_DIMENSION.get(si, si)}, expected {expected} "
            f"({unit or 'no unit'}; units: {_units_for(unit or '1')})"
        )
    v = validate.real(what, float(m.group(1)) * UNITS[given])
    if unit == "rad" and not given:
        validate.radians_meant(what, v)
    return v


def _parse_arg(token: str):
    token = token.strip().strip("'\"")
    if re.fullmatch(rf"{_NUMBER}(\s*[A-Za-z/^0-9]+)?", token):
        return parse_quantity(token, "argument")
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", token):
        raise MechanismError(f"bad measure argument {token!r}")
    return token


def parse_measure(text: str) -> Measure:
    """``"peak_velocity(C, direction=90 deg)"`` -> the Measure."""
    m = re.fullmatch(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*(?:\((.*)\))?\s*", text)
    if not m:
        raise MechanismError(f"cannot read the measure {text!r}: expected name or name(args)")
    name, argtext = m.group(1), m.group(2)
    if name not in MEASURES:
        load_registrations()  # the machines register their measures when imported
    if name not in MEASURES:
        raise MechanismError(
            f"unknown measure {name!r}; known measures: {', '.join(sorted(MEASURES))}"
        )
    args, kwargs = [], {}
    if argtext and argtext.strip():
        for part in argtext.split(","):
            key, sep, value = part.partition("=")
            if sep:
                kwargs[key.strip()] = _parse_arg(value)
            else:
                args.append(_parse_arg(part))
    try:
        return MEASURES[name](*args, **kwargs)
    except TypeError as exc:
        raise MechanismError(f"measure {text!r}: {exc}") from exc


def _expected_unit(measure) -> str | None:
    """The SI unit a bound of ``measure`` must have, None when it is not one of the checked
    dimensions (a bare number is then taken as SI)."""
    unit = getattr(measure, "unit", None)
    if unit == "":
        return ""
    return unit if unit in _DIMENSION else None


def parse_constraint(spec) -> Constraint:
    """A constraint from ``"measure <op> number [unit]"`` or a table (see the module notes).
    The bound's unit must fit the measure (no stroke in degrees, no angle in mm)."""
    if isinstance(spec, dict):
        known = {"measure", "args", "kwargs", "op", "value", "unit"}
        extra = set(spec) - known
        if extra:
            raise MechanismError(
                f"constraint table: unknown keys {sorted(extra)}; use {sorted(known)}"
            )
        try:
            name, op, value = spec["measure"], spec["op"], spec["value"]
        except KeyError as exc:
            raise MechanismError(f"constraint table needs measure, op and value: {spec!r}") from exc
        if isinstance(name, str) and name not in MEASURES:
            load_registrations()
        if not isinstance(name, str) or name not in MEASURES:
            raise MechanismError(f"unknown measure {name!r}; known: {', '.join(sorted(MEASURES))}")
        args, kwargs = spec.get("args", []), spec.get("kwargs", {})
        if not isinstance(args, list) or not isinstance(kwargs, dict):
            raise MechanismError(
                f"constraint {name}: args must be a list and kwargs a table, got {args!r}, "
                f"{kwargs!r}"
            )
        try:
            measure = MEASURES[name](*args, **kwargs)
        except TypeError as exc:
            raise MechanismError(f"constraint {name}: {exc}") from None
        unit = spec.get("unit", "")
        if not isinstance(unit, str) or unit not in UNITS:
            raise MechanismError(
                f"constraint {name}: unknown unit {unit!r}; known: "
                + ", ".join(u for u in UNITS if u)
            )
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise MechanismError(f"constraint {name}: value must be a number, got {value!r}")
        bound = parse_quantity(
            f"{float(value)!r} {unit}".strip(), f"constraint {name}", _expected_unit(measure)
        )
    else:
        if not isinstance(spec, str):
            raise MechanismError(
                f"a constraint is a string 'measure <= value' or a table, got {spec!r}"
            )
        m = re.fullmatch(r"(.*?)\s*(<=|>=|==)\s*(.+)", spec)
        if not m:
            raise MechanismError(
                f"cannot read the constraint {spec!r}: expected 'measure <= value'"
            )
        measure, op = parse_measure(m.group(1)), m.group(2)
        bound = parse_quantity(m.group(3), f"constraint {spec!r}", _expected_unit(measure))
    if op not in ("<=", ">=", "=="):
        raise MechanismError(f"constraint operator must be <=, >= or ==, got {op!r}")
    return Constraint(measure, op, bound)


class ProblemSpec:
    """A problem read from a file, with its solver settings.

    Attributes
    ----------
    problem : the :class:`Problem`.
    solve_options : keyword arguments for :meth:`Problem.solve` (method, starts, seed).
    source : the file path.
    """

    def __init__(self, problem: Problem, solve_options: dict, source=None):
        self.problem, self.solve_options, self.source = problem, solve_options, source

    def solve(self, **overrides):
        return self.problem.solve(**{**self.solve_options, **overrides})


#: fixed parameters that are words, not quantities
_TEXT_FIXED = ("branch", "unit_class", "rotation")

_TOP_KEYS = {
    "mechanism",
    "minimize",
    "maximize",
    "constraints",
    "speed",
    "method",
    "starts",
    "seed",
    "angles",
    "variables",
    "fixed",
    "title",
}


def _table(data, key, where) -> dict:
    value = data.get(key) or {}
    if not isinstance(value, dict):
        raise MechanismError(
            f"{where}{key} must be a table ([{key}] with name = value lines), got {value!r}"
        )
    return value


def _unit_of(mechanism, name) -> str | None:
    """SI unit of a mechanism's parameter for checking file units (None: not known)."""
    fn = getattr(mechanism, "unit_of", None) or getattr(mechanism, "parameter_unit", None)
    if fn is None:
        return None
    try:
        unit = fn(name)
    except (KeyError, ValueError, TypeError):
        return None
    return unit if unit in _DIMENSION else None


def load_problem(source) -> ProblemSpec:
    """Read a problem file (a path, or a dict already parsed from TOML).

    The schema (see the module notes): every top-level key has a type and a range (``starts``
    a whole number 1..10,000, ``angles`` 8..1,000,000, ``seed`` >= 0, ``method`` one of
    ipopt/slsqp/de, ``speed`` an angular velocity, ``[variables]`` and ``[fixed]`` tables whose
    values have the parameter's dimension); unknown keys are refused with the valid ones
    listed. Every failure is a one-line MechanismError naming the file and the key.
    """
    data, path = read_toml(source, "problem file")
    where = f"{path}: " if path else ""
    name = data.get("mechanism")
    if isinstance(name, str) and name not in MECHANISMS:
        load_registrations()  # the machines register their mechanisms when imported
    # a mechanism read from the file's own tables (a linkage) declares them
    kind = MECHANISMS.get(name) if isinstance(name, str) else None
    valid = _TOP_KEYS | set(getattr(kind, "file_keys", ()))
    unknown = set(data) - valid
    if unknown:
        raise MechanismError(
            f"{where}unknown keys {sorted(unknown)}; a problem file has {sorted(valid)} (a key "
            "written after a [table] header belongs to that table: put top-level keys first)"
        )
    if not isinstance(name, str) or name not in MECHANISMS:
        raise MechanismError(
            f"{where}mechanism must be one of {', '.join(sorted(MECHANISMS))}, got {name!r}"
        )
    for key in ("minimize", "maximize", "title"):
        if key in data and not isinstance(data[key], str):
            raise MechanismError(f"{where}{key} must be a string, got {data[key]!r}")
    try:
        return _build(data, name, where, path)
    except MechanismError as exc:
        text = str(exc)
        raise MechanismError(
            text if not where or text.startswith(where) else where + text
        ) from None


def _build(data, name, where, path) -> ProblemSpec:
    mechanism = MECHANISMS[name]
    if hasattr(mechanism, "from_problem_data"):
        mechanism = mechanism.from_problem_data(data, path)
    variables = {}
    for k, bounds in _table(data, "variables", where).items():
        if not isinstance(bounds, list) or len(bounds) != 2:
            raise MechanismError(f"variable {k!r}: expected [lower, upper], got {bounds!r}")
        unit = _unit_of(mechanism, k)
        variables[k] = tuple(parse_quantity(b, f"variable {k!r}", unit) for b in bounds)
    fixed = {}
    for k, v in _table(data, "fixed", where).items():
        text = isinstance(v, bool) or k in _TEXT_FIXED
        fixed[k] = v if text else parse_quantity(v, f"fixed {k!r}", _unit_of(mechanism, k))
    speed = data.get("speed")
    try:  # a linkage driven by a slider moves at a linear speed
        linear = getattr(mechanism, "input_unit", "rad") == "m"
    except (MechanismError, AttributeError):
        linear = False
    speed = None if speed is None else parse_quantity(speed, "speed", "m/s" if linear else "rad/s")
    angles = data.get("angles", 64)
    angles = validate.integer("angles", angles, 8, validate.MAX_ANGLES)
    prob = Problem(mechanism, variables, fixed, speed=speed, angles=angles)
    if ("minimize" in data) == ("maximize" in data):
        raise MechanismError("give exactly one of minimize = '...' or maximize = '...'")
    if "minimize" in data:
        prob.minimize(parse_measure(data["minimize"]))
    else:
        prob.maximize(parse_measure(data["maximize"]))
    constraints = data.get("constraints", [])
    if not isinstance(constraints, list):
        raise MechanismError("constraints must be a list of strings or [[constraints]] tables")
    prob.subject_to(*[parse_constraint(c) for c in constraints])
    opts = {}
    if "method" in data:
        opts["method"] = validate.option("method", data["method"], ("ipopt", "slsqp", "de"))
    if "starts" in data:
        opts["starts"] = validate.integer("starts", data["starts"], 1, validate.MAX_STARTS)
    if "seed" in data:
        opts["seed"] = validate.integer("seed", data["seed"], 0)
    return ProblemSpec(prob, opts, path)
