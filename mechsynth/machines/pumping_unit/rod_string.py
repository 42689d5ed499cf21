"""A predicted surface dynamometer card: the damped wave equation of the rod string (Gibbs).

The sucker-rod string is an elastic bar of length ``L`` hanging in the well fluid. Its axial
displacement ``u(x, t)`` (m, positive downward, measured from the string hanging at rest under
its own buoyant weight; ``x`` the depth) obeys the damped wave equation

    u_tt = a^2 u_xx - c u_t,       a = sqrt(E / rho),   c = pi a nu / (2 L)

with the dimensionless damping factor ``nu`` (Gibbs' viscous damping of the fluid and the
tubing; 0.05-0.2 in practice). Boundary conditions:

* at the surface the rods follow the polished rod: ``u(0, t) = -PR(t)``, ``PR`` the unit's exact
  polished-rod position (up from the bottom of the stroke) at constant crank speed;
* at the pump, an ideal full pump (incompressible liquid, no gas): when the plunger turns upward
  the travelling valve shuts and holds it (``u_t(L) = 0``) while the rods stretch until their
  bottom tension reaches the fluid load ``F_o = rho_f g H A_p`` (net lift ``H``, plunger area
  ``A_p``); it then rises carrying ``E A u_x(L, t) = F_o``; when it turns downward the standing
  valve shuts and holds it until the load is off, and it falls with ``E A u_x(L, t) = 0``.

The surface (polished-rod) load is ``W = W_rf + E A u_x(0, t)``, ``W_rf`` the buoyant weight of
the string. The equation is integrated by central differences (second order in space and time)
over several cycles until the card repeats; the last cycle is returned as a
:class:`~mechsynth.machines.pumping_unit.DynamometerCard`. A single-diameter steel string is
modelled (tapered strings and friction are not).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...errors import MechanismError
from ...kinematics.mechanism import check_finite, check_length
from .torque import GRAVITY, DynamometerCard

__all__ = ["RodString", "wave_equation_card"]

PICKUP, UP, RELEASE, DOWN = range(4)


@dataclass(frozen=True)
class RodString:
    """A rod string and its pump (SI units).

    Parameters
    ----------
    depth : pump depth = string length ``L`` (m).
    diameter : rod diameter (m).
    pump_diameter : plunger diameter (m).
    lift : net lift ``H`` (m): the depth of the dynamic fluid level (the pump's pressure rise
        over the fluid column).
    fluid_density : kg/m^3.
    damping : Gibbs' dimensionless damping factor ``nu``.
    E, density : the rods' Young's modulus (Pa) and density (kg/m^3).
    """

    depth: float
    diameter: float
    pump_diameter: float
    lift: float
    fluid_density: float = 900.0
    damping: float = 0.1
    E: float = 2.06e11
    density: float = 7850.0

    def __post_init__(self):
        for name in ("depth", "diameter", "pump_diameter", "lift", "fluid_density", "E", "density"):
            object.__setattr__(self, name, check_length(name, getattr(self, name)))
        v = check_finite("damping", self.damping)
        if v < 0.0:
            raise MechanismError(f"damping must not be negative, got {v}")
        object.__setattr__(self, "damping", v)
        if self.lift > self.depth:
            raise MechanismError(
                f"lift ({self.lift} m) cannot exceed the pump depth ({self.depth} m)"
            )
        if self.fluid_density >= self.density:
            raise MechanismError("the rods must be denser than the well fluid")

    @property
    def area(self) -> float:
        return float(np.pi * self.diameter**2 / 4.0)

    @property
    def wave_speed(self) -> float:
        return float(np.sqrt(self.E / self.density))

    @property
    def buoyant_weight(self) -> float:
        """``W_rf`` (N): the string's weight in the fluid."""
        return float(self.area * self.depth * GRAVITY * (self.density - self.fluid_density))

    @property
    def fluid_load(self) -> float:
        """``F_o`` (N): the fluid load on the plunger."""
        return float(self.fluid_density * GRAVITY * self.lift * np.pi * self.pump_diameter**2 / 4)


