"""What the explorer page shows, without a browser: mechanisms, their dimensions, the state of
the page as a design and a problem, validation messages, curves, sweeps and exports.

The page (:mod:`mechsynth.explore.app`) only turns widgets into a :class:`State` and this
module's answers into glyphs; everything here is plain Python and numpy, tested without a
browser.

>>> from mechsynth.explore.model import State
>>> st = State.default("slider-crank")
>>> float(st.design().stroke)               # SI inside: 2 x crank for a centric slider-crank
0.14
>>> text = st.problem_toml()                # the page's problem, readable by `mechsynth optimize`
>>> 'mechanism = "slider-crank"' in text
True
"""

from __future__ import annotations

import copy
import math
import re
import tomllib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..display import PRESETS, DisplayUnits
from ..errors import MechanismError
from ..tomlwrite import to_toml  # noqa: F401  (the explorer's exports write with it)

__all__ = [
    "Dim",
    "Kind",
    "KINDS",
    "State",
    "Check",
    "kind_names",
    "load_file",
    "to_toml",
    "curves",
    "checks",
    "sweep_chart",
    "solve_data",
    "solve_worker",
    "parse_number",
    "inputs",
]


# ------------------------------------------------------------------------------ dimensions
@dataclass(frozen=True)
class Dim:
    """One dimension on the page: ``name``, SI ``unit`` (``"m"``, ``"rad"`` or ``""``), the
    slider's range ``lo``..``hi`` (SI), what it is (``label``), ``positive`` when it must be
    greater than zero, and ``varies``: False when it cannot be an optimization variable."""

    name: str
    unit: str
    lo: float
    hi: float
    label: str = ""
    positive: bool = False
    varies: bool = True


@dataclass
class Kind:
    """A mechanism the page offers.

    Attributes
    ----------
    key, title : name (as in problem files where it has one) and what the menu shows.
    dims : the dimensions shown as sliders, in order.
    values : their start values (SI).
    build : ``fn(values) -> design``.
    to_params : ``fn(values) -> {parameter: value}`` of the mechanism in problem files (the
        API dimensions of a pumping unit map to its parameters); ``to_param(dim, value,
        values) -> (parameter, value)`` maps one dimension (for bounds) and ``from_param``
        back; identity when None.
    mechanism : the name in problem files, None when it has none.
    text : parameters that are words (``unit_class``, ``branch``) written to ``[fixed]``.
    speed : crank speed (rad/s) or None; ``objective``, ``sense``, ``constraints`` and
        ``vary`` (``{dim: (lo, hi)}``) the problem the page starts with.
    curve : ``("slider", name)``, ``("link", name)`` or ``("point", name)``: the output whose
        position, velocity and acceleration the curves show.
    trace : points whose paths are drawn.
    file_data : a linkage's tables (``[linkage]``, ``[ground]``, ``[[group]]``).
    """

    key: str
    title: str
    dims: tuple[Dim, ...]
    values: dict[str, float]
    build: Callable[[dict], Any]
    mechanism: str | None
    speed: float | None = None
    objective: str = ""
    sense: str = "minimize"
    constraints: tuple[str, ...] = ()
    vary: dict[str, tuple[float, float]] = field(default_factory=dict)
    curve: tuple[str, str] = ("slider", "")
    trace: tuple[str, ...] = ()
    to_params: Callable[[dict], dict] | None = None
    to_param: Callable[[str, float, dict], tuple[str, float]] | None = None
    from_param: Callable[[str, float, dict], tuple[str, float]] | None = None
    text: dict[str, str] = field(default_factory=dict)
    file_data: dict | None = None

    def dim(self, name: str) -> Dim:
        for d in self.dims:
            if d.name == name:
                return d
        raise MechanismError(
            f"{self.title} has no dimension {name!r}; its dimensions: "
            + ", ".join(d.name for d in self.dims)
        )


def _mm(x):
    return x * 1e-3


def _deg(x):
    return math.radians(x)


def _slider_crank() -> Kind:
    from ..kinematics import SliderCrank

    return Kind(
        key="slider-crank",
        title="Slider-crank",
        dims=(
            Dim("crank", "m", _mm(5), _mm(300), "crank OA", positive=True),
            Dim("rod", "m", _mm(20), _mm(1000), "connecting rod AB", positive=True),
            Dim("offset", "m", _mm(-200), _mm(200), "offset of the slider's line"),
        ),
        values={"crank": 0.07, "rod": 0.24, "offset": 0.0},
        build=lambda v: SliderCrank(**v),
        mechanism="slider-crank",
        speed=2 * math.pi * 600 / 60,
        objective="peak_acceleration(slider)",
        constraints=("stroke(slider) == 100 mm", "max_pressure_angle <= 30 deg"),
        vary={
            "crank": (_mm(10), _mm(200)),
            "rod": (_mm(50), _mm(200)),
            "offset": (_mm(-100), _mm(100)),
        },
        curve=("slider", "B"),
        trace=("B",),
    )


