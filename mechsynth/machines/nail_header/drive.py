"""Speed fluctuation of the AB4115 nail header driven by an induction motor (paper 003's machine,
paper 001's method).

The machine is :class:`~mechsynth.machines.nail_header.model.NailHeader` itself: its bodies
(crank with the centre of mass beyond O and any counterweight, rod, punch-slider, ejector rocker)
come from
``NailHeader.force_model()`` and its loads (upsetting force while the punch advances, ejector
spring, gravity) are reduced to the crank through the general kinetostatics' power function
``applied_power``. Nothing of the machine is restated here, so any ``NailHeader`` (another slider
mass, a counterweight, another spring) gets its own speed fluctuation.

Conventions
-----------
The machine turns clockwise (``NailHeader.omega < 0``). The reduced model is written in the
machine's own coordinate: the **clockwise** crank angle ``theta = -phi`` (rad) from the outer dead
centre and the crank speed ``w = d theta / dt > 0`` (rad/s). Reduced moments are positive when
they drive the crank clockwise, forward. Then

* ``J(theta) = 2 T / w^2`` (kg m^2), ``T`` the kinetic energy of the bodies: the same for either
  sense of rotation, but ``dJ/dtheta = -dJ/dphi``;
* ``M(theta) = P_applied / w`` (N m), ``P_applied`` the power of the loads computed on the
  machine's real motion ``NailHeader.motion(-theta, speed=NailHeader.omega)``, so that the
  upsetting force acts where the punch really advances (the last ``h`` before the outer dead
  centre, ``theta`` just below ``2 pi``; ``NailHeader.upsetting`` reads an analog motion the
  same way, as the clockwise machine's). The loads' magnitudes do not depend on the speed,
  only on the sense of motion, so ``M`` is a function of ``theta`` alone;
* the kinetostatic balancing torque (counter-clockwise positive) of ``NailHeader.forces`` at
  constant speed is ``T_b = M(theta) - J'(theta) w^2 / 2`` (power balance, tested).

The upsetting force jumps from 0 to ``F_e0`` (about 6.1 kN) at the first contact, so ``M`` jumps
too: ``M`` is tabulated on a fine grid that holds the two sides of the contact angle (found by
bisection on ``NailHeader.upsetting``) and interpolated linearly, as the run-time moment of the
:class:`~mechsynth.dynamics.reduced.ReducedModel`; ``J`` is its Hermite spline with the exact
derivative.

Motor: the paper gives none. The default is a representative 4 kW induction motor (rated
1440 rpm, synchronous 1500 rpm, breakdown/rated torque 2.2, Kloss), gear losses ignored, with the
gear ratio chosen so that the motor's static characteristic carries the mean load torque at the
header's speed ``n1`` (600 rpm).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ...dynamics.equation_of_motion import energy_stepping, steady_cycle
from ...dynamics.inertia import kinetic_energy, reduced_inertia
from ...dynamics.kinetostatics import applied_power
from ...dynamics.loads import TabulatedLoad
from ...dynamics.motor import InductionMotor
from ...dynamics.reduced import ReducedModel
from ...errors import MechanismError
from ...units import rpm, to_rpm
from .model import NailHeader

__all__ = [
    "MOTOR_ASSUMPTION",
    "TabulatedMoment",
    "check_header",
    "crank_speed",
    "reduced_load_moments",
    "reduced_load_moment",
    "nail_header_inertia",
    "kinetic_energy_at_speed",
    "load_table",
    "contact_angles",
    "mean_load_torque",
    "default_motor",
    "nail_header_drive",
    "nail_header_speed_fluctuation",
]

TWO_PI = 2 * np.pi

MOTOR_ASSUMPTION = {
    "rated_power_W": 4000.0,
    "rated_rpm": 1440.0,
    "sync_rpm": 1500.0,
    "overload_ratio": 2.2,
    "gear_efficiency": 1.0,
    "note": (
        "paper 003 gives no motor: a representative 4 kW, 1440/1500 rpm induction motor "
        "(Kloss, breakdown/rated torque 2.2), gear losses ignored; the gear ratio is chosen so "
        "that the motor carries the mean load torque at 600 rpm"
    ),
}

_LOAD_NAMES = {"Gravity": "gravity", "TorsionSpring": "spring"}


@dataclass(frozen=True)
class TabulatedMoment:
    """Periodic, piecewise-linear reduced moment ``M(theta)`` (N m) over one turn.

    ``theta`` (rad) strictly increasing from 0 to ``2 pi``; calling it with ``(theta, omega)``
    returns the interpolated moment (``omega`` is ignored: the table depends on position only).
    """

    theta: np.ndarray
    moment: np.ndarray

    def __post_init__(self):
        # the load tables' checks (finite, same length, strictly increasing, one period)
        table = TabulatedLoad(self.theta, self.moment, TWO_PI, "theta", "moment")
        if table.x[0] != 0.0 or abs(table.x[-1] - TWO_PI) > 1e-12:
            raise MechanismError(
                f"theta must run from 0 to 2 pi, got {table.x[0]:.6g} .. {table.x[-1]:.6g}"
            )
        object.__setattr__(self, "theta", table.x)
        object.__setattr__(self, "moment", table.y)

    def __call__(self, theta, omega=None):
        return np.interp(np.mod(np.asarray(theta, dtype=float), TWO_PI), self.theta, self.moment)

    @property
    def work(self) -> float:
        """Work of the loads over one turn (J), exact for the piecewise-linear table."""
        return float(np.trapezoid(self.moment, self.theta))


def check_header(header=None, slider_mass=None) -> NailHeader:
    """The header to analyse: ``header`` (default ``NailHeader()``) with the slider mass
    replaced by ``slider_mass`` (kg) when given."""
    if header is None:
        header = NailHeader()
    if not isinstance(header, NailHeader):
        raise MechanismError(
            f"header must be a NailHeader, got {type(header).__name__}: {header!r}"
        )
    if slider_mass is not None:
        header = dataclasses.replace(header, m3=float(slider_mass))
    if not header.n1 > 0:
        raise MechanismError(f"header speed n1 must be positive (rpm), got {header.n1}")
    return header


def crank_speed(header: NailHeader) -> float:
    """The machine's crank speed ``w = -NailHeader.omega > 0`` (rad/s, clockwise)."""
    return -float(header.omega)


