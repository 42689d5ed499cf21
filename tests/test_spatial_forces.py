"""Kinetostatics of the spatial pumping-unit drive: redundant (revolute) and rational
(spherical) pairs, power balance, the planar unit as the limit, the elastic closure."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.kinematics.spatial import cross, dot
from mechsynth.machines.pumping_unit import (
    Counterbalance,
    DynamometerCard,
    SpatialMasses,
    planar_torque,
    power_balance,
    size_counterbalance,
)

C320 = dict(A=155.0, C=111.06, I=111.02, P=132.01, R=42.01, H=231.97, G=95.98, units="in")
MARK_II = dict(
    A=334.0, C=270.0, I=202.56, P=193.5, R=63.56, H=295.13, G=112.13, units="in",
    unit_class="mark-ii", rotation="ccw",
)  # fmt: skip
MASSES = SpatialMasses(
    pitman=150.0,
    pitman_com=0.45,
    pitman_axial_inertia=0.4,
    equalizer=200.0,
    equalizer_axial_inertia=3.0,
    beam=2500.0,
    beam_com=(-0.8, 0.3),
    beam_inertia=4000.0,
    head=600.0,
    head_com=(3.6, 0.1),
    head_inertia=300.0,
    crank_inertia=5000.0,
)
DEV = dict(
    phase_mismatch=ms.deg(0.3),
    crank_difference=0.002,
    pitman_difference=0.003,
    shaft_tilt=5e-4,
    shaft_skew=1e-3,
    beam_tilt=1e-3,
    beam_skew=-5e-4,
    equalizer_offset=0.004,
)
TH = np.linspace(0.0, 2.0 * np.pi, 72, endpoint=False) + 0.02
SPEED = ms.spm(8.0)
CB = Counterbalance(60e3, 0.1)


def _unit(kind="conventional"):
    return ms.BeamPumpingUnit.from_api(**(C320 if kind == "conventional" else MARK_II))


@pytest.mark.parametrize("kind", ["conventional", "mark-ii"])
@pytest.mark.parametrize("joints", ["revolute", "spherical"])
def test_ideal_drive_torque_is_the_planar_units(kind, joints):
    u = _unit(kind)
    s = ms.SpatialPumpingUnit.from_planar(u, 1.2, joints=joints)
    # massless links: torque factor x load, by virtual work
    f = s.forces(TH, SPEED, load=80e3)
    tf = u.motion(TH).torque_factor
    np.testing.assert_allclose(
        f.crank_torque, tf * 80e3, rtol=0, atol=1e-9 * 80e3 * np.abs(tf).max()
    )
    # with the same masses: the planar kinetostatics of the same unit
    f = s.forces(TH, SPEED, load=80e3, counterbalance=CB, masses=MASSES, epsilon=0.04)
    tp = planar_torque(s, TH, SPEED, load=80e3, counterbalance=CB, masses=MASSES, epsilon=0.04)
    np.testing.assert_allclose(f.crank_torque, tp, rtol=0, atol=1e-9 * np.abs(tp).max())
    # the two pitmans share the load equally; no moments in the pairs
    fl, fr = f.pitman_force["left"], f.pitman_force["right"]
    np.testing.assert_allclose(fl, fr, rtol=0, atol=1e-9 * np.abs(fl).max())
    for side in ("left", "right"):
        for k in ("torsion", "bending_A", "bending_B"):
            assert np.max(np.abs(f.elastic[side][k])) < 1e-6
    assert np.max(f.residual) < 1e-6


def test_splayed_pitmans_of_an_ideal_drive_are_not_strained():
    """Crank spacing and equalizer width differ: the pitmans lean (by 0.06 rad here), their pin
    holes are made parallel to the shaft, so the ideal drive has no misfit; only the pitmans'
    stretch under load, which moves B and B1 along the shaft against the rigid equalizer, bends
    them a little (a few N m, where holes square to the pitman would bend them by ~1e4 N m)."""
    s = ms.SpatialPumpingUnit.from_planar(_unit(), 1.4, 1.0)
    rev = s.forces(TH, SPEED, load=80e3)
    rat = s.with_joints("spherical").forces(TH, SPEED, load=80e3)
    for side in ("left", "right"):
        assert np.max(np.abs(rev.elastic[side]["bending_B"])) < 10.0
        np.testing.assert_allclose(rev.pitman_force[side], rat.pitman_force[side], rtol=1e-4)
    assert rev.peak_split < 1e-9  # symmetric
    np.testing.assert_allclose(rev.crank_torque, rat.crank_torque, atol=1e-3)


def test_both_ideal_variants_give_the_same_forces():
    s = ms.SpatialPumpingUnit.from_planar(_unit(), 1.2)
    a = s.forces(TH, SPEED, load=80e3, counterbalance=CB, masses=MASSES)
    b = s.with_joints("spherical").forces(TH, SPEED, load=80e3, counterbalance=CB, masses=MASSES)
    scale = np.abs(a.pitman_force["left"]).max()
    for side in ("left", "right"):
        np.testing.assert_allclose(a.pitman_force[side], b.pitman_force[side], atol=1e-6 * scale)
    for name in a.reactions:
        np.testing.assert_allclose(
            a.reactions[name].force, b.reactions[name].force, atol=1e-6 * scale
        )
    np.testing.assert_allclose(
        a.crank_torque, b.crank_torque, atol=1e-6 * np.abs(a.crank_torque).max()
    )
    assert (a.info["nullity"], b.info["nullity"]) == (5, 0)  # 5 self-stress states (not 4)
    assert (a.info["rank"], b.info["rank"]) == (29, 26)


def _independent_power(s, f, masses, cb):
    """Energy balance written out from the motion alone (not from the force model's parts)."""
    m = f.motion
    P, K = m.points, m.links
    g = np.array([0.0, -9.80665, 0.0])
    dke = pg = 0.0

    def axisym(jt, ja, ax, vec):
        return jt * vec + (ja - jt) * dot(ax, vec)[:, None] * ax

    for a, b, lk, side in (
        ("A", "B", "pitman_left", "left"),
        ("A1", "B1", "pitman_right", "right"),
    ):
        r = masses.pitman_com * (P[b].position - P[a].position)
        w, e, ax = K[lk].omega, K[lk].epsilon, K[lk].axis
        v = P[a].velocity + cross(w, r)
        acc = P[a].acceleration + cross(e, r) + cross(w, cross(w, r))
        jt = masses.pitman * s.lengths[f"pitman_{side}"] ** 2 / 12.0
        dke = (
            dke
            + masses.pitman * dot(v, acc)
            + dot(w, axisym(jt, masses.pitman_axial_inertia, ax, e))
        )
        pg = pg + masses.pitman * dot(g, v)
    w, e, ax = K["equalizer"].omega, K["equalizer"].epsilon, K["equalizer"].axis
    v = 0.5 * (P["B"].velocity + P["B1"].velocity)
    acc = 0.5 * (P["B"].acceleration + P["B1"].acceleration)
    jt = masses.equalizer * s.equalizer_width**2 / 12.0
    dke = (
        dke
        + masses.equalizer * dot(v, acc)
        + dot(w, axisym(jt, masses.equalizer_axial_inertia, ax, e))
    )
    pg = pg + masses.equalizer * dot(g, v)
    w, e, n = K["beam"].omega, K["beam"].epsilon, K["beam"].axis
    C = P["C"].position
    h = (P["E"].position - C) / s.front_arm
    up = cross(n, h)
    for mass, (cu, cv), jj in (
        (masses.beam, masses.beam_com, masses.beam_inertia),
        (masses.head, masses.head_com, masses.head_inertia),
    ):
        r = cu * h + cv * up
        v = cross(w, r)
        dke = dke + mass * dot(v, cross(e, r) + cross(w, cross(w, r))) + jj * dot(w, e)
        pg = pg + mass * dot(g, v)
    dke = dke + masses.crank_inertia * dot(K["crank"].omega, K["crank"].epsilon)
    speed = f.omega
    om = {k: K[k].omega for k in ("crank", "pitman_left", "pitman_right", "equalizer", "beam")}
    pairs = {"R12": ("pitman_left", "crank"), "R13": ("pitman_right", "crank"),
             "R24": ("equalizer", "pitman_left"), "R34": ("equalizer", "pitman_right")}  # fmt: skip
    pj = sum(dot(f.reactions[k].moment, om[a] - om[b]) for k, (a, b) in pairs.items())
    pj = pj + dot(f.reactions["R05"].moment, om["beam"])
    drive = f.crank_torque * speed
    rest = cb.torque(TH) * speed + pg - f.load * m.polished_rod.velocity + pj - dke
    return drive, rest, pj


@pytest.mark.parametrize("joints", ["revolute", "spherical"])
@pytest.mark.parametrize("deviated", [False, True])
def test_power_balance_of_the_crank_torque(joints, deviated):
    s = ms.SpatialPumpingUnit.from_planar(
        _unit(), 1.2, 1.15, joints=joints, **(DEV if deviated else {})
    )
    from mechsynth.machines.pumping_unit import crank_speed

    w, e = crank_speed(TH, SPEED, fluctuation=0.25)
    card = DynamometerCard(
        np.r_[np.linspace(0, 1, 40), np.linspace(1, 0, 40)],
        np.r_[np.full(40, 90e3), np.full(40, 40e3)],
    )
    f = s.forces(TH, w, load=card, counterbalance=CB, masses=MASSES, epsilon=e)
    drive, rest, pj = _independent_power(s, f, MASSES, CB)
    pb = power_balance(f, CB)
    unb = pb["unbalanced"]
    # the rational drive as built leaves its equalizer yaw a little unbalanced: that power counts
    scale = np.abs(drive).max()
    np.testing.assert_allclose(drive + rest - unb, 0.0, atol=1e-9 * scale)
    np.testing.assert_allclose(pb["error"], 0.0, atol=1e-9 * scale)
    if joints == "revolute" and deviated:
        assert np.max(np.abs(pj)) > 1.0  # the pairs' moments do work on the misfit rates
    if not deviated:
        assert np.max(np.abs(unb)) < 1e-9 * scale


def test_the_redundant_drive_splits_the_load_and_the_rational_one_equalizes_it():
    s = ms.SpatialPumpingUnit.from_planar(_unit(), 1.2)
    for name in (
        "phase_mismatch",
        "crank_difference",
        "pitman_difference",
        "shaft_tilt",
        "beam_skew",
    ):
        value = {"phase_mismatch": ms.deg(0.5)}.get(name, 3e-3)
        rev = s.replace(**{name: value}).forces(TH, SPEED, load=80e3)
        rat = s.replace(**{name: value}, joints="spherical").forces(TH, SPEED, load=80e3)
        assert rev.peak_split > 0.01, name
        assert rat.peak_split < 1e-4, name
        assert np.max(np.abs(rat.elastic["left"]["bending_B"])) == 0.0


def test_elastic_closure_is_linear_and_follows_the_pitman_stiffness():
    s = ms.SpatialPumpingUnit.from_planar(_unit(), 1.2)
    one = s.replace(crank_difference=1e-3).forces(TH, SPEED, load=80e3)
    two = s.replace(crank_difference=2e-3).forces(TH, SPEED, load=80e3)
    d1 = one.pitman_force["left"] - one.pitman_force["right"]
    d2 = two.pitman_force["left"] - two.pitman_force["right"]
    np.testing.assert_allclose(d2, 2.0 * d1, rtol=0, atol=2e-3 * np.abs(d2).max())
    # the split comes from bending the pitmans out of their plane: twice as stiff, twice the split
    sec = s.pitman_section
    stiff = s.replace(
        crank_difference=1e-3,
        pitman_section=type(sec)(sec.E, sec.G, sec.area, 2 * sec.J_y, 2 * sec.J_z, 2 * sec.J_p),
    ).forces(TH, SPEED, load=80e3)
    ratio = stiff.peak_split / one.peak_split
    assert 1.95 < ratio < 2.0


def test_rational_drive_splits_by_the_lever_rule_of_an_off_centre_equalizer():
    s = ms.SpatialPumpingUnit.from_planar(_unit(), 1.2, joints="spherical", equalizer_offset=0.01)
    f = s.forces(TH, SPEED, load=80e3)
    lever = (0.6 - 0.01) / (0.6 + 0.01)  # F_left / F_right = l_B1D / l_BD
    np.testing.assert_allclose(f.pitman_force["left"] / f.pitman_force["right"], lever, rtol=1e-6)


def test_loads_counterbalance_and_batches():
    s = ms.SpatialPumpingUnit.from_planar(_unit(), 1.2, **DEV)
    a = s.forces(TH, SPEED, load=lambda m: 60e3 + 20e3 * np.cos(m.theta))
    b = s.forces(TH, SPEED, load=60e3 + 20e3 * np.cos(TH))
    np.testing.assert_allclose(a.crank_torque, b.crank_torque, rtol=1e-13)
    # the counterbalance is a moment on the crank alone: the torque is affine in it
    base = s.forces(TH, SPEED, load=80e3, masses=MASSES)
    cbf = s.forces(TH, SPEED, load=80e3, masses=MASSES, counterbalance=CB)
    np.testing.assert_allclose(cbf.crank_torque, base.crank_torque - CB.torque(TH), atol=1e-6)
    for side in ("left", "right"):
        np.testing.assert_allclose(cbf.pitman_force[side], base.pitman_force[side], atol=1e-6)
    # point-mass counterweights of the same moment: the same torque at constant speed
    heavy = SpatialMasses(**{**MASSES.__dict__, "counterweight": 4000.0})
    pm = s.ideal().forces(TH, SPEED, load=80e3, masses=heavy, counterbalance=CB)
    mo = s.ideal().forces(TH, SPEED, load=80e3, masses=MASSES, counterbalance=CB)
    np.testing.assert_allclose(pm.crank_torque, mo.crank_torque, atol=1e-6)
    assert np.max(np.abs(pm.reactions["R01"].force - mo.reactions["R01"].force)) > 1e3
    # a card on a batch of designs equals the designs one by one
    card = DynamometerCard(
        np.r_[np.linspace(0, 1, 40), np.linspace(1, 0, 40)],
        np.r_[np.full(40, 90e3), np.full(40, 40e3)],
    )
    batch = s.replace(phase_mismatch=np.array([0.0, 0.005])[:, None])
    fb = batch.forces(TH, SPEED, load=card)
    for k, p in enumerate((0.0, 0.005)):
        fk = s.replace(phase_mismatch=p).forces(TH, SPEED, load=card)
        np.testing.assert_allclose(fb.crank_torque[k], fk.crank_torque, rtol=0, atol=1e-6)
        np.testing.assert_allclose(fb.peak_split[k], fk.peak_split, rtol=1e-10)


def test_counterbalance_sizing_is_the_certified_minimum():
    s = ms.SpatialPumpingUnit.from_planar(_unit(), 1.2, phase_mismatch=ms.deg(0.3))
    res = size_counterbalance(s, SPEED, 80e3, MASSES, phase=0.0, angles=48, n_dense=192)
    assert res.success and res.certified
    th = np.linspace(0.0, 2.0 * np.pi, 720, endpoint=False)
    peak = lambda m: np.abs(  # noqa: E731
        s.forces(
            th, SPEED, load=80e3, masses=MASSES, counterbalance=Counterbalance(m, 0.0)
        ).crank_torque
    ).max()
    M = res.counterbalance.moment
    assert peak(M) <= res.peak_torque * (1 + 1e-9)
    assert peak(M * 1.01) > peak(M) and peak(M * 0.99) > peak(M)
    assert res.peak_split > 0.01  # the counterbalance does not touch the split
    with pytest.raises(ValueError, match="not affine"):
        size_counterbalance(s, SPEED, 80e3, SpatialMasses(counterweight=100.0))


def test_bad_force_input_is_named():
    s = ms.SpatialPumpingUnit.from_planar(_unit(), 1.2)
    with pytest.raises(ValueError, match="crank speed"):
        s.forces(TH, None)
    with pytest.raises(ValueError, match="speed must be positive"):
        s.forces(TH, -1.0)
    with pytest.raises(ValueError, match="load: shape"):
        s.forces(TH, SPEED, load=np.ones(5))
    with pytest.raises(ValueError, match="masses.pitman must not be negative"):
        SpatialMasses(pitman=-1.0)
    with pytest.raises(ValueError, match="pitman_com must lie in"):
        SpatialMasses(pitman_com=1.5)
    with pytest.raises(ValueError, match="counterbalance must be"):
        s.forces(TH, SPEED, counterbalance=5.0)
    with pytest.raises(ValueError, match="unknown pair"):
        s.forces(TH, SPEED).pair("Z")


def test_pin_play_frees_the_redundant_drive():
    """Wear clearance: a pin that tilts freely in its hole by the misfit the rigid motion asks
    for carries no moment, so with the largest misfit as play the redundant drive is the
    rational one; the split falls monotonically with the play in between."""
    from mechsynth.errors import MechanismError

    built = ms.SpatialPumpingUnit.from_planar(_unit(), 1.2).replace(**DEV)
    th = TH[::3]
    kw = dict(load=50e3, masses=MASSES, counterbalance=CB)
    f0 = built.forces(th, SPEED, **kw)
    rat = built.with_joints("spherical").forces(th, SPEED, **kw)
    need = max(float(np.max(v)) for v in f0.info["misfit_angle"].values())
    assert 1e-4 < need < 1e-2  # a few mrad
    splits = [built.forces(th, SPEED, pin_play=p * need, **kw).peak_split for p in (0, 0.5, 1)]
    assert splits[0] > splits[1] > splits[2]
    free = built.forces(th, SPEED, pin_play=need, **kw)
    np.testing.assert_allclose(free.crank_torque, rat.crank_torque, atol=1e-6 * 50e3)
    # the pitman forces to 2e-4: the rational drive as built leaves the equalizer's yaw
    # unbalanced by a few newtons (its kinematics places the equalizer for massless pitmans)
    np.testing.assert_allclose(free.pitman_force["left"], rat.pitman_force["left"], rtol=2e-4)
    with pytest.raises(MechanismError, match="pin_play"):
        built.forces(th, SPEED, pin_play=-1.0, **kw)
