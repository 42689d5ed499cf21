"""Equation of motion of a machine reduced to its crank, driven by a motor.

With the crank angle as independent variable (``omega' = d omega / d phi``)::

    J(phi) omega omega' + (1/2) J'(phi) omega^2 = M_drive(omega) + M(phi, omega)

where ``M`` is the reduced moment of the applied loads (negative when resisting).
Two solvers of the steady periodic cycle: :func:`steady_cycle` (scipy ``solve_ivp`` with a
fixed-point/secant shooting on ``omega(0)``) and :func:`energy_stepping` (paper 001: energy form
over steps ``dphi`` with trapezoidal works; with a Kloss motor each step is a quartic in omega_i,
see ``docs/dynamics.md``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import MechanismError
from .motor import InductionMotor

__all__ = [
    "CycleResult",
    "steady_cycle",
    "run_up",
    "energy_stepping",
    "quartic_coefficients",
    "fluctuation",
    "size_flywheel",
    "energy_method_flywheel",
]


@dataclass(frozen=True)
class CycleResult:
    """Steady cycle: crank angle grid (rad), crank speed (rad/s), motor torque at the crank
    (N m), reduced inertia (kg m^2), load moment (N m); ``delta`` = (max-min)/mean of omega."""

    phi: np.ndarray
    omega: np.ndarray
    drive_torque: np.ndarray
    inertia: np.ndarray
    load_moment: np.ndarray
    cycles: int
    converged: bool
    method: str

    @property
    def omega_mean(self):
        # time mean over the cycle: 2 pi / T with T = int dphi / omega
        return 2 * np.pi / np.trapezoid(1.0 / self.omega, self.phi)

    @property
    def delta(self):
        return (self.omega.max() - self.omega.min()) / self.omega_mean

    def plot(self, fig=None):
        """Plot omega(phi), motor torque and J(phi); returns the figure."""
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig = fig or plt.figure(figsize=(7, 7))
        axs = fig.subplots(3, 1, sharex=True)
        d = np.degrees(self.phi)
        axs[0].plot(d, self.omega)
        axs[0].set_ylabel("omega (rad/s)")
        axs[0].set_title(f"{self.method}: delta = {self.delta:.4g}")
        axs[1].plot(d, self.drive_torque, label="motor")
        axs[1].plot(d, -self.load_moment, label="resistance")
        axs[1].set_ylabel("torque at crank (N m)")
        axs[1].legend()
        axs[2].plot(d, self.inertia)
        axs[2].set_ylabel("J (kg m^2)")
        axs[2].set_xlabel("crank angle (deg)")
        return fig


def _check_omega0(omega0):
    w = float(omega0)
    if not np.isfinite(w) or w <= 0:
        raise MechanismError(f"omega0 must be a positive finite speed, got {omega0}")
    return w


def _rhs(model, drive):
    def f(phi, y):
        w = float(y[0])
        j, dj, m = model.terms(phi, w)
        return [(drive.torque(w) + m - 0.5 * dj * w * w) / (j * w)]

    return f


def integrate_speed(model, drive, phi, w0, rtol=1e-10, atol=1e-12):
    """Crank speed (rad/s) at the crank angles ``phi`` (increasing) from ``w0`` at ``phi[0]``:
    the energy-form equation of motion integrated by ``solve_ivp`` (DOP853); ``atol`` relative
    to ``w0``. Raises MechanismError if the machine stalls or the integration fails."""
    from scipy.integrate import solve_ivp  # deferred: a heavy import few scripts need

    sol = solve_ivp(
        _rhs(model, drive),
        (phi[0], phi[-1]),
        [w0],
        t_eval=phi,
        rtol=rtol,
        atol=atol * w0,
        method="DOP853",
    )
    if not sol.success or sol.y.shape[1] != phi.size or np.any(sol.y[0] <= 0):
        raise MechanismError(
            f"integration failed from omega0={w0}: {sol.message} (machine stalls?)"
        )
    return sol.y[0]


def _one_cycle(model, drive, w0, n, rtol):
    phi = np.linspace(0.0, 2 * np.pi, n + 1)
    return phi, integrate_speed(model, drive, phi, w0, rtol)


def run_up(model, drive, omega0, turns=1.0, n=360, rtol=1e-10):
    """Integrate the equation of motion from ``omega0`` at phi = 0 over ``turns`` crank turns.

    Returns ``(phi, omega)`` on ``n`` steps per turn (transients, start-up, checks).
    """
    w0 = _check_omega0(omega0)
    end = 2 * np.pi * float(turns)
    phi = np.linspace(0.0, end, int(round(n * turns)) + 1)
    from scipy.integrate import solve_ivp  # deferred: a heavy import few scripts need

    sol = solve_ivp(
        _rhs(model, drive),
        (0.0, end),
        [w0],
        t_eval=phi,
        rtol=rtol,
        atol=1e-12 * w0,
        method="DOP853",
    )
    if not sol.success or sol.y.shape[1] != phi.size:
        raise MechanismError(f"integration failed from omega0={w0}: {sol.message}")
    return phi, sol.y[0]


def _result(model, drive, phi, w, cycles, converged, method):
    return CycleResult(
        phi,
        w,
        np.asarray(drive.torque(w)),
        np.asarray(model.inertia(phi)),
        np.asarray(model.moment(phi, w)),
        cycles,
        converged,
        method,
    )


def steady_cycle(model, drive, omega0, n=360, tol=1e-8, max_cycles=100, rtol=1e-10):
    """Steady periodic cycle by integrating turn after turn (solve_ivp) with secant acceleration
    of the fixed point ``omega(2 pi) = omega(0)``."""
    w0 = _check_omega0(omega0)
    cycles = 0
    g = lambda w: _one_cycle(model, drive, w, n, rtol)[1][-1]  # noqa: E731
    x0, f0 = w0, g(w0) - w0
    x1 = w0 + f0
    cycles = 1
    converged = False
    while cycles < max_cycles:
        f1 = g(x1) - x1
        cycles += 1
        if abs(f1) <= tol * abs(x1):
            converged = True
            break
        x2 = x1 - f1 * (x1 - x0) / (f1 - f0) if f1 != f0 else x1 + f1
        if not np.isfinite(x2) or x2 <= 0:
            x2 = x1 + f1
        x0, f0, x1 = x1, f1, x2
    phi, w = _one_cycle(model, drive, x1, n, rtol)
    return _result(model, drive, phi, w, cycles, converged, "solve_ivp")


def quartic_coefficients(j_i, c, motor: InductionMotor, dphi):
    """Coefficients (highest first) of the step quartic in omega_i.

    ``J_i w^2 / 2 - C = (dphi/2) M_motor(w)`` with ``C = J_{i-1} w_{i-1}^2/2 + (dphi/2)
    (M_motor(w_{i-1}) + M_{i-1} + M_i)``; with ``a = U / omega_sync``, ``s = 1 - a w``,
    ``q = 1 + s_k^2``, ``K = dphi eta U M_k s_k``, multiplying by ``s^2 + s_k^2`` gives
    ``(J_i/2 w^2 - C)(a^2 w^2 - 2 a w + q) - K (1 - a w) = 0``.
    """
    a = motor.gear_ratio / motor.sync_speed
    sk = motor.critical_slip
    q = 1.0 + sk * sk
    k = dphi * motor.efficiency * motor.gear_ratio * motor.breakdown_torque * sk
    h = 0.5 * j_i
    return np.array([h * a * a, -2.0 * a * h, h * q - c * a * a, 2.0 * a * c + k * a, -c * q - k])


def _stepping_cycle(model, motor, w0, phi):
    dphi = phi[1] - phi[0]
    j = model.inertia(phi)
    w = np.empty_like(phi)
    w[0] = w0
    m_prev = model.moment(phi[0], w0)
    for i in range(1, phi.size):
        # load at the new angle taken at the previous speed (exact for speed-independent loads)
        m_i = model.moment(phi[i], w[i - 1])
        c = 0.5 * j[i - 1] * w[i - 1] ** 2 + 0.5 * dphi * (motor.torque(w[i - 1]) + m_prev + m_i)
        r = np.roots(quartic_coefficients(j[i], c, motor, dphi))
        r = r[(np.abs(r.imag) < 1e-9 * np.abs(r)) & (r.real > 0)].real
        if r.size == 0:
            raise MechanismError(f"no positive real root at phi={phi[i]:.4g}: machine stalls")
        w[i] = r[np.argmin(np.abs(r - w[i - 1]))]
        m_prev = m_i
    return w


def energy_stepping(model, motor: InductionMotor, omega0, n=360, tol=1e-10, max_cycles=500):
    """Steady cycle by the paper's energy-form stepping (quartic per step), repeated turn after
    turn with secant acceleration until periodic. Second-order accurate in ``dphi``."""
    if not isinstance(motor, InductionMotor):
        raise MechanismError(
            "energy_stepping needs an InductionMotor (the quartic is Kloss-specific)"
        )
    w0 = _check_omega0(omega0)
    phi = np.linspace(0.0, 2 * np.pi, int(n) + 1)
    g = lambda w: _stepping_cycle(model, motor, w, phi)[-1]  # noqa: E731
    x0, f0 = w0, g(w0) - w0
    x1 = w0 + f0
    cycles, converged = 1, False
    while cycles < max_cycles:
        f1 = g(x1) - x1
        cycles += 1
        if abs(f1) <= tol * abs(x1):
            converged = True
            break
        x2 = x1 - f1 * (x1 - x0) / (f1 - f0) if f1 != f0 else x1 + f1
        if not np.isfinite(x2) or x2 <= 0:
            x2 = x1 + f1
        x0, f0, x1 = x1, f1, x2
    w = _stepping_cycle(model, motor, x1, phi)
    return _result(model, motor, phi, w, cycles, converged, "energy stepping")


def fluctuation(model, drive, omega0, n=360):
    """Coefficient of speed fluctuation of the steady cycle."""
    return steady_cycle(model, drive, omega0, n=n).delta


def energy_method_flywheel(model, omega_mean, delta, n=3600):
    """Classic estimate ``J_fly = Delta E_max / (delta omega_mean^2)``: Delta E_max is the largest
    swing of the work of (mean load - load) over the cycle at constant speed."""
    phi = np.linspace(0.0, 2 * np.pi, n + 1)
    m = model.moment(phi, omega_mean)
    excess = m - np.trapezoid(m, phi) / (2 * np.pi)
    e = np.concatenate([[0.0], np.cumsum(0.5 * (excess[1:] + excess[:-1]) * np.diff(phi))])
    e = e + 0.5 * omega_mean**2 * (model.inertia(phi) - model.inertia(0.0))
    de = e.max() - e.min()
    return de / (delta * omega_mean**2), de


def size_flywheel(model, drive, omega0, delta, n=180, j_max=None, rtol=1e-6):
    """Flywheel inertia at the crank (kg m^2) giving speed fluctuation ``delta`` (root find on
    the simulated delta, relative tolerance ``rtol``). Returns ``(J_fly, CycleResult)``;
    ``J_fly = 0`` when the machine already meets ``delta``."""
    if not np.isfinite(delta) or delta <= 0:
        raise MechanismError(f"delta must be positive, got {delta}")
    start = [_check_omega0(omega0)]

    def f(jf):
        cyc = steady_cycle(model.with_flywheel(jf), drive, start[0], n=n, tol=1e-7, rtol=1e-8)
        start[0] = cyc.omega[0]  # warm start the next shooting
        return cyc.delta - delta

    if f(0.0) <= 0:
        return 0.0, steady_cycle(model, drive, omega0, n=n)
    hi = j_max or max(float(np.max(model.j_grid)), 1e-6)
    while f(hi) > 0:
        hi *= 4.0
        if hi > 1e9:
            raise MechanismError("no flywheel up to 1e9 kg m^2 reaches the requested delta")
    from scipy.optimize import brentq

    jf = brentq(f, 0.0, hi, rtol=rtol)
    return jf, steady_cycle(model.with_flywheel(jf), drive, start[0], n=n)
