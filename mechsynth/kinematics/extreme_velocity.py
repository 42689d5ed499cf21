"""Extreme slider velocities of the offset slider-crank (Dzhavadyan, paper 004), exactly.

The paper's notation, with the crank OA = 1: rod ``i = b/a``, offset ``e0 = e/a`` and

    m0 = sqrt(i^2 - (e0 + sin phi)^2)                                        (1)
    s0 = sin phi + (e0 + sin phi) cos phi / m0                               (2)

``s0`` is the slider velocity analog per crank length measured *towards* the crank pivot. With
``u = sin phi``, ``w = e0 + u`` and ``c^2 = 1 - u^2`` the extremum condition ``s0' = 0`` reads
``c m0^3 = -[(1 - u^2) m0^2 - w u m0^2 + w^2 (1 - u^2)]``; squaring gives a polynomial of degree 6
in ``u`` (the ``u^8`` and ``u^7`` terms cancel)::

    p6 = 1 - i^2
    p5 = 2 e0 (3 - i^2)
    p4 = i^2 (i^2 - 1) + 15 e0^2
    p3 = 2 e0 (e0^2 i^2 + 10 e0^2 - i^4 - 3 i^2)
    p2 = i^4 (i^2 - 1) + e0^2 (15 e0^2 + e0^2 i^2 - 2 i^4 - 12 i^2)
    p1 = 2 e0 (3 e0^4 + 2 i^4 - 5 e0^2 i^2)
    p0 = i^4 - (i^2 - e0^2)^3

The printed equation (4) differs in three places (see :data:`ERRATA`). Squaring adds spurious
roots (those of ``c m0^3 = +[...]``); each real root ``u`` gives two crank angles ``asin u`` and
``pi - asin u``, and only those where ``s0'`` vanishes are kept.

Sign conventions in mechsynth: the guide is ``y = offset`` and the slider position is the x of B,
so the paper's offset is ``e = -offset`` and its ``s0 = -(dx_B/dphi) / a``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import MechanismError

__all__ = [
    "ERRATA",
    "Extremum",
    "ExtremeVelocity",
    "polynomial_coefficients",
    "printed_coefficients",
    "velocity_analog",
    "velocity_analog_derivative",
    "extreme_velocity",
    "stroke_crank_angle",
]

ERRATA = (
    "Paper 004, eq. (4): the leading term is printed as p0 sin^6; it is p6 sin^6.",
    "Paper 004, eq. (4): p3 is printed 2e0(10e0^2 - e0^2 i^2 - i^4 - 3i^2); the e0^2 i^2 term "
    "has the wrong sign: p3 = 2e0(e0^2 i^2 + 10e0^2 - i^4 - 3i^2).",
    "Paper 004, eq. (4): p0 is printed i^4(1 - i^2) + e0^2(e0^2 - 3i^4 - 3e0^2 i^2); it is "
    "i^4(1 - i^2) + e0^2(e0^4 - 3e0^2 i^2 + 3i^4) = i^4 - (i^2 - e0^2)^3.",
)


def polynomial_coefficients(i, e0):
    """Coefficients ``(p6, p5, ..., p0)`` of the extremum condition (4), derived (see module).

    ``i`` and ``e0`` broadcast; the result has a leading axis of length 7, highest power first.
    """
    i = np.asarray(i, dtype=float)
    e0 = np.asarray(e0, dtype=float)
    i2, e2 = i * i, e0 * e0
    i4 = i2 * i2
    return np.stack(
        np.broadcast_arrays(
            1.0 - i2,
            2.0 * e0 * (3.0 - i2),
            i2 * (i2 - 1.0) + 15.0 * e2,
            2.0 * e0 * (e2 * i2 + 10.0 * e2 - i4 - 3.0 * i2),
            i4 * (i2 - 1.0) + e2 * (15.0 * e2 + e2 * i2 - 2.0 * i4 - 12.0 * i2),
            2.0 * e0 * (3.0 * e2 * e2 + 2.0 * i4 - 5.0 * e2 * i2),
            i4 - (i2 - e2) ** 3,
        )
    )


def printed_coefficients(i, e0):
    """The coefficients of eq. (4) exactly as printed in paper 004 (wrong for ``e0 != 0``), kept to
    document the erratum; same layout as :func:`polynomial_coefficients`. They differ from the
    derived ones in ``p3`` and ``p0`` only (see :data:`ERRATA`)."""
    coeffs = polynomial_coefficients(i, e0)
    i2 = np.asarray(i, dtype=float) ** 2
    e2 = np.asarray(e0, dtype=float) ** 2
    i4 = i2 * i2
    coeffs[3] = 2.0 * np.asarray(e0, dtype=float) * (10.0 * e2 - e2 * i2 - i4 - 3.0 * i2)
    coeffs[6] = i4 * (1.0 - i2) + e2 * (e2 - 3.0 * i4 - 3.0 * e2 * i2)
    return coeffs


def velocity_analog(phi, i, e0):
    """The paper's ``s0(phi)`` (2): slider velocity analog per crank length, towards the pivot."""
    s, c = np.sin(phi), np.cos(phi)
    w = e0 + s
    return s + w * c / np.sqrt(i * i - w * w)


