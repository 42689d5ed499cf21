"""Public names a package imports on first use (a module ``__getattr__``, PEP 562): how
``import mechsynth`` and its layers stay light."""

from __future__ import annotations

import importlib

__all__ = ["lazy_names"]


def lazy_names(namespace: dict, names: dict, modules=()):
    """``(__getattr__, __dir__)`` for the package whose globals are ``namespace``: each of
    ``names`` (``{name: submodule}``, relative to the package) is taken from its submodule, and
    each of ``modules`` (submodules) is imported, on first access; the value is then stored in
    ``namespace``, so later accesses are plain lookups."""
    package = namespace["__name__"]

    def __getattr__(name: str):
        if name in names:
            value = getattr(importlib.import_module(f"{package}.{names[name]}"), name)
        elif name in modules:
            value = importlib.import_module(f"{package}.{name}")
        else:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(names) | set(modules))

    return __getattr__, __dir__
