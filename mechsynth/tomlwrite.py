"""A small TOML writer (the standard library reads TOML but does not write it): the problem,
design and linkage files the commands and the explorer export, read back by ``tomllib``."""

from __future__ import annotations

import re
from collections.abc import Mapping

import numpy as np

from .errors import MechanismError


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        if not np.isfinite(v):
            raise MechanismError(f"cannot write the non-finite number {v} to TOML")
        return repr(float(v))
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, Mapping):
        return "{ " + ", ".join(f"{_key(k)} = {_toml_value(x)}" for k, x in v.items()) + " }"
    raise MechanismError(f"cannot write {v!r} to TOML")


def _key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else _toml_value(str(k))


def to_toml(data: Mapping) -> str:
    """A small TOML writer for problem and linkage files: scalars and lists at the top, then
    tables, then arrays of tables (their nested tables inline). ``tomllib.loads`` reads back
    exactly ``data``."""
    top, tables, arrays = [], [], []
    for k, v in data.items():
        if isinstance(v, Mapping):
            tables.append((k, v))
        elif isinstance(v, list) and v and all(isinstance(x, Mapping) for x in v):
            arrays.append((k, v))
        elif isinstance(v, list) and len(v) > 2 and all(isinstance(x, str) for x in v):
            top.append(f"{_key(k)} = [\n" + "".join(f"    {_toml_value(x)},\n" for x in v) + "]")
        else:
            top.append(f"{_key(k)} = {_toml_value(v)}")
    parts = ["\n".join(top)]
    for k, v in tables:
        body = "\n".join(f"{_key(a)} = {_toml_value(b)}" for a, b in v.items())
        parts.append(f"[{_key(k)}]\n{body}")
    for k, items in arrays:
        for item in items:
            body = "\n".join(f"{_key(a)} = {_toml_value(b)}" for a, b in item.items())
            parts.append(f"[[{_key(k)}]]\n{body}")
    return "\n\n".join(p for p in parts if p) + "\n"
