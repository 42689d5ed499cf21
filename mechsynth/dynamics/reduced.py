"""Reduced (to the crank) moment of inertia and reduced moments of applied loads.

Conventions: the crank angle ``phi`` is the independent coordinate; analog velocities are
velocities per unit crank speed (``v / omega``). A reduced moment follows from power
equivalence, ``M_red = sum F . v / omega``; it is positive when it drives the crank forward.
The gravity moment of a body is ``M_G = m g_vec . v_S / omega`` (paper 001, eq. (11), with any
gravity direction: tilt angle measured from -y, counter-clockwise).
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import MechanismError
from .inertia import com_track, reduced_inertia

__all__ = ["ReducedModel", "reduced_model", "gravity_moment", "point_force_moment"]

G = 9.80665
_TURN = 2.0 * math.pi


def gravity_moment(mechanism, bodies, phi, g=G, tilt=0.0):
    """Reduced gravity moment (N m) and its derivative over ``phi`` (exact, from analogs).

    Gravity acts along ``(sin tilt, -cos tilt) * g``.
    """
    m = mechanism.motion(phi)
    gx, gy = g * np.sin(tilt), -g * np.cos(tilt)
    mg = 0.0
    dmg = 0.0
    for body in bodies:
        t = com_track(m, body)
        mg = mg + body.mass * (gx * t.vx + gy * t.vy)
        dmg = dmg + body.mass * (gx * t.ax + gy * t.ay)
    return np.asarray(mg, dtype=float), np.asarray(dmg, dtype=float)


def point_force_moment(mechanism, point, force, phi, omega=None):
    """Reduced moment (N m) of a force ``force(phi, omega) -> (Fx, Fy)`` at point ``point``.

    ``M = F . v_point / omega`` (power equivalence).
    """
    m = mechanism.motion(phi)
    p = m.points[point]
    fx, fy = force(phi, omega)
    return np.asarray(fx * p.vx + fy * p.vy, dtype=float)


@dataclass(frozen=True)
class ReducedModel:
    """Periodic reduced model of a machine on the crank: inertia ``J(phi)`` and moments.

    ``J`` and the position-only moment ``M_phi`` are periodic cubic Hermite splines over a
    crank-angle grid (exact derivatives at the nodes); ``extra`` are callables
    ``(phi, omega) -> moment`` (N m, positive driving) evaluated at run time, for speed-dependent
    loads. ``flywheel`` is a constant inertia (kg m^2) added at the crank.
    """

    phi_grid: np.ndarray
    j_grid: np.ndarray
    dj_grid: np.ndarray
    m_grid: np.ndarray
    dm_grid: np.ndarray | None = None
    extra: tuple = ()
    flywheel: float = 0.0
    _splines: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        phi = np.asarray(self.phi_grid, dtype=float)
        for name in ("phi_grid", "j_grid", "dj_grid", "m_grid"):
            a = np.asarray(getattr(self, name), dtype=float)
            if a.shape != phi.shape or not np.all(np.isfinite(a)):
                raise MechanismError(
                    f"{name} must be finite with the shape of phi_grid {phi.shape}"
                )
        if phi.ndim != 1 or phi.size < 4 or np.any(np.diff(phi) <= 0):
            raise MechanismError("phi_grid must be 1-D, increasing, with at least 4 angles")
        if abs(phi[-1] - phi[0] - 2 * np.pi) > 1e-9:
            raise MechanismError(
                "phi_grid must span exactly one turn (closed: last = first + 2 pi)"
            )
        if not np.isfinite(self.flywheel) or self.flywheel < 0:
            raise MechanismError(f"flywheel must be a non-negative inertia, got {self.flywheel}")
        j = np.asarray(self.j_grid, dtype=float)
        if np.any(j + self.flywheel <= 0):
            raise MechanismError(f"reduced inertia must be positive, min {j.min() + self.flywheel}")
        from scipy.interpolate import CubicHermiteSpline  # deferred: heavy

        sj = CubicHermiteSpline(phi, j, np.asarray(self.dj_grid, dtype=float))
        m = np.asarray(self.m_grid, dtype=float)
        if self.dm_grid is None:
            from scipy.interpolate import CubicSpline

            mm = m.copy()
            mm[-1] = mm[0]
            sm = CubicSpline(phi, mm, bc_type="periodic")
        else:
            sm = CubicHermiteSpline(phi, m, np.asarray(self.dm_grid, dtype=float))
        dsj = sj.derivative()
        object.__setattr__(self, "_splines", (sj, dsj, sm))
        # the three splines' coefficients per interval as Python floats, for the integrators'
        # scalar calls (:meth:`terms`): a scipy spline's call costs ~25 us on one number
        rows = np.concatenate([sj.c, dsj.c, sm.c]).T.tolist()
        object.__setattr__(self, "_scalar", (phi.tolist(), rows))

    def _wrap(self, phi):
        p0 = self.phi_grid[0]
        return p0 + np.mod(np.asarray(phi, dtype=float) - p0, 2 * np.pi)

    def inertia(self, phi):
        """Reduced moment of inertia J(phi) (kg m^2), flywheel included."""
        return self._splines[0](self._wrap(phi)) + self.flywheel

    def inertia_derivative(self, phi):
        """dJ/dphi (kg m^2 / rad)."""
        return self._splines[1](self._wrap(phi))

    def terms(self, phi: float, omega: float) -> tuple[float, float, float]:
        """``(J, dJ/dphi, M)`` at one crank angle and speed (floats): the three splines
        evaluated in one pass (the same Horner sums as :meth:`inertia`,
        :meth:`inertia_derivative` and :meth:`moment`, to round-off), for the equation of
        motion's right-hand side, which the integrators call one angle at a time."""
        x, rows = self._scalar
        p0 = x[0]
        p = p0 + (float(phi) - p0) % _TURN
        i = min(max(bisect.bisect_right(x, p) - 1, 0), len(rows) - 1)
        d = p - x[i]
        a0, a1, a2, a3, b0, b1, b2, c0, c1, c2, c3 = rows[i]
        j = ((a0 * d + a1) * d + a2) * d + a3 + self.flywheel
        dj = (b0 * d + b1) * d + b2
        m = ((c0 * d + c1) * d + c2) * d + c3
        for f in self.extra:
            m = m + float(f(phi, omega))
        return j, dj, m

    def moment(self, phi, omega):
        """Reduced moment of all applied loads (N m, positive driving) at (phi, omega)."""
        out = self._splines[2](self._wrap(phi))
        for f in self.extra:
            out = out + f(phi, omega)
        return out

    def with_flywheel(self, inertia):
        """Copy with a constant flywheel inertia (kg m^2) at the crank."""
        return ReducedModel(
            self.phi_grid,
            self.j_grid,
            self.dj_grid,
            self.m_grid,
            self.dm_grid,
            self.extra,
            float(inertia),
        )

    @classmethod
    def constant(cls, inertia, moment=0.0, n=16):
        """Constant inertia and constant moment (for checks)."""
        phi = np.linspace(0.0, 2 * np.pi, n + 1)
        z = np.zeros_like(phi)
        return cls(phi, z + inertia, z, z + moment, z)


