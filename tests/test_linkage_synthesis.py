"""Synthesis over general linkages: Problem with certified assembly margins, the optimum checked
by a dense scan, designs that fail between grid angles repaired by refinement, starts that cannot
assemble skipped, the time ratio's CasADi derivative, sweeps, force measures."""

import casadi as ca
import numpy as np
import pytest

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth.synthesis import sweep
from mechsynth.synthesis.solvers import _Certifier


def six_link():
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
        .attach("K", on=("D", "B"), along=-0.05)
        .rrp("N", ("K", 0.10), guide=((0.12, 0.0), ms.deg(57)))
    )


def test_problem_over_a_linkage_is_certified_and_beats_a_scan():
    """Maximize the striker's stroke over the rocker DB and the rod KN with the rocker's
    transmission angle >= 45 deg and the rod's pressure angle <= 30 deg: the certified optimum
    is at least the best of a 60 x 60 scan of the box, and no scanned design that meets the
    limits beats it."""
    lk = six_link()
    prob = ms.Problem(lk, variables={"DB": (0.04, 0.12), "KN": (0.06, 0.2)})
    prob.maximize(ob.stroke("N"))
    prob.subject_to(
        ob.min_transmission_angle("B") >= ms.deg(45), ob.max_pressure_angle("N") <= ms.deg(30)
    )
    res = prob.solve(starts=3)
    assert res.status == "optimal" and res.certification.certified
    # reported values are the certified true peaks
    by_name = {p.name: p.true_value for p in res.certification.peaks}
    assert res.value == pytest.approx(
        by_name["max stroke(N)"] - by_name["min stroke(N)"], abs=1e-12
    )
    for c in res.constraints:
        assert c.satisfied
    ch = sweep(
        lk,
        grid={"DB": np.linspace(0.04, 0.12, 60), "KN": np.linspace(0.06, 0.2, 60)},
        measures={
            "stroke": ob.stroke("N"),
            "mu": ob.min_transmission_angle("B"),
            "p": ob.max_pressure_angle("N"),
        },
        angles=720,
        progress=False,
    )
    ok = {"mu": (">=", ms.deg(45)), "p": ("<=", ms.deg(30))}
    best = ch.argbest("stroke", where=ok, sense="max")
    assert best["values"]["stroke"] <= res.value * (1 + 1e-6)
    assert best["values"]["stroke"] >= 0.97 * res.value  # the scan comes close


def test_certifier_repairs_a_design_that_fails_between_grid_angles():
    """On a coarse grid (8 angles) the optimizer finds a rocker that assembles at every grid angle
    but not between them; the dense check names the angles, they join the grid, and the
    re-solve ends at a design with the required margin everywhere."""
    lk = six_link()
    prob = ms.Problem(lk, variables={"DB": (0.03, 0.12), "KN": (0.05, 0.2)}, angles=8)
    prob.maximize(ob.stroke("N"))
    failing = lk(DB=0.03816)  # assembles at the 8 grid angles only
    assert min(failing.assembly_margins(ms.cycle(8))["B"]) > 0
    assert min(failing.assembly_margins(ms.cycle(3600))["B"]) < -0.1
    cert = _Certifier(prob, "ipopt", None, 1e-9, 12, 2048)
    checks, new, _ = cert.checks(failing)
    assert checks == [] and len(new) >= 1
    assert failing.assembly_margins(np.array(new))["B"].min() < 0
    res = prob.solve(starts=1)
    assert res.status == "optimal" and res.certification.refinement_rounds >= 1
    assert res.design.assembly_margins(ms.cycle(20000))["B"].min() >= 1e-3 * (1 - 1e-6)


