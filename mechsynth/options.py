"""Declared options of studies and charts.

Each study and chart states its options once -- name, type, default, unit, meaning and the rule a
value must satisfy -- and that one declaration serves ``--set KEY=VALUE`` (values read from text),
``--set help`` and ``--help`` (the table of options), and calls from Python (values checked the
same way). A bad value names the option, what was given and what is expected; an unknown key
lists the valid ones.

>>> opts = Options(Option("n", 40, "grid points per axis", minimum=3),
...                Option("stroke", 0.1, "required stroke", unit="m", minimum=0.0, exclusive=True))
>>> opts.resolve({"n": "60"}, owner="chart demo")
{'n': 60, 'stroke': 0.1}
>>> opts.resolve({"stroke": "0"}, owner="chart demo")
Traceback (most recent call last):
...
mechsynth.errors.MechanismError: chart demo: option stroke (m) must be > 0, got 0.0
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from .errors import MechanismError

__all__ = ["Option", "Options", "chart_options", "takes_options"]

#: option kinds and how their values are written on the command line
KINDS = {
    "int": "an integer",
    "float": "a number",
    "str": "text",
    "path": "a file path",
    "bool": "true or false",
    "ints": "integers separated by commas",
    "floats": "numbers separated by commas",
    "span": "LOW:HIGH",
}

_TRUE = {"true", "yes", "on", "1"}
_FALSE = {"false", "no", "off", "0"}


def _kind_of(default) -> str:
    if isinstance(default, bool):
        return "bool"
    if isinstance(default, int):
        return "int"
    if isinstance(default, float):
        return "float"
    if isinstance(default, tuple) and default:
        return "ints" if all(isinstance(v, int) for v in default) else "floats"
    return "str"


@dataclass(frozen=True)
class Option:
    """One option: ``name``, ``default`` (None: unset unless given), ``help`` (its meaning),
    ``unit`` (shown beside the name), ``kind`` (one of :data:`KINDS`; inferred from the default
    when empty), a range ``minimum``/``maximum`` (each value of a list, both ends of a span;
    ``exclusive`` makes the minimum strict), ``choices`` and ``required``."""

    name: str
    default: object
    help: str
    unit: str = ""
    kind: str = ""
    minimum: float | None = None
    maximum: float | None = None
    exclusive: bool = False
    choices: tuple = ()
    required: bool = False

    def __post_init__(self):
        if not self.kind:
            object.__setattr__(self, "kind", _kind_of(self.default))
        if self.kind not in KINDS:
            raise MechanismError(f"option {self.name}: unknown kind {self.kind!r}")

    @property
    def label(self) -> str:
        if not self.unit or self.name.endswith("_" + self.unit):
            return self.name
        return f"{self.name} ({self.unit})"

    def _fail(self, owner, value, rule):
        where = f"{owner}: " if owner else ""
        raise MechanismError(f"{where}option {self.label} must be {rule}, got {value!r}")

    def _number(self, value, owner, integer):
        rule = "an integer" if integer else "a finite number"
        if isinstance(value, str):
            text = value.strip()
            try:
                number = int(text) if integer else float(text)
            except ValueError:
                self._fail(owner, value, rule)
        elif isinstance(value, bool) or not isinstance(value, int | float):
            self._fail(owner, value, rule)
        elif integer and isinstance(value, float):
            if not value.is_integer():
                self._fail(owner, value, rule)
            number = int(value)
        else:
            number = int(value) if integer else float(value)
        if not integer and not math.isfinite(number):
            self._fail(owner, value, rule)
        self._in_range(number, owner)
        return number

    def _in_range(self, number, owner):
        lo, hi = self.minimum, self.maximum
        if lo is not None and (number <= lo if self.exclusive else number < lo):
            self._fail(owner, number, f"{'>' if self.exclusive else '>='} {lo:g}")
        if hi is not None and number > hi:
            self._fail(owner, number, f"<= {hi:g}")

    def read(self, value, owner: str = ""):
        """``value`` (text from the command line, or a Python value) as this option's type,
        checked against its rule; raises ValueError naming the option."""
        kind = self.kind
        if value is None and not self.required:
            return None
        if kind in ("int", "float"):
            return self._number(value, owner, kind == "int")
        if kind == "bool":
            if isinstance(value, bool):
                return value
            text = str(value).strip().lower()
            if text in _TRUE | _FALSE:
                return text in _TRUE
            self._fail(owner, value, KINDS["bool"])
        if kind in ("ints", "floats", "span"):
            sep = ":" if kind == "span" else ","
            if isinstance(value, str):
                parts = [p for p in (t.strip() for t in value.split(sep))]
                if not value.strip() or any(not p for p in parts):
                    self._fail(owner, value, KINDS[kind])
            elif isinstance(value, Sequence) or hasattr(value, "__array__"):
                parts = list(value)
            else:
                parts = [value]
            integer = kind == "ints"
            numbers = []
            for part in parts:
                try:
                    numbers.append(self._number(part, "", integer))
                except ValueError:
                    self._fail(owner, value, self.rule())
            numbers = tuple(numbers)
            if kind == "span" and (len(numbers) != 2 or not numbers[0] < numbers[1]):
                self._fail(owner, value, "LOW:HIGH with LOW < HIGH")
            return numbers
        text = str(value) if not isinstance(value, str) else value
        if kind == "path" and self.required and not text.strip():
            self._fail(owner, value, "a file path")
        if self.choices and text not in self.choices:
            self._fail(owner, value, "one of " + ", ".join(map(str, self.choices)))
        return text

    def rule(self) -> str:
        """The value's type and range in words, e.g. ``an integer >= 3``."""
        parts = [KINDS[self.kind]]
        if self.minimum is not None:
            parts.append(f"{'>' if self.exclusive else '>='} {self.minimum:g}")
        if self.maximum is not None:
            parts.append(f"<= {self.maximum:g}")
        if self.choices:
            parts.append("one of " + ", ".join(map(str, self.choices)))
        return " ".join(parts[:1]) + ("" if len(parts) == 1 else ", " + ", ".join(parts[1:]))

    def shown_default(self) -> str:
        d = self.default
        if self.required:
            return "(required)"
        if d is None:
            return "(unset)"
        if self.kind == "span":
            return f"{d[0]:g}:{d[1]:g}"
        if isinstance(d, tuple):
            return ",".join(f"{v:g}" for v in d)
        if d == "":
            return '""'
        if isinstance(d, bool):
            return str(d).lower()
        return f"{d:g}" if isinstance(d, float) else str(d)


