"""Units at the edges: what printed reports, tables and figure labels show.

mechsynth computes in SI (m, kg, s, rad, N) and stays in SI inside. This setting only decides how
numbers are *shown*: reports (``Result.report()``, study and chart summaries), CSV tables
(``to_csv``) and figure labels. Three presets, or any combination of units:

============ ====== ===== ===== ====== ====
preset       length angle force torque mass
============ ====== ===== ===== ====== ====
``si``       m      deg   N     N m    kg
``mm-deg``   mm     deg   N     N m    kg
``oilfield`` in     deg   lbf   in-lb  lb
============ ====== ===== ===== ====== ====

``si`` (the default) shows angles in degrees, as engineers read them; ``angle="rad"`` shows
radians. Velocities and accelerations follow the length unit (mm/s, mm/s^2); analogs stay per
radian of crank angle (mm/rad); angular velocities stay in rad/s.

>>> import mechsynth as ms
>>> with ms.display_units("mm-deg"):
...     print(ms.display.fmt(0.1, "m"), ms.display.fmt(ms.deg(30), "rad"))
100 mm 30 deg
>>> print(ms.display.fmt(0.1, "m"))
0.1 m

``ms.display_units(...)`` changes the setting at once; used in a ``with`` block it restores the
previous one on exit. Crank positions are shown in [0, 360) deg (:func:`angle_position`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .errors import MechanismError

__all__ = [
    "DisplayUnits",
    "PRESETS",
    "display_units",
    "current",
    "convert",
    "thousands",
    "fmt",
    "label",
    "angle_position",
]

#: unit name -> size in SI
LENGTH = {"m": 1.0, "mm": 1e-3, "cm": 1e-2, "in": 0.0254, "ft": 0.3048}
ANGLE = {"rad": 1.0, "deg": np.pi / 180.0}
FORCE = {"N": 1.0, "kN": 1e3, "lbf": 4.4482216152605}
TORQUE = {"N m": 1.0, "kN m": 1e3, "in-lb": 0.0254 * 4.4482216152605}
MASS = {"kg": 1.0, "lb": 0.45359237}

_KINDS = {"length": LENGTH, "angle": ANGLE, "force": FORCE, "torque": TORQUE, "mass": MASS}

PRESETS = {
    "si": dict(length="m", angle="deg", force="N", torque="N m", mass="kg"),
    "mm-deg": dict(length="mm", angle="deg", force="N", torque="N m", mass="kg"),
    "oilfield": dict(length="in", angle="deg", force="lbf", torque="in-lb", mass="lb"),
}


@dataclass(frozen=True)
class DisplayUnits:
    """Units in which numbers are shown (SI inside is unchanged)."""

    length: str = "m"
    angle: str = "deg"
    force: str = "N"
    torque: str = "N m"
    mass: str = "kg"

    def __post_init__(self):
        for kind, table in _KINDS.items():
            value = getattr(self, kind)
            if value not in table:
                raise MechanismError(
                    f"display {kind} unit must be one of {', '.join(table)}, got {value!r}"
                )

    @property
    def name(self) -> str:
        """The preset's name, or the units joined by commas."""
        for key, units in PRESETS.items():
            if all(getattr(self, k) == v for k, v in units.items()):
                return key
        return ", ".join(getattr(self, k) for k in _KINDS)

    def convert(self, value, unit: str):
        """``value`` in SI ``unit`` -> (value, unit) for display. Units other than the SI units
        of length, angle, force, torque and mass (and their rates: ``m/s``, ``m/s^2``,
        ``m/rad``, ``m/rad^2``, ``kg m``) are returned unchanged."""
        factor, shown = self._rule(unit)
        if factor == 1.0:
            return value, shown
        if isinstance(value, (list, tuple)):
            value = np.asarray(value, dtype=float)
        return value / factor, shown

    def factor(self, unit: str) -> float:
        """Size in SI of one displayed unit of ``unit`` (divide SI values by it)."""
        return self._rule(unit)[0]

    def unit(self, unit: str) -> str:
        """The displayed unit of the SI ``unit``."""
        return self._rule(unit)[1]

    def _rule(self, unit: str):
        u = unit.strip().replace("²", "^2")
        ln, lf = self.length, LENGTH[self.length]
        rules = {
            "m": (lf, ln),
            "m/s": (lf, f"{ln}/s"),
            "m/s^2": (lf, f"{ln}/s^2"),
            "m/rad": (lf, f"{ln}/rad"),
            "m/rad^2": (lf, f"{ln}/rad^2"),
            "rad": (ANGLE[self.angle], self.angle),
            "N": (FORCE[self.force], self.force),
            "N m": (TORQUE[self.torque], self.torque),
            "kg": (MASS[self.mass], self.mass),
            "kg m": (MASS[self.mass] * lf, f"{self.mass} {ln}"),
        }
        return rules.get(u, (1.0, unit))


