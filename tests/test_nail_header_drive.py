"""Nail-header drive built from the one NailHeader model: reduced inertia and load moments in the
machine's clockwise crank angle, power balance against the kinetostatics, speed fluctuation."""

import numpy as np
import pytest
from scipy.optimize import brentq

from mechsynth.dynamics import InductionMotor
from mechsynth.dynamics.equation_of_motion import steady_cycle
from mechsynth.dynamics.inertia import com_track
from mechsynth.dynamics.kinetostatics import kinetostatics
from mechsynth.machines.nail_header.drive import (
    contact_angles,
    crank_speed,
    default_motor,
    kinetic_energy_at_speed,
    load_table,
    nail_header_drive,
    nail_header_inertia,
    nail_header_speed_fluctuation,
    reduced_load_moment,
    reduced_load_moments,
)
from mechsynth.machines.nail_header.model import NailHeader

HEADERS = [
    NailHeader(),
    NailHeader(m3=50.0),
    NailHeader(m3=30.0, counterweight=1.5, m2=20.0, spring_sense=1),
]


def _upsetting_work(nh):
    # paper 003: F_e = F_e0 + c1 l_e^4 over the last h of the stroke, l_e = 1e3 (h - s) mm
    f0 = nh.sigma_t * (1 + nh.mu * nh.d / (3 * nh.l_blank)) * np.pi * nh.d**2 / 4
    h_mm = 1e3 * nh.h
    return f0 * nh.h + nh.c1 * h_mm**5 / 5 * 1e-3  # J


@pytest.mark.parametrize("nh", HEADERS)
def test_reduced_inertia_is_twice_kinetic_energy_over_w2(nh):
    model, _ = nail_header_drive(nh, n=360)
    w = crank_speed(nh)
    theta = np.linspace(0.0, 2 * np.pi, 997)  # mostly between the spline's nodes
    exact = 2 * kinetic_energy_at_speed(nh, theta) / w**2
    assert np.allclose(model.inertia(theta), exact, rtol=1e-7)
    # nodes and derivative: dJ/dtheta is minus dJ/dphi (clockwise angle), checked by differences
    j, dj = nail_header_inertia(nh, model.phi_grid)
    assert np.allclose(model.inertia(model.phi_grid), j, rtol=1e-13)
    k = 1e-5
    fd = (
        (kinetic_energy_at_speed(nh, theta + k) - kinetic_energy_at_speed(nh, theta - k)) / k / w**2
    )
    assert np.allclose(model.inertia_derivative(theta), fd, atol=1e-6 * np.max(np.abs(fd)))


@pytest.mark.parametrize("nh", HEADERS)
def test_power_balance_against_kinetostatics_at_600_rpm(nh):
    # balancing torque T (ccw) of NailHeader.forces at the clockwise 600 rpm:
    # T omega = dT/dt - P_applied  <=>  T = M(theta) - J'(theta) w^2 / 2 with theta = -phi
    model, _ = nail_header_drive(nh, n=720)
    theta = model.phi_grid[np.abs(np.sin(model.phi_grid)) > 1e-3]  # not at the dead centres
    w = crank_speed(nh)
    res = nh.forces(-theta)
    expected = model.moment(theta, w) - 0.5 * model.inertia_derivative(theta) * w**2
    assert np.max(np.abs(res.torque - expected)) <= 1e-9 * np.max(np.abs(res.torque))
    # and the loads alone equal the inertia-free kinetostatics: all masses of the slider train
    # kept (gravity needs them), so compare the torque change when the upsetting force is removed
    model_nf = nh.force_model().replace_loads(nh.force_model().loads[1:])
    t_nf = kinetostatics(model_nf, nh.motion(-theta, speed=nh.omega)).torque
    m = reduced_load_moments(nh, theta)
    assert np.allclose(res.torque - t_nf, m["upsetting"], atol=1e-9 * np.max(np.abs(res.torque)))