def _four_bar() -> Kind:
    from ..kinematics import FourBar

    return Kind(
        key="four-bar",
        title="Four-bar",
        dims=(
            Dim("crank", "m", 0.01, 1.0, "crank O1A", positive=True),
            Dim("coupler", "m", 0.05, 3.0, "coupler AB", positive=True),
            Dim("rocker", "m", 0.05, 3.0, "rocker O2B", positive=True),
            Dim("ground", "m", 0.05, 3.0, "ground O1O2", positive=True),
        ),
        values={"crank": 0.2, "coupler": 1.0, "rocker": 0.8, "ground": 1.0},
        build=lambda v: FourBar(**v),
        mechanism="four-bar",
        objective="min_transmission_angle",
        sense="maximize",
        constraints=("swing_angle(rocker) == 40 deg", "time_ratio == 1"),
        vary={"crank": (0.05, 0.5), "coupler": (0.3, 2.0), "rocker": (0.3, 1.5)},
        curve=("link", "rocker"),
        trace=("B",),
    )


# API 11E geometry of a conventional C-320D-256-120 unit (examples/pump_unit_c320.toml), in m
_INCH = 0.0254
_C320 = {"A": 155.00, "C": 111.06, "I": 111.02, "P": 132.01, "R": 42.01, "H": 231.97, "G": 95.98}


_PUMP = {
    "A": "front_arm",
    "C": "rear_arm",
    "I": "pivot_x",
    "P": "pitman",
    "R": "crank",
    "H": "pivot_y",
}


def _pump_sign(text) -> float:
    return (
        -1.0 if str(text.get("unit_class", "conventional")).replace("_", "-") == "mark-ii" else 1.0
    )


def _pump_kind_maps(text: dict):
    """The maps between the API dimensions and the unit's parameters (``pivot_x = +-I`` by
    the unit class, ``pivot_y = H - G``)."""

    def to_params(v):
        return dict(_pump_param(d, v[d], v, text) for d in _PUMP)

    def to_param(d, x, v):
        return _pump_param(d, x, v, text)

    def from_param(p, x, v):
        name = {b: a for a, b in _PUMP.items()}.get(p, p)
        if name == "I":
            return name, _pump_sign(text) * x
        if name == "H":
            return name, x + v["G"]
        return name, x

    return to_params, to_param, from_param


def _pump_param(d, x, v, text):
    if d == "I":
        return "pivot_x", _pump_sign(text) * x
    if d == "H":
        return "pivot_y", x - v["G"]
    return _PUMP.get(d, d), x


def _beam_pump() -> Kind:
    from ..machines.pumping_unit import BeamPumpingUnit

    text = {"unit_class": "conventional", "rotation": "cw"}

    def build(v):
        return BeamPumpingUnit.from_api(
            **v, unit_class=text["unit_class"], rotation=text["rotation"], units="m"
        )

    to_params, to_param, from_param = _pump_kind_maps(text)

    dims = (
        Dim("A", "m", 1.0, 8.0, "centre bearing to polished rod", positive=True),
        Dim("C", "m", 1.0, 8.0, "centre bearing to equalizer bearing", positive=True),
        Dim("I", "m", 0.5, 8.0, "centre bearing to crankshaft, horizontal", positive=True),
        Dim("P", "m", 0.5, 8.0, "pitman", positive=True),
        Dim("R", "m", 0.2, 2.5, "crank radius", positive=True),
        Dim("H", "m", 2.0, 12.0, "centre bearing height"),
        Dim("G", "m", 0.5, 6.0, "crankshaft height", varies=False),
    )
    return Kind(
        key="beam-pump",
        title="Beam pumping unit (API 11E dimensions)",
        dims=dims,
        values={k: v * _INCH for k, v in _C320.items()},
        build=build,
        mechanism="beam-pump",
        speed=2 * math.pi * 8 / 60,
        objective="peak_acceleration(slider)",
        constraints=("stroke(slider) == 3.048 m", "max_pressure_angle <= 30 deg"),
        vary={"R": (0.8, 1.3), "P": (2.8, 4.5)},
        curve=("slider", "polished_rod"),
        trace=("PR",),
        to_params=to_params,
        to_param=to_param,
        from_param=from_param,
        text=text,
    )


def _dwell() -> Kind:
    from ..machines.dwell import DwellSliderCrank

    return Kind(
        key="dwell",
        title="Dwell linkage (paper 003)",
        dims=(
            Dim("r", "", 0.1, 0.9, "crank / rod", positive=True),
            Dim("k", "", 0.5, 2.5, "coupler point distance / rod", positive=True),
            Dim("gamma", "rad", _deg(-90), _deg(90), "angle of the coupler point"),
            Dim("xi", "rad", _deg(-90), _deg(90), "angle of the slot of link 5"),
            Dim("rod", "m", 0.1, 3.0, "rod length", positive=True, varies=False),
        ),
        values={"r": 0.4998, "k": 1.2109, "gamma": _deg(-20.39), "xi": _deg(17.75), "rod": 1.0},
        build=lambda v: DwellSliderCrank(**v),
        mechanism="dwell",
        objective="max_pressure_angle",
        constraints=("stroke(slider) >= 0.3",),
        vary={"r": (0.3, 0.6), "gamma": (_deg(-40), _deg(0))},
        curve=("slider", "5"),
        trace=("C",),
    )