def velocity_analog_derivative(phi, i, e0):
    """``ds0/dphi`` (the acceleration analog per crank length), from (1)-(3) simplified:
    ``c + (c^2 - w u) / m0 + w^2 c^2 / m0^3``."""
    s, c = np.sin(phi), np.cos(phi)
    w = e0 + s
    m = np.sqrt(i * i - w * w)
    return c + (c * c - w * s) / m + (w * c) ** 2 / m**3


def _real_roots(coeffs):
    """All roots of the degree-6 polynomials ``coeffs`` (shape (7, *batch)) via batched companion
    matrices; returns complex roots of shape (*batch, 6)."""
    c = np.moveaxis(coeffs, 0, -1)
    batch = c.shape[:-1]
    comp = np.zeros(batch + (6, 6))
    comp[..., 0, :] = -c[..., 1:] / c[..., :1]
    comp[..., np.arange(1, 6), np.arange(5)] = 1.0
    return np.linalg.eigvals(comp)


@dataclass(frozen=True)
class Extremum:
    """One extreme of the slider velocity analog: crank ``angle`` (rad, in [0, 2 pi)) and the
    ``value`` (m/rad, along +x of the guide), with the ``lambda_s`` velocity coefficient of the
    stroke it lies in (peak over mean speed of that stroke, eq. 6)."""

    angle: np.ndarray | float
    value: np.ndarray | float
    lambda_s: np.ndarray | float


@dataclass(frozen=True)
class ExtremeVelocity:
    """Both extremes of the slider velocity analog ``dx_B/dphi`` over a crank turn."""

    maximum: Extremum
    minimum: Extremum
    stroke: np.ndarray | float
    inward_span: np.ndarray | float
    outward_span: np.ndarray | float


def stroke_crank_angle(crank, rod, offset):
    """Paper 004's (7): the crank rotation ``phi_u`` (rad) for the stroke during which the crank
    turns the larger way round, ``pi + arccos((2(b^2 + a^2) - S_u^2) / (2(b^2 - a^2)))`` for an
    offset slider-crank (the other stroke takes ``2 pi - phi_u``); ``pi`` for a centric one."""
    a, b, e = (np.asarray(v, dtype=float) for v in (crank, rod, offset))
    s_u = np.sqrt((b + a) ** 2 - e * e) - np.sqrt((b - a) ** 2 - e * e)
    cos_t = (2.0 * (b * b + a * a) - s_u * s_u) / (2.0 * (b * b - a * a))
    return np.pi + np.arccos(np.minimum(cos_t, 1.0))


#: largest rod/crank ratio for which the polynomial's roots are resolved (tested to 1e6)
MAX_RATIO = 1e6


