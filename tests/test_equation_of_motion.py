import numpy as np
import pytest
import sympy as sp

import mechsynth as ms
from mechsynth.dynamics import (
    InductionMotor,
    LinearDrive,
    LinkInertia,
    ReducedModel,
    energy_method_flywheel,
    energy_stepping,
    quartic_coefficients,
    reduced_model,
    run_up,
    size_flywheel,
    steady_cycle,
)

RPM = np.pi / 30
MOTOR = InductionMotor.from_catalogue(4000.0, 1440 * RPM, 1500 * RPM, 2.2, gear_ratio=2.4)
SC = ms.SliderCrank(crank=0.07, rod=0.24)
BODIES = [
    LinkInertia("crank", "O", 2.0, (0.035, 0.0), 0.001),
    LinkInertia("rod", "A", 3.0, (0.08, 0.0), 0.02),
    LinkInertia(None, "B", 15.0),
]


def machine(flywheel=0.5):
    load = lambda phi: -40.0 * (1.0 + np.sin(phi))  # noqa: E731
    return reduced_model(SC, BODIES, n=360, phi_loads=[load]).with_flywheel(flywheel)


def test_quartic_coefficients_match_symbolic_derivation():
    w, ji, c, a, sk, k = sp.symbols("w J_i C a s_k K", positive=True)
    s = 1 - a * w
    # energy balance J_i w^2/2 - C = (dphi/2) M(w), M(w) = 2 eta U M_k s s_k / (s^2 + s_k^2),
    # multiplied by (s^2 + s_k^2), with K = dphi eta U M_k s_k
    expr = sp.expand((ji * w**2 / 2 - c) * (s**2 + sk**2) - k * s)
    poly = sp.Poly(expr, w).all_coeffs()
    m, dphi, jval, cval = MOTOR, 0.01, 0.7, 1234.0
    kval = dphi * m.efficiency * m.gear_ratio * m.breakdown_torque * m.critical_slip
    subs = {ji: jval, c: cval, a: m.gear_ratio / m.sync_speed, sk: m.critical_slip, k: kval}
    expected = np.array([float(p.subs(subs)) for p in poly])
    assert np.allclose(quartic_coefficients(jval, cval, m, dphi), expected, rtol=1e-12)
    # and the root satisfies the original (non-polynomial) energy equation
    roots = np.roots(expected)
    r = roots[(abs(roots.imag) < 1e-9) & (roots.real > 0)].real
    wr = r[np.argmin(abs(r - 60.0))]
    assert 0.5 * jval * wr**2 - cval == pytest.approx(0.5 * dphi * m.torque(wr), rel=1e-9)


def test_stepping_agrees_with_solve_ivp_second_order():
    model = machine()
    ref = steady_cycle(model, MOTOR, 60.0, n=90)
    assert ref.converged
    errs = []
    for n in (90, 180):
        e = energy_stepping(model, MOTOR, 60.0, n=n)
        assert e.converged
        errs.append(np.max(np.abs(e.omega[:: n // 90] - ref.omega)))
    # trapezoidal works are O(dphi^2): halving the step divides the error by about 4
    assert 3.0 < errs[0] / errs[1] < 5.0
    assert errs[1] < 1e-3 * ref.omega.mean()
    assert abs(e.delta - ref.delta) < 0.01 * ref.delta


def test_constant_inertia_linear_drive_analytic_run_up():
    j, a, b, ml = 2.0, 300.0, 4.0, 60.0
    model = ReducedModel.constant(j, -ml)
    drive = LinearDrive(a, b)
    ws = (a - ml) / b
    w0 = 20.0
    phi, w = run_up(model, drive, w0, turns=5, n=72)
    # dphi/dw = J w / (b (w* - w))  ->  phi(w) = (J/b)[-(w - w0) - w* ln((w* - w)/(w* - w0))]
    phi_exact = (j / b) * (-(w - w0) - ws * np.log((ws - w) / (ws - w0)))
    assert np.allclose(phi_exact, phi, atol=1e-7)
    cyc = steady_cycle(model, drive, w0, n=36)
    assert np.allclose(cyc.omega, ws, rtol=1e-8)
    assert cyc.delta < 1e-8


def test_constant_inertia_kloss_steady_state_exact():
    ml = 50.0  # below the breakdown torque at the crank (about 140 N m)
    model = ReducedModel.constant(1.0, -ml)
    e = energy_stepping(model, MOTOR, 60.0, n=36)
    assert np.allclose(MOTOR.torque(e.omega), ml, rtol=1e-9)


def test_flywheel_sizing_reaches_requested_delta():
    model = machine(0.1)  # a light existing flywheel: the bare linkage nearly stalls
    jf, cyc = size_flywheel(model, MOTOR, 60.0, 0.02, n=45, j_max=4.0)
    assert cyc.delta == pytest.approx(0.02, rel=1e-4)
    est, de = energy_method_flywheel(model, cyc.omega_mean, 0.02)
    assert de > 0
    # the energy method ignores the motor's own damping: it is conservative (larger) here
    assert jf < est < 1.5 * jf
    with pytest.raises(ValueError, match="delta"):
        size_flywheel(model, MOTOR, 60.0, -0.1)


def test_result_plot_and_bad_speed():
    cyc = steady_cycle(machine(), MOTOR, 60.0, n=36)
    fig = cyc.plot()
    assert len(fig.axes) == 3
    with pytest.raises(ValueError, match="omega0"):
        steady_cycle(machine(), MOTOR, float("nan"))
    with pytest.raises(ValueError, match="omega0"):
        energy_stepping(machine(), MOTOR, -5.0)


def test_nail_header_drive_solvers_agree_and_upsetting_force():
    from mechsynth.dynamics.loads import upsetting_force
    from mechsynth.machines.nail_header.drive import nail_header_speed_fluctuation
    from mechsynth.machines.nail_header.model import NailHeader

    # paper 003 / seeds README: the upsetting force at full contact is about 52.3 kN
    assert float(upsetting_force(0.0)) == pytest.approx(52.3e3, rel=2e-3)
    assert float(upsetting_force(0.0031)) == 0.0
    # the NailHeader model itself (clockwise, ejector, spring, gravity) with the assumed motor
    r = nail_header_speed_fluctuation(NailHeader(m3=15.0), n=360)
    assert r["ivp"].converged and r["stepping"].converged
    assert r["delta_stepping"] == pytest.approx(r["delta"], rel=0.005)
    assert r["mean_rpm"] == pytest.approx(600.0, rel=1e-3)
    # the two speed curves on the same 1 deg grid (the upsetting force's jump at first contact
    # falls inside one step of the trapezoidal works: first order there, still small)
    gap = np.max(np.abs(r["stepping"].omega - r["ivp"].omega))
    assert gap < 2e-4 * r["ivp"].omega_mean


def test_steady_cycle_energy_balance():
    # periodic cycle: the motor's work over a turn equals the work of the resistance
    model = machine()
    cyc = steady_cycle(model, MOTOR, 60.0, n=360)
    work = np.trapezoid(cyc.drive_torque + cyc.load_moment, cyc.phi)
    assert abs(work) < 1e-4 * np.trapezoid(np.abs(cyc.load_moment), cyc.phi)
    assert cyc.omega[-1] == pytest.approx(cyc.omega[0], rel=1e-7)
