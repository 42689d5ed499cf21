"""The impact machine driven by an induction motor: reduced model against paper 001's (11)-(12),
the energy stepping against solve_ivp, energy per turn, start-up, flywheel sizing."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.dynamics.inertia import LinkInertia, com_track, reduced_inertia
from mechsynth.dynamics.reduced import gravity_moment
from mechsynth.machines.impact import five_link, six_link
from mechsynth.machines.impact.drive import (
    ImpactMachine,
    motor_for,
    size_flywheel,
    start_up,
    steady_state,
)
from mechsynth.machines.impact.impact import Tool
from mechsynth.machines.impact.paper001 import eq11_gravity_moment, eq12_reduced_inertia

INERTIAS = {
    "OA": (0.3, (0.0, 0.0), 2e-4),
    "AB": (0.2, (0.031, 0.0), 7e-5),
    "DB": (0.4, (0.0, 0.0), 3e-4),
    "KN": (0.15, (0.035, 0.0), 6e-5),
    "N": (3.0, (0.0, 0.0), 0.0),
}
PHI = np.linspace(0, 2 * np.pi, 181)


@pytest.fixture(scope="module")
def machine():
    m = ImpactMachine(six_link(), INERTIAS, Tool(1.5, 0.5), flywheel=0.01)
    mot = motor_for(m)
    return m.replace(gear_ratio=mot.gear_ratio), mot


def test_paper_eq12_and_eq11_on_the_five_link():
    five = five_link()
    bodies = [
        LinkInertia("OA", "O", 0.0, (0, 0), 2e-4),
        LinkInertia("AB", "A", 0.2, (0.031, 0.0), 7e-5),
        LinkInertia("DB", "D", 0.0, (0, 0), 3e-4),  # J_3D: the rocker's inertia about D
        LinkInertia("N", "N", 3.0),
    ]
    j, _ = reduced_inertia(five, bodies, PHI)
    m = five.motion(PHI)
    s2 = com_track(m, bodies[1])
    j12 = eq12_reduced_inertia(
        2e-4,
        0.2,
        np.hypot(s2.vx, s2.vy),
        7e-5,
        m.links["AB"].omega,
        3e-4,
        m.links["DB"].omega,
        3.0,
        m.sliders["N"].velocity,
    )
    assert np.allclose(j, j12, rtol=1e-13, atol=0)
    for psi, gamma in ((0.0, 0.0), (0.3, 0.2), (-1.0, 0.4)):
        mg, _ = gravity_moment(five, bodies[3:], PHI, tilt=-(psi + gamma))
        m11 = eq11_gravity_moment(3.0 * 9.80665, m.sliders["N"].velocity, psi, gamma)
        assert np.allclose(mg, m11, rtol=1e-13, atol=1e-15)


def test_stepping_against_solve_ivp(machine):
    m, mot = machine
    ivp = steady_state(m, mot)
    step = steady_state(m, mot, method="stepping")
    assert ivp.converged and step.converged
    assert np.max(np.abs(step.omega / ivp.omega - 1.0)) < 1e-6
    # the paper's claim: each step's quartic has exactly one positive real root
    assert np.all(step.positive_roots == 1)
    # one blow per turn; the motor's work per turn = what the blow takes (gravity: none net)
    work = np.trapezoid(ivp.motor_torque, ivp.phi)
    assert work == pytest.approx(ivp.blow.energy_delivered + ivp.blow.energy_lost, rel=1e-5)
    # the speed jumps at the blow
    assert ivp.blow.omega_before == pytest.approx(ivp.omega[-1], rel=1e-12)
    assert ivp.omega[0] == pytest.approx(ivp.blow.omega_after, rel=1e-9)
    assert abs(ivp.blows_per_minute - 2000.0) < 20.0


def test_start_up_reaches_the_steady_state(machine):
    m, mot = machine
    ss = steady_state(m, mot)
    su = start_up(m, mot, duration=0.8)
    assert su.blows.shape[0] > 10
    last = su.t > su.t[-1] - 0.1
    mean = (su.phi[last][-1] - su.phi[last][0]) / (su.t[last][-1] - su.t[last][0])
    assert mean == pytest.approx(ss.omega_mean, rel=5e-3)


def test_tilt_changes_the_gravity_moment_only(machine):
    m, _ = machine
    a = m.reduced_model(n=90)
    b = m.replace(psi=0.4, gamma=0.3).reduced_model(n=90)
    assert np.allclose(a.j_grid, b.j_grid) and not np.allclose(a.m_grid, b.m_grid)


@pytest.mark.slow
def test_flywheel_sizing(machine):
    m, mot = machine
    jf, ss = size_flywheel(m.replace(flywheel=0.0), 0.05, mot)
    assert jf > 0 and ss.delta == pytest.approx(0.05, rel=1e-3)


def test_bad_input(machine):
    m, _ = machine
    with pytest.raises(ms.MechanismError, match="flywheel"):
        m.replace(flywheel=-1.0)
    with pytest.raises(ms.MechanismError, match="striker"):
        ImpactMachine(six_link(), INERTIAS, striker="Z")
    with pytest.raises(ms.MechanismError, match="method"):
        steady_state(m, method="euler")
    with pytest.raises(ms.MechanismError, match="motor cannot carry"):
        motor_for(m.replace(tool=Tool(30.0, 0.0), inertias={**INERTIAS, "N": (40.0, (0, 0), 0)}))


def test_bad_input_is_refused_at_the_door(machine):
    """Each of these raised a bare exception, returned NaN or 0, or was taken silently."""
    from mechsynth.machines.impact.impact import newton_impact
    from mechsynth.machines.impact.synthesis import impact_problem

    m, _ = machine
    with pytest.raises(ms.MechanismError, match="striker speed v must be finite, got nan"):
        newton_impact(3.0, float("nan"), Tool())  # returned NaN energies
    with pytest.raises(ms.MechanismError, match="tool mass must be a number"):
        Tool(mass="fast")
    with pytest.raises(ms.MechanismError, match="linkage must be a Linkage .* got 42"):
        ImpactMachine(42)  # AttributeError
    with pytest.raises(ms.MechanismError, match="speed_rpm must be a number"):
        ImpactMachine(six_link(), INERTIAS, speed_rpm=None)  # TypeError
    with pytest.raises(ms.MechanismError, match="gear_ratio must be positive"):
        m.replace(gear_ratio=-1.0)
    with pytest.raises(ms.MechanismError, match="gear_ratio must be positive"):
        motor_for(m, -2.0)
    with pytest.raises(ms.MechanismError, match="no field 'restitution' .*tool=Tool"):
        m.replace(restitution=2)  # a bare TypeError
    with pytest.raises(ms.MechanismError, match="samples must be between 2"):
        start_up(m, samples=0)  # IndexError
    with pytest.raises(ms.MechanismError, match=r"delta .* must lie in \(0, 1\)"):
        size_flywheel(m, 2.0)  # returned 0
    for kw, match in [
        ({"stroke": 0}, "stroke must be positive"),
        ({"max_joint_force": -1}, "max_joint_force must be positive"),
        ({"min_transmission_deg": 120}, r"must lie in \[0, 90\) deg"),  # solved 28 s
    ]:
        with pytest.raises(ms.MechanismError, match=match):
            impact_problem(m, **kw)


def test_time_to_a_speed_not_reached_is_none_not_nan():
    from mechsynth.machines.impact.drive import StartUp

    su = StartUp(np.linspace(0, 0.1, 11), np.zeros(11), np.linspace(0, 50, 11), np.zeros((0, 4)))
    assert su.time_to(0.5, 100.0) == pytest.approx(0.1)
    assert su.time_to(0.95, 100.0) is None  # was NaN, printed as "after nan s"