def extreme_velocity(crank, rod, offset=0.0, residual_tol=1e-7, check_points=720):
    """Maximum and minimum of the slider velocity analog of ``SliderCrank(crank, rod, offset)``.

    Solves the derived degree-6 polynomial (batched over designs), keeps the roots where the
    acceleration analog truly vanishes, and confirms the result against ``check_points`` samples
    of the velocity analog (an internal consistency check that raises ``RuntimeError`` if the
    polynomial missed an extremum). Parameters broadcast; lengths in m, offset signed as in
    :class:`~mechsynth.kinematics.SliderCrank`.
    """
    a, b, off = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (crank, rod, offset)))
    i, e0 = b / a, -off / a
    if np.any(i > MAX_RATIO):
        raise MechanismError(
            f"extreme_velocity: rod/crank {float(np.max(i)):.3g} is above {MAX_RATIO:g}: the "
            "degree-6 polynomial's roots drown in round-off there (the velocity analog is then "
            "within (crank/rod)^2 of a pure sine's, whose extremes are +-crank at 90 and 270 deg)"
        )
    roots = _real_roots(polynomial_coefficients(i, e0))  # (*batch, 6)
    real = np.abs(roots.imag) <= 1e-9 * (1.0 + np.abs(roots.real))
    u = roots.real
    # Round-off can put a root of sin(phi) = +-1 a hair outside [-1, 1]; beyond 1e-9 it is no angle.
    real &= np.abs(u) <= 1.0 + 1e-9
    base = np.arcsin(np.clip(u, -1.0, 1.0))
    cand = np.concatenate([base, np.pi - base], axis=-1)  # (*batch, 12)
    ok = np.concatenate([real, real], axis=-1)
    ib, eb = i[..., None], e0[..., None]
    w = eb + np.sin(cand)
    ok &= w * w < ib * ib
    safe = np.where(ok, cand, 0.0)
    s0 = velocity_analog(safe, ib, eb)
    ds0 = velocity_analog_derivative(safe, ib, eb)
    ok &= np.abs(ds0) <= residual_tol * (1.0 + np.abs(s0))
    if not np.all(ok.any(axis=-1)):
        raise RuntimeError(
            "extreme_velocity: no root of the extremum polynomial was a true extremum"
        )
    v = -a[..., None] * s0  # dx_B/dphi
    kmax = np.argmax(np.where(ok, v, -np.inf), axis=-1)[..., None]
    kmin = np.argmin(np.where(ok, v, np.inf), axis=-1)[..., None]
    vmax = np.take_along_axis(v, kmax, -1)[..., 0]
    vmin = np.take_along_axis(v, kmin, -1)[..., 0]
    pmax = np.mod(np.take_along_axis(cand, kmax, -1)[..., 0], 2 * np.pi)
    pmin = np.mod(np.take_along_axis(cand, kmin, -1)[..., 0], 2 * np.pi)

    grid = np.linspace(0.0, 2 * np.pi, check_points, endpoint=False)
    vg = -a[..., None] * velocity_analog(grid, ib, eb)
    slack = 1e-9 * a
    if np.any(vg.max(axis=-1) > vmax + slack) or np.any(vg.min(axis=-1) < vmin - slack):
        raise RuntimeError("extreme_velocity: the polynomial roots missed an extremum")

    stroke = np.sqrt((b + a) ** 2 - off**2) - np.sqrt((b - a) ** 2 - off**2)
    outer = np.arcsin(off / (a + b))
    inner = np.pi + np.arcsin(off / (b - a))
    inward = inner - outer
    outward = 2 * np.pi - inward
    # The maximum (v > 0) lies in the outward stroke, the minimum in the inward one.
    lam_max = vmax * outward / stroke
    lam_min = -vmin * inward / stroke

    def _out(x):
        return float(x) if np.ndim(x) == 0 else x

    return ExtremeVelocity(
        maximum=Extremum(_out(pmax), _out(vmax), _out(lam_max)),
        minimum=Extremum(_out(pmin), _out(vmin), _out(lam_min)),
        stroke=_out(stroke),
        inward_span=_out(inward),
        outward_span=_out(outward),
    )