_current = [DisplayUnits()]


class _Setting:
    """What :func:`display_units` returns: the new setting, a context manager restoring the
    previous one on exit."""

    def __init__(self, new: DisplayUnits, previous: DisplayUnits):
        self.units, self._previous = new, previous

    def __enter__(self) -> DisplayUnits:
        return self.units

    def __exit__(self, *exc) -> None:
        _current[0] = self._previous

    def __repr__(self) -> str:
        return f"display_units({self.units.name!r})"


def display_units(
    preset: str | DisplayUnits | None = None,
    *,
    length: str | None = None,
    angle: str | None = None,
    force: str | None = None,
    torque: str | None = None,
    mass: str | None = None,
) -> _Setting:
    """Set the units of reports, tables and figure labels (SI inside is unchanged).

    Parameters
    ----------
    preset : ``"si"``, ``"mm-deg"`` or ``"oilfield"`` (see the module notes), a
        :class:`DisplayUnits`, or None to start from the current setting.
    length, angle, force, torque, mass : single units changed on top of the preset: length
        ``m, mm, cm, in, ft``; angle ``deg, rad``; force ``N, kN, lbf``; torque ``N m, kN m,
        in-lb``; mass ``kg, lb``.

    Returns
    -------
    A context manager: ``with ms.display_units("mm-deg"): ...`` restores the previous setting
    on exit; called alone the setting stays.
    """
    previous = _current[0]
    if preset is None:
        base = previous
    elif isinstance(preset, DisplayUnits):
        base = preset
    elif isinstance(preset, str) and preset in PRESETS:
        base = DisplayUnits(**PRESETS[preset])
    else:
        raise MechanismError(
            f"display units preset must be one of {', '.join(PRESETS)}, got {preset!r}"
        )
    changes = dict(length=length, angle=angle, force=force, torque=torque, mass=mass)
    new = replace(base, **{k: v for k, v in changes.items() if v is not None})
    _current[0] = new
    return _Setting(new, previous)


def current() -> DisplayUnits:
    """The display units in force."""
    return _current[0]


def convert(value, unit: str):
    """(value, unit) of an SI ``value`` in the current display units."""
    return current().convert(value, unit)


#: a thousand of a display unit, by name (mm -> m), for values that would need five digits
_KILO = {"mm": "m", "mm/s": "m/s", "mm/s^2": "m/s^2", "N": "kN", "N m": "kN m", "lbf": "klbf"}


def thousands(values, unit: str):
    """``(values, unit)`` of displayed values, in a thousand of ``unit`` when the largest
    magnitude reaches 10,000, so that tick labels keep at most four digits (300000 mm/s^2 is
    shown as 300 m/s^2, 250000 N as 250 kN)."""
    arr = np.asarray(values, dtype=float)
    finite = np.abs(arr[np.isfinite(arr)])
    if finite.size == 0 or not finite.max() >= 1e4:
        return values, unit
    return arr / 1e3, _KILO.get(unit, f"1000 {unit}")


def label(name: str, unit: str) -> str:
    """An axis or column label ``"name, unit"`` in display units (``name`` alone without a
    unit)."""
    shown = current().unit(unit)
    return f"{name}, {shown}" if shown else name


def fmt(value, unit: str, digits: int = 6) -> str:
    """``value`` (SI ``unit``) as ``"<number> <unit>"`` in display units, ``digits``
    significant digits."""
    v, shown = convert(float(value), unit)
    return f"{v:.{digits}g} {shown}".rstrip()


def angle_position(angle, unit: str | None = None):
    """A crank or link *position* (rad) wrapped into one turn and shown in the display angle
    unit: [0, 360) deg or [0, 2 pi) rad. ``unit`` overrides the setting."""
    a = np.mod(np.asarray(angle, dtype=float), 2.0 * np.pi)
    # within 1e-8 rad of a full turn is the start of the turn (no '360.000000 deg')
    a = np.where(a >= 2.0 * np.pi - 1e-8, 0.0, a)
    shown = unit or current().angle
    out = a / ANGLE[shown]
    return float(out) if out.ndim == 0 else out