def test_starts_that_cannot_assemble_are_skipped_and_a_hopeless_box_fails_cleanly():
    lk = six_link()
    prob = ms.Problem(lk, variables={"DB": (0.02, 0.12)}).minimize(ob.peak_acceleration("N"))
    res = prob.solve(starts=2)
    assert res.success and res.certification.starts_skipped > 0
    hopeless = ms.Problem(lk, variables={"DB": (0.01, 0.03)}).minimize(ob.peak_acceleration("N"))
    res = hopeless.solve(starts=2)
    assert res.status == "solver_failed" and "RRR group B" in res.message
    with pytest.raises(ValueError, match="'AB' is a length: its lower bound must be positive"):
        ms.Problem(lk, variables={"AB": (0.0, 0.2)})
    with pytest.raises(ValueError, match="has no parameter 'rod'"):
        ms.Problem(lk, variables={"rod": (0.1, 0.2)})


def test_time_ratio_and_its_casadi_derivative():
    """The linkage's time ratio (dead centres by Newton on the velocity analog) equals the
    four-bar's closed form, and its CasADi derivative equals differences."""
    fb = ms.FourBar(1.0, 4.3, 3.0, 5.2)
    lk = (
        ms.Linkage(ground={"O1": (0, 0), "O2": (5.2, 0)})
        .crank("A", about="O1", length=1.0)
        .rrr("B", ("A", 4.3), ("O2", 3.0))
    )
    assert lk.time_ratio == pytest.approx(fb.time_ratio, abs=1e-12)
    six = six_link()
    measure = ob.time_ratio().bind(six)
    x = ca.SX.sym("x", 2)
    f = ca.Function("f", [x], [ca.gradient(measure.fn(six(DB=x[0], KN=x[1])), x)])
    g = np.asarray(f([0.08, 0.1])).ravel()
    h = 1e-6
    for i, name in enumerate(("DB", "KN")):
        up = six(**{name: six.parameters[name] + h}).time_ratio
        dn = six(**{name: six.parameters[name] - h}).time_ratio
        assert g[i] == pytest.approx((up - dn) / (2 * h), rel=1e-6, abs=1e-9)
    # numeric dead centres are where the slider's velocity vanishes
    hi, lo = six.dead_centres()
    v = six.motion(np.array([hi, lo])).sliders["N"].velocity
    assert np.max(np.abs(v)) < 1e-12


def test_sweep_over_a_linkage_masks_designs_that_cannot_assemble():
    lk = six_link()
    ch = sweep(
        lk,
        grid={"DB": np.linspace(0.02, 0.12, 9), "KN": np.linspace(0.05, 0.2, 5)},
        measures={"stroke": ob.stroke("N")},
        angles=180,
        progress=False,
    )
    for i, db in enumerate(np.linspace(0.02, 0.12, 9)):
        for j, kn in enumerate(np.linspace(0.05, 0.2, 5)):
            try:
                s = np.ptp(lk(DB=db, KN=kn).motion(ms.cycle(180)).sliders["N"].position)
            except ms.MechanismError:
                assert not ch.feasible[i, j]
                continue
            assert ch.feasible[i, j] and ch.values["stroke"][i, j] == pytest.approx(s, rel=1e-12)
    assert not ch.feasible.all() and ch.feasible.any()


def test_force_measures_on_a_linkage():
    """Peak crank torque of the six-link with a striker mass, through the linkage's force model
    and the existing force measures, numpy and CasADi alike."""
    lk = six_link()

    def model(mech):
        return mech.force_model({"N": (2.0, (0.0, 0.0), 0.0), "KN": (0.5, (0.05, 0.0), 1e-4)})

    peak = ob.peak_torque(model)
    value = peak.evaluate(lk, ms.cycle(720), speed=ms.rpm(1500))
    assert np.isfinite(value) and value > 0
    prob = ms.Problem(lk, variables={"KN": (0.08, 0.2)}, speed=ms.rpm(1500), angles=24)
    prob.minimize(peak)
    res = prob.solve(starts=1)
    assert res.status == "optimal"
    scan = [
        peak.evaluate(lk(KN=k), ms.cycle(2880), speed=ms.rpm(1500))
        for k in np.linspace(0.08, 0.2, 25)
    ]
    # the certified value is the continuous peak: at or above a dense grid's, and no scanned
    # design is better beyond the grid's error
    assert min(scan) * (1 - 1e-9) <= res.value <= min(scan) * (1 + 1e-5)