#: the six-link of paper 001 (the striker N on a guide at 57 deg), inline as a linkage file
SIX_LINK = {
    "linkage": {"name": "six-link", "output": "N"},
    "ground": {"O": [0, 0], "D": ["120 mm", "50 mm"]},
    "group": [
        {"type": "crank", "point": "A", "about": "O", "length": "30 mm"},
        {"type": "rrr", "point": "B", "first": ["A", "120 mm"], "second": ["D", "80 mm"]},
        {"type": "attach", "point": "K", "on": ["D", "B"], "along": "-50 mm"},
        {
            "type": "rrp",
            "point": "N",
            "rod": ["K", "100 mm"],
            "guide": {"through": ["120 mm", 0], "angle": "57 deg"},
        },
    ],
}


def linkage_kind(tables: Mapping, problem: Mapping | None = None, title: str | None = None):
    """The page's entry for a linkage given by its tables (``[linkage]``, ``[ground]``,
    ``[[group]]``), with the problem of a problem file when given."""
    from ..synthesis.linkage_file import linkage_from_data

    tables = copy.deepcopy({k: tables[k] for k in ("linkage", "ground", "group") if k in tables})
    lk = linkage_from_data(tables)
    values = {k: float(v) for k, v in lk.parameters.items()}
    kinds = lk.parameter_kinds
    roles = lk.parameter_roles
    scale = max([abs(v) for k, v in values.items() if kinds[k] == "length"] or [1.0])
    dims = []
    for k, v in values.items():
        kind = kinds[k]
        if kind == "angle":
            dims.append(Dim(k, "rad", v - math.pi, v + math.pi, roles[k]))
        elif kind in ("length", "radius"):
            dims.append(
                Dim(
                    k,
                    "m",
                    min(v, scale) * 0.1,
                    max(3.0 * v, 1.5 * scale),
                    roles[k],
                    positive=kind == "length",
                )
            )
        else:
            dims.append(Dim(k, "m", v - 2.0 * scale, v + 2.0 * scale, roles[k]))
    out = lk.default_output
    curve = ("slider", out) if out in lk.sliders else ("point", out)
    kind = Kind(
        key="linkage",
        title=title or f"Linkage {lk.name}",
        dims=tuple(dims),
        values=values,
        build=lambda v, lk=lk: lk(**v),
        mechanism="linkage",
        objective=f"peak_acceleration({out})",
        constraints=(),
        vary={},
        curve=curve,
        trace=(out,),
        file_data=tables,
    )
    if problem:
        _apply_problem(kind, problem)
    return kind


def _apply_problem(kind: Kind, data: Mapping) -> None:
    """Objective, constraints, speed and variables of a problem file onto ``kind``."""
    from ..synthesis.problem_file import parse_quantity

    if "minimize" in data:
        kind.objective, kind.sense = str(data["minimize"]), "minimize"
    elif "maximize" in data:
        kind.objective, kind.sense = str(data["maximize"]), "maximize"
    if "constraints" in data:
        cons = data["constraints"]
        if not all(isinstance(c, str) for c in cons):
            raise MechanismError(
                "the explorer reads constraints written as strings ('measure <= value')"
            )
        kind.constraints = tuple(cons)
    if data.get("speed") is not None:
        kind.speed = parse_quantity(data["speed"], "speed")
    names = {d.name for d in kind.dims}
    fixed = data.get("fixed") or {}
    for k, v in fixed.items():
        if isinstance(v, bool) or k in ("branch", "unit_class", "rotation"):
            kind.text[k] = v
    unmap = kind.from_param or (lambda p, x, v: (p, x))
    numbers = {k: parse_quantity(v, f"fixed {k!r}") for k, v in fixed.items() if k not in kind.text}
    for k, x in sorted(numbers.items(), key=lambda kv: kv[0] == "pivot_y"):
        name, x = unmap(k, x, kind.values)
        if name in names:
            kind.values[name] = x
    vary = {}
    for k, bounds in (data.get("variables") or {}).items():
        lo, hi = (parse_quantity(b, f"variable {k!r}") for b in bounds)
        name, lo = unmap(k, lo, kind.values)
        _, hi = unmap(k, hi, kind.values)
        if name not in names:
            raise MechanismError(f"variable {k!r} is not a dimension of {kind.title}")
        lo, hi = sorted((lo, hi))
        vary[name] = (lo, hi)
        kind.values[name] = 0.5 * (lo + hi)  # start in the middle of the box
    if vary:
        kind.vary = vary
    for key in ("method", "starts", "seed"):
        if key in data:
            kind.text.setdefault("_" + key, data[key])


_FACTORIES = {
    "slider-crank": _slider_crank,
    "four-bar": _four_bar,
    "beam-pump": _beam_pump,
    "dwell": _dwell,
    "linkage": lambda: _six_link(),
    "impact": lambda: _impact(),
}


def impact_tables() -> dict:
    """The impact machine of paper 001 (``ms.six_link()``: the representative breaker, the
    striker N on a guide at 90 deg) as linkage tables, so that the page can write its problem
    file."""
    from ..machines.impact import six_link

    p = six_link().parameters
    return {
        "linkage": {"name": "impact six-link", "output": "N"},
        "ground": {"O": [p["O_x"], p["O_y"]], "D": [p["D_x"], p["D_y"]]},
        "group": [
            {"type": "crank", "point": "A", "about": "O", "length": p["OA"]},
            {"type": "rrr", "point": "B", "first": ["A", p["AB"]], "second": ["D", p["DB"]]},
            {
                "type": "attach",
                "point": "K",
                "on": ["D", "B"],
                "along": p["K_along"],
                "left": p["K_left"],
            },
            {
                "type": "rrp",
                "point": "N",
                "rod": ["K", p["KN"]],
                "branch": -1,
                "guide": {
                    "through": "O",
                    "angle": p["N_guide_angle"],
                    "offset": p["N_guide_offset"],
                },
            },
        ],
    }


