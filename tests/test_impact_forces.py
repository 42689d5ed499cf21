"""Forces in the impact machines: power balance, paper 001's (20)-(21), the guide's side load
and the transverse load on the housing against the base crank-rocker machine."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.machines.impact import crank_rocker, five_link, six_link
from mechsynth.machines.impact.drive import ImpactMachine
from mechsynth.machines.impact.forces import cycle_forces, force_findings, power_balance
from mechsynth.machines.impact.paper001 import eq20_f43, eq21_f45

SIX = {
    "OA": (0.3, (0.002, 0.001), 2e-4),
    "AB": (0.2, (0.031, 0.0), 7e-5),
    "DB": (0.4, (0.01, -0.01), 3e-4),
    "KN": (0.15, (0.035, 0.0), 6e-5),
    "N": (3.0, (0.0, 0.0), 0.0),
}
FIVE = {k: v for k, v in SIX.items() if k != "KN"}
PHI = np.linspace(0.0, 2 * np.pi, 97)


def _base():
    cr = crank_rocker()
    ku, kv = cr.parameters["K_along"], cr.parameters["K_left"]
    m = 3.4
    rocker = (m, (3.0 * ku / m, 3.0 * kv / m), 3e-4 + 3.0 * (ku**2 + kv**2) * 0.4 / m)
    return ImpactMachine(cr, {"OA": SIX["OA"], "AB": SIX["AB"], "DB": rocker}, striker="K")


MACHINES = {
    "six": lambda: ImpactMachine(six_link(), SIX),
    "six-57": lambda: ImpactMachine(six_link(ms.deg(57)), SIX),
    "five": lambda: ImpactMachine(five_link(), FIVE),
    "arc": lambda: ImpactMachine(five_link("arc"), FIVE),
    "base": _base,
}


@pytest.mark.parametrize("name", list(MACHINES))
def test_power_balance(name):
    m = MACHINES[name]().replace(psi=0.35, gamma=-0.1)
    w = ms.rpm(2000) * (1 + 0.05 * np.sin(PHI))  # a speed varying over the turn
    for omega, eps in ((ms.rpm(2000), 0.0), (w, 400.0 * np.cos(PHI))):
        r, scale = power_balance(m, PHI, omega, eps)
        assert np.max(np.abs(r)) < 1e-9 * scale


@pytest.mark.parametrize("psi, gamma", [(0.0, 0.0), (0.3, 0.1), (-0.5, 0.2)])
def test_paper_eq20_eq21_on_the_involute_five_link(psi, gamma):
    m = MACHINES["five"]().replace(psi=psi, gamma=gamma)
    f = cycle_forces(m, PHI)
    g4 = 3.0 * 9.80665
    a = f.motion.sliders["N"].acceleration  # along the guide (+y at rho = 90 deg)
    # the contact force on the striker lies along the guide; projected on the downward guide
    # axis it is (20) -- the rocker's force on the striker (the text calls it the striker's on
    # the rocker: an erratum)
    fx, fy = f.result.reactions["N_contact"]
    assert np.allclose(fx, 0.0, atol=1e-9)
    phi4_down = -3.0 * (-a)  # inertia force along the downward axis
    assert np.allclose(-fy, eq20_f43(g4, phi4_down, psi, gamma), rtol=1e-12, atol=1e-9)
    # to round-off of the forces (1e-12 of the model; its compiled kernel, which a structure's
    # repeated motions take, agrees with it to 1e-12 of the positions)
    assert np.allclose(f.guide, eq21_f45(g4, psi, gamma), rtol=1e-12, atol=1e-9)


def test_involute_puts_no_side_load_on_the_guide_the_arc_does():
    inv = cycle_forces(MACHINES["five"](), PHI, gravity=False)
    arc = cycle_forces(MACHINES["arc"](), PHI, gravity=False)
    assert np.max(np.abs(inv.guide)) < 1e-9
    assert np.max(np.abs(arc.guide)) > 50.0


def test_transverse_housing_load_against_the_base_machine():
    base = force_findings(MACHINES["base"]())
    for name in ("six", "five", "arc"):
        f = force_findings(MACHINES[name]())
        assert f["transverse_peak_N"] < 0.3 * base["transverse_peak_N"]
    # the housing's total load is the bodies' momentum rate: the profile changes where it goes
    # (guide or pivot), not its sum
    inv, arc = cycle_forces(MACHINES["five"](), PHI), cycle_forces(MACHINES["arc"](), PHI)
    assert np.allclose(inv.transverse, arc.transverse, atol=1e-9)


def test_findings_reported():
    f = force_findings(MACHINES["six"]())
    assert f["rocker_striker_joint"] == "K" and 0 < f["rocker_striker_ratio"] < 1
    assert len(f["dead_centres_deg"]) == 2
    for j in ("A", "B", "D"):
        assert f["peaks"][j]["from_dead_centre_deg"] < 30.0


@pytest.mark.parametrize("rho", [57.0, 90.0, 123.0])
def test_symbolic_six_link_forces_equal_the_numeric_ones(rho):
    """The synthesis differentiates the general kinetostatics written with CasADi symbols for
    the dimensions (solved group by group, each group's elimination mapped over the angles): at
    the design's values it gives the numeric solve's forces, and its size stays near a
    hand-eliminated form's."""
    import casadi as ca

    from mechsynth.dynamics.kinetostatics import kinetostatics
    from mechsynth.dynamics.loads import Gravity
    from mechsynth.machines.impact.design import representative_machine
    from mechsynth.machines.impact.forces import housing_load

    m = representative_machine("six", rho, psi=0.3, gamma=0.1)
    names = ("OA", "AB", "DB", "K_along", "K_left", "KN", "N_guide_angle", "N_guide_offset")
    sym = {k: ca.SX.sym(k) for k in names}
    lk = m.linkage.with_parameters(**sym)
    w = ms.rpm(2000) * (1 + 0.05 * np.sin(PHI))
    model = lk.force_model(m.inertias, [Gravity(tilt=m.tilt)])
    res = kinetostatics(model, lk.motion(PHI, speed=w, epsilon=300.0))
    hx, hy = housing_load(model, res)
    joints = ("O", "A", "B", "D", "K", "N", "N_guide")
    out = [res.reactions[j][k] for j in joints for k in (0, 1)] + [hx, hy, res.torque]
    fn = ca.Function("f", [ca.vertcat(*sym.values())], [ca.horzcat(*out)])
    got = np.array(fn([m.linkage.parameters[k] for k in names]))
    f = cycle_forces(m, PHI, w, 300.0)
    want = [np.asarray(f.result.reactions[j][k]) for j in joints for k in (0, 1)]
    want += [f.housing[0], f.housing[1], np.asarray(f.result.torque)]
    want = np.column_stack([np.broadcast_to(v, PHI.shape) for v in want])
    assert np.max(np.abs(got - want)) < 1e-11 * np.max(np.abs(want))
    assert fn.n_nodes() < 400 * PHI.size  # a dense symbolic solve: some 3600 per angle