def wave_equation_card(unit, rods: RodString, speed, cycles=8, nodes=100, points=200):
    """The surface card of ``unit`` (any unit with ``motion(theta).polished_rod`` and
    ``stroke``) pumping with ``rods`` at crank ``speed`` (rad/s), by the damped wave equation
    (module notes).

    Returns ``(card, info)``: the :class:`DynamometerCard` of the last cycle sampled at
    ``points`` equal time steps (positions in m up from the bottom, loads in N) and a dict with
    the peak and minimum loads, the plunger stroke, the change of the peak load over the last
    cycle (periodicity) and the model's constants.
    """
    speed = check_length("speed", speed)
    n = int(nodes)
    if n < 10:
        raise MechanismError(f"nodes must be at least 10, got {nodes}")
    L, a = rods.depth, rods.wave_speed
    dx = L / n
    period = 2.0 * np.pi / speed
    steps = int(np.ceil(period * a / (0.9 * dx)))  # Courant number 0.9
    dt = period / steps
    c = np.pi * a * rods.damping / (2.0 * L)
    r2 = (a * dt / dx) ** 2
    EA = rods.E * rods.area
    f_o = rods.fluid_load
    # the polished rod over one cycle at every time step, from the unit's exact kinematics
    theta0 = float(np.asarray(unit.dead_centres[0])) if hasattr(unit, "dead_centres") else 0.0
    theta = theta0 + speed * dt * np.arange(steps)
    pr = np.asarray(unit.motion(theta).polished_rod.position, dtype=float)

    u_prev = np.zeros(n + 1)
    u = np.zeros(n + 1)
    u[0] = u_prev[0] = -pr[0]
    # the ideal full pump: PICKUP (plunger held while the rods stretch to the fluid load), UP
    # (fluid load on), RELEASE (plunger held while the load comes off), DOWN (no load)
    state = PICKUP
    surface = np.empty(steps)
    plunger = np.empty(steps)
    peaks = []
    lap = np.empty(n + 1)
    for _ in range(int(cycles)):
        for k in range(steps):
            bottom = EA * (3.0 * u[n] - 4.0 * u[n - 1] + u[n - 2]) / (2.0 * dx)
            v_p = -(u[n] - u_prev[n]) / dt
            if state == PICKUP and bottom >= f_o:
                state = UP
            elif state == UP and v_p <= 0.0:
                state = RELEASE
            elif state == RELEASE and bottom <= 0.0:
                state = DOWN
            elif state == DOWN and v_p >= 0.0:
                state = PICKUP
            lap[1:n] = u[2:] - 2.0 * u[1:n] + u[:-2]
            f_pump = f_o if state == UP else 0.0
            lap[n] = 2.0 * (u[n - 1] - u[n]) + 2.0 * dx * f_pump / EA  # ghost node
            u_next = (2.0 * u - (1.0 - 0.5 * c * dt) * u_prev + r2 * lap) / (1.0 + 0.5 * c * dt)
            u_next[0] = -pr[(k + 1) % steps]
            if state in (PICKUP, RELEASE):
                u_next[n] = u[n]  # the plunger is held by the shut valves
            u_prev, u = u, u_next
            surface[k] = (-3.0 * u[0] + 4.0 * u[1] - u[2]) / (2.0 * dx)
            plunger[k] = -u[n]
        peaks.append(float(np.max(surface)))
    load = rods.buoyant_weight + EA * surface
    pos = np.roll(pr, -1)  # surface[k] is at time step k + 1
    pick = np.linspace(0, steps, int(points), endpoint=False).astype(int)
    card = DynamometerCard(
        pos[pick],
        load[pick],
        f"wave-equation card: {rods.depth:g} m of {rods.diameter * 1e3:g} mm rods, "
        f"{rods.pump_diameter * 1e3:g} mm pump, lift {rods.lift:g} m, damping {rods.damping:g}, "
        f"{speed * 30.0 / np.pi:.3g} SPM",
    )
    change = (
        abs(peaks[-1] - peaks[-2]) * EA / max(float(np.max(load)), 1.0) if cycles > 1 else np.nan
    )
    info = {
        "peak_load": float(np.max(load)),
        "min_load": float(np.min(load)),
        "buoyant_rod_weight": rods.buoyant_weight,
        "fluid_load": f_o,
        "plunger_stroke": float(np.ptp(plunger)),
        "surface_stroke": float(np.ptp(pr)),
        "wave_speed": a,
        "damping_c": c,
        "time_steps_per_cycle": steps,
        "last_cycle_change": float(change),
    }
    return card, info
