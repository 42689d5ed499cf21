"""Ticks placed by the value density of a scale on the page.

A nomogram's scales are rarely uniform: a logarithmic or projective scale crowds its values at
one end. Ticks come from a nested ladder of steps (..., 10, 5, 1, 0.5, 0.1, ...: each step
divides the one before it) in the shown unit. A tick value belongs to the coarsest step it is a
multiple of. It is *labelled* where the distance on the page to its neighbours at that step
leaves room for its label (the label's extent along the scale plus a gap), drawn as a *major*
tick where they are at least 1.6 mm apart and as a *minor* tick down to 0.8 mm. So a log scale
is labelled 1, 2, 3, ... 10 where it is open and 10, 20, 50 where it is crowded, without a
collision.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Ticks", "ticks", "tick_text", "number_text"]

FONT_MM = 7.0 * 25.4 / 72.0  # 7 pt labels: the em, mm
LABEL_GAP = 1.0  # mm between neighbouring labels along a scale
MAJOR_MM = 1.6
MINOR_MM = 0.8


@dataclass(frozen=True)
class Ticks:
    """Tick values (shown unit) of one scale: ``labelled`` with their ``texts``, ``major``
    (unlabelled, long) and ``minor`` (short)."""

    labelled: np.ndarray
    texts: tuple[str, ...]
    major: np.ndarray
    minor: np.ndarray


def _ladder(lo: float, hi: float):
    """Steps from about the whole span down to a ten-thousandth of it: 10^k x (1, 0.5)."""
    top = 10.0 ** np.ceil(np.log10(hi - lo))
    steps = []
    s = top
    while s > (hi - lo) * 1e-4:
        steps += [s, s / 2.0]
        s /= 10.0
    return steps


def number_text(value: float, digits: int = 4) -> str:
    """A value for the margin: ``digits`` significant digits, whole numbers from 10,000 up
    grouped by thin spaces instead of an exponent."""
    v = float(value)
    if 1e4 <= abs(v) < 1e12:
        return f"{round(v):,}".replace(",", "\u2009")
    return f"{v:.{digits}g}"


def tick_text(value: float, step: float) -> str:
    """The label of a tick at ``value`` on a ladder step ``step``: as many decimals as the
    step needs, thousands grouped by a thin space above 9999."""
    d = max(0, int(-np.floor(np.log10(step) + 1e-9)))
    text = f"{value:.{d}f}"
    if text.startswith("-") and float(text) == 0.0:
        text = text[1:]
    whole = text.split(".")[0].lstrip("-")
    if len(whole) > 4:
        sign = "-" if text.startswith("-") else ""
        rest = text[len(sign) + len(whole):]
        grouped = f"{int(whole):,}".replace(",", "\u2009")
        text = sign + grouped + rest
    return text


def ticks(position, lo: float, hi: float, factor: float, vertical_text=True) -> Ticks:
    """Ticks of a scale shown as ``value / factor`` over ``[lo, hi]`` (SI).

    Parameters
    ----------
    position : ``values (SI, n) -> (n, 2)`` page points in mm.
    lo, hi : the domain (SI).
    factor : size in SI of one shown unit.
    vertical_text : labels written horizontally (the text's height lies along a vertical
        scale, its width along a horizontal one).
    """
    a, b = sorted((lo / factor, hi / factor))
    eps = 1e-9 * (b - a)
    done: dict[float, tuple[str, float]] = {}  # value -> (kind, step)
    for step in _ladder(a, b):
        k0, k1 = int(np.ceil((a - eps) / step)), int(np.floor((b + eps) / step))
        if k1 - k0 > 20000:
            break
        ks = np.arange(k0, k1 + 1)
        vals = ks * step
        keys = np.round(vals, 12)
        new = np.array([k not in done for k in keys.tolist()], dtype=bool)
        if not new.any():
            continue
        p = position(vals * factor)
        pm = position(np.clip(vals - step, a, b) * factor)
        pp = position(np.clip(vals + step, a, b) * factor)
        dm = np.hypot(*(p - pm).T)
        dp = np.hypot(*(pp - p).T)
        at_lo, at_hi = vals - step < a - eps, vals + step > b + eps
        gap = np.minimum(np.where(at_lo, np.inf, dm), np.where(at_hi, np.inf, dp))
        tangent = pp - pm
        tangent /= np.maximum(np.hypot(*tangent.T), 1e-12)[:, None]
        idx = np.flatnonzero(new)
        width = np.array([0.55 * FONT_MM * len(tick_text(v, step)) for v in vals[idx]])
        height = 0.75 * FONT_MM
        # the label's extent along the scale
        extent = np.abs(tangent[idx, 0]) * width + np.abs(tangent[idx, 1]) * height
        for i, ext in zip(idx, extent, strict=True):
            v = float(keys[i])
            if gap[i] >= ext + LABEL_GAP:
                done[v] = ("label", step)
            elif gap[i] >= MAJOR_MM:
                done[v] = ("major", step)
            elif gap[i] >= MINOR_MM:
                done[v] = ("minor", step)
        if np.all(gap < MINOR_MM):
            break
    labelled = sorted(v for v, (kind, _) in done.items() if kind == "label")
    texts = tuple(tick_text(v, done[v][1]) for v in labelled)
    major = sorted(v for v, (kind, _) in done.items() if kind == "major")
    minor = sorted(v for v, (kind, _) in done.items() if kind == "minor")
    return Ticks(np.array(labelled), texts, np.array(major), np.array(minor))
