"""Scales of a nomogram: a variable's values mapped to points of the plane.

A :class:`Scale` holds the *base* map of its variable, ``value -> (f, g, h)``: homogeneous
coordinates, the rows of the nomographic determinant. The page position is that row through
the nomogram's projective transform (:mod:`mechsynth.nomograms.layout`), so a scale here knows
nothing of paper, millimetres or matplotlib. Values are SI; the shown unit of a scale comes from
the display units (:mod:`mechsynth.display`) or from the scale's own ``shown`` table for
quantities the display units do not cover (barrels a day, strokes a minute).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from .. import display
from ..errors import MechanismError

__all__ = ["Scale", "Grid", "shown_unit", "homogeneous", "base_curves"]


def homogeneous(f, g, h=1.0):
    """Stack the three rows of a determinant into an ``(n, 3)`` array (broadcast)."""
    f, g, h = np.broadcast_arrays(
        np.asarray(f, dtype=float), np.asarray(g, dtype=float), np.asarray(h, dtype=float)
    )
    return np.stack([f, g, h], axis=-1)


@dataclass(frozen=True)
class Scale:
    """One variable's scale in the base frame of a nomogram.

    Parameters
    ----------
    name : the variable's keyword in :meth:`Nomogram.read` (``"rod_crank"``).
    xyz : ``values (n,) -> (n, 3)`` homogeneous base coordinates ``(f, g, h)``; the point is
        ``(f / h, g / h)`` before the page transform.
    domain : ``(low, high)`` of the drawn part, in SI.
    title : the printed name (``"rod / crank"``); the name when empty.
    unit : the SI unit of the values (``"m"``, ``"N m"``, ``"rad"``, ``""`` for a ratio); the
        display units decide how it is shown.
    spacing : ``"linear"`` or ``"log"``: how values are sampled when the scale is searched,
        fitted or checked (log for ranges of positive values over a decade or more).
    turning : an unlabelled turning axis of a compound chart (no ticks; its values are those of
        the blocks' intermediate quantity).
    shown : ``{preset: (size in SI of one shown unit, label)}`` for units the display units do
        not know; the key ``"*"`` serves every preset.
    """

    name: str
    xyz: Callable[[np.ndarray], np.ndarray]
    domain: tuple[float, float]
    title: str = ""
    unit: str = ""
    spacing: str = "linear"
    turning: bool = False
    shown: Mapping[str, tuple[float, str]] = field(default_factory=dict)

    def __post_init__(self):
        lo, hi = (float(v) for v in self.domain)
        if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
            raise MechanismError(
                f"scale {self.name}: domain must be two finite numbers low < high, got "
                f"{self.domain}"
            )
        if self.spacing not in ("linear", "log"):
            raise MechanismError(
                f"scale {self.name}: spacing must be 'linear' or 'log', got {self.spacing!r}"
            )
        if self.spacing == "log" and lo <= 0.0:
            raise MechanismError(
                f"scale {self.name}: a log spacing needs positive values, domain {self.domain}"
            )
        object.__setattr__(self, "domain", (lo, hi))
        if not self.title:
            object.__setattr__(self, "title", self.name)

    # -------------------------------------------------------------- parameter <-> value
    def to_param(self, values):
        """Values -> the sampling parameter in [0, 1] over the domain (linear or log)."""
        lo, hi = self.domain
        v = np.asarray(values, dtype=float)
        if self.spacing == "log":
            return np.log(v / lo) / np.log(hi / lo)
        return (v - lo) / (hi - lo)

    def from_param(self, t):
        """The sampling parameter (0 at the low end, 1 at the high end) -> values."""
        lo, hi = self.domain
        t = np.asarray(t, dtype=float)
        if self.spacing == "log":
            return lo * (hi / lo) ** t
        return lo + t * (hi - lo)

    def sample(self, n: int = 101):
        """``n`` values over the domain, evenly spaced in the sampling parameter."""
        return self.from_param(np.linspace(0.0, 1.0, n))

    def base(self, values) -> np.ndarray:
        """Homogeneous base coordinates ``(n, 3)`` of ``values`` (SI)."""
        v = np.atleast_1d(np.asarray(values, dtype=float))
        out = np.asarray(self.xyz(v), dtype=float)
        if out.shape != v.shape + (3,):
            raise MechanismError(
                f"scale {self.name}: its map must give (n, 3) homogeneous rows, got shape "
                f"{out.shape} for {v.shape[0]} values"
            )
        return out

    def label(self) -> str:
        """``"title, unit"`` in the display units (the title alone for a ratio)."""
        _, unit = shown_unit(self)
        return f"{self.title}, {unit}" if unit else self.title


def shown_unit(scale: Scale) -> tuple[float, str]:
    """(size in SI of one shown unit, its label) for ``scale`` under the current display
    units: divide SI values by the size to show them."""
    preset = display.current().name
    if scale.shown:
        if preset in scale.shown:
            return scale.shown[preset]
        if "*" in scale.shown:
            return scale.shown["*"]
    if not scale.unit:
        return 1.0, ""
    du = display.current()
    return du.factor(scale.unit), du.unit(scale.unit)


@dataclass(frozen=True)
class Grid:
    """A two-variable (grid) scale: a point of the plane for each pair of values, drawn as the
    two families of curves on which one variable is constant.

    Parameters
    ----------
    name : the grid's name in the blocks.
    axes : two :class:`Scale` objects describing its variables (name, domain, title, unit,
        spacing, shown units); their ``xyz`` is not used.
    xyz : ``(a, b) -> (n, 3)`` homogeneous base coordinates of the value pairs (broadcast).
    """

    name: str
    axes: tuple[Scale, Scale]
    xyz: Callable[[np.ndarray, np.ndarray], np.ndarray]
    turning: bool = False

    def __post_init__(self):
        if len(self.axes) != 2 or self.axes[0].name == self.axes[1].name:
            raise MechanismError(f"grid {self.name}: give two differently named variables")

    @property
    def variables(self) -> tuple[str, str]:
        return (self.axes[0].name, self.axes[1].name)

    def base(self, a, b) -> np.ndarray:
        """Homogeneous base coordinates ``(..., 3)`` of the value pairs (SI, broadcast)."""
        a, b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
        out = np.asarray(self.xyz(a.ravel(), b.ravel()), dtype=float)
        if out.shape != (a.size, 3):
            raise MechanismError(
                f"grid {self.name}: its map must give (n, 3) homogeneous rows, got {out.shape}"
            )
        return out.reshape(a.shape + (3,))

    def curves(self, n: int = 64, lines: int = 5) -> list[np.ndarray]:
        """Base points of ``lines`` curves of each family (the edges included), ``(n, 3)``
        each: what the layout keeps on the page."""
        t = np.linspace(0.0, 1.0, n)
        out = []
        for k in np.linspace(0.0, 1.0, lines):
            a, b = self.axes[0].from_param(t), self.axes[1].from_param(np.full(n, k))
            out.append(self.base(a, b))
            a, b = self.axes[0].from_param(np.full(n, k)), self.axes[1].from_param(t)
            out.append(self.base(a, b))
        return out


def base_curves(item, n: int = 64) -> list[np.ndarray]:
    """The base points a layout must place for a :class:`Scale` or a :class:`Grid`."""
    if isinstance(item, Grid):
        return item.curves(n)
    return [item.base(item.sample(n))]