def _impact() -> Kind:
    from ..machines.impact.model import REPRESENTATIVE

    kind = linkage_kind(impact_tables(), title="Impact machine: six-link of paper 001")
    kind.key = "impact"
    kind.speed = 2 * math.pi * REPRESENTATIVE["speed_rpm"] / 60
    kind.objective = "peak_acceleration(N)"
    kind.constraints = ("stroke(N) >= 38 mm", "max_pressure_angle(N) <= 30 deg")
    kind.vary = {"KN": (0.05, 0.1), "N_guide_offset": (-0.16, -0.12)}
    kind.trace = ("N", "K")
    return kind


def _six_link() -> Kind:
    kind = linkage_kind(SIX_LINK, title="Linkage: six-link of paper 001")
    # the problem of examples/optimize_six_link.toml
    kind.speed = 2 * math.pi * 1500 / 60
    kind.constraints = (
        "stroke(N) == 60 mm",
        "min_transmission_angle(B) >= 45 deg",
        "max_pressure_angle(N) <= 30 deg",
    )
    kind.vary = {
        "OA": (0.01, 0.05),
        "DB": (0.05, 0.12),
        "K_along": (-0.1, -0.02),
        "KN": (0.06, 0.2),
    }
    return kind


def kind_names() -> dict[str, str]:
    """``{key: title}`` of the mechanisms the page offers."""
    return {
        "slider-crank": "Slider-crank",
        "four-bar": "Four-bar",
        "beam-pump": "Beam pumping unit (API 11E dimensions)",
        "dwell": "Dwell linkage (paper 003)",
        "linkage": "Linkage (six-link of paper 001, or a TOML file)",
        "impact": "Impact machine (paper 001, ms.six_link)",
    }


class _Kinds(dict):
    """``KINDS[key]`` builds a fresh :class:`Kind` (its start values may be changed)."""

    def __missing__(self, key):
        if key not in _FACTORIES:
            raise MechanismError(
                f"unknown mechanism {key!r}; the explorer offers " + ", ".join(_FACTORIES)
            )
        return _FACTORIES[key]()

    def __contains__(self, key):
        return key in _FACTORIES


KINDS = _Kinds()


# ------------------------------------------------------------------------------ state
@dataclass(frozen=True)
class Check:
    """A measure of the page's problem at the current design: ``name``, ``value`` (SI),
    ``unit``; for a constraint ``op`` and ``bound`` and ``ok``; ``objective`` for the
    objective."""

    name: str
    value: float
    unit: str
    op: str = ""
    bound: float = float("nan")
    ok: bool = True
    objective: bool = False