def test_load_moments_names_sum_and_conservative_loads():
    nh = NailHeader()
    tab = load_table(nh, 5760)
    m = reduced_load_moments(nh, tab.theta)
    assert set(m) == {"upsetting", "spring", "gravity"}
    total = m["upsetting"] + m["spring"] + m["gravity"]
    assert np.allclose(total, reduced_load_moment(nh, tab.theta), rtol=0, atol=1e-9)
    assert np.allclose(tab.moment, total, rtol=0, atol=1e-9)
    # spring and gravity are conservative: no work over a turn
    assert abs(np.trapezoid(m["spring"], tab.theta)) < 1e-8
    assert abs(np.trapezoid(m["gravity"], tab.theta)) < 1e-8


def test_gravity_moment_is_minus_derivative_of_potential_energy():
    nh = NailHeader(counterweight=0.8)
    theta = np.linspace(0.0, 2 * np.pi, 181)
    bodies = list(nh.force_model().bodies.values())

    def potential(t):
        m = nh.motion(-t)
        return sum(b.mass * nh.g * com_track(m, b).y for b in bodies)

    k = 1e-6
    fd = -(potential(theta + k) - potential(theta - k)) / (2 * k)
    got = reduced_load_moments(nh, theta)["gravity"]
    assert np.allclose(got, fd, atol=1e-6 * np.max(np.abs(fd)))
    # the counterweight opposite A sits at y = r_cw sin(theta) (A at y = -l_OA sin(theta) when
    # the crank turns clockwise): it adds -m_cw r_cw g cos(theta), resisting as it rises
    base = reduced_load_moments(NailHeader(), theta)["gravity"]
    assert np.allclose(got - base, -0.8 * nh.g * np.cos(theta), atol=1e-9)


@pytest.mark.parametrize("m3", [15.0, 50.0])
def test_upsetting_acts_while_the_punch_advances_clockwise(m3):
    nh = NailHeader(m3=m3)
    r, l, h = nh.l_oa, nh.l_ab, nh.h
    # contact at s_B = h on the advancing (second) half of the clockwise turn, closed form
    theta_c = brentq(
        lambda t: r * np.cos(t) + np.sqrt(l * l - (r * np.sin(t)) ** 2) - (r + l - h),
        np.pi,
        2 * np.pi,
        xtol=1e-15,
    )
    pairs = contact_angles(nh)
    start = pairs[np.argmin(np.abs(pairs[:, 0] - theta_c))]
    assert start[0] == pytest.approx(theta_c, abs=1e-12) and start[1] - start[0] < 1e-12
    assert np.rad2deg(theta_c) == pytest.approx(345.17, abs=0.01)
    tab = load_table(nh, 5760)
    up = reduced_load_moments(nh, tab.theta)["upsetting"]
    before = tab.theta < theta_c
    assert np.all(np.abs(up[before]) < 1e-5)  # zero out of contact (up to the dead centre)
    assert np.all(up[~before & (tab.theta < 2 * np.pi - 1e-6)] < 0)  # it resists
    # the jump at first contact: -F_e0 times the punch's velocity analog there
    f0 = nh.sigma_t * (1 + nh.mu * nh.d / (3 * nh.l_blank)) * np.pi * nh.d**2 / 4
    v = nh.motion(np.array([-start[1]])).points["B"].vx  # dx_B/dphi; dx_B/dtheta = -v
    assert tab(start[1]) == pytest.approx(f0 * v[0] + tab(start[0]), rel=1e-6)
    # work per turn: minus the integral of F_e over the last h of the stroke
    assert tab.work == pytest.approx(-_upsetting_work(nh), rel=2e-5)


def test_analog_motion_puts_the_upsetting_on_the_advancing_stroke():
    # NailHeader.upsetting judges "advancing" on the clockwise machine also for an analog motion
    # (analogs per counter-clockwise radian), so the analog reading gives the same negative
    # upsetting work per turn as the real motion, not the mirror stroke's positive work
    nh = NailHeader()
    theta = np.linspace(0.0, 2 * np.pi, 5761)
    m = nh.motion(-theta)
    f = nh.upsetting(m)
    work = np.trapezoid(-f * m.points["B"].vx, -theta)
    assert work == pytest.approx(-_upsetting_work(nh), rel=2e-3)
    assert load_table(nh).work < -0.9 * _upsetting_work(nh)


