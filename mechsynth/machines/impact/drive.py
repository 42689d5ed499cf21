"""The impact machine driven by an induction motor: reduced model with the machine's tilts,
blows at the anvil, the periodic steady state (``solve_ivp`` and paper 001's energy stepping
with its quartic), the start-up from rest, speed fluctuation and flywheel sizing.

Conventions
-----------
The crank turns counter-clockwise, ``phi`` (rad) and ``omega > 0`` (rad/s) as everywhere in the
package. The machine is tilted by ``psi`` (the housing's angle to the horizontal) and the
mechanism by ``gamma`` in the housing (both counter-clockwise, rad): gravity in the mechanism's
frame points along ``(-sin(psi + gamma), -cos(psi + gamma))`` -- a
:class:`~mechsynth.dynamics.loads.Gravity` with ``tilt = -(psi + gamma)``. One blow per turn at
the crank angle where the striker reaches the anvil moving towards the tool; the crank speed
jumps there by the factor ``omega^+ / omega^-`` of :func:`~.impact.blow` (constant for a given
machine: Newton's law is linear in the speed).

Between blows: ``J(phi) omega omega' + J'(phi) omega^2 / 2 = M_motor(omega) + M_G(phi)``
(:mod:`mechsynth.dynamics.equation_of_motion`), ``J`` with the drive's inertia (motor rotor and
gear referred to the crank, flywheel).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from ... import validate
from ...dynamics.equation_of_motion import integrate_speed, quartic_coefficients
from ...dynamics.inertia import reduced_inertia
from ...dynamics.motor import InductionMotor
from ...dynamics.reduced import ReducedModel, gravity_moment
from ...errors import MechanismError
from ...kinematics.linkage import Linkage
from ...units import rpm, to_rpm
from .impact import Blow, Tool, _bodies, blow, blow_angle, striker_track
from .model import special_angles

__all__ = [
    "MOTOR_ASSUMPTION",
    "ImpactMachine",
    "SteadyState",
    "StartUp",
    "motor_for",
    "steady_state",
    "start_up",
    "size_flywheel",
]

TWO_PI = 2 * np.pi

MOTOR_ASSUMPTION = {
    "rated_power_W": 1500.0,
    "rated_rpm": 2850.0,
    "sync_rpm": 3000.0,
    "overload_ratio": 2.2,
    "rotor_inertia_kgm2": 1.5e-3,
    "note": (
        "paper 001 names no motor: a 1.5 kW two-pole induction motor (2850/3000 rpm, breakdown/"
        "rated torque 2.2, Kloss; rotor 1.5e-3 kg m^2), the power class of hand-held breakers "
        "of 15-20 J at about 1900 blows/min; the gear ratio is chosen so that the motor carries "
        "the machine's mean torque at the nominal speed"
    ),
}


@dataclass(frozen=True)
class ImpactMachine:
    """A percussive machine: the linkage, its masses, the tool, the drive and the tilts.

    Parameters
    ----------
    linkage : :func:`~.model.six_link`, :func:`~.model.five_link` or
        :func:`~.model.crank_rocker` (any linkage whose striker is ``striker``).
    inertias : ``{body: (mass, (u, v), J)}`` as :meth:`Linkage.force_model` takes them.
    tool : :class:`~.impact.Tool`.
    striker : the striking point (``"N"``, or ``"K"`` for the base machine).
    anvil : the striker's coordinate at the blow (m); None: where it passes the special position
        on its faster pass (the blow at the rocker's special position).
    sense : +1/-1, the striker's direction of motion at the blow; None: that of the faster pass.
    flywheel : kg m^2 on the crankshaft; the motor rotor (``MOTOR_ASSUMPTION``) through the gear
        is added by :meth:`drive_inertia`.
    psi, gamma : the machine's tilt to the horizontal and the mechanism's in the housing (rad).
    speed_rpm : nominal crank speed (rpm) = blows per minute.
    """

    linkage: Linkage
    inertias: Mapping = field(default_factory=dict)
    tool: Tool = field(default_factory=Tool)
    striker: str = "N"
    anvil: float | None = None
    sense: int | None = None
    flywheel: float = 0.0
    psi: float = 0.0
    gamma: float = 0.0
    speed_rpm: float = 2000.0
    gear_ratio: float | None = None

    def __post_init__(self):
        if not isinstance(self.linkage, Linkage):
            raise MechanismError(
                "linkage must be a Linkage (ms.six_link(), ms.five_link() or ms.crank_rocker()), "
                f"got {self.linkage!r} (a {type(self.linkage).__name__})"
            )
        if not isinstance(self.tool, Tool):
            raise MechanismError(f"tool must be a Tool, got {self.tool!r}")
        if not isinstance(self.inertias, Mapping):
            raise MechanismError(
                f"inertias must be a dict {{body: (mass, (u, v), J)}}, got {self.inertias!r}"
            )
        units = {"flywheel": "kg m^2", "psi": "rad", "gamma": "rad", "speed_rpm": "rpm"}
        for name, unit in units.items():
            object.__setattr__(self, name, validate.number(name, getattr(self, name), unit))
        if self.gear_ratio is not None:
            object.__setattr__(
                self, "gear_ratio", validate.number("gear_ratio", self.gear_ratio)
            )
            if self.gear_ratio <= 0:
                raise MechanismError(
                    f"gear_ratio must be positive (motor speed / crank speed), got "
                    f"{self.gear_ratio}"
                )
        if self.sense is not None and (
            isinstance(self.sense, (bool, np.bool_)) or self.sense not in (1, -1)
        ):
            raise MechanismError(f"sense must be +1, -1 or None, got {self.sense!r}")
        if self.anvil is not None:
            object.__setattr__(self, "anvil", validate.number("anvil", self.anvil, "m"))
        if not isinstance(self.striker, str):
            raise MechanismError(f"striker must be a point name, got {self.striker!r}")
        if self.flywheel < 0:
            raise MechanismError(
                f"flywheel must be a non-negative inertia (kg m^2), got {self.flywheel}"
            )
        if self.speed_rpm <= 0:
            raise MechanismError(f"speed_rpm must be positive, got {self.speed_rpm}")
        if self.striker not in self.linkage.points:
            raise MechanismError(
                f"striker {self.striker!r} is not a point of the linkage "
                f"({', '.join(self.linkage.points)})"
            )
        if self.anvil is None or self.sense is None:
            phis = special_angles(self.linkage)
            us = [float(striker_track(self.linkage, self.striker, p)[1]) for p in phis]
            k = int(np.argmax(np.abs(us)))
            if self.anvil is None:
                s = striker_track(self.linkage, self.striker, phis[k])[0]
                object.__setattr__(self, "anvil", float(s))
            if self.sense is None:
                object.__setattr__(self, "sense", 1 if us[k] > 0 else -1)
        object.__setattr__(self, "inertias", dict(self.inertias))

    def replace(self, **changes) -> ImpactMachine:
        """The same machine with other fields (the tool's are changed through ``tool=``)."""
        fields = [f.name for f in dataclasses.fields(self)]
        unknown = [k for k in changes if k not in fields]
        if unknown:
            hint = " (a Tool's: tool=Tool(...))" if {"mass", "restitution"} & set(unknown) else ""
            raise MechanismError(
                f"ImpactMachine has no field {unknown[0]!r}{hint}; its fields: {', '.join(fields)}"
            )
        return dataclasses.replace(self, **changes)

    @property
    def omega(self) -> float:
        """Nominal crank speed (rad/s)."""
        return float(rpm(self.speed_rpm))

    @property
    def tilt(self) -> float:
        """The :class:`~mechsynth.dynamics.loads.Gravity` tilt of the mechanism's frame."""
        return -(self.psi + self.gamma)

    def blow_angle(self) -> float:
        """Crank angle of the blow (rad)."""
        return blow_angle(self.linkage, self.striker, self.anvil, self.sense)

    def drive_inertia(self, gear_ratio=None) -> float:
        """Motor rotor (through the gear) and flywheel at the crank (kg m^2)."""
        u = self.gear_ratio if gear_ratio is None else gear_ratio
        rotor = MOTOR_ASSUMPTION["rotor_inertia_kgm2"] * (0.0 if u is None else u * u)
        return rotor + self.flywheel

    def blow(self, omega=None, gear_ratio=None) -> Blow:
        """The blow at crank speed ``omega`` (rad/s; default nominal) just before it."""
        return blow(
            self.linkage,
            self.inertias,
            self.blow_angle(),
            self.omega if omega is None else omega,
            self.tool,
            striker=self.striker,
            sense=self.sense,
            drive_inertia=self.drive_inertia(gear_ratio),
        )

    def bodies(self, gear_ratio=None):
        """LinkInertia of every body, the drive's inertia in the crank's."""
        return list(
            _bodies(self.linkage, self.inertias, self.drive_inertia(gear_ratio))[1].values()
        )

    def reduced_model(self, n=720, gear_ratio=None) -> ReducedModel:
        """``J(phi)`` (drive included) and the reduced gravity moment at the machine's tilt."""
        phi = np.linspace(0.0, TWO_PI, int(n) + 1)
        bodies = self.bodies(gear_ratio)
        j, dj = reduced_inertia(self.linkage, bodies, phi)
        mg, dmg = gravity_moment(self.linkage, bodies, phi, tilt=self.tilt)
        b = lambda x: np.broadcast_to(np.asarray(x, float), phi.shape).copy()  # noqa: E731
        return ReducedModel(phi, b(j), b(dj), b(mg), b(dmg))


def motor_for(machine: ImpactMachine, gear_ratio=None) -> InductionMotor:
    """The assumed motor (:data:`MOTOR_ASSUMPTION`) through ``gear_ratio``; None solves the
    ratio (stable branch of Kloss's curve) so that the motor's torque at the nominal crank speed
    equals the mean torque the blows take, ``(E_delivered + E_lost) / (2 pi)`` per turn (the
    rotor's inertia changes with the ratio: a fixed point, iterated)."""
    a = MOTOR_ASSUMPTION

    def motor(u):
        return InductionMotor.from_catalogue(
            a["rated_power_W"],
            rpm(a["rated_rpm"]),
            rpm(a["sync_rpm"]),
            a["overload_ratio"],
            gear_ratio=u,
        )

    if gear_ratio is not None:
        u = validate.number("gear_ratio", gear_ratio)
        if u <= 0:
            raise MechanismError(
                f"gear_ratio must be positive (motor speed / crank speed), got {gear_ratio}"
            )
        return motor(u)
    w = machine.omega
    base = motor(1.0)
    u = base.sync_speed / w
    for _ in range(50):
        b = machine.blow(w, gear_ratio=u)
        m_l = (b.energy_delivered + b.energy_lost) / TWO_PI
        u_sync = base.sync_speed / w
        u_k = (1.0 - base.critical_slip) * u_sync
        if m_l >= u_k * base.breakdown_torque:
            raise MechanismError(
                f"the assumed {a['rated_power_W'] / 1e3:.3g} kW motor cannot carry the blows' "
                f"mean torque {m_l:.6g} N m at {machine.speed_rpm:.6g} rpm (breakdown "
                f"{u_k * base.breakdown_torque:.6g} N m at the crank)"
            )
        from scipy.optimize import brentq  # deferred: heavy

        new = brentq(lambda x, m_l=m_l: float(motor(x).torque(w)) - m_l, u_k, u_sync, xtol=1e-14)
        if abs(new - u) < 1e-12 * u:
            u = new
            break
        u = new
    return motor(u)


@dataclass(frozen=True)
class SteadyState:
    """The periodic motion with one blow per turn, over the turn that starts just after a blow.

    ``phi`` (rad, from the blow angle to the next), ``omega`` (rad/s; the last value is the
    speed just before the next blow), ``blow`` (the :class:`~.impact.Blow` at the steady speed),
    ``turns`` (turns iterated), ``converged``, ``method``, and per-turn numbers: ``omega_mean``
    (time mean, rad/s), ``delta`` ((max - min) / mean), ``blows_per_minute``,
    ``power_delivered`` (W to the tool), ``motor_power`` (mean W at the crank), and for the
    stepping the count of positive real roots of each step's quartic (``positive_roots``)."""

    phi: np.ndarray
    omega: np.ndarray
    blow: Blow
    turns: int
    converged: bool
    method: str
    motor_torque: np.ndarray
    positive_roots: np.ndarray | None = None

    @property
    def omega_mean(self) -> float:
        return float(TWO_PI / np.trapezoid(1.0 / self.omega, self.phi))

    @property
    def delta(self) -> float:
        w = np.concatenate([self.omega, [self.blow.omega_after]])
        return float((w.max() - w.min()) / self.omega_mean)

    @property
    def blows_per_minute(self) -> float:
        return float(to_rpm(self.omega_mean))

    @property
    def power_delivered(self) -> float:
        return float(self.blow.energy_delivered * self.omega_mean / TWO_PI)

    @property
    def motor_power(self) -> float:
        t = np.trapezoid(1.0 / self.omega, self.phi)
        return float(np.trapezoid(self.motor_torque, self.phi) / t)

    def summary(self) -> dict:
        b = self.blow
        return {
            "method": self.method,
            "converged": bool(self.converged),
            "turns": int(self.turns),
            "mean_rpm": float(to_rpm(self.omega_mean)),
            "min_rpm": float(to_rpm(np.min(self.omega))),
            "max_rpm": float(to_rpm(max(np.max(self.omega), b.omega_after))),
            "delta": self.delta,
            "blows_per_minute": self.blows_per_minute,
            "impact_velocity": b.striker_before,
            "energy_delivered": b.energy_delivered,
            "energy_lost": b.energy_lost,
            "power_delivered_W": self.power_delivered,
            "motor_power_W": self.motor_power,
            "omega_before_blow": b.omega_before,
            "omega_after_blow": b.omega_after,
        }


def _turn_ivp(model, motor, phi, w0, rtol):
    try:
        return integrate_speed(model, motor, phi, w0, rtol, atol=1e-13), None
    except MechanismError as exc:
        raise MechanismError(f"the machine stalls between blows: {exc}") from None


def _turn_stepping(model, motor, phi, w0):
    """Paper 001's energy form over steps dphi: one quartic per step, the positive real root
    continuing the previous speed (see docs/dynamics.md for the quartic)."""
    dphi = phi[1] - phi[0]
    j = model.inertia(phi)
    m = model.moment(phi, 0.0)
    w = np.empty_like(phi)
    count = np.zeros(phi.size - 1, dtype=int)
    w[0] = w0
    for i in range(1, phi.size):
        c = 0.5 * j[i - 1] * w[i - 1] ** 2 + 0.5 * dphi * (motor.torque(w[i - 1]) + m[i - 1] + m[i])
        r = np.roots(quartic_coefficients(j[i], c, motor, dphi))
        r = r[(np.abs(r.imag) <= 1e-9 * np.abs(r)) & (r.real > 0)].real
        count[i - 1] = r.size
        if r.size == 0:
            raise MechanismError(
                f"no positive real root at phi = {phi[i]:.6g} rad: the machine stalls"
            )
        w[i] = r[np.argmin(np.abs(r - w[i - 1]))]
    return w, count


def steady_state(
    machine: ImpactMachine,
    motor=None,
    *,
    method="ivp",
    n=720,
    tol=1e-10,
    max_turns=60,
    model=None,
    rtol=1e-12,
) -> SteadyState:
    """The periodic steady state with one blow per turn.

    Integrates the turn from just after a blow to just before the next (``method="ivp"``:
    ``solve_ivp`` DOP853; ``"stepping"``: the energy form with its quartic on ``n`` steps),
    applies the blow's speed jump and solves ``omega^+ = jump(turn(omega^+))`` by secant
    iteration to ``tol`` (relative).
    """
    if method not in ("ivp", "stepping"):
        raise MechanismError(f"method must be 'ivp' or 'stepping', got {method!r}")
    motor = motor_for(machine) if motor is None else motor
    model = machine.reduced_model(gear_ratio=motor.gear_ratio) if model is None else model
    phi_b = machine.blow_angle()
    phi = phi_b + np.linspace(0.0, TWO_PI, int(n) + 1)
    ref = machine.blow(machine.omega, gear_ratio=motor.gear_ratio)
    k = ref.omega_after / ref.omega_before  # the jump is linear in the speed

    def turn(w):
        if method == "ivp":
            return _turn_ivp(model, motor, phi, w, rtol)
        return _turn_stepping(model, motor, phi, w)

    x0 = ref.omega_after
    f0 = k * turn(x0)[0][-1] - x0
    x1 = x0 + f0
    turns, converged = 1, False
    while turns < max_turns:
        w, count = turn(x1)
        f1 = k * w[-1] - x1
        turns += 1
        if abs(f1) <= tol * x1:
            converged = True
            break
        x2 = x1 - f1 * (x1 - x0) / (f1 - f0) if f1 != f0 else x1 + f1
        if not np.isfinite(x2) or x2 <= 0:
            x2 = x1 + f1
        x0, f0, x1 = x1, f1, x2
    w, count = turn(x1)
    b = machine.blow(w[-1], gear_ratio=motor.gear_ratio)
    return SteadyState(phi, w, b, turns, converged, method, np.asarray(motor.torque(w)), count)


@dataclass(frozen=True)
class StartUp:
    """Start-up from rest: time ``t`` (s), crank angle ``phi`` (rad, unwrapped), speed ``omega``
    (rad/s) and the blows ``(t, omega_before, omega_after, energy_delivered)``."""

    t: np.ndarray
    phi: np.ndarray
    omega: np.ndarray
    blows: np.ndarray

    def time_to(self, fraction, omega_ref):
        """First time (s) the speed reaches ``fraction * omega_ref``; None if it does not within
        the integrated time."""
        i = np.flatnonzero(self.omega >= fraction * omega_ref)
        return float(self.t[i[0]]) if i.size else None


def start_up(machine: ImpactMachine, motor=None, *, duration=0.6, samples=3000, model=None):
    """Integrate from rest at crank angle 0 for ``duration`` s (time domain: ``phi' = omega``,
    ``omega' = (M_motor + M_G - J' omega^2 / 2) / J``), a blow each time the crank passes the
    blow angle moving forward (its jump scales with the speed)."""
    duration = validate.positive("duration", duration, "s")
    samples = validate.integer("samples", samples, lo=2, hi=validate.MAX_ANGLES)
    motor = motor_for(machine) if motor is None else motor
    model = machine.reduced_model(gear_ratio=motor.gear_ratio) if model is None else model
    phi_b = machine.blow_angle()
    ref = machine.blow(machine.omega, gear_ratio=motor.gear_ratio)
    k = ref.omega_after / ref.omega_before
    per_joule = ref.energy_delivered / ref.omega_before**2

    def f(t, y):
        p, w = float(y[0]), float(y[1])
        j, dj, m = model.terms(p, w)
        return [w, (motor.torque(w) + m - 0.5 * dj * w * w) / j]

    t_grid = np.linspace(0.0, float(duration), int(samples) + 1)
    ts, ps, ws, blows = [], [], [], []
    t0, y = 0.0, np.array([0.0, 0.0])
    target = phi_b
    while t0 < duration - 1e-12:

        def hit(t, yy, target=target):
            return yy[0] - target

        hit.terminal, hit.direction = True, 1
        grid = t_grid[(t_grid > t0) & (t_grid <= duration)]
        from scipy.integrate import solve_ivp  # deferred: heavy

        sol = solve_ivp(
            f, (t0, duration), y, t_eval=grid, events=hit, rtol=1e-10, atol=1e-12, method="DOP853"
        )
        ts.append(sol.t)
        ps.append(sol.y[0])
        ws.append(sol.y[1])
        if sol.status == 1 and sol.t_events[0].size:
            te, ye = sol.t_events[0][0], sol.y_events[0][0]
            w_after = k * ye[1]
            blows.append((te, ye[1], w_after, per_joule * ye[1] ** 2))
            t0, y = te, np.array([ye[0], w_after])
            target += TWO_PI
        else:
            break
    return StartUp(
        np.concatenate(ts), np.concatenate(ps), np.concatenate(ws), np.array(blows).reshape(-1, 4)
    )


def size_flywheel(machine: ImpactMachine, delta, motor=None, *, n=360, hi=1.0):
    """Flywheel (kg m^2 on the crankshaft) for the steady speed fluctuation ``delta``:
    ``brentq`` on the simulated steady state (the flywheel raises the machine's effective mass
    at the blow too, so the blow itself changes). Returns ``(flywheel, SteadyState)``; 0 when
    the machine already meets ``delta``."""
    delta = validate.number("delta (coefficient of speed fluctuation)", delta)
    if not 0.0 < delta < 1.0:
        raise MechanismError(
            "delta (coefficient of speed fluctuation, (w_max - w_min) / w_mean) must lie in "
            f"(0, 1); machines run at 0.01-0.2; got {delta}"
        )
    motor = motor_for(machine) if motor is None else motor

    def run(jf):
        m = machine.replace(flywheel=jf, gear_ratio=motor.gear_ratio)
        return steady_state(m, motor, n=n, tol=1e-9, rtol=1e-9)

    if run(0.0).delta <= delta:
        return 0.0, run(0.0)
    while run(hi).delta > delta:
        hi *= 4.0
        if hi > 1e4:
            raise MechanismError(f"no flywheel up to 1e4 kg m^2 reaches delta = {delta}")
    from scipy.optimize import brentq  # deferred: heavy

    jf = brentq(lambda x: run(x).delta - delta, 0.0, hi, rtol=1e-6)
    return float(jf), run(jf)