@dataclass
class State:
    """The page: a mechanism, its dimensions (SI), the problem, the display units.

    ``vary`` maps the dimensions that are optimization variables to their bounds (SI).
    """

    kind: Kind
    values: dict[str, float]
    vary: dict[str, tuple[float, float]]
    objective: str
    sense: str
    constraints: list[str]
    speed: float | None
    units: str = "si"
    method: str = "ipopt"
    starts: int = 4
    seed: int = 0

    @classmethod
    def of(cls, kind: Kind, units: str = "si") -> State:
        return cls(
            kind=kind,
            values=dict(kind.values),
            vary=dict(kind.vary),
            objective=kind.objective,
            sense=kind.sense,
            constraints=list(kind.constraints),
            speed=kind.speed,
            units=units,
            method=str(kind.text.get("_method", "ipopt")),
            starts=int(kind.text.get("_starts", 4)),
            seed=int(kind.text.get("_seed", 0)),
        )

    @classmethod
    def default(cls, key: str, units: str = "si") -> State:
        return cls.of(KINDS[key], units)

    # -------------------------------------------------------------- units
    @property
    def display(self) -> DisplayUnits:
        if self.units not in PRESETS:
            raise MechanismError(f"units must be one of {', '.join(PRESETS)}, got {self.units!r}")
        return DisplayUnits(**PRESETS[self.units])

    def shown(self, value: float, unit: str) -> float:
        """An SI value in the page's units."""
        return float(value) / self.display.factor(unit)

    def si(self, value: float, unit: str) -> float:
        """A value typed in the page's units, in SI."""
        return float(value) * self.display.factor(unit)

    def unit_label(self, unit: str) -> str:
        return self.display.unit(unit) if unit else ""

    # -------------------------------------------------------------- input speed
    @property
    def slider_driven(self) -> bool:
        """True when the input is a driving slider (a length), not a crank."""
        if self.kind.mechanism != "linkage":
            return False
        try:
            return not is_periodic(self.kind.build(dict(self.kind.values)))
        except (MechanismError, ValueError):
            return False

    def speed_field(self) -> tuple[str, float]:
        """The speed field's label and its value shown: rpm for a crank, the display's
        speed unit (m/s, mm/s, in/s) for a driving slider; 0 for none (analogs)."""
        if self.slider_driven:
            unit = self.unit_label("m/s")
            value = 0.0 if self.speed is None else self.shown(self.speed, "m/s")
            return f"Input speed (driving slider), {unit}", _r6(value)
        value = 0.0 if self.speed is None else self.speed * 60 / (2 * math.pi)
        return "Crank speed, rpm", _r6(value)

    def set_speed(self, text) -> None:
        """Set the speed from the field's text (its unit as :meth:`speed_field` says); 0 means
        none (velocities and accelerations as analogs per unit of input). Raises
        MechanismError naming the field for text that is not a number or a negative speed."""
        label = self.speed_field()[0]
        v = parse_number(text, label)
        if v < 0:
            raise MechanismError(
                f"{label} must be positive, or 0 for analogs (the sense of motion is the "
                f"mechanism's), got {v:g}"
            )
        if v == 0:
            self.speed = None
        elif self.slider_driven:
            self.speed = self.si(v, "m/s")
        else:
            self.speed = v * 2 * math.pi / 60

    # -------------------------------------------------------------- design
    def field_messages(self) -> dict[str, str]:
        """``{dimension: message}`` for values that are not numbers or must be positive."""
        out = {}
        for d in self.kind.dims:
            v = self.values.get(d.name)
            if v is None or not np.isfinite(v):
                out[d.name] = f"{d.name} must be a number, got {v!r}"
            elif d.positive and v <= 0:
                out[d.name] = f"{d.name} must be positive (a length), got {self._fmt(v, d.unit)}"
        return out

    def _fmt(self, v, unit):
        return f"{self.shown(v, unit):.6g} {self.unit_label(unit)}".rstrip()

    def design(self):
        """The design of the current values; raises ValueError/MechanismError naming the
        condition when it cannot be built."""
        bad = self.field_messages()
        if bad:
            raise MechanismError(next(iter(bad.values())))
        return self.kind.build(dict(self.values))

    def check_design(self, n: int = 360):
        """``(design, None)`` or ``(None, message)``: the design must be built and assemble
        over a whole turn."""
        try:
            design = self.design()
            design.motion(_turn(design, n))
        except (MechanismError, ValueError, ZeroDivisionError) as exc:
            return None, str(exc)
        return design, None

    def bound_messages(self) -> dict[str, str]:
        """``{dimension: message}`` for the optimization bounds: reversed, not finite, a
        length's lower bound not positive, a dimension that cannot vary."""
        out = {}
        for name, (lo, hi) in self.vary.items():
            d = self.kind.dim(name)
            if not d.varies:
                out[name] = f"{name} cannot be an optimization variable of {self.kind.title}"
            elif not (np.isfinite(lo) and np.isfinite(hi)):
                out[name] = f"{name}: the bounds must be numbers"
            elif not lo < hi:
                out[name] = (
                    f"{name}: lower bound {self._fmt(lo, d.unit)} is not below the "
                    f"upper bound {self._fmt(hi, d.unit)}"
                )
            elif d.positive and lo <= 0:
                out[name] = (
                    f"{name} is a length: its lower bound must be positive, got "
                    f"{self._fmt(lo, d.unit)}"
                )
        return out

    # -------------------------------------------------------------- problem
    def problem_data(self) -> dict:
        """The page's problem as the dict of a problem file (SI numbers)."""
        k = self.kind
        if k.mechanism is None:
            raise MechanismError(f"{k.title} has no problem-file form")
        if not self.objective.strip():
            raise MechanismError("give an objective measure, e.g. peak_acceleration(slider)")
        bad = self.bound_messages()
        if bad:
            raise MechanismError(next(iter(bad.values())))
        if not self.vary:
            raise MechanismError("tick at least one dimension to vary (with its bounds)")
        params = k.to_params(dict(self.values)) if k.to_params else dict(self.values)
        variables = {}
        as_param = k.to_param or (lambda d, x, v: (d, x))
        for name, (lo, hi) in self.vary.items():
            p, lo = as_param(name, lo, self.values)
            _, hi = as_param(name, hi, self.values)
            lo, hi = sorted((lo, hi))
            variables[p] = [float(lo), float(hi)]
        fixed = {p: float(v) for p, v in params.items() if p not in variables}
        fixed.update({t: v for t, v in k.text.items() if not t.startswith("_")})
        data: dict[str, Any] = {
            "mechanism": k.mechanism,
            ("minimize" if self.sense == "minimize" else "maximize"): self.objective.strip(),
        }
        data["constraints"] = [c.strip() for c in self.constraints if c.strip()]
        if self.speed is not None:
            data["speed"] = float(self.speed)
        data.update(method=self.method, starts=int(self.starts), seed=int(self.seed))
        if k.file_data:
            data.update(copy.deepcopy(k.file_data))
        data["variables"] = variables
        if fixed:
            data["fixed"] = fixed
        return data

    def design_data(self) -> dict:
        """The current design as the dict of a design file (``mechsynth animate FILE``; the
        explorer loads it back): the mechanism, the speed and ``[design]`` (SI numbers); a
        linkage's tables inline."""
        k = self.kind
        if k.mechanism is None:
            raise MechanismError(f"{k.title} has no design-file form")
        bad = self.field_messages()
        if bad:
            raise MechanismError(next(iter(bad.values())))
        params = k.to_params(dict(self.values)) if k.to_params else dict(self.values)
        data: dict[str, Any] = {"mechanism": k.mechanism}
        if self.speed is not None:
            data["speed"] = float(self.speed)
        if k.file_data:
            data.update(copy.deepcopy(k.file_data))
        design = {p: float(v) for p, v in params.items()}
        design.update({t: v for t, v in k.text.items() if not t.startswith("_")})
        data["design"] = design
        return data

    def design_toml(self) -> str:
        """The current design as a TOML design file (SI numbers)."""
        head = (
            f"# {self.kind.title}: the design shown by the explorer (SI: m, rad, rad/s).\n"
            "#   mechsynth animate THIS_FILE --out anim\n"
        )
        return head + to_toml(self.design_data())

    def problem_toml(self) -> str:
        """The page's problem as a TOML problem file (``mechsynth optimize FILE``)."""
        head = (
            f"# {self.kind.title}: the problem of the explorer page (SI: m, rad, rad/s).\n"
            "#   mechsynth optimize THIS_FILE --out results\n"
        )
        data = self.problem_data()
        params = self.kind.to_params(dict(self.values)) if self.kind.to_params else self.values
        # problem files take no start point: the design on the page goes in as comments (the
        # design file export carries it in a form the explorer and `mechsynth animate` read)
        current = "".join(
            f"#   {p} = {float(v)!r}\n" for p, v in params.items() if p in data["variables"]
        )
        return head + "# the design on the page when exported (SI):\n" + current + to_toml(data)

    def problem(self):
        """The :class:`~mechsynth.synthesis.problem_file.ProblemSpec` of the page."""
        from ..synthesis.problem_file import load_problem

        return load_problem(self.problem_data())

    def values_of(self, params: Mapping[str, float]) -> dict[str, float]:
        """Dimension values from a solution's parameters (``{parameter: value}``)."""
        unmap = self.kind.from_param or (lambda p, x, v: (p, x))
        out = dict(self.values)
        for p, v in params.items():
            name, x = unmap(p, float(v), out)
            if name in out:
                out[name] = x
        return out