def _angles(theta):
    t = np.atleast_1d(np.asarray(theta, dtype=float))
    if not np.all(np.isfinite(t)):
        raise MechanismError(f"crank angles theta must be finite, got {t[~np.isfinite(t)][:3]}")
    return t


def _machine_motion(header, theta):
    return header.motion(-_angles(theta), speed=header.omega)


def _load_name(load):
    return getattr(load, "name", None) or _LOAD_NAMES.get(type(load).__name__, type(load).__name__)


def reduced_load_moments(header: NailHeader, theta) -> dict[str, np.ndarray]:
    """Reduced moment (N m, positive driving the clockwise crank) of every load of
    ``header.force_model()`` at clockwise crank angles ``theta`` (rad): ``{"upsetting", "spring",
    "gravity"}``, each ``P_applied / w`` on the machine's real motion."""
    header = check_header(header)
    model = header.force_model()
    motion = _machine_motion(header, theta)
    w = crank_speed(header)
    out = {}
    for load in model.loads:
        p = applied_power(model.replace_loads([load]), motion)
        out[_load_name(load)] = np.broadcast_to(np.asarray(p, dtype=float) / w, motion.phi.shape)
    return out


def reduced_load_moment(header: NailHeader, theta) -> np.ndarray:
    """Total reduced moment of the loads (N m, positive driving) at clockwise angles ``theta``."""
    header = check_header(header)
    model = header.force_model()
    p = applied_power(model, _machine_motion(header, theta))
    return np.broadcast_to(np.asarray(p, dtype=float), _angles(theta).shape) / crank_speed(header)