@pytest.mark.parametrize("m3", [15.0, 50.0])
def test_speed_fluctuation_solvers_agree_and_mean_speed(m3):
    r = nail_header_speed_fluctuation(slider_mass=m3, n=720)
    assert r["ivp"].converged and r["stepping"].converged
    assert r["delta_stepping"] == pytest.approx(r["delta"], rel=2e-3)
    # gear ratio solved so that the motor carries the mean load at 600 rpm
    assert r["mean_rpm"] == pytest.approx(600.0, rel=2e-4)
    assert r["mean_power_W"] == pytest.approx(_upsetting_work(NailHeader()) * 10, rel=1e-3)
    # periodic cycle: the motor's work per turn equals the work of the loads
    c = r["ivp"]
    motor_work = np.trapezoid(c.drive_torque, c.phi)
    assert motor_work == pytest.approx(-r["load_work_J"], rel=1e-3)


def test_heavier_slider_fluctuates_more_and_energy_estimate():
    a = nail_header_speed_fluctuation(slider_mass=15.0, n=360)
    b = nail_header_speed_fluctuation(slider_mass=50.0, n=360)
    assert b["delta"] > 3 * a["delta"]
    # the fluctuation is dominated by the varying inertia: with J w^2 ~ const over the turn,
    # delta ~ sqrt(J_max / J_min) - 1 (an estimate: the motor and the loads add to it)
    for r in (a, b):
        est = np.sqrt(r["inertia_max"] / r["inertia_min"]) - 1
        assert 0.8 * est < r["delta"] < 1.5 * est


def test_header_instance_equals_slider_mass_convenience():
    m1, mot1 = nail_header_drive(NailHeader(m3=50.0), n=90)
    m2, mot2 = nail_header_drive(slider_mass=50.0, n=90)
    assert np.array_equal(m1.j_grid, m2.j_grid) and mot1 == mot2
    theta = np.linspace(0, 6.2, 50)
    assert np.array_equal(m1.moment(theta, 60.0), m2.moment(theta, 60.0))


def test_given_gear_ratio_and_motor():
    model, motor = nail_header_drive(gear_ratio=2.4, n=180)
    assert motor.gear_ratio == 2.4
    cyc = steady_cycle(model, motor, 63.0, n=180)
    # with U = 2.4 the synchronous crank speed is 625 rpm: the lightly loaded motor runs near it
    assert 615 < cyc.omega_mean * 30 / np.pi < 625
    m = InductionMotor(50.0, 0.1, 157.0, 2.5)
    assert nail_header_drive(motor=m, n=90)[1] is m


def test_bad_input():
    with pytest.raises(ValueError, match="header must be a NailHeader"):
        nail_header_drive(15.0)
    with pytest.raises(ValueError, match="n1"):
        nail_header_drive(NailHeader(n1=0.0))
    with pytest.raises(ValueError, match="m3"):
        nail_header_drive(slider_mass=-1.0)
    with pytest.raises(ValueError, match="n must be at least 8"):
        nail_header_drive(n=4)
    with pytest.raises(ValueError, match="motor must be an InductionMotor"):
        nail_header_drive(motor="4 kW")
    with pytest.raises(ValueError, match="cannot carry a mean load torque of 100000 N m"):
        default_motor(header=NailHeader(), load_torque=1e5)
    with pytest.raises(ValueError, match="theta must be finite"):
        reduced_load_moments(NailHeader(), [0.1, np.nan])
    with pytest.raises(ValueError, match="theta must be finite"):
        nail_header_inertia(NailHeader(), np.inf)
    with pytest.raises(ValueError, match="n must be at least 8, got 2"):
        contact_angles(NailHeader(), 2)
    r = nail_header_speed_fluctuation(n=90)
    assert all(
        np.isfinite(v) for k, v in r.items() if k not in ("ivp", "stepping", "model", "motor")
    )