def inputs(design, n: int) -> np.ndarray:
    """``n`` inputs over one cycle of ``design``: crank angles over a turn in the machine's
    direction, or equal steps over a driving slider's travel (m), both ends included."""
    from ..kinematics.mechanism import input_domain, input_grid

    if input_domain(design)[2]:
        return getattr(design, "turn_sign", 1) * input_grid(design, int(n))
    return input_grid(design, int(n))


def is_periodic(design) -> bool:
    """True when the input is a crank angle; False for a linkage driven by a slider."""
    from ..kinematics.mechanism import input_domain

    return input_domain(design)[2]


_turn = inputs


def _r6(x: float) -> float:
    return float(f"{x:.6g}")


def parse_number(text, what: str) -> float:
    """A number typed in a field: ``float`` of the whole text, or MechanismError naming the
    field (an empty field, text that is not a number as a whole, NaN or infinity)."""
    if isinstance(text, (int, float, np.integer, np.floating)) and not isinstance(text, bool):
        value = float(text)
    else:
        raw = "" if text is None else str(text).strip()
        if not raw:
            raise MechanismError(f"{what}: the field is empty; type a number")
        try:
            value = float(raw)
        except ValueError:
            raise MechanismError(f"{what}: {raw!r} is not a number") from None
    if not math.isfinite(value):
        raise MechanismError(f"{what}: must be a finite number, got {value}")
    return value


# ------------------------------------------------------------------------------ files
def load_file(path, units: str = "si") -> State:
    """The page's state from a TOML file: a problem file (its mechanism, bounds, objective and
    constraints), a design file (its mechanism and values) or a linkage file."""
    from ..synthesis.design_file import load_design
    from ..synthesis.linkage_file import _linkage_of

    path = Path(path)
    if not path.exists():
        raise FileNotFoundError(f"{path} not found")
    with open(path, "rb") as fh:
        try:
            data = tomllib.load(fh)
        except tomllib.TOMLDecodeError as exc:
            raise MechanismError(f"{path}: not valid TOML ({exc})") from exc
    name = data.get("mechanism")
    is_problem = "minimize" in data or "maximize" in data or "variables" in data
    if name is None and ("group" in data or "ground" in data):
        return State.of(linkage_kind(data, title=f"Linkage from {path.name}"), units)
    if name == "linkage":
        lk_data = data
        if isinstance(data.get("linkage"), str):
            target = path.parent / data["linkage"]
            with open(target, "rb") as fh:
                lk_data = tomllib.load(fh)
            _linkage_of(data, path)  # its messages name the file
        kind = linkage_kind(
            lk_data, data if is_problem else None, title=f"Linkage from {path.name}"
        )
        state = State.of(kind, units)
        if not is_problem:
            spec = load_design(path)
            state.values.update({k: float(v) for k, v in spec.design.as_dict().items()})
            state.speed = spec.speed
        return state
    if name not in KINDS:
        raise MechanismError(
            f"{path}: the explorer shows the mechanisms "
            f"{', '.join(kind_names())}; got mechanism = {name!r}"
        )
    kind = KINDS[name]
    if is_problem:
        _apply_problem(kind, data)
        return State.of(kind, units)
    spec = load_design(path)
    state = State.of(kind, units)
    given = spec.design.as_dict()
    if kind.to_params:  # API dimensions from the parameters
        for t in ("unit_class", "rotation"):
            if t in given:
                kind.text[t] = given.pop(t)
        unmap = kind.from_param
        for p, x in sorted(given.items(), key=lambda kv: kv[0] == "pivot_y"):
            name, x = unmap(p, x, state.values)
            if name in state.values:
                state.values[name] = float(x)
        given = {}
    state.values.update({k: float(v) for k, v in given.items() if k in state.values})
    state.speed = spec.speed if spec.speed is not None else state.speed
    return state


