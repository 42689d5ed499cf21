"""Precision-point equations of function generation: Freudenstein's equation of the four-bar and
the loop equation of the slider-crank, both linear in suitable unknowns.

Four-bar (:class:`~mechsynth.kinematics.FourBar` conventions: crank pivot O1 at the origin,
rocker pivot O2 at ``(d, 0)``, crank angle ``phi`` of O1 -> A and rocker angle ``psi`` of
O2 -> B, both from +x counter-clockwise). Closing the loop ``|B - A| = b`` gives

    K1 cos(psi) - K2 cos(phi) + K3 = cos(phi - psi),
    K1 = d / a,  K2 = d / c,  K3 = (a^2 - b^2 + c^2 + d^2) / (2 a c),

linear in ``K1, K2, K3``: three pairs ``(phi_i, psi_i)`` fix them, more are fitted by least
squares. A negative ``a`` (or ``c``) is the crank (rocker) pointing the other way: the design
has length ``|a|`` and its crank angle is ``phi + pi`` (:func:`four_bar_lengths`).

Slider-crank (:class:`~mechsynth.kinematics.SliderCrank`: guide ``y = e``, slider position
``s`` the x of B). With crank ``r``, rod ``L`` and ``s = h + u`` (``h`` the slider's position
where the output range starts, ``u`` the prescribed travel from there),

    (2 u - 2 r cos(phi)) h - (2 r sin(phi)) e + K = 2 r u cos(phi) - u^2,
    K = h^2 + r^2 + e^2 - L^2,

linear in ``h, e, K`` for a given crank ``r``.
"""

from __future__ import annotations

import numpy as np

from ..errors import MechanismError

__all__ = [
    "chebyshev_spacing",
    "freudenstein_k",
    "four_bar_lengths",
    "slider_crank_coefficients",
    "slider_crank_lengths",
]

#: the precision-point systems are refused as degenerate beyond this condition number
MAX_CONDITION = 1e12


def chebyshev_spacing(x0: float, x1: float, n: int) -> np.ndarray:
    """Chebyshev's precision points on ``[x0, x1]``:
    ``x_j = (x0 + x1)/2 - (x1 - x0)/2 cos((2j - 1) pi / (2n))``, ``j = 1..n`` (increasing when
    ``x0 < x1``)."""
    j = np.arange(1, int(n) + 1)
    return 0.5 * (x0 + x1) - 0.5 * (x1 - x0) * np.cos((2 * j - 1) * np.pi / (2 * int(n)))


def _solve_rows(a, b, what: str):
    """Solve ``a k = b`` (exactly for 3 rows, in the least-squares sense for more), batched over
    leading axes; MechanismError when the rows are (nearly) dependent."""
    at = np.swapaxes(a, -1, -2)
    if a.shape[-2] == a.shape[-1]:
        m, rhs = a, b
    else:
        m, rhs = at @ a, (at @ b[..., None])[..., 0]
    cond = np.linalg.cond(a)
    bad = ~(cond < MAX_CONDITION)
    if np.all(bad):
        raise MechanismError(
            f"the {what} equations of these precision points are degenerate (condition number "
            f"{float(np.min(cond)):.3g}): two precision points are equal or the pairs are "
            "linearly dependent"
        )
    m = np.where(bad[..., None, None], np.eye(a.shape[-1]), m)
    k = np.linalg.solve(m, rhs[..., None])[..., 0]
    return np.where(bad[..., None], np.nan, k)


def freudenstein_k(phi, psi) -> np.ndarray:
    """``(K1, K2, K3)`` from precision pairs ``(phi_i, psi_i)`` (rad; arrays ``(..., n)``,
    ``n >= 3``): exact for three pairs, least squares on the equation's residual for more.
    Returns an array ``(..., 3)``; NaN rows where a batch's system is degenerate (all of them
    degenerate raises MechanismError)."""
    phi, psi = np.broadcast_arrays(np.asarray(phi, float), np.asarray(psi, float))
    a = np.stack([np.cos(psi), -np.cos(phi), np.ones_like(phi)], axis=-1)
    return _solve_rows(a, np.cos(phi - psi), "Freudenstein")


def four_bar_lengths(k, ground: float):
    """Link lengths and phase shifts of the four-bar with Freudenstein constants ``k``
    (``(..., 3)``) and ground ``d``.

    Returns ``(crank, coupler_squared, rocker, crank_shift, rocker_shift)``: the lengths
    ``|a|`` and ``|c|``, ``b^2`` (negative: no coupler closes the loop), and the angles (0 or
    pi) added to the prescribed crank and rocker angles where ``a`` or ``c`` came out negative
    (the same points reached by the link turned half a turn).
    """
    k = np.asarray(k, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        a = ground / k[..., 0]
        c = ground / k[..., 1]
        b2 = a * a + c * c + ground * ground - 2.0 * a * c * k[..., 2]
    return np.abs(a), b2, np.abs(c), np.where(a < 0, np.pi, 0.0), np.where(c < 0, np.pi, 0.0)


def slider_crank_coefficients(phi, u, crank: float) -> np.ndarray:
    """``(h, e, K)`` of the slider-crank loop equation (module notes) for precision pairs
    ``(phi_i, u_i)`` (rad, m; arrays ``(..., n)``) and the crank ``r``: exact for three pairs,
    least squares for more."""
    phi, u = np.broadcast_arrays(np.asarray(phi, float), np.asarray(u, float))
    c, s = np.cos(phi), np.sin(phi)
    a = np.stack([2.0 * u - 2.0 * crank * c, -2.0 * crank * s, np.ones_like(phi)], axis=-1)
    return _solve_rows(a, 2.0 * crank * u * c - u * u, "slider-crank")


def slider_crank_lengths(coef, crank: float):
    """``(s0, offset, rod_squared)`` from :func:`slider_crank_coefficients`: the slider's
    position where the output range starts, the guide's offset, and ``L^2`` (not positive: no
    rod closes the loop)."""
    coef = np.asarray(coef, float)
    h, e, kk = coef[..., 0], coef[..., 1], coef[..., 2]
    return h, e, h * h + crank * crank + e * e - kk