def nail_header_inertia(header: NailHeader, theta):
    """Reduced moment of inertia ``J`` (kg m^2) and ``dJ/dtheta`` (kg m^2/rad) of every body of
    ``header.force_model()`` at clockwise crank angles ``theta`` (rad)."""
    header = check_header(header)
    bodies = list(header.force_model().bodies.values())
    phi = -_angles(theta)
    j, dj_dphi = reduced_inertia(header, bodies, phi)
    j = np.broadcast_to(np.asarray(j, dtype=float), phi.shape)
    return j, -np.broadcast_to(np.asarray(dj_dphi, dtype=float), phi.shape)


def kinetic_energy_at_speed(header: NailHeader, theta):
    """Kinetic energy (J) of the bodies at ``theta`` when the crank turns at the header's speed."""
    header = check_header(header)
    bodies = list(header.force_model().bodies.values())
    return kinetic_energy(_machine_motion(header, theta), bodies)


def _upsetting_on(header, theta):
    return np.asarray(header.upsetting(_machine_motion(header, theta))) > 0


def contact_angles(header: NailHeader, n=5760) -> np.ndarray:
    """Clockwise crank angles (rad) where the upsetting force switches on or off between the
    samples of an ``n``-interval grid, each located by bisection to machine precision; returned
    as bracketing pairs ``[[lo, hi], ...]`` (``lo < hi``, adjacent floats apart at most 1e-13)."""
    header = check_header(header)
    if int(n) < 8:
        raise MechanismError(f"contact search intervals n must be at least 8, got {n}")
    theta = np.linspace(0.0, TWO_PI, int(n) + 1)
    on = _upsetting_on(header, theta)
    pairs = []
    for i in np.flatnonzero(on[1:] != on[:-1]):
        lo, hi = theta[i], theta[i + 1]
        state_lo = on[i]
        while hi - lo > 1e-13:
            mid = 0.5 * (lo + hi)
            if _upsetting_on(header, mid)[0] == state_lo:
                lo = mid
            else:
                hi = mid
        pairs.append((lo, hi))
    return np.array(pairs, dtype=float).reshape(-1, 2)


def load_table(header: NailHeader, n=5760) -> TabulatedMoment:
    """The total reduced load moment tabulated on ``n`` intervals plus both sides of every
    contact switch of the upsetting force (so its jump is represented exactly)."""
    header = check_header(header)
    n = int(n)
    if n < 8:
        raise MechanismError(f"load table intervals n must be at least 8, got {n}")
    theta = np.unique(
        np.concatenate([np.linspace(0.0, TWO_PI, n + 1), contact_angles(header, n).ravel()])
    )
    return TabulatedMoment(theta, reduced_load_moment(header, theta))


def mean_load_torque(header: NailHeader, n=5760) -> float:
    """Mean resisting torque at the crank (N m): minus the loads' work per turn over ``2 pi``."""
    return -load_table(header, n).work / TWO_PI


def default_motor(gear_ratio=None, header: NailHeader | None = None, load_torque=None):
    """The assumed motor (:data:`MOTOR_ASSUMPTION`) through ``gear_ratio``.

    With ``gear_ratio=None`` the ratio is solved (stable branch of Kloss's curve) so that the
    motor's torque at the crank equals ``load_torque`` (N m; default: the header's mean load
    torque) at the header's speed ``n1``.
    """
    a = MOTOR_ASSUMPTION

    def motor(u):
        return InductionMotor.from_catalogue(
            a["rated_power_W"],
            rpm(a["rated_rpm"]),
            rpm(a["sync_rpm"]),
            a["overload_ratio"],
            gear_ratio=u,
            efficiency=a["gear_efficiency"],
        )

    if gear_ratio is not None:
        return motor(gear_ratio)
    header = check_header(header)
    m_l = mean_load_torque(header) if load_torque is None else float(load_torque)
    w = crank_speed(header)
    base = motor(1.0)
    u_sync = base.sync_speed / w  # zero slip: no torque
    u_k = (1.0 - base.critical_slip) * u_sync  # breakdown torque
    if not np.isfinite(m_l) or m_l >= base.efficiency * u_k * base.breakdown_torque:
        raise MechanismError(
            f"the assumed {a['rated_power_W'] / 1e3:.3g} kW motor cannot carry a mean load "
            f"torque of {m_l:.6g} N m at {header.n1:.6g} rpm (breakdown "
            f"{base.efficiency * u_k * base.breakdown_torque:.6g} N m at the crank)"
        )
    from scipy.optimize import brentq  # deferred: heavy

    u = brentq(lambda x: float(motor(x).torque(w)) - m_l, u_k, u_sync, xtol=1e-14, rtol=1e-14)
    return motor(u)