# ------------------------------------------------------------------------------ analysis
def curves(state: State, design, n: int = 361) -> dict[str, Any]:
    """Motion curves over one cycle (SI): ``angle``, the input (deg: the crank angle 0..360 in
    the machine's direction; or m: a driving slider's displacement over its travel) with
    ``input_unit`` ("deg" or "m"), ``position``, ``velocity``, ``acceleration`` of the kind's
    output with ``unit`` ("m" or "rad"), ``pressure`` and ``transmission`` angles (rad or
    None), and ``stroke`` (m or rad)."""
    from ..units import cycle

    if is_periodic(design):
        deg = np.linspace(0.0, 360.0, n)
        phi = getattr(design, "turn_sign", 1) * cycle(n - 1)
        phi = np.append(phi, phi[0] + getattr(design, "turn_sign", 1) * 2 * np.pi)
        input_unit = "deg"
    else:
        phi = inputs(design, n)
        deg = phi.copy()
        input_unit = "m"
    speed = state.speed
    m = design.motion(phi, speed=speed) if speed else design.motion(phi)
    what, name = state.kind.curve
    if what == "slider":
        tr = m.sliders.get(name) or m.slider
        pos, vel, acc, unit = tr.position, tr.velocity, tr.acceleration, "m"
    elif what == "link":
        tr = m.links[name]
        pos, vel, acc, unit = tr.angle, tr.omega, tr.epsilon, "rad"
        pos = np.unwrap(np.asarray(pos, dtype=float))
    else:
        tr = m.points[name]
        pos = np.hypot(tr.x - tr.x[0], tr.y - tr.y[0])
        vel, acc, unit = np.hypot(tr.vx, tr.vy), np.hypot(tr.ax, tr.ay), "m"
    pos, vel, acc = (
        np.broadcast_to(np.asarray(a, dtype=float), phi.shape) for a in (pos, vel, acc)
    )
    out = dict(
        angle=deg,
        position=pos,
        velocity=vel,
        acceleration=acc,
        unit=unit,
        speed=speed,
        output=name or what,
        input_unit=input_unit,
    )
    out["pressure"] = (
        None
        if m.pressure_angle is None
        else np.broadcast_to(np.asarray(m.pressure_angle, float), phi.shape)
    )
    out["transmission"] = (
        None
        if m.transmission_angle is None
        else np.broadcast_to(np.asarray(m.transmission_angle, float), phi.shape)
    )
    out["stroke"] = stroke(state, design)
    return out


def stroke(state: State, design) -> float:
    """The output's stroke (m) or swing (rad) as the API gives it (closed forms where the
    mechanism has them)."""
    from ..objectives.kinematic import stroke as stroke_measure
    from ..objectives.kinematic import swing_angle

    what, name = state.kind.curve
    if what == "link":
        return float(swing_angle(name).bind(type(design)).evaluate(design, _turn(design, 2048)))
    if (
        hasattr(design, "stroke")
        and not callable(design.stroke)
        and what == "slider"
        and (state.kind.key in ("slider-crank", "beam-pump"))
    ):
        return float(design.stroke)
    out = "slider" if what == "slider" and state.kind.mechanism != "linkage" else name
    return float(stroke_measure(out).bind(type(design)).evaluate(design, _turn(design, 2048)))


def checks(state: State, design, n: int = 2048) -> list[Check]:
    """The objective and every constraint of the page's problem at ``design``, evaluated on
    ``n`` crank angles (the certified solve refines the peaks; this is the live view)."""
    from ..synthesis.problem_file import parse_constraint, parse_measure

    phi = _turn(design, n)
    motion = design.motion(phi, speed=state.speed) if state.speed else design.motion(phi)
    out = []
    if state.objective.strip():
        m = parse_measure(state.objective).bind(type(design))
        out.append(
            Check(
                m.name, float(m.from_motion(design, motion)), m.unit, op=state.sense, objective=True
            )
        )
    for text in state.constraints:
        if not text.strip():
            continue
        c = parse_constraint(text)
        m = c.measure.bind(type(design))
        v = float(m.from_motion(design, motion))
        tol = 1e-6 * max(1.0, abs(c.bound)) if c.op != "==" else 1e-4 * max(1e-3, abs(c.bound))
        ok = {"<=": v <= c.bound + tol, ">=": v >= c.bound - tol, "==": abs(v - c.bound) <= tol}[
            c.op
        ]
        out.append(Check(m.name, v, m.unit, c.op, float(c.bound), bool(ok)))
    return out


