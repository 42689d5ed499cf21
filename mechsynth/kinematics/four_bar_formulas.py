"""Closed-form four-bar formulas of paper 000 (one-armed beam pumping unit), checked and corrected.

Notation of the paper: crank ``r`` (O1A), coupler/pitman ``l`` (AB), rocker/rear beam arm ``k``
(O2B), ground ``d`` = |O1O2|. In the paper's auxiliary frame (x along O1 -> O2, which is the frame
of :class:`~mechsynth.kinematics.FourBar`) the loop is ``r e^{i phi1} + l e^{i phi2} = d +
k e^{i phi3}`` (5): ``phi1`` crank angle, ``phi2`` coupler angle (A -> B), ``phi3`` rocker angle
(O2 -> B), all from +x, counter-clockwise, in rad.

* Position functions (6)-(7)::

      q = d - r cos(phi1),  p = r sin(phi1),  tan(beta) = p / q
      a = (l^2 + q^2 + p^2 - k^2) / (2 q l),  b = (q^2 + k^2 + p^2 - l^2) / (2 q k)
      phi2 = arccos(a cos(beta)) - beta,   phi3 = pi - arccos(b cos(beta)) - beta

  These are the ``"open"`` branch of FourBar (B to the left of A -> O2). With ``sigma = -1`` in
  front of both arccos terms they give the ``"crossed"`` branch. ``beta`` is taken as
  ``arctan2(p, q)`` (not ``arctan(p/q)``), which keeps (6)-(7) right when ``q < 0`` (crank longer
  than the ground); the products ``a cos(beta)`` and ``b cos(beta)`` are evaluated as
  ``(l^2 + rho^2 - k^2) / (2 l rho)`` and ``(k^2 + rho^2 - l^2) / (2 k rho)`` with
  ``rho = |AO2| = hypot(p, q)``, equal to the printed products but finite at ``q = 0``.

* Velocity ratios (11), from the differentiated loop (8): ``omega2 = omega1 U2``,
  ``omega3 = omega1 U3`` with ::

      U2 = r sin(phi3 - phi1) / (l sin(phi2 - phi3))      (printed: sin(phi1 - phi3), wrong sign)
      U3 = r sin(phi2 - phi1) / (k sin(phi2 - phi3))      (as printed)

* Derivatives ``U' = dU/dphi1`` and the angular accelerations (12)
  ``eps_i = eps1 U_i + omega1^2 U_i'``, derived here from (11) with ``phi2' = U2``,
  ``phi3' = U3``::

      U2' = r [(U3 - 1) cos(phi3 - phi1) sin(phi2 - phi3)
               - (U2 - U3) cos(phi2 - phi3) sin(phi3 - phi1)] / (l sin^2(phi2 - phi3))
      U3' = r [(U2 - 1) cos(phi2 - phi1) sin(phi2 - phi3)
               - (U2 - U3) cos(phi2 - phi3) sin(phi2 - phi1)] / (k sin^2(phi2 - phi3))

Errata in paper 000 (reproduced by :func:`printed_velocity_ratio_derivatives` and shown wrong by
the tests against finite differences):

1. (9) and (11) print ``U2 = r sin(phi1 - phi3) / (l sin(phi2 - phi3))``: solving (8) gives the
   opposite sign, ``sin(phi3 - phi1)`` (checked against finite differences of (6) and against
   the RRR dyad). U3 (10)-(11) is right.
2. (12) prints ``eps_i = eps1 U_i + omega1^2 U_i``; the second term must be ``omega1^2 U_i'``.
3. (13) puts the factor ``r`` on the first term of the bracket only; it multiplies the whole
   bracket. With the sign of U2 corrected the bracket of U2' changes sign as well (the printed
   bracket, with ``r`` outside, is minus the correct one).
4. (14) has the same misplaced ``r`` and, in addition, the angles of the numerator ``sin(phi2 -
   phi1)`` of U3 are replaced by ``phi1 - phi3`` in both terms: it must read ``cos(phi2 - phi1)``
   and ``sin(phi2 - phi1)``.

All functions broadcast over crank angles and arrays of designs and accept CasADi symbols (they
are written with :mod:`mechsynth.kinematics.ops`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import MechanismError
from . import ops
from .mechanism import check_length

__all__ = [
    "PaperFourBar",
    "position_coefficients",
    "position_functions",
    "velocity_ratios",
    "printed_velocity_ratios",
    "velocity_ratio_derivatives",
    "printed_velocity_ratio_derivatives",
    "paper_four_bar",
]

_SIGMA = {"open": 1.0, "crossed": -1.0}
_RTOL = 1e-12


def _sigma(branch) -> float:
    if branch not in _SIGMA:
        raise MechanismError(f"branch must be 'open' or 'crossed', got {branch!r}")
    return _SIGMA[branch]


def _checked_lengths(r, l, k, d):
    return tuple(check_length(n, v) for n, v in (("r", r), ("l", l), ("k", k), ("d", d)))


def position_coefficients(phi1, r, l, k, d):
    """The auxiliary quantities of (6)-(7) as printed: ``q, p, beta, a, b``.

    ``a`` and ``b`` divide by ``q`` (infinite at ``q = 0``); :func:`position_functions` uses the
    equivalent finite products ``a cos(beta)``, ``b cos(beta)`` instead.
    """
    q = d - r * ops.cos(phi1)
    p = r * ops.sin(phi1)
    beta = ops.arctan2(p, q)
    a = (l * l + q * q + p * p - k * k) / (2.0 * q * l)
    b = (q * q + k * k + p * p - l * l) / (2.0 * q * k)
    return q, p, beta, a, b


def _check_cosine(value, what, phi1):
    """MechanismError where |value| > 1 beyond round-off; clamp only the round-off excess."""
    if ops.is_symbolic(value):
        return value
    value = np.asarray(value, dtype=float)
    bad = np.abs(value) > 1.0 + _RTOL
    if np.any(bad):
        idx = np.unravel_index(int(np.argmax(bad)), bad.shape)
        at = ""
        if not ops.is_symbolic(phi1):
            ph = np.broadcast_to(np.asarray(phi1, dtype=float), bad.shape)[idx]
            at = f" at crank angle {np.rad2deg(ph):.6g} deg"
        raise MechanismError(
            f"{what} = {value[idx]:.6g} outside [-1, 1]{at}: the four-bar cannot be assembled "
            "(|AO2| outside [|l - k|, l + k])"
        )
    return np.clip(value, -1.0, 1.0)


def position_functions(phi1, r, l, k, d, branch="open"):
    """Coupler and rocker angles ``(phi2, phi3)`` (rad) by the position functions (6)-(7).

    Parameters
    ----------
    phi1 : crank angle(s), rad.
    r, l, k, d : crank, coupler, rocker and ground lengths (m), > 0; arrays broadcast.
    branch : ``"open"`` (the paper's formulas) or ``"crossed"``.

    Returns
    -------
    phi2, phi3 : coupler angle in (-3 pi / 2, pi] and rocker angle in (-pi / 2, 2 pi) (not
        wrapped; compare modulo 2 pi with other angle sources).

    Raises
    ------
    MechanismError where the loop cannot close (``|a cos(beta)| > 1``).
    """
    r, l, k, d = _checked_lengths(r, l, k, d)
    sigma = _sigma(branch)
    q = d - r * ops.cos(phi1)
    p = r * ops.sin(phi1)
    beta = ops.arctan2(p, q)
    rho = ops.hypot(p, q)
    a_cos = _check_cosine((l * l + rho * rho - k * k) / (2.0 * l * rho), "a cos(beta)", phi1)
    b_cos = _check_cosine((k * k + rho * rho - l * l) / (2.0 * k * rho), "b cos(beta)", phi1)
    phi2 = sigma * ops.arccos(a_cos) - beta
    phi3 = np.pi - sigma * ops.arccos(b_cos) - beta
    return phi2, phi3


def velocity_ratios(phi1, phi2, phi3, r, l, k):
    """Velocity ratios (analogs) ``U2 = dphi2/dphi1`` and ``U3 = dphi3/dphi1`` of (11), with the
    sign of U2 corrected (see the module docstring)."""
    s23 = ops.sin(phi2 - phi3)
    u2 = r * ops.sin(phi3 - phi1) / (l * s23)
    u3 = r * ops.sin(phi2 - phi1) / (k * s23)
    return u2, u3


def printed_velocity_ratios(phi1, phi2, phi3, r, l, k):
    """U2, U3 exactly as printed in (11) of paper 000 (U2 has the wrong sign)."""
    s23 = ops.sin(phi2 - phi3)
    return r * ops.sin(phi1 - phi3) / (l * s23), r * ops.sin(phi2 - phi1) / (k * s23)


def velocity_ratio_derivatives(phi1, phi2, phi3, u2, u3, r, l, k):
    """Correct ``U2' = dU2/dphi1`` and ``U3' = dU3/dphi1`` (rad^-1), derived from (11).

    These are the angular acceleration analogs of coupler and rocker: with crank speed
    ``omega1`` and acceleration ``eps1``, ``eps_i = eps1 U_i + omega1^2 U_i'``.
    """
    s23, c23 = ops.sin(phi2 - phi3), ops.cos(phi2 - phi3)
    s31, c31 = ops.sin(phi3 - phi1), ops.cos(phi3 - phi1)
    s21, c21 = ops.sin(phi2 - phi1), ops.cos(phi2 - phi1)
    du2 = r * ((u3 - 1.0) * c31 * s23 - (u2 - u3) * c23 * s31) / (l * s23 * s23)
    du3 = r * ((u2 - 1.0) * c21 * s23 - (u2 - u3) * c23 * s21) / (k * s23 * s23)
    return du2, du3


def printed_velocity_ratio_derivatives(phi1, phi2, phi3, u2, u3, r, l, k):
    """U2', U3' exactly as printed in (13)-(14) of paper 000 (wrong; kept to document the
    erratum, see the module docstring). ``u2``, ``u3`` are the ratios to insert (the paper's own
    are :func:`printed_velocity_ratios`)."""
    s23, c23 = ops.sin(phi2 - phi3), ops.cos(phi2 - phi3)
    s13, c13 = ops.sin(phi1 - phi3), ops.cos(phi1 - phi3)
    du2 = (r * (1.0 - u3) * c13 * s23 - (u2 - u3) * c23 * s13) / (l * s23 * s23)
    du3 = (r * (u2 - 1.0) * c13 * s23 - (u2 - u3) * c23 * s13) / (k * s23 * s23)
    return du2, du3


@dataclass(frozen=True)
class PaperFourBar:
    """Angles and ratios of the four-bar by the formulas of paper 000 (arrays broadcast over
    designs and crank angles).

    Attributes
    ----------
    phi2, phi3 : coupler and rocker angles (rad), unwrapped as in :func:`position_functions`.
    u2, u3 : velocity ratios (11) (dimensionless, = angular velocity analogs).
    du2, du3 : their crank-angle derivatives (rad^-1, = angular acceleration analogs).
    """

    phi2: Any
    phi3: Any
    u2: Any
    u3: Any
    du2: Any
    du3: Any

    def angular_velocities(self, omega1):
        """``(omega2, omega3) = omega1 (U2, U3)`` in rad/s for crank speed ``omega1``."""
        return omega1 * self.u2, omega1 * self.u3

    def angular_accelerations(self, omega1, eps1=0.0):
        """``eps_i = eps1 U_i + omega1^2 U_i'`` (rad/s^2), formula (12) corrected."""
        return (
            eps1 * self.u2 + omega1 * omega1 * self.du2,
            eps1 * self.u3 + omega1 * omega1 * self.du3,
        )


def paper_four_bar(phi1, r, l, k, d, branch="open") -> PaperFourBar:
    """All of (6)-(7), (11) and the corrected U' for crank angles ``phi1`` (rad).

    Examples
    --------
    >>> import numpy as np
    >>> from mechsynth.kinematics.four_bar_formulas import paper_four_bar
    >>> res = paper_four_bar(np.deg2rad(30.0), r=1.068, l=4.3, k=3.0, d=5.0)
    >>> print(f"{res.u2:.6f} {res.u3:.6f}")
    -0.255992 -0.028976
    """
    phi2, phi3 = position_functions(phi1, r, l, k, d, branch)
    u2, u3 = velocity_ratios(phi1, phi2, phi3, r, l, k)
    du2, du3 = velocity_ratio_derivatives(phi1, phi2, phi3, u2, u3, r, l, k)
    return PaperFourBar(phi2, phi3, u2, u3, du2, du3)
