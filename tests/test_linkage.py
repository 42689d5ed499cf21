"""General linkages: the named mechanisms written as Linkages agree with them (motion and
reactions to 1e-12), the builders, parameters, failures and the structure a drawing needs."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.dynamics import LinkInertia, kinetostatics, slider_crank_model
from mechsynth.dynamics.kinetostatics import four_bar_model
from mechsynth.dynamics.loads import Gravity, PointForce, TorsionSpring
from mechsynth.errors import MechanismError
from mechsynth.kinematics import Circle, Param
from mechsynth.machines.nail_header import NailHeader

PHI = ms.cycle(360)
FIELDS = ("x", "y", "vx", "vy", "ax", "ay")
LINK_FIELDS = ("angle", "omega", "epsilon")


def six_link():
    """The six-link of paper 001: crank O-A, rod AB, rocker DB, K on the rocker's extension,
    rod KN, slider N on a guide at 57 deg."""
    return (
        ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)})
        .crank("A", about="O", length=0.03)
        .rrr("B", ("A", 0.12), ("D", 0.08))
        .attach("K", on=("D", "B"), along=-0.05)
        .rrp("N", ("K", 0.10), guide=((0.12, 0.0), ms.deg(57)))
    )


def slider_crank_linkage(a, b, e):
    return (
        ms.Linkage(ground={"O": (0, 0)})
        .crank("A", about="O", length=a, link="crank")
        .rrp("B", ("A", b), guide=((0.0, e), 0.0), link="rod", slider="slider")
    )


def four_bar_linkage(a, b, c, d, branch=1):
    return (
        ms.Linkage(ground={"O1": (0, 0), "O2": (d, 0)})
        .crank("A", about="O1", length=a, link="crank")
        .rrr("B", ("A", b), ("O2", c), branch=branch, links=("coupler", "rocker"))
    )


def nail_header_linkage(nh: NailHeader):
    return (
        ms.Linkage(ground={"O": (0, 0), "E": (nh.x_e, nh.y_e)})
        .crank("A", about="O", length=nh.l_oa, link="crank")
        .rrp("B", ("A", nh.l_ab), guide=((0.0, 0.0), 0.0), link="rod", slider="slider")
        .attach("C", on="slider", along=nh.x_bc, left=nh.y_c)
        .rpr("ejector", about="E", through="C", offset=nh.l_de, block="block")
        .with_output("B")
    )


def _same_points(m1, m2, names, tol=1e-12):
    for k in names:
        for f in FIELDS:
            a, b = getattr(m1.points[k], f), getattr(m2.points[k], f)
            scale = max(1.0, float(np.max(np.abs(a))))
            assert np.max(np.abs(np.asarray(a) - b)) <= tol * scale, (k, f)


def _same_links(m1, m2, pairs, tol=1e-12):
    for k1, k2 in pairs:
        for f in LINK_FIELDS:
            a, b = getattr(m1.links[k1], f), getattr(m2.links[k2], f)
            scale = max(1.0, float(np.max(np.abs(a))))
            assert np.max(np.abs(np.asarray(a) - b)) <= tol * scale, (k1, f)


def _same_reactions(f1, f2, pairs, tol=1e-12):
    for j1, j2 in pairs:
        scale = max(1.0, float(np.max(f1.magnitude(j1))))
        for i in range(2):
            assert np.max(np.abs(np.asarray(f1.reactions[j1][i]) - f2.reactions[j2][i])) <= (
                tol * scale
            ), (j1, j2)
    scale = max(1.0, float(np.max(np.abs(f1.torque))))
    assert np.max(np.abs(f1.torque - f2.torque)) <= tol * scale


# --------------------------------------------------------------------------- named mechanisms
@pytest.mark.parametrize("a, b, e", [(0.07, 0.24, 0.0), (0.05, 0.2, 0.03), (0.1, 0.3, -0.05)])
def test_slider_crank_as_linkage(a, b, e):
    sc, lk = ms.SliderCrank(a, b, e), slider_crank_linkage(a, b, e)
    m1, m2 = sc.motion(PHI, speed=ms.rpm(600)), lk.motion(PHI, speed=ms.rpm(600))
    _same_points(m1, m2, "OAB")
    _same_links(m1, m2, [("crank", "crank"), ("rod", "rod")])
    np.testing.assert_allclose(m2.slider.acceleration, m1.slider.acceleration, rtol=0, atol=1e-12)
    np.testing.assert_allclose(m2.pressure_angle, m1.pressure_angle, rtol=0, atol=1e-15)
    np.testing.assert_allclose(m2.transmission_angle, m1.transmission_angle, atol=1e-15)
    assert abs(lk.time_ratio - sc.time_ratio) < 1e-12
    # reactions: the same bodies and loads through the linkage's force model
    crank = LinkInertia("crank", "O", 5.0, (0.01, 0.002), 0.02)
    rod = LinkInertia("rod", "A", 2.0, (0.1, 0.01), 0.01)
    loads = [Gravity(), PointForce("slider", "B", lambda m: (-100 - 10 * m.points["B"].vx, 0.0))]
    named = slider_crank_model(crank, rod, LinkInertia(None, "B", 3.0, (0.02, -0.01)), loads)
    ours = lk.force_model({"crank": crank, "rod": rod, "slider": (3.0, (0.02, -0.01), 0.0)}, loads)
    f1, f2 = kinetostatics(named, m1), kinetostatics(ours, m2)
    _same_reactions(f1, f2, [("R10", "O"), ("R21", "A"), ("R32", "B"), ("R30", "slider_guide")])


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_four_bar_as_linkage(branch):
    fb = ms.FourBar(1.0, 4.3, 3.0, 5.2, branch=branch)
    lk = four_bar_linkage(1.0, 4.3, 3.0, 5.2, branch=fb.sigma)
    m1, m2 = fb.motion(PHI, speed=10.0), lk.motion(PHI, speed=10.0, kernel=False)
    _same_points(m1, m2, ["O1", "A", "B", "O2"])
    _same_links(m1, m2, [(k, k) for k in ("crank", "coupler", "rocker")])
    np.testing.assert_allclose(m2.pressure_angle, m1.pressure_angle, rtol=0, atol=1e-15)
    assert lk.default_output == "B"
    assert abs(lk.time_ratio - fb.time_ratio) < 1e-12
    spans = lk.crank_spans
    assert abs(spans[0] + spans[1] - 2 * np.pi) < 1e-12
    assert min(abs(spans[0] - fb.crank_spans[0]), abs(spans[0] - fb.crank_spans[1])) < 1e-10
    bodies = dict(
        crank=LinkInertia("crank", "O1", 1.0, (0.3, 0.0), 0.1),
        coupler=LinkInertia("coupler", "A", 2.0, (2.0, 0.5), 0.2),
        rocker=LinkInertia("rocker", "O2", 3.0, (1.5, -0.2), 0.3),
    )
    loads = [Gravity(), TorsionSpring("rocker", "rocker", 1.0, 2.0, 2.0)]
    f1 = kinetostatics(four_bar_model(*bodies.values(), loads=loads), m1)
    f2 = kinetostatics(lk.force_model(bodies, loads), m2)
    _same_reactions(f1, f2, [("R10", "O1"), ("R21", "A"), ("R32", "B"), ("R30", "O2")])


def test_nail_header_as_linkage():
    nh = NailHeader()
    lk = nail_header_linkage(nh)
    m1, m2 = nh.motion(PHI, speed=nh.omega), lk.motion(PHI, speed=nh.omega)
    _same_points(m1, m2, "OABCE")
    _same_links(m1, m2, [("crank", "crank"), ("rod", "rod"), ("ejector", "ejector")])
    np.testing.assert_allclose(m2.sliders["block"].acceleration, m1.sliders["slot"].acceleration)
    np.testing.assert_allclose(m2.slider.position, m1.slider.position, rtol=0, atol=1e-15)
    fm = nh.force_model()
    f1 = kinetostatics(fm, m1)
    f2 = kinetostatics(lk.force_model(fm.bodies, fm.loads), m2)
    pairs = [
        ("R10", "O"),
        ("R21", "A"),
        ("R32", "B"),
        ("R30", "slider_guide"),
        ("R43", "C"),
        ("R54", "ejector_slot"),
        ("R50", "E"),
    ]
    _same_reactions(f1, f2, pairs)


# --------------------------------------------------------------------------- the six-link
def test_six_link_parameters_and_motion():
    lk = six_link()
    assert list(lk.parameters) == [
        "O_x",
        "O_y",
        "D_x",
        "D_y",
        "OA",
        "phase",
        "AB",
        "DB",
        "K_along",
        "K_left",
        "KN",
        "N_guide_x",
        "N_guide_y",
        "N_guide_angle",
    ]
    assert lk.parameter_kinds["AB"] == "length" and lk.parameter_kinds["N_guide_angle"] == "angle"
    m = lk.motion(PHI, speed=ms.rpm(1500))
    for what in (m.points["N"].vx, m.sliders["N"].velocity, m.links["DB"].omega):
        assert what.shape == PHI.shape and np.all(np.isfinite(what))
    assert set(m.pressure_angles) == {"B", "N"} and m.slider is not None
    np.testing.assert_array_equal(m.pressure_angle, m.pressure_angles["N"])
    # N slides on its guide: its velocity is the slider velocity along the guide direction
    a = ms.deg(57)
    np.testing.assert_allclose(
        m.points["N"].vx, m.sliders["N"].velocity * np.cos(a), rtol=0, atol=1e-12
    )
    assert lk.links == ("OA", "AB", "DB", "N", "KN")
    assert lk.default_output == "N"
    assert set(lk.assembly_conditions) == {"B", "N"}


def test_immutable_builders_and_parameters():
    lk = six_link()
    before = lk.parameters
    other = lk.with_parameters(AB=0.13, N_guide_angle=ms.deg(60))
    assert lk.parameters == before and other.parameters["AB"] == 0.13
    assert lk(AB=0.13).parameters == other.parameters | {"N_guide_angle": before["N_guide_angle"]}
    with pytest.raises(AttributeError, match="immutable"):
        lk._name = "x"
    with pytest.raises(ValueError, match=r"has no parameter 'ab'.*AB"):
        lk.with_parameters(ab=0.1)
    with pytest.raises(ValueError, match="AB must be positive"):
        lk.with_parameters(AB=-0.1)
    with pytest.raises(ValueError, match="must be finite"):
        lk.with_parameters(D_x=np.nan)
    renamed = lk.rename(AB="coupler", OA="r")
    assert "coupler" in renamed.parameters and "AB" not in renamed.parameters
    np.testing.assert_array_equal(
        renamed.motion(PHI, kernel=False).points["N"].x, lk.motion(PHI, kernel=False).points["N"].x
    )
    with pytest.raises(ValueError, match="same name"):
        lk.rename(AB="DB")
    named = ms.Linkage(ground={"O": (0, 0), "D": (Param("d", 0.12), 0.05)}).crank(
        "A", about="O", length=Param("r", 0.03)
    )
    assert {"d", "r"} <= set(named.parameters)


def test_batches_of_designs():
    lk = six_link()
    ab = np.linspace(0.11, 0.13, 5)[:, None]
    m = lk(AB=ab).motion(PHI)
    assert m.sliders["N"].position.shape == (5, 360)
    for i in range(5):
        one = lk(AB=float(ab[i, 0])).motion(PHI)
        np.testing.assert_allclose(m.sliders["N"].acceleration[i], one.sliders["N"].acceleration)


def test_assembly_failure_names_group_angle_and_condition():
    lk = six_link()
    with pytest.raises(MechanismError) as err:
        lk(DB=0.03).motion(PHI)
    msg = str(err.value)
    assert msg.startswith("RRR group B (links AB, DB): RRR dyad: distance between its pivots")
    assert "at crank angle" in msg and "cannot be assembled" in msg
    assert err.value.angles and err.value.group == "B"
    with pytest.raises(MechanismError, match=r"RRP group N .* farther from the guide .* crank"):
        lk(KN=0.02).motion(PHI)
    with pytest.raises(MechanismError, match=r"design index \(1,\)"):
        lk(DB=np.array([0.08, 0.03])[:, None]).motion(PHI)
    # the margins exist for any design and are negative where it fails
    margins = lk(DB=0.03).assembly_margins(PHI)
    assert np.min(margins["B"]) < 0 and np.all(np.isfinite(margins["B"]))


def test_builder_refuses_what_it_used_to_take_silently():
    with pytest.raises(MechanismError, match=r"ground must be a dict .* got 'O' \(a str\)"):
        ms.Linkage(ground="O")
    with pytest.raises(MechanismError, match="ground must be a dict"):
        ms.Linkage(ground=[(0, 0)])
    with pytest.raises(MechanismError, match="name must be a non-empty string, got None"):
        ms.Linkage(ground={"O": (0, 0)}, name=None)
    lk = ms.Linkage(ground={"O": (0, 0), "D": (0.1, 0)})
    with pytest.raises(MechanismError, match="link name must be an identifier, got ''"):
        lk.crank("A", about="O", length=0.02, link="")
    c = lk.crank("A", about="O", length=0.02)
    for branch in (1.0, True, -1.0, np.True_):
        with pytest.raises(MechanismError, match=r"branch must be \+1 or -1 \(an integer\)"):
            c.rrr("B", ("A", 0.1), ("D", 0.1), branch=branch)
    assert c.rrr("B", ("A", 0.1), ("D", 0.1), branch=np.int64(-1)).groups[-1].branch == -1
    with pytest.raises(MechanismError, match="links must be a pair of link names"):
        c.rrr("B", ("A", 0.1), ("D", 0.1), links="AB")
    b = c.rrr("B", ("A", 0.1), ("D", 0.1))
    with pytest.raises(MechanismError, match="origin and axis point must differ, got 'A' twice"):
        b.attach("K", on=("A", "A"), along=0.01)
    with pytest.raises(MechanismError, match="'O' is a ground point .* moving points: A, B"):
        b.with_output("O")


def test_builder_errors_name_what_is_wrong():
    lk = ms.Linkage(ground={"O": (0, 0), "D": (0.1, 0)})
    with pytest.raises(ValueError, match="add the driver first"):
        lk.rrr("B", ("O", 0.1), ("D", 0.1))
    c = lk.crank("A", about="O", length=0.02)
    with pytest.raises(ValueError, match="one driver"):
        c.crank("A2", about="D", length=0.02)
    with pytest.raises(ValueError, match=r"unknown point 'X'; known points: O, D, A"):
        c.rrr("B", ("X", 0.1), ("D", 0.1))
    with pytest.raises(ValueError, match="point 'A' exists already"):
        c.rrr("A", ("A", 0.1), ("D", 0.1))
    with pytest.raises(ValueError, match="must be \\(point, length\\)"):
        c.rrr("B", 0.1, ("D", 0.1))
    with pytest.raises(ValueError, match="branch must be \\+1 or -1"):
        c.rrr("B", ("A", 0.1), ("D", 0.1), branch=2)
    b = c.rrr("B", ("A", 0.1), ("D", 0.1))
    with pytest.raises(ValueError, match="not on one moving link"):
        b.attach("K", on=("A", "D"))
    with pytest.raises(ValueError, match="unknown link 'XY'"):
        b.attach("K", on="XY")
    with pytest.raises(ValueError, match="length of link AB.*must be a number"):
        c.rrr("B", ("A", "long"), ("D", 0.1))
    with pytest.raises(ValueError, match="guide must be \\(through, angle\\)"):
        b.rrp("N", ("B", 0.1), guide=0.3)
    with pytest.raises(TypeError, match="profile must be a curve"):
        b.follower("N", on="DB", profile="circle", guide=((0, 0), 0.0))
    with pytest.raises(ValueError, match="give roller .* or face .*, not both"):
        b.follower("N", on="DB", profile=Circle(0.05), guide=((0, 0), 0.0), roller=0.01, face=0.0)
    with pytest.raises(ValueError, match="phi must be crank angles in rad, got 'a'"):
        b.motion("a")


def test_guide_through_a_ground_point_with_offset_and_a_carried_guide():
    """A fixed guide through D, offset h to its left, is the guide through D + h n; a guide
    carried by a moving link moves with it (the slider stays on the link's line)."""
    base = ms.Linkage(ground={"O": (0, 0), "D": (0.12, 0.05)}).crank("A", about="O", length=0.03)
    b = base.rrr("B", ("A", 0.12), ("D", 0.08)).attach("K", on=("D", "B"), along=-0.05)
    rho, h = ms.deg(57), 0.01
    g1 = b.rrp("N", ("K", 0.10), guide=("D", rho), offset=h)
    gx, gy = 0.12 - h * np.sin(rho), 0.05 + h * np.cos(rho)
    g2 = b.rrp("N", ("K", 0.10), guide=((gx, gy), rho))
    np.testing.assert_allclose(
        g1.motion(PHI).sliders["N"].acceleration,
        g2.motion(PHI).sliders["N"].acceleration,
        atol=1e-12,
    )
    assert "N_guide_offset" in g1.parameters
    carried = base.rrr("B", ("A", 0.12), ("D", 0.08)).rrp("C", ("A", 0.2), guide=("DB", 0.0))
    m = carried.motion(PHI)
    d, bb, c = m.points["D"], m.points["B"], m.points["C"]
    cross = (bb.x - d.x) * (c.y - d.y) - (bb.y - d.y) * (c.x - d.x)
    assert np.max(np.abs(cross)) < 1e-15
    np.testing.assert_allclose(np.hypot(c.x - m.points["A"].x, c.y - m.points["A"].y), 0.2)
    s = m.sliders["C"].position
    np.testing.assert_allclose(np.hypot(c.x - d.x, c.y - d.y), np.abs(s), atol=1e-15)


def test_topology_for_drawings():
    lk = six_link()
    topo = lk.topology()
    assert topo.ground == {"O": (0.0, 0.0), "D": (0.12, 0.05)}
    assert topo.points["DB"] == ("D", "B", "K") and topo.points["OA"] == ("O", "A")
    assert topo.driver == "OA"
    kinds = [(j.kind, j.name, j.on, j.by) for j in topo.joints]
    assert kinds == [
        ("revolute", "O", "OA", "frame"),
        ("revolute", "A", "AB", "OA"),
        ("revolute", "D", "DB", "frame"),
        ("revolute", "B", "DB", "AB"),
        ("revolute", "K", "KN", "DB"),
        ("revolute", "N", "N", "KN"),
        ("prismatic", "N_guide", "N", "frame"),
    ]
    m = lk.motion(PHI)
    x, y, angle = topo.guides["N"].line(m)
    np.testing.assert_allclose(angle, ms.deg(57))
    n = m.points["N"]
    np.testing.assert_allclose((n.y - y) * np.cos(angle) - (n.x - x) * np.sin(angle), 0, atol=1e-15)


def test_topology_profiles_place_the_cam():
    cam = (
        ms.Linkage(ground={"O": (0, 0)})
        .crank("A", about="O", length=0.02)
        .follower("N", on="OA", profile=Circle(0.05, (0.02, 0.0)), guide=((0, 0), np.pi / 2))
    )
    topo = cam.topology()
    m = cam.motion(PHI)
    X, Y = topo.profiles["N"].world(m, n=400)
    c = m.points["N_contact"]
    gap = np.min(np.hypot(X - np.asarray(c.x)[:, None], Y - np.asarray(c.y)[:, None]), axis=1)
    assert np.max(gap) < 0.05 * 2 * np.pi / 400  # the contact point lies on the drawn profile
    assert [j.kind for j in topo.joints] == ["revolute", "prismatic", "contact"]


def test_measures_bound_to_a_linkage():
    """The existing measures on a linkage: stroke of a slider on an inclined guide is its
    travel along the guide, swing of a rocker equals the four-bar's closed form, time ratio,
    per-group pressure and transmission angles; unknown names fail clearly."""
    from mechsynth import objectives as ob

    lk = six_link()
    phi = ms.cycle(4096)
    m = lk.motion(phi, speed=ms.rpm(1500))
    assert ob.stroke("N").evaluate(lk, phi) == pytest.approx(np.ptp(m.sliders["N"].position))
    assert ob.stroke("N").evaluate(lk, phi) != pytest.approx(np.ptp(m.points["N"].x))
    assert ob.max_pressure_angle("N").evaluate(lk, phi) == pytest.approx(
        m.pressure_angles["N"].max()
    )
    mu = m.transmission_angles["B"]
    assert ob.min_transmission_angle("B").evaluate(lk, phi) == pytest.approx(
        np.min(np.minimum(mu, np.pi - mu))
    )
    fb = ms.FourBar(1.0, 4.3, 3.0, 5.2)
    four = four_bar_linkage(1.0, 4.3, 3.0, 5.2)
    assert ob.swing_angle("rocker").evaluate(four, phi) == pytest.approx(fb.swing_angle, rel=1e-6)
    assert ob.time_ratio().bind(four).fn(four) == pytest.approx(fb.time_ratio, rel=1e-12)
    assert ob.peak_velocity("N").evaluate(lk, phi, speed=ms.rpm(1500)) == pytest.approx(
        np.max(m.points["N"].velocity)
    )
    with pytest.raises(ValueError, match="no pressure angle of group 'Q'; groups with one: B, N"):
        ob.max_pressure_angle("Q").evaluate(lk, phi)
    with pytest.raises(ValueError, match="no assembly condition 'Q'; conditions: B, N"):
        ob.assembly_margin("Q").evaluate(lk, phi)
    with pytest.raises(ValueError, match="reports no assembly margins"):
        ob.assembly_margin("B").evaluate(fb, phi)


def test_a_motion_too_big_for_memory_is_refused_before_any_work():
    lk = ms.six_link()
    with pytest.raises(MechanismError, match=r"10000000 angles would need about .* GiB"):
        lk.motion(np.linspace(0.0, 6.0, 10**7))  # numpy's MemoryError after a long wait
    batch = lk(DB=np.linspace(0.07, 0.09, 10**6)[:, None])
    with pytest.raises(MechanismError, match=r"360000000 designs x angles would need"):
        batch.motion(ms.cycle(360))
    with pytest.raises(MechanismError, match="do not broadcast: .*DB \\(3, 1\\)"):
        lk(DB=np.full((3, 1), 0.08)).motion(np.zeros((2, 4)))