def sweep_chart(
    state: State, x: str, y: str, n: int = 30, angles: int = 180, x_range=None, y_range=None
):
    """The page's measures over a grid of two dimensions (the others at their current
    values): a :class:`~mechsynth.synthesis.charts.Chart` whose values are labelled by the
    measures' names (the objective first, then the constraints' measures)."""
    from ..synthesis.charts import sweep
    from ..synthesis.problem_file import parse_constraint, parse_measure

    if x == y:
        raise MechanismError("choose two different dimensions for the chart")
    n = int(n)
    if not 2 <= n <= 200:
        raise MechanismError(f"chart points per axis must be 2 to 200, got {n}")
    axes = {}
    for name, rng in ((x, x_range), (y, y_range)):
        d = state.kind.dim(name)
        lo, hi = rng if rng is not None else (d.lo, d.hi)
        if not lo < hi:
            raise MechanismError(f"chart axis {name}: lower end not below the upper end")
        axes[name] = np.linspace(lo, hi, n)
    measures = {}
    if state.objective.strip():
        m = parse_measure(state.objective)
        measures[m.name] = m
    for text in state.constraints:
        if text.strip():
            c = parse_constraint(text)
            measures.setdefault(c.measure.name, c.measure)
    if not measures:
        raise MechanismError("the chart shows the problem's measures: give an objective")
    fixed_vals = {k: v for k, v in state.values.items() if k not in (x, y)}
    # the sweep's axes stay in SI (its figure's labels say so)
    labels = {n: f"{n}, {state.kind.dim(n).unit}" if state.kind.dim(n).unit else n for n in axes}
    kind = state.kind

    if kind.mechanism == "linkage":
        lk = kind.build(dict(state.values))
        return sweep(
            lk,
            axes,
            measures,
            fixed=fixed_vals,
            angles=angles,
            speed=state.speed,
            progress=False,
            labels=labels,
        )
    if kind.to_params:  # the API dimensions map to the mechanism's parameters
        cls = type(kind.build(dict(state.values)))

        def design(vals):
            return kind.to_params({**fixed_vals, **vals})

        text = {k: v for k, v in kind.text.items() if not k.startswith("_")}
        return sweep(
            cls,
            axes,
            measures,
            fixed=text,
            design=design,
            angles=angles,
            speed=state.speed,
            progress=False,
            labels=labels,
        )
    cls = type(kind.build(dict(state.values)))
    return sweep(
        cls,
        axes,
        measures,
        fixed=fixed_vals,
        angles=angles,
        speed=state.speed,
        progress=False,
        labels=labels,
    )


# ------------------------------------------------------------------------------ solving
def solve_data(data: dict, messages=None) -> dict:
    """Solve a problem given as a problem file's dict; returns a plain dict (the result's
    ``to_dict`` plus ``variables``). ``messages``, a queue, receives ``("progress", desc, k,
    total)`` while the starts run. Meant for a worker process."""
    from .. import progress
    from ..synthesis.problem_file import load_problem

    spec = load_problem(data)

    def report(desc, k, total):
        if messages is not None:
            messages.put(("progress", str(desc or ""), int(k), int(total or 0)))

    with progress.observe(report):
        res = spec.solve(progress=False)
    out = res.to_dict()
    out["variables"] = dict(res.variables or {})
    out["report"] = res.report()
    return out


def solve_worker(data: dict, messages) -> None:
    """A worker process's work: solve and post ``("done", result)`` or ``("error", text)`` on
    ``messages`` (this module imports no web framework, so the worker starts light)."""
    try:
        messages.put(("done", solve_data(data, messages)))
    except Exception as exc:  # noqa: BLE001 - every failure goes back to the page as text
        messages.put(("error", f"{type(exc).__name__}: {exc}"))


# ------------------------------------------------------------------------------ synthesis
def parse_poses(text: str, state: State) -> np.ndarray:
    """Target poses typed one a line, ``x, y, angle`` in the page's units (lengths in its
    length unit, the angle in degrees; commas or spaces between them), as rows ``(x, y,
    angle)`` in SI (m, m, rad). MechanismError names the line that is not three numbers."""
    rows = []
    for i, line in enumerate(str(text or "").splitlines(), start=1):
        line = line.split("#")[0].strip()
        if not line:
            continue
        parts = [p for p in re.split(r"[,\s;]+", line) if p]
        if len(parts) != 3:
            raise MechanismError(
                f"pose line {i}: give x, y and angle (3 numbers), got {len(parts)}: {line!r}"
            )
        x, y, a = (parse_number(p, f"pose line {i}") for p in parts)
        rows.append((state.si(x, "m"), state.si(y, "m"), math.radians(a)))
    if not 2 <= len(rows) <= 5:
        raise MechanismError(f"motion generation takes 2 to 5 poses, got {len(rows)}")
    return np.array(rows, dtype=float)


def motion_candidates(text: str, state: State, limit: int = 12):
    """Four-bars and slider-cranks that carry a coupler through the poses typed in ``text``
    (:func:`parse_poses`), ranked by :func:`mechsynth.motion_generation` (defect-free first):
    ``(poses, candidates)`` with at most ``limit`` candidates."""
    from ..synthesis.motion_generation import motion_generation

    poses = parse_poses(text, state)
    mg = motion_generation(poses)
    if not mg.candidates:
        raise MechanismError("no four-bar or slider-crank carries the coupler through the poses")
    return poses, list(mg.candidates[: int(limit)])


def candidate_state(candidate, rank: int, units: str = "si") -> State:
    """The page's state of a motion-generation candidate: its linkage (the coupler point P on
    the first pose's origin, Q along its x axis) with P's path traced."""
    kind = linkage_kind(candidate.linkage_data(), title=f"Motion generation: solution {rank}")
    kind.trace = ("P",)
    return State.of(kind, units)
