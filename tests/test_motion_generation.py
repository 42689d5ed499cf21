"""Motion generation: Burmester theory and the pairing of dyads into linkages."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.synthesis import burmester as bmod
from mechsynth.synthesis.burmester import displace
from mechsynth.synthesis.motion_generation import pair, pose_error_measure, pose_errors

# a crank-rocker in its standard frame, carried into a general frame (rotated, shifted)
FB = ms.FourBar(crank=1.2, coupler=3.5, rocker=3.0, ground=4.0)
COUPLER_POINT = (1.1, 0.9)  # along A -> B, left of it (m)
DELTA = 0.4  # pose angle = coupler angle + DELTA (rad)
ROT, SHIFT = 0.5, np.array([2.0, -1.0])


def _to_user(x, y):
    c, s = np.cos(ROT), np.sin(ROT)
    return c * x - s * y + SHIFT[0], s * x + c * y + SHIFT[1]


def _poses_of(fb, phi, coupler_point=COUPLER_POINT):
    m = fb.motion(np.asarray(phi, float), coupler_points={"P": coupler_point})
    x, y = _to_user(m.points["P"].x, m.points["P"].y)
    return np.column_stack([x, y, m.links["coupler"].angle + DELTA + ROT])


def _pivots(fb, phi0):
    m = fb.motion(np.array([phi0]))
    o1 = np.array(_to_user(0.0, 0.0))
    o2 = np.array(_to_user(fb.ground, 0.0))
    a = np.array(_to_user(m.points["A"].x[0], m.points["A"].y[0]))
    b = np.array(_to_user(m.points["B"].x[0], m.points["B"].y[0]))
    return o1, a, o2, b


PHI5 = np.radians([10.0, 55.0, 110.0, 170.0, 230.0])
POSES5 = _poses_of(FB, PHI5)

# random poses with 0, 2 and 4 real Burmester points (found by a search; the counts are
# checked below against an independent multistart root finder)
POSES_0 = [[-0.83, -0.53, -0.33], [0.6, 0.16, 0.05], [-0.81, -0.13, -0.21],
           [-0.04, -0.68, 0.26], [0.47, -0.77, 0.71]]  # fmt: skip
POSES_2 = [[-0.25, -0.82, 0.99], [0.32, 0.86, 0.47], [-0.59, 0.26, 0.55],
           [-0.4, 0.48, 0.96], [0.44, -0.56, -0.21]]  # fmt: skip
POSES_4 = [[0.52, 0.76, -0.67], [-0.8, 0.7, 0.19], [-0.21, -0.04, -0.3],
           [-0.71, 0.4, 0.34], [-0.42, 0.74, -0.91]]  # fmt: skip


def _independent_roots(poses, starts=400, seed=0):
    """All real (c, z) with |D_j z - c| = |z - c| for j = 2..5, by scipy's root finder from
    random starts over a wide box: written from the definition, not from the module's
    equations."""
    from scipy.optimize import root

    poses = np.asarray(poses, float)
    scale = np.ptp(poses[:, :2], axis=0).max()

    def f(v):
        c, z = v[:2], v[2:]
        pos = displace(poses, z)
        r2 = np.sum((pos - c) ** 2, axis=1)
        return (r2[1:] - r2[0]) / scale**2

    rng = np.random.default_rng(seed)
    found = []
    for _ in range(starts):
        v0 = poses[0, :2].repeat(2) + scale * rng.standard_cauchy(4).clip(-60, 60)
        sol = root(f, v0, method="lm", options={"xtol": 1e-15, "ftol": 1e-15, "maxiter": 300})
        if np.max(np.abs(f(sol.x))) < 1e-11 and np.all(np.isfinite(sol.x)):
            if not any(np.allclose(sol.x, g, atol=1e-6 * (1 + np.abs(g).max())) for g in found):
                found.append(sol.x)
    return found


# ----------------------------------------------------------------------------- poles, 3 poses
def test_poles_are_fixed_points_of_the_displacements():
    bm = ms.burmester(POSES5)
    assert len(bm.poles) == 10
    for (i, j), p in bm.poles.items():
        # the displacement from pose i to pose j leaves the pole in place
        pi, pj = bm.poses[i - 1], bm.poses[j - 1]
        t = pj[2] - pi[2]
        rel = np.asarray(p) - pi[:2]
        moved = pj[:2] + [np.cos(t) * rel[0] - np.sin(t) * rel[1],
                          np.sin(t) * rel[0] + np.cos(t) * rel[1]]  # fmt: skip
        assert np.allclose(moved, p, atol=1e-12)


def test_three_poses_centre_is_the_circumcentre_and_maps_invert():
    poses = POSES5[:3]
    bm = ms.burmester(poses)
    z = np.array([0.3, 1.7])
    d = bm.centre_point(z)
    # the circumcentre of the three positions of z, from the textbook construction
    # (intersection of the perpendicular bisectors, Norton, Design of Machinery, sec. 5.8)
    (ax, ay), (bx, by), (cx, cy) = displace(poses, z)
    den = 2 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
    ux = (ax**2 + ay**2) * (by - cy) + (bx**2 + by**2) * (cy - ay) + (cx**2 + cy**2) * (ay - by)
    uy = (ax**2 + ay**2) * (cx - bx) + (bx**2 + by**2) * (ax - cx) + (cx**2 + cy**2) * (bx - ax)
    assert np.allclose(d.centre, (ux / den, uy / den), atol=1e-12)
    back = bm.circle_point(d.centre)
    assert np.allclose(back.circle, z, atol=1e-12)
    assert back.residual < 1e-12
    # the moving-frame coordinates place the circle point in every pose
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    lx, ly = back.local
    assert np.allclose(
        np.column_stack([poses[:, 0] + c * lx - s * ly, poses[:, 1] + s * lx + c * ly]),
        back.positions(poses),
        atol=1e-12,
    )


def test_three_poses_slider_point_is_collinear_along_its_guide():
    bm = ms.burmester(POSES5[:3])
    for g in np.radians([0.0, 30.0, 100.0]):
        d = bm.slider_point(g)
        pos = d.positions(bm.poses)
        normal = np.array([-np.sin(g), np.cos(g)])
        assert np.ptp(pos @ normal) < 1e-12
        assert d.kind == "PR" and d.residual < 1e-12


# ----------------------------------------------------------------------------- 4 poses
def test_four_poses_curves_pass_through_the_poles_and_map_onto_each_other():
    bm = ms.burmester(POSES5[:4])
    for p in bm.poles.values():  # Burmester: the centre-point curve passes all six poles
        assert bm.centre_residual(p) < 1e-12
    cc = bm.centre_curve(400)
    ok = np.isfinite(cc[:, 0])
    assert ok.sum() > 300
    lengths = []
    for c in cc[ok][::13]:
        try:
            d = bm.circle_point(c)
        except ms.MechanismError:  # a sample next to a pole (a line of partners)
            continue
        lengths.append(d.residual)
    assert len(lengths) > 15 and max(lengths) < 1e-9
    kc = bm.circle_curve(400)
    for z in kc[np.isfinite(kc[:, 0])][::29]:
        assert bm.centre_point(z).residual < 1e-9
    # the four-bar's own pivots lie on the curves
    o1, a, o2, b = _pivots(FB, PHI5[0])
    assert np.allclose(bm.circle_point(o1).circle, a, atol=1e-10)
    assert np.allclose(bm.circle_point(o2).circle, b, atol=1e-10)


def test_four_poses_off_curve_centre_is_refused():
    bm = ms.burmester(POSES5[:4])
    with pytest.raises(ms.MechanismError, match="not on the centre-point curve"):
        bm.circle_point((10.0, 10.0))


def test_four_poses_slider_dyad_of_a_slider_crank():
    lk = (
        ms.Linkage(ground={"O": (0.3, 0.2)})
        .crank("A", about="O", length=0.5)
        .rrp("B", ("A", 1.6), guide=((0.0, -0.1), np.radians(20.0)))
        .attach("P", on=("A", "B"), along=0.7, left=0.4)
        .attach("Q", on=("A", "B"), along=1.7, left=0.4)
    )
    phi = np.radians([0.0, 70.0, 140.0, 210.0, 280.0])
    m = lk.motion(phi)
    px, py = m.points["P"].x, m.points["P"].y
    poses = np.column_stack([px, py, np.arctan2(m.points["Q"].y - py, m.points["Q"].x - px)])
    b1 = np.array([m.points["B"].x[0], m.points["B"].y[0]])
    sl = ms.burmester(poses[:4]).sliders()
    assert len(sl) == 1 and np.allclose(sl[0].circle, b1, atol=1e-10)
    assert abs(sl[0].guide_angle - np.radians(20.0)) < 1e-10
    # five poses of a slider-crank: its slider is a Burmester point at infinity
    bm5 = ms.burmester(poses)
    assert [d.kind for d in bm5.points].count("PR") == 1
    mg = ms.motion_generation(poses)
    sc = [c for c in mg.candidates if c.kind == "slider-crank" and c.defect_free][0]
    assert np.allclose(sc.crank.centre, (0.3, 0.2), atol=1e-9)
    assert max(pose_errors(sc.linkage, poses)[0]) < 1e-9
    assert isinstance(sc.mechanism, ms.SliderCrank)
    assert abs(sc.mechanism.rod - 1.6) < 1e-9 and abs(sc.mechanism.crank - 0.5) < 1e-9


# ----------------------------------------------------------------------------- 5 poses
def test_five_poses_recover_the_four_bar_they_were_sampled_from():
    bm = ms.burmester(POSES5)
    o1, a, o2, b = _pivots(FB, PHI5[0])
    centres = np.array([d.centre for d in bm.points if d.kind == "RR"])
    for pivot, moving in ((o1, a), (o2, b)):
        k = np.argmin(np.hypot(*(centres - pivot).T))
        d = [d for d in bm.points if d.kind == "RR"][k]
        assert np.allclose(d.centre, pivot, atol=1e-9)
        assert np.allclose(d.circle, moving, atol=1e-9)
    mg = ms.motion_generation(POSES5)
    own = [
        c for c in mg.candidates
        if np.allclose(c.crank.centre, o1, atol=1e-9) and c.driven.centre is not None
        and np.allclose(c.driven.centre, o2, atol=1e-9)
    ]  # fmt: skip
    assert len(own) == 1
    c = own[0]
    assert c.defect_free and c.grashof == "crank-rocker" and c.branch == 1
    fb = c.mechanism
    for name in ("crank", "coupler", "rocker", "ground"):
        assert abs(getattr(fb, name) - getattr(FB, name)) < 1e-9
    assert np.allclose(np.mod(c.standard_angles - PHI5, 2 * np.pi), 0.0, atol=1e-9)
    pos, ang = pose_errors(c.linkage, POSES5)
    assert pos.max() < 1e-9 and ang.max() < 1e-9
    # the standard-frame FourBar moves B where the linkage does
    mb = fb.motion(c.standard_angles)
    b_std = c.from_standard(np.column_stack([mb.points["B"].x, mb.points["B"].y]))
    assert np.allclose(b_std, c.driven.positions(POSES5), atol=1e-9)
    assert np.allclose(c.to_standard(b_std), np.column_stack([mb.points["B"].x, mb.points["B"].y]))


@pytest.mark.parametrize("poses, count", [(POSES_0, 0), (POSES_2, 2), (POSES_4, 4)])
def test_count_of_real_burmester_points(poses, count):
    bm = ms.burmester(poses)
    rr = [d for d in bm.points if d.kind == "RR"]
    assert len(rr) == count
    for d in rr:  # constant dyad length over all poses, to round-off
        assert d.residual < 1e-12 * np.ptp(np.asarray(poses)[:, :2], axis=0).max()
    found = _independent_roots(poses, starts=150)
    assert len(found) == count
    for g in found:
        assert min(np.hypot(*(np.asarray(d.centre) - g[:2])) for d in rr) < 1e-7


def test_order_of_the_poses_does_not_change_the_burmester_points():
    ref = sorted(d.centre for d in ms.burmester(POSES_4).points)
    perm = np.asarray(POSES_4)[[3, 1, 4, 0, 2]]
    got = sorted(d.centre for d in ms.burmester(perm).points)
    assert np.allclose(ref, got, atol=1e-9)


def test_newton_jacobian_matches_finite_differences():
    bm = ms.burmester(POSES_4)
    q = bm._q()
    x = np.array([0.3, -0.2, 0.7, 0.1])
    e, jac = bmod.residual_jacobian(q, x)
    h = 1e-6
    fd = np.column_stack([
        (bmod.residual_jacobian(q, x + h * np.eye(4)[k])[0]
         - bmod.residual_jacobian(q, x - h * np.eye(4)[k])[0]) / (2 * h)
        for k in range(4)
    ])  # fmt: skip
    assert np.allclose(jac, fd, atol=1e-8)


# ----------------------------------------------------------------------------- defects
def test_order_defect_when_poses_come_out_of_order():
    poses = POSES5[[0, 2, 1, 3, 4]]
    o1, _, o2, _ = _pivots(FB, PHI5[0])
    bm = ms.burmester(poses)
    a = bm.circle_point(o1)
    b = bm.circle_point(o2)
    c = pair(poses, a, b)
    assert c.defects == ("order",)


def test_branch_defect_when_poses_lie_on_both_assembly_branches():
    crossed = ms.FourBar(crank=1.2, coupler=3.5, rocker=3.0, ground=4.0, branch="crossed")
    # the same dyad lengths: a point on the coupler seen from both branches
    poses = np.concatenate([_poses_of(FB, PHI5[:3]), _poses_of(crossed, PHI5[3:4])])
    o1, a, o2, b = _pivots(FB, PHI5[0])
    bm = ms.burmester(poses)
    c = pair(poses, bm.circle_point(o1), bm.circle_point(o2))
    assert "branch" in c.defects and c.branch == 0


def test_grashof_defect_and_ranking():
    mg = ms.motion_generation(POSES5)
    keys = [(len(c.defects), -c.min_transmission) for c in mg.candidates]
    assert keys == sorted(keys)
    assert mg.best.defect_free
    rockers = [c for c in mg.candidates if c.grashof in ("triple-rocker", "double-rocker")]
    assert rockers and all("grashof" in c.defects for c in rockers)
    # the transmission angle is the linkage's, folded to [0, 90 deg], over the poses' span
    c = mg.best
    travel = abs(c.crank_angles[-1] - c.crank_angles[0])
    phi = c.crank_angles[0] + c.direction * np.linspace(0, travel, 181)
    mu = c.linkage.motion(phi).transmission_angles["B"]
    assert abs(np.min(np.fmin(mu, np.pi - mu)) - c.min_transmission) < 1e-12


# ----------------------------------------------------------------------------- exact to optimal
def test_pose_error_measure_is_zero_on_exact_designs_and_grows_off_them():
    mg = ms.motion_generation(POSES5)
    err = pose_error_measure(POSES5)
    lk = mg.best.linkage
    assert err.fn(lk) < 1e-12
    assert abs(err.fn(lk(OA=lk.parameters["OA"] + 1e-3)) - 1e-3) < 1e-9


def test_pose_error_measure_derivative_matches_finite_differences():
    import casadi as ca

    mg = ms.motion_generation(POSES5)
    lk = mg.best.linkage
    err = pose_error_measure(POSES5)
    names = ["O_x", "AB", "P_along", "Q_left"]
    x = ca.SX.sym("x", len(names))
    p = {k: float(v) for k, v in lk.parameters.items()}
    sym = lk(**{**p, **{n: x[i] for i, n in enumerate(names)}})
    branches = err.branches(sym)
    f = ca.Function("f", [x], [branches[3], ca.jacobian(branches[3], x)])
    x0 = np.array([p[n] for n in names]) + 0.01
    val, jac = (np.asarray(v, float).ravel() for v in f(x0))
    h = 1e-6
    fd = [(float(f(x0 + h * np.eye(4)[k])[0]) - float(f(x0 - h * np.eye(4)[k])[0])) / (2 * h)
          for k in range(4)]  # fmt: skip
    assert np.allclose(jac, fd, atol=1e-7)


@pytest.mark.slow
@pytest.mark.parametrize("tol, mu_deg", [(0.05, 66.85074), (0.01, 62.96660)])
def test_problem_from_an_exact_candidate_raises_the_transmission_angle(tol, mu_deg):
    # the example of docs/precision_synthesis.md (its numbers quoted there)
    cr = ms.FourBar(crank=1.2, coupler=3.5, rocker=3.0, ground=4.0)
    mo = cr.motion(ms.deg([10, 55, 110, 170, 230]), coupler_points={"P": (1.1, 0.9)})
    poses = np.column_stack([mo.points["P"].x, mo.points["P"].y, mo.links["coupler"].angle + 0.4])
    mg = ms.motion_generation(poses)
    assert abs(ms.to_deg(mg.best.min_transmission) - 58.884) < 1e-3
    res = mg.problem(0, tol=tol).solve(progress=False)
    assert res.success and res.certification.certified
    assert abs(ms.to_deg(res.value) - mu_deg) < 0.01
    assert pose_error_measure(poses).fn(res.design) <= tol + 1e-6


# ----------------------------------------------------------------------------- errors, figure
@pytest.mark.parametrize(
    "poses, match",
    [
        ([[0, 0, 0]], "at least 2"),
        ([[0, 0, 0]] * 2, "coincide"),
        ([[0, 0, 0], [1, np.nan, 0]], "finite"),
        ([[0, 0], [1, 1]], r"\(n, 3\)"),
        ([[0, 0, 0], [0, 0, 1]], "share the point"),
        ([[i, 0, 0.1 * i] for i in range(6)], "at most 5"),
    ],
)
def test_bad_poses(poses, match):
    with pytest.raises(ms.MechanismError, match=match):
        ms.burmester(poses)


def test_three_poses_need_centres():
    with pytest.raises(ms.MechanismError, match="choose the fixed pivots"):
        ms.motion_generation(POSES5[:3])
    mg = ms.motion_generation(POSES5[:3], centres=[(0.0, 0.0), (4.0, 1.0)])
    assert len(mg.candidates) == 2


def test_five_poses_without_real_points_say_so():
    with pytest.raises(ms.MechanismError, match="no real Burmester points"):
        ms.motion_generation(POSES_0)


@pytest.mark.parametrize("n", [4, 5])
def test_figure_has_no_layout_problems(n):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from mechsynth.plotting import layout_problems

    mg = ms.motion_generation(POSES5[:n])
    fig = mg.plot()
    assert layout_problems(fig) == []
    plt.close(fig)


def test_all_pairs_are_candidates():
    mg = ms.motion_generation(POSES5)
    rr = [d for d in mg.dyads if d.kind == "RR"]
    assert len(mg.candidates) == len(list(itertools.permutations(rr, 2)))


def test_poses_differing_by_a_translation_use_another_pole():
    poses = [[0, 0, 0], [1, 0, 0], [2, 1, 0.5], [0, 1, 0.9]]  # P12 at infinity
    bm = ms.burmester(poses)
    assert bm.poles[(1, 2)] is None
    kc = bm.circle_curve(200)
    kc = kc[np.isfinite(kc[:, 0])]
    assert len(kc) > 50 and max(bm.centre_point(z).residual for z in kc[::10]) < 1e-12
    assert ms.motion_generation(poses).defect_free
    five = [[0, 0, 0], [1, 0, 0], [2, 1, 0.5], [0, 1, 0.9], [1, 1, 1.5]]
    for d in ms.burmester(five).points:
        assert d.residual < 1e-12
    with pytest.raises(ms.MechanismError, match="translations only"):
        ms.burmester([[0, 0, 0], [1, 0, 0], [2, 1, 0], [3, 0, 0]]).centre_curve()


def test_burmester_plot_draws_a_candidate():
    import matplotlib.pyplot as plt

    mg = ms.motion_generation(POSES5)
    fig = mg.burmester.plot(mg.best)
    assert "defects: none" in fig.axes[0].get_title()
    plt.close(fig)


FUZZ = [pytest.param(20, id="quick"), pytest.param(300, id="full", marks=pytest.mark.slow)]


@pytest.mark.parametrize("n", FUZZ)
def test_hostile_poses_succeed_finitely_or_refuse(n):
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    value = st.one_of(
        st.floats(allow_nan=True, allow_infinity=True, width=64),
        st.floats(-10.0, 10.0),
        st.sampled_from([0.0, 1e-300, 1e300, -1e16, 1e-9, 2 * np.pi, np.pi]),
    )
    rows = st.lists(st.lists(value, min_size=3, max_size=3), min_size=0, max_size=6)

    @settings(max_examples=n, deadline=None, database=None, derandomize=True,
              suppress_health_check=list(HealthCheck))  # fmt: skip
    @given(rows)
    def prop(poses):
        try:
            bm = ms.burmester(poses)
            for d in bm.points:
                assert np.all(np.isfinite(d.circle)) and np.isfinite(d.residual)
            if bm.n == 4:
                for d in bm.sliders():
                    assert np.all(np.isfinite(d.circle))
            if bm.n >= 4:
                mg = ms.motion_generation(poses, samples=4)
                for c in mg.candidates:
                    assert np.isfinite(c.min_transmission)
                    assert np.all(np.isfinite(c.crank_angles))
        except ms.MechanismError:
            pass

    prop()


def test_linkage_tables_read_back_for_both_kinds():
    import tomllib

    from mechsynth.explore.model import to_toml
    from mechsynth.synthesis.linkage_file import linkage_from_data

    lk = (
        ms.Linkage(ground={"O": (0.3, 0.2)})
        .crank("A", about="O", length=0.5)
        .rrp("B", ("A", 1.6), guide=((0.0, -0.1), np.radians(20.0)))
        .attach("P", on=("A", "B"), along=0.7, left=0.4)
        .attach("Q", on=("A", "B"), along=1.7, left=0.4)
    )
    m = lk.motion(np.radians([0.0, 70.0, 140.0, 210.0, 280.0]))
    px, py = m.points["P"].x, m.points["P"].y
    poses = np.column_stack([px, py, np.arctan2(m.points["Q"].y - py, m.points["Q"].x - px)])
    for p in (poses, POSES5):
        for c in ms.motion_generation(p).candidates:
            back = linkage_from_data(tomllib.loads(to_toml(c.linkage_data())))
            assert back.parameters.keys() == c.linkage.parameters.keys()
            for k, v in c.linkage.parameters.items():
                assert back.parameters[k] == pytest.approx(v, abs=1e-15)
            assert np.allclose(pose_errors(back, p)[0], pose_errors(c.linkage, p)[0], atol=1e-12)
