"""Speed fluctuation of the AB4115 nail-header drive (paper 003 data, paper 001 method).

The crank train of the nail header (crank OA, rod AB, punch-slider B; the light ejector rocker is
left out) with the masses of paper 003, the upsetting force ``F_e = F_e0 + c1 l_e^4`` acting on
the punch while it upsets (the last ``h`` = 3 mm before the outer dead centre, punch advancing),
driven by an induction motor. The motor is not given in the paper: a representative 4 kW,
1440/1500 rpm motor with overload ratio 2.2 is used, geared by U = 2.4 so that the rated motor
speed gives 600 rpm at the crank. Modelled here as a counter-clockwise crank (the clockwise turn of
the paper is the mirror image and gives the same speed fluctuation).
"""

from __future__ import annotations

import numpy as np

from ..kinematics.slider_crank import SliderCrank
from .equation_of_motion import energy_stepping, steady_cycle
from .inertia import LinkInertia
from .loads import upsetting_force as _upsetting
from .motor import InductionMotor
from .reduced import reduced_model

__all__ = ["nail_header_drive", "nail_header_speed_fluctuation", "upsetting_force"]

RPM = np.pi / 30


def upsetting_force(s_b, h=0.003, c1=571.0, sigma_t=850.0, mu=0.3, d=3.0, l_zag=20.0):
    """Upsetting force (N) at punch distance ``s_b`` (m) from the outer dead centre (paper 003):
    ``F_e = F_e0 + c1 l_e^4`` with ``l_e = 1e3 (h - s_B)`` mm, zero when ``s_B >= h``."""
    return _upsetting(np.asarray(s_b, dtype=float), h, c1, sigma_t, mu, d, l_zag)


def nail_header_drive(slider_mass=15.0, gear_ratio=2.4, n=720):
    """Reduced model and motor of the nail-header drive; returns ``(model, motor)``."""
    sc = SliderCrank(crank=0.07, rod=0.24)
    bodies = [
        LinkInertia("crank", "O", 72.0, (0.0057, 0.0), 4.24),
        LinkInertia("rod", "A", 12.0, (0.05, 0.0), 0.543),
        LinkInertia(None, "B", float(slider_mass)),
    ]
    top = sc.crank + sc.rod

    def upsetting_moment(phi):
        b = sc.motion(phi).points["B"]
        f = upsetting_force(top - b.x) * (b.vx > 0)  # only while the punch advances
        return -f * b.vx

    model = reduced_model(sc, bodies, n=n, phi_loads=[upsetting_moment])
    motor = InductionMotor.from_catalogue(
        4000.0, 1440 * RPM, 1500 * RPM, 2.2, gear_ratio=gear_ratio, efficiency=1.0
    )
    return model, motor


def nail_header_speed_fluctuation(slider_mass=15.0, gear_ratio=2.4, n=720):
    """Steady cycle of the nail header at about 600 rpm: dict with delta, mean/min/max speed
    (rpm), both solvers' results (``"ivp"``, ``"stepping"``)."""
    model, motor = nail_header_drive(slider_mass, gear_ratio, n)
    w0 = 1440 * RPM / gear_ratio
    ivp = steady_cycle(model, motor, w0, n=360)
    step = energy_stepping(model, motor, w0, n=n)
    return {
        "slider_mass": float(slider_mass),
        "delta": float(ivp.delta),
        "delta_stepping": float(step.delta),
        "mean_rpm": float(ivp.omega_mean / RPM),
        "min_rpm": float(ivp.omega.min() / RPM),
        "max_rpm": float(ivp.omega.max() / RPM),
        "ivp": ivp,
        "stepping": step,
    }