def reduced_model(
    mechanism, bodies, n=360, *, gravity=True, g=G, tilt=0.0, loads=(), phi_loads=(), extra=()
):
    """Build a :class:`ReducedModel` of ``mechanism`` with ``bodies`` (LinkInertia).

    Parameters
    ----------
    n : number of grid intervals over one turn.
    gravity : include the reduced gravity moment of the bodies.
    loads : sequence of ``(point, force)`` with ``force(phi, omega) -> (Fx, Fy)`` (N) independent
        of omega (pass ``omega=None``); tabulated on the grid by power equivalence.
    phi_loads : callables ``phi -> reduced moment`` (N m), tabulated on the grid.
    extra : callables ``(phi, omega) -> reduced moment`` evaluated at run time.
    """
    phi = np.linspace(0.0, 2 * np.pi, int(n) + 1)
    j, dj = reduced_inertia(mechanism, bodies, phi)
    j = np.broadcast_to(np.asarray(j, dtype=float), phi.shape).copy()
    dj = np.broadcast_to(np.asarray(dj, dtype=float), phi.shape).copy()
    m = np.zeros_like(phi)
    dm = np.zeros_like(phi)
    exact_dm = True
    if gravity and bodies:
        mg, dmg = gravity_moment(mechanism, bodies, phi, g=g, tilt=tilt)
        m = m + mg
        dm = dm + dmg
    for point, force in loads:
        m = m + point_force_moment(mechanism, point, force, phi)
        exact_dm = False
    for f in phi_loads:
        m = m + np.asarray(f(phi), dtype=float)
        exact_dm = False
    return ReducedModel(phi, j, dj, m, dm if exact_dm else None, tuple(extra))
