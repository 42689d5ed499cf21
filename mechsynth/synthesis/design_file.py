"""Design files: one design of a named mechanism in TOML, as read by ``mechsynth animate``.

Format (top-level keys first, then the ``[design]`` table)::

    mechanism = "slider-crank"     # slider-crank, four-bar, beam-pump, dwell, nail-header
    speed = "600 rpm"              # optional: the machine's crank speed (rpm, spm or rad/s)
    trace = ["B"]                  # optional: points whose paths are drawn

    [design]                       # the parameters; numbers are SI (m, rad, kg), or strings
    crank = "70 mm"                # with a unit ("70 mm", "20 deg")
    rod = "240 mm"
    offset = "10 mm"

Parameters left out take the class's defaults (the nail header has all of paper 003's).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

from .. import load_registrations
from ..errors import MechanismError
from .problem_file import MECHANISMS, parse_quantity

__all__ = ["DesignSpec", "load_design", "design_mechanisms", "read_toml", "register_design"]

_TOP_KEYS = {"mechanism", "speed", "trace", "design", "title"}
_TEXT = ("branch", "unit_class", "rotation", "spring_zero")


#: mechanisms that design files name beyond those of problem files (the machines register theirs)
_DESIGNS: dict[str, type] = {}


def register_design(name: str, cls) -> None:
    """Make ``cls`` available as ``mechanism = "name"`` in design files (``mechsynth animate``)."""
    _DESIGNS[name] = cls


def design_mechanisms() -> dict[str, type]:
    """Mechanism name in design files -> class: those of problem files and those the machines
    registered (the dwell linkage, the nail header)."""
    load_registrations()
    return {**MECHANISMS, **_DESIGNS}


@dataclasses.dataclass(frozen=True)
class DesignSpec:
    """A design read from a file: ``design`` (the mechanism), ``speed`` (rad/s or None),
    ``trace`` (point names or None for the mechanism's default), ``source``."""

    design: Any
    speed: float | None
    trace: tuple[str, ...] | None
    source: Path | None = None


def read_toml(source, what: str = "design file") -> tuple[dict, Path | None]:
    """``(data, path)`` of a TOML file (``path`` None when ``source`` is a dict already):
    :func:`mechsynth.fileio.read_toml` (regular UTF-8 files only, one-line errors)."""
    from ..fileio import read_toml as _read_toml

    return _read_toml(source, what)


def load_design(source) -> DesignSpec:
    """Read a design file (a path, or a dict already parsed from TOML)."""
    data, path = read_toml(source)
    where = f"{path}: " if path else ""
    if "minimize" in data or "maximize" in data or "variables" in data:
        raise MechanismError(
            f"{where}this is a problem file; `mechsynth optimize FILE --animate --out DIR` "
            "animates its optimum"
        )
    known = design_mechanisms()
    name = data.get("mechanism")
    kind = known.get(name) if isinstance(name, str) else None
    # a mechanism read from the file's own tables (a linkage) declares them
    unknown = set(data) - _TOP_KEYS - set(getattr(kind, "file_keys", ()))
    if unknown:
        raise MechanismError(
            f"{where}unknown keys {sorted(unknown)}; a design file has {sorted(_TOP_KEYS)} "
            "(top-level keys before the [design] table)"
        )
    if not isinstance(name, str) or name not in known:
        raise MechanismError(
            f"{where}mechanism must be one of {', '.join(sorted(known))}, got {name!r}"
        )
    cls = known[name]
    table = data.get("design") or {}
    if not isinstance(table, dict):
        raise MechanismError(f"{where}[design] must be a table of parameters")
    if hasattr(cls, "from_problem_data"):  # a linkage: its file, then [design] overrides
        linkage = cls.from_problem_data(data, path)
        for key in table:
            if key not in linkage.parameters:
                raise MechanismError(
                    f"{where}{linkage.name} has no parameter {key!r}; its parameters: "
                    f"{', '.join(linkage.parameters)}"
                )
        values = {k: parse_quantity(v, f"design {k!r}") for k, v in table.items()}
        return _spec(linkage(**values) if values else linkage, data, where, path)
    fields = {f.name: f for f in dataclasses.fields(cls)}
    values = {}
    for key, value in table.items():
        if key not in fields:
            raise MechanismError(
                f"{where}{cls.__name__} has no parameter {key!r}; its parameters: "
                f"{', '.join(fields)}"
            )
        if isinstance(value, bool) or key in _TEXT:
            values[key] = value
        else:
            values[key] = parse_quantity(value, f"design {key!r}")
    missing = [
        k
        for k, f in fields.items()
        if k not in values
        and f.default is dataclasses.MISSING
        and f.default_factory is dataclasses.MISSING
    ]
    if missing:
        raise MechanismError(f"{where}[design] must give {', '.join(missing)}")
    return _spec(cls(**values), data, where, path)


def _spec(design, data, where, path) -> DesignSpec:
    """The design with the file's speed and traced points."""
    speed = data.get("speed")
    speed = None if speed is None else parse_quantity(speed, "speed")
    trace = data.get("trace")
    if trace is not None:
        if not isinstance(trace, list) or not all(isinstance(t, str) for t in trace):
            raise MechanismError(f"{where}trace must be a list of point names, got {trace!r}")
        trace = tuple(trace)
    return DesignSpec(design, speed, trace, path)