class Options:
    """An ordered, immutable set of :class:`Option` -- the options of one study or chart."""

    def __init__(self, *options: Option):
        names = [o.name for o in options]
        if len(set(names)) != len(names):
            raise MechanismError(f"duplicate option names in {names}")
        self._options = {o.name: o for o in options}

    def __iter__(self):
        return iter(self._options.values())

    def __len__(self):
        return len(self._options)

    def __contains__(self, name):
        return name in self._options

    def __getitem__(self, name) -> Option:
        return self._options[name]

    @property
    def defaults(self) -> dict:
        return {o.name: o.default for o in self}

    def resolve(self, given: Mapping | None = None, owner: str = "") -> dict:
        """Every option's value: ``given`` (text or Python values) read and checked, the
        defaults for the rest. Unknown keys and missing required options raise ValueError."""
        given = dict(given or {})
        unknown = sorted(set(given) - set(self._options))
        where = f"{owner}: " if owner else ""
        if unknown:
            valid = ", ".join(self._options) or "none"
            s = "s" if len(unknown) > 1 else ""
            raise MechanismError(f"{where}unknown option{s} {', '.join(unknown)}; options: {valid}")
        values = {}
        for opt in self:
            if opt.name in given:
                values[opt.name] = opt.read(given[opt.name], owner)
            elif opt.required:
                raise MechanismError(f"{where}option {opt.label} is required ({opt.help})")
            else:
                values[opt.name] = opt.default
        return values

    def help(self, title: str = "") -> str:
        """A table of the options: name, unit, default, type and range, meaning."""
        if not len(self):
            return f"{title}: no options" if title else "no options"
        rows = [(o.label, o.shown_default(), o.rule(), o.help) for o in self]
        w = [max(len(r[i]) for r in rows) for i in range(3)]
        head = f"{title} (--set KEY=VALUE):\n" if title else ""
        return head + "\n".join(
            f"  {a:<{w[0]}}  default {b:<{w[1]}}  {c:<{w[2]}}  {d}" for a, b, c, d in rows
        )


def takes_options(*options: Option, owner: str = ""):
    """Declare the keyword options of a ``run(out=None, **options)`` function: calls are
    checked against the declaration (text values are read as from ``--set``), and the
    declaration is ``run.options``. Keyword arguments that are not declared options pass through
    unchanged when the function itself names them."""
    opts = Options(*options)

    def wrap(fn):
        import inspect

        names = list(inspect.signature(fn).parameters)
        own = {k for k in names if k not in opts and k != "out"}

        @functools.wraps(fn)
        def run(*args, **kwargs):
            if len(args) > len(names):
                raise TypeError(f"{fn.__name__}() takes at most {len(names)} positional arguments")
            for name, value in zip(names, args, strict=False):
                if name in kwargs:
                    raise TypeError(f"{fn.__name__}() got multiple values for {name!r}")
                kwargs[name] = value
            out = kwargs.pop("out", None)
            extra = {k: kwargs.pop(k) for k in list(kwargs) if k in own}
            values = opts.resolve(kwargs, owner or fn.__module__.rsplit(".", 1)[-1])
            return fn(out=out, **values, **extra)

        run.options = opts
        return run

    return wrap


def chart_options(*options: Option, owner: str = ""):
    """Declare the options of a chart function ``chart(out, options)``: the function receives
    every option's value, read and checked (text values as from ``--set``), defaults filled in;
    the declaration is ``chart.options``."""
    opts = Options(*options)

    def wrap(fn):
        @functools.wraps(fn)
        def chart(out=None, options=None):
            return fn(out, opts.resolve(options, owner or fn.__name__))

        chart.options = opts
        return chart

    return wrap
