"""Kinematics of the spatial pumping-unit drive (paper 002, eqs. 1-16)."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.kinematics.spatial import cross, dot
from mechsynth.machines.pumping_unit import paper002

C320 = dict(A=155.0, C=111.06, I=111.02, P=132.01, R=42.01, H=231.97, G=95.98, units="in")
MARK_II = dict(
    A=334.0, C=270.0, I=202.56, P=193.5, R=63.56, H=295.13, G=112.13, units="in",
    unit_class="mark-ii",
)  # fmt: skip
ALL = dict(
    phase_mismatch=ms.deg(0.4),
    crank_difference=0.003,
    pitman_difference=-0.004,
    shaft_tilt=1e-3,
    shaft_skew=-2e-3,
    beam_tilt=1.5e-3,
    beam_skew=1e-3,
    equalizer_offset=0.006,
)
TH = np.linspace(0.0, 2.0 * np.pi, 48, endpoint=False) + 0.01


def unit(kind="conventional", rotation=None):
    geo = dict(C320 if kind == "conventional" else MARK_II)
    if rotation:
        geo["rotation"] = rotation
    return ms.BeamPumpingUnit.from_api(**geo)


@pytest.mark.parametrize(
    "kind, rotation", [("conventional", "cw"), ("conventional", "ccw"), ("mark-ii", "ccw")]
)
@pytest.mark.parametrize("joints", ["revolute", "spherical"])
def test_ideal_drive_moves_the_polished_rod_as_the_planar_unit(kind, rotation, joints):
    u = unit(kind, rotation)
    s = ms.SpatialPumpingUnit.from_planar(u, 1.2, 1.2, joints=joints)
    speed, eps = ms.spm(8.0), 0.03
    m, mp = s.motion(TH, speed=speed, epsilon=eps), u.motion(TH, speed=speed, epsilon=eps)
    for q in ("position", "velocity", "acceleration"):
        np.testing.assert_allclose(
            getattr(m.polished_rod, q), getattr(mp.polished_rod, q), rtol=0, atol=1e-9
        )
    np.testing.assert_allclose(m.torque_factor, mp.torque_factor, rtol=0, atol=1e-9)
    np.testing.assert_allclose(m.beam.angle, mp.beam.angle, rtol=0, atol=1e-12)
    assert abs(s.stroke - u.stroke) < 1e-9
    # the pitmans stay in their planes and parallel, the equalizer along the shaft
    np.testing.assert_allclose(
        m.links["equalizer"].axis, np.broadcast_to([0, 0, 1.0], (48, 3)), atol=1e-12
    )
    np.testing.assert_allclose(m.points["B"].x, mp.points["B"].x, atol=1e-12)
    np.testing.assert_allclose(m.points["B"].z, -0.6, atol=1e-12)
    np.testing.assert_allclose(
        m.links["pitman_left"].omega[:, 2], mp.links["pitman"].omega, atol=1e-9
    )


def test_splayed_pitmans_move_the_rod_as_the_planar_unit_with_the_projected_pitman():
    u = unit()
    s = ms.SpatialPumpingUnit.from_planar(u, crank_spacing=1.3, equalizer_width=1.1)
    assert s.pitman > u.pitman
    np.testing.assert_allclose(
        s.motion(TH).polished_rod.position, u.motion(TH).polished_rod.position, atol=1e-9
    )
    np.testing.assert_allclose(s.planar.pitman, u.pitman, rtol=1e-15)


@pytest.mark.parametrize("kind", ["conventional", "mark-ii"])
def test_loop_closure_and_bour_equations_hold_with_every_deviation(kind):
    s = ms.SpatialPumpingUnit.from_planar(unit(kind), 1.2, **ALL)
    m = s.motion(TH, speed=ms.spm(7.0), epsilon=0.05)
    assert np.max(m.extra["residual"]) < 1e-12
    # paper 002, eqs. (5)-(6) and (9)-(12), on our solution (time derivatives)
    f = s.with_joints("spherical").forces(TH, ms.spm(7.0), load=0.0, epsilon=0.05)
    v = paper002.vectors(s, f)
    res = paper002.kinematic_residuals(v)
    for eq in ("5", "6"):
        assert np.max(np.abs(res[eq])) < 1e-12, eq
    for eq in ("9", "10"):
        assert np.max(np.abs(res[eq])) < 1e-12 * ms.spm(7.0) * 10, eq
    for eq in ("11", "12"):
        assert np.max(np.abs(res[eq])) < 1e-11, eq
    # the printed (12) (eps4 x l4 for eps4 x l41) does not hold once the equalizer turns
    assert np.max(np.abs(res["12_printed"])) > 1e3 * np.max(np.abs(res["12"]))
    # the rational closure: pitman axes and equalizer axis coplanar
    u_, w_ = m.links["pitman_left"].axis, m.links["pitman_right"].axis
    assert np.max(np.abs(dot(cross(u_, w_), m.links["equalizer"].axis))) < 1e-13


def test_analogs_against_finite_differences():
    s = ms.SpatialPumpingUnit.from_planar(unit(), 1.2, **ALL)
    h = 1e-5
    m0, mp, mm = s.motion(TH), s.motion(TH + h), s.motion(TH - h)
    for name in ("A", "A1", "B", "B1", "D", "E"):
        fd_v = (mp.points[name].position - mm.points[name].position) / (2 * h)
        fd_a = (mp.points[name].velocity - mm.points[name].velocity) / (2 * h)
        np.testing.assert_allclose(m0.points[name].velocity, fd_v, rtol=0, atol=1e-8)
        np.testing.assert_allclose(m0.points[name].acceleration, fd_a, rtol=0, atol=1e-7)
    for name in ("pitman_left", "pitman_right", "equalizer", "beam"):
        lk = m0.links[name]
        fd_axis = (mp.links[name].axis - mm.links[name].axis) / (2 * h)
        np.testing.assert_allclose(cross(lk.omega, lk.axis), fd_axis, rtol=0, atol=1e-8)
        fd_w = (mp.links[name].omega - mm.links[name].omega) / (2 * h)
        np.testing.assert_allclose(lk.epsilon, fd_w, rtol=0, atol=1e-7)
    fd = (mp.polished_rod.position - mm.polished_rod.position) / (2 * h)
    np.testing.assert_allclose(m0.torque_factor, fd, rtol=0, atol=1e-8)
    fd2 = (mp.polished_rod.velocity - mm.polished_rod.velocity) / (2 * h)
    np.testing.assert_allclose(m0.polished_rod.acceleration, fd2, rtol=0, atol=1e-7)


def test_time_derivatives_with_a_varying_crank_speed():
    from mechsynth.machines.pumping_unit import crank_speed

    s = ms.SpatialPumpingUnit.from_planar(unit(), 1.2, **ALL)
    th = np.linspace(0.0, 2.0 * np.pi, 4001)
    w, e = crank_speed(th, ms.spm(8.0), fluctuation=0.3)
    m = s.motion(th, speed=w, epsilon=e)
    # dv/dt = dv/dtheta * omega along the run
    dv = np.gradient(m.points["D"].velocity, th, axis=0) * w[:, None]
    np.testing.assert_allclose(m.points["D"].acceleration[5:-5], dv[5:-5], rtol=0, atol=2e-5)


def test_stroke_dead_centres_and_rod_position_with_deviations():
    s = ms.SpatialPumpingUnit.from_planar(unit(), 1.2, **ALL)
    pos = s.motion(np.linspace(0.0, 2.0 * np.pi, 2001)).polished_rod.position
    assert pos.min() > -1e-12 and pos.max() < s.stroke + 1e-12
    m = s.motion(np.array(s.dead_centres))
    np.testing.assert_allclose(m.polished_rod.position, [0.0, s.stroke], rtol=0, atol=1e-12)
    np.testing.assert_allclose(m.torque_factor, 0.0, atol=1e-12)
    # the ideal drive's dead centres are the planar unit's
    np.testing.assert_allclose(s.ideal().dead_centres, unit().dead_centres, atol=1e-10)
    # the saddle bearing out of level: the rod rises cos(tilt) per unit of horsehead arc
    assert abs(s.rod_tilt_factor - np.cos(ALL["beam_tilt"])) < 1e-15


def test_batch_of_designs_equals_single_designs():
    base = ms.SpatialPumpingUnit.from_planar(unit(), 1.2, **ALL)
    phases = np.array([0.0, 0.004, 0.009])
    batch = base.replace(
        phase_mismatch=phases[:, None], equalizer_width=np.array([1.1, 1.2, 1.3])[:, None]
    )
    mb = batch.motion(TH)
    assert mb.polished_rod.position.shape == (3, TH.size)
    for k, (p, w) in enumerate(zip(phases, (1.1, 1.2, 1.3))):
        one = base.replace(phase_mismatch=p, equalizer_width=w).motion(TH)
        np.testing.assert_allclose(
            mb.polished_rod.position[k], one.polished_rod.position, atol=1e-12
        )
        np.testing.assert_allclose(
            mb.points["B1"].position[k], one.points["B1"].position, atol=1e-12
        )


def test_paper_point_kinematics_13_to_16():
    s = ms.SpatialPumpingUnit.from_planar(unit(), 1.2)  # conventional: E ahead of C, D behind
    f = s.forces(TH, ms.spm(8.0), epsilon=0.02)
    v = paper002.vectors(s, f)
    m = f.motion
    l_cs = 1.7 * (m.points["E"].position - m.points["C"].position) / s.front_arm
    l_os = 0.9 * (m.points["A"].position - m.points["O"].position) / s.crank
    pk = paper002.point_kinematics(v, "conventional", l_cs=l_cs, l_osnp=l_os)
    np.testing.assert_allclose(pk["13_V"], m.points["E"].velocity, atol=1e-12)
    np.testing.assert_allclose(pk["13_a"], m.points["E"].acceleration, atol=1e-12)
    np.testing.assert_allclose(pk["14_V"], m.points["D"].velocity, atol=1e-12)
    np.testing.assert_allclose(pk["14_a"], m.points["D"].acceleration, atol=1e-12)
    # (15), (16) against finite differences in time of the points they describe
    h = 1e-5
    speed = ms.spm(8.0)
    for key, base, frac, length in (("15", "E", 1.7, s.front_arm), ("16", "A", 0.9, s.crank)):
        origin = "C" if key == "15" else "O"
        p = [
            frac * (mm.points[base].position - mm.points[origin].position) / length
            for mm in (s.motion(TH + h), s.motion(TH - h))
        ]
        fd = (p[0] - p[1]) / (2 * h / speed)
        np.testing.assert_allclose(pk[f"{key}_V"], fd, rtol=0, atol=1e-8)
    # (16): a point of the crank at 0.9 of OA moves as 0.9 / r of the crank pin A
    np.testing.assert_allclose(pk["16_a"], 0.9 / s.crank * m.points["A"].acceleration, atol=1e-12)


def test_mark_ii_point_e_is_behind_the_direction_d_c():
    s = ms.SpatialPumpingUnit.from_planar(unit("mark-ii"), 1.2)
    f = s.forces(TH, ms.spm(8.0))
    pk = paper002.point_kinematics(paper002.vectors(s, f), "mark-ii")
    np.testing.assert_allclose(pk["13_V"], f.motion.points["E"].velocity, atol=1e-12)


def test_bad_input_is_named():
    u = unit()
    with pytest.raises(ValueError, match="joints must be"):
        ms.SpatialPumpingUnit.from_planar(u, 1.2, joints="welded")
    with pytest.raises(ValueError, match="unknown deviation"):
        ms.SpatialPumpingUnit.from_planar(u, 1.2, crank_phase=0.1)
    with pytest.raises(ValueError, match="crank_spacing must be positive"):
        ms.SpatialPumpingUnit.from_planar(u, -1.0)
    with pytest.raises(ValueError, match="not a small deviation"):
        ms.SpatialPumpingUnit.from_planar(u, 1.2, phase_mismatch=0.5)
    with pytest.raises(ValueError, match="not a small deviation"):
        ms.SpatialPumpingUnit.from_planar(u, 1.2, crank_difference=2.0)
    with pytest.raises(ValueError, match="must be a BeamPumpingUnit"):
        ms.SpatialPumpingUnit.from_planar("C-320", 1.2)
    with pytest.raises(ValueError, match="equalizer_offset must be finite"):
        ms.SpatialPumpingUnit.from_planar(u, 1.2, equalizer_offset=float("nan"))
    with pytest.raises(ms.MechanismError, match="full turn"):
        ms.SpatialPumpingUnit.from_planar(u.replace(crank=3.0), 1.2)


def test_shapes_and_large_deviations_end_in_one_named_error():
    """A flat list of spacings was a numpy broadcast error; deviations inside the documented
    limits but too large for the geometry were 'LinAlgError: Singular matrix'."""
    u = unit()
    with pytest.raises(ms.MechanismError, match=r"crank_spacing has shape \(2,\): a batch of"):
        ms.SpatialPumpingUnit.from_planar(u, [1.1, 1.2]).motion(TH)
    with pytest.raises(ms.MechanismError, match="do not broadcast"):
        ms.SpatialPumpingUnit.from_planar(
            u, np.full((2, 1), 1.2), phase_mismatch=np.zeros((3, 1))
        )
    base = ms.SpatialPumpingUnit.from_planar(u, 1.2)
    with pytest.raises(ms.MechanismError, match="does not assemble at crank angle"):
        ms.SpatialPumpingUnit.from_planar(u, 1.2, pitman_difference=0.5 * base.pitman).motion(TH)