def nail_header_drive(
    header=None, *, slider_mass=None, motor=None, gear_ratio=None, n=720, table=8
):
    """Reduced model and motor of a nail header; returns ``(model, motor)``.

    Parameters
    ----------
    header : NailHeader, default ``NailHeader()`` (paper 003's serial machine).
    slider_mass : kg, replaces ``header.m3`` when given (convenience).
    motor : an :class:`InductionMotor` at the crank; default :func:`default_motor`.
    gear_ratio : used with the default motor; ``None`` solves it for the mean speed ``n1``.
    n : crank-angle intervals of the inertia spline (the model's grid over ``theta``).
    table : the load moment is tabulated on ``table * n`` intervals (plus the contact angles).

    The model's coordinate is the clockwise crank angle ``theta`` (see the module docstring).
    """
    header = check_header(header, slider_mass)
    n = int(n)
    if n < 8 or int(table) < 1:
        raise MechanismError(f"n must be at least 8 and table at least 1, got n={n}, table={table}")
    theta = np.linspace(0.0, TWO_PI, n + 1)
    j, dj = nail_header_inertia(header, theta)
    loads = load_table(header, int(table) * n)
    zero = np.zeros_like(theta)
    model = ReducedModel(theta, j.copy(), dj.copy(), zero, zero, (loads,))
    if motor is None:
        motor = default_motor(gear_ratio, header, -loads.work / TWO_PI)
    elif not isinstance(motor, InductionMotor):
        raise MechanismError(f"motor must be an InductionMotor, got {type(motor).__name__}")
    return model, motor


def nail_header_speed_fluctuation(
    header=None, *, slider_mass=None, motor=None, gear_ratio=None, n=720
):
    """Steady cycle of a nail header with its motor, by ``solve_ivp`` and by energy stepping.

    Returns a dict: ``slider_mass`` (kg), ``delta`` (``(w_max - w_min) / w_mean``, solve_ivp),
    ``delta_stepping``, ``mean_rpm``, ``min_rpm``, ``max_rpm`` (crank, clockwise), ``gear_ratio``,
    ``load_work_J`` (work of the loads per turn, negative), ``mean_power_W``, ``inertia_min`` and
    ``inertia_max`` (kg m^2), the two :class:`CycleResult` (``"ivp"``, ``"stepping"``) over
    the clockwise crank angle, and the ``"model"`` and ``"motor"`` they ran on.
    """
    header = check_header(header, slider_mass)
    model, motor = nail_header_drive(header, motor=motor, gear_ratio=gear_ratio, n=n)
    w0 = crank_speed(header)
    ivp = steady_cycle(model, motor, w0, n=int(n))
    step = energy_stepping(model, motor, w0, n=int(n))
    work = model.extra[0].work
    return {
        "slider_mass": float(header.m3),
        "delta": float(ivp.delta),
        "delta_stepping": float(step.delta),
        "mean_rpm": float(to_rpm(ivp.omega_mean)),
        "min_rpm": float(to_rpm(ivp.omega.min())),
        "max_rpm": float(to_rpm(ivp.omega.max())),
        "gear_ratio": float(motor.gear_ratio),
        "load_work_J": float(work),
        "mean_power_W": float(-work * ivp.omega_mean / TWO_PI),
        "inertia_min": float(model.j_grid.min()),
        "inertia_max": float(model.j_grid.max()),
        "ivp": ivp,
        "stepping": step,
        "model": model,
        "motor": motor,
    }
