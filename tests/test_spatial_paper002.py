"""Paper 002's printed kinetostatic equations (17)-(48), evaluated on the computed reactions:
the corrected forms hold, the misprinted ones do not (errata)."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.dynamics.spatial_kinetostatics import cantilever_compliance
from mechsynth.machines.pumping_unit import Counterbalance, SpatialMasses, paper002

UNIT = ms.BeamPumpingUnit.from_api(
    A=155.0, C=111.06, I=111.02, P=132.01, R=42.01, H=231.97, G=95.98, units="in"
)
# the paper's bodies: beam and head on the beam line, equalizer centred at D (no offset)
MASSES = SpatialMasses(
    pitman=150.0,
    pitman_com=0.45,
    equalizer=200.0,
    beam=2500.0,
    beam_com=(-0.8, 0.0),
    beam_inertia=4000.0,
    head=600.0,
    head_com=(3.6, 0.0),
)
DEV = dict(phase_mismatch=ms.deg(0.3), crank_difference=2e-3, shaft_tilt=5e-4, beam_skew=8e-4)
TH = np.linspace(0.0, 2.0 * np.pi, 36, endpoint=False) + 0.03
SPEED = ms.spm(8.0)


def _solve(joints, **dev):
    s = ms.SpatialPumpingUnit.from_planar(UNIT, 1.2, joints=joints, **dev)
    f = s.forces(TH, SPEED, load=80e3, masses=MASSES, epsilon=0.05)
    return s, f, paper002.vectors(s, f)


def _size(v):
    return max(80e3, np.abs(v).max())


@pytest.mark.parametrize("deviated", [False, True])
def test_redundant_drive_equations_22_to_39(deviated):
    s, f, v = _solve("revolute", **(DEV if deviated else {}))
    res = paper002.kinetostatic_residuals(v)
    scale = 80e3 * s.front_arm
    for eq in [str(k) for k in range(22, 40)]:
        assert np.max(np.abs(res[eq])) < 1e-9 * scale, eq
    # misprints: the masses' arms lambda l_E, the rod force's arm about D in (31), R42 in (29)
    for eq in ("23_printed", "31_printed", "39_printed", "29_printed"):
        assert np.max(np.abs(res[eq])) > 1.0, eq  # N m, against a tolerance of 3e-4
    # M_R05 = 0 holds for the ideal unit only
    m05 = np.abs(f.reactions["R05"].moment).max()
    assert (m05 > 10.0) if deviated else (m05 < 1e-6)


def test_the_paper_elastic_moments_as_loads_break_the_pitman_balance():
    s, f, v = _solve("revolute", **DEV)
    sec = s.pitman_section
    dbeta = paper002.angle_between_pitmans(f.motion)
    mf = paper002.paper_bending_moment(sec.E, sec.J_z, dbeta, s.pitman)[:, None] * v["l4"] / 0.6
    res = paper002.kinetostatic_residuals(v, elastic=(mf, -mf))
    assert np.max(np.abs(res["27"])) < 1e-6
    assert np.max(np.abs(res["27_printed"])) > 1.0


@pytest.mark.parametrize("deviated", [False, True])
def test_rational_drive_equations_40_to_46(deviated):
    s, f, v = _solve("spherical", **(DEV if deviated else {}))
    res = paper002.kinetostatic_residuals(v, rational=True)
    # with deviations the equalizer's yaw is balanced only to the residual of the local mobility
    tol = 1e-9 * 80e3 * s.front_arm + (10 * s.front_arm * np.max(f.residual) if deviated else 0)
    for eq in ("40", "41", "42", "43", "44", "45", "46"):
        assert np.max(np.abs(res[eq])) < tol, eq
    for eq in ("41_printed", "42_printed"):
        assert np.max(np.abs(res[eq])) > 1e3, eq


def test_crank_equations_47_48_and_the_double_counted_inertia():
    s = ms.SpatialPumpingUnit.from_planar(UNIT, 1.2, **DEV)
    masses = SpatialMasses(**{**MASSES.__dict__, "crank_inertia": 300.0, "counterweight": 3000.0})
    cb = Counterbalance(40e3, 0.0)
    f = s.forces(TH, SPEED, load=80e3, masses=masses, counterbalance=cb, epsilon=0.05)
    res = paper002.crank_residuals(s, f, cb)
    assert np.max(np.abs(res["47"])) < 1e-8 * 80e3
    assert np.max(np.abs(res["48"])) < 1e-8 * 80e3
    # J_z as printed counts the counterweights' m r^2 a second time: off by that times eps
    r = cb.moment / (3000.0 * 9.80665)
    np.testing.assert_allclose(np.abs(res["47_printed"]), 3000.0 * r**2 * 0.05, rtol=1e-9)


def test_elastic_formulas_18_to_21_against_beam_theory():
    sec = ms.SpatialPumpingUnit.from_planar(UNIT, 1.2).pitman_section
    L = 3.35
    C = cantilever_compliance(L, sec)
    # (18)-(19): G J_p phi / l is the torsional stiffness of the bar
    np.testing.assert_allclose(
        paper002.paper_torsion_moment(sec.G, sec.J_p, 1e-3, L), 1e-3 / C[3, 3]
    )
    # (20)-(21): 3 E J_z sin(db/2) / l^2 is the END FORCE of a cantilever deflected by
    # l sin(db/2) (a force, in N), not a moment; the clamp moment is that force times l
    db = 2e-3
    delta = L * np.sin(db / 2)
    tip_force = delta / C[1, 1]
    np.testing.assert_allclose(paper002.paper_bending_moment(sec.E, sec.J_z, db, L), tip_force)
    np.testing.assert_allclose(tip_force * L, 3 * sec.E * sec.J_z * np.sin(db / 2) / L)
    # scaling every length by k scales a moment by k^3 here (E J / l) but the printed
    # expression by k^2: it is not a moment
    k = 2.0
    ratio = paper002.paper_bending_moment(
        sec.E, sec.J_z * k**4, db, L * k
    ) / paper002.paper_bending_moment(sec.E, sec.J_z, db, L)
    assert abs(ratio - k**2) < 1e-12


def test_errata_are_listed():
    assert len(paper002.ERRATA) >= 10
    assert any("5 times" in e for e in paper002.ERRATA)


def test_link_vectors_of_eq_4_in_the_ideal_drive():
    """Eq. (4): l1 = l_OA (cos phi1, sin phi1, 0), l11 likewise, l4 = l_BD e_BD,
    l41 = -l_B1D e_BD, l5 = l_DC (x_DC, y_DC, 0) with the shaft along z."""
    s, f, v = _solve("revolute")
    phi1 = s.sense * TH + np.pi / 2
    ring = s.crank * np.stack([np.cos(phi1), np.sin(phi1), 0 * phi1], axis=-1)
    np.testing.assert_allclose(v["l1"], ring, atol=1e-12)
    np.testing.assert_allclose(v["l11"], ring, atol=1e-12)
    e_bd = f.motion.links["equalizer"].axis
    np.testing.assert_allclose(v["l4"], 0.6 * e_bd, atol=1e-12)
    np.testing.assert_allclose(v["l41"], -0.6 * e_bd, atol=1e-12)
    np.testing.assert_allclose(v["l5"][:, 2], 0.0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(v["l5"], axis=-1), s.rear_arm, rtol=1e-12)
