"""One Linkage design's motion with less Python around the same numpy work: what a motion reads
of the structure derived once per linkage (its plan), the tracks made from the jets without a
call per track, an RRR group's pivot distance shared by its margin and its dyad, the two second
analogs of a dyad tested in one pass -- every output the same, bit for bit."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.errors import MechanismError
from mechsynth.kinematics import blocks
from mechsynth.kinematics.tracks import (
    Jet,
    LinkTrack,
    PointJet,
    PointTrack,
    SliderTrack,
    Tracks,
    _as_tracks,
)


def _jets(rng, shape=(7,)):
    points = {
        "A": PointJet(*rng.normal(size=(6, *shape))),
        "B": PointJet(*rng.normal(size=(6, *shape))),
    }
    links = {"AB": Jet(*rng.normal(size=(3, *shape)))}
    sliders = {"S": Jet(*rng.normal(size=(3, *shape)))}
    return points, links, sliders


@pytest.mark.parametrize(
    "omega, epsilon",
    [
        (1.0, 0.0),
        (2.5, 0.0),
        (-31.4, 0.0),
        (2.5, 3.0),
        (np.arange(1.0, 8.0), 0.0),
    ],
)
def test_tracks_of_jets_are_each_tracks_from_jet_bit_for_bit(omega, epsilon):
    points, links, sliders = _jets(np.random.default_rng(3))
    kept = PointTrack.of(*np.ones((6, 7)))  # a track given is kept as it is
    got = _as_tracks({**points, "O": kept}, links, sliders, omega, epsilon)
    assert [type(t).__name__ for t in got] == ["_Points", "_Links", "_Sliders"]
    assert all(isinstance(t, Tracks) for t in got)
    assert got[0]["O"] is kept
    pairs = [(got[0][k], PointTrack.from_jet(j, omega, epsilon)) for k, j in points.items()]
    pairs += [(got[1][k], LinkTrack.from_jet(j, omega, epsilon)) for k, j in links.items()]
    pairs += [(got[2][k], SliderTrack.from_jet(j, omega, epsilon)) for k, j in sliders.items()]
    for fast, ref in pairs:
        assert type(fast) is type(ref)
        for a, b in zip(vars(fast).values(), vars(ref).values(), strict=True):
            np.testing.assert_array_equal(a, b, strict=True)
    if (
        type(omega) is float and omega == 1.0 and epsilon == 0.0
    ):  # the analogs themselves, not copies
        assert got[0]["A"].vx is points["A"].dx and got[1]["AB"].epsilon is links["AB"].d2
    with pytest.raises(MechanismError, match="no point 'Z'"):
        got[0]["Z"]


def test_a_shared_pivot_distance_gives_the_dyads_own_bit_for_bit():
    phi = ms.cycle(360)
    c, s = np.cos(phi), np.sin(phi)  # a crank pin about (0.05, 0.02) and its analogs
    a = PointJet(0.05 + 0.03 * c, 0.02 + 0.03 * s, -0.03 * s, 0.03 * c, -0.03 * c, -0.03 * s)
    for p2 in (PointJet(0.0, 0.0, 0.0, 0.0, 0.0, 0.0), PointJet(0.1, -0.0, 0.0, 0.0, 0.0, 0.0)):
        apart = blocks.rrr_apart(a, p2)
        assert np.array_equal(apart[2], apart[0] ** 2 + apart[1] ** 2)
        own = blocks.dyad_rrr(a, p2, 0.10, 0.09, -1, phi=phi)
        shared = blocks.dyad_rrr(a, p2, 0.10, 0.09, -1, phi=phi, apart=apart)
        for x, y in zip(np.concatenate(own), np.concatenate(shared), strict=True):
            np.testing.assert_array_equal(x, y, strict=True)
        assert np.all(np.signbit(own[0].x) == np.signbit(shared[0].x))


@pytest.mark.parametrize("bad", [np.inf, -np.inf, np.nan])
def test_the_pair_test_finds_a_non_finite_analog_anywhere(bad):
    phi = ms.cycle(360)
    rng = np.random.default_rng(11)
    e1, e2 = rng.normal(size=(2, 360))
    assert not blocks._failed(phi, e1, e2)
    for k in (0, 17, 359):
        for which in (0, 1):
            pair = [e1.copy(), e2.copy()]
            pair[which][k] = bad
            assert blocks._failed(phi, *pair)
    zeros = np.zeros(360)  # inf times 0 is NaN: still found
    hit = zeros.copy()
    hit[5] = bad
    assert blocks._failed(phi, hit, zeros) and blocks._failed(phi, zeros, hit)
    # a batch's analogs past one design's grid: each tested on its own (no threaded BLAS)
    rows = np.zeros((30, 360))
    assert not blocks._failed(phi, rows, rows)
    late = rows.copy()
    late[29, 359] = bad
    assert blocks._failed(phi, rows, late) and blocks._failed(phi, late, rows)
    # finite analogs whose products overflow: looked at closer, and no toggle is reported
    huge = np.full(360, 1e200)
    assert blocks._failed(phi, huge, huge)
    blocks._check_toggle("x", phi, huge, huge)


def _six_link():
    return ms.six_link()


def test_a_motion_of_angles_past_a_dot_products_range_is_still_made():
    # finite angles whose squares overflow are tested entry by entry, not refused
    lk = ms.Linkage(ground={"O": (0, 0), "D": (0.10, 0.0)}).crank("A", about="O", length=0.03)
    lk = lk.rrr("B", ("A", 0.10), ("D", 0.07))
    big = np.array([1e155, 2e155])
    m = lk.motion(big)
    ref = lk.motion(np.fmod(big, 2 * np.pi) + 0.0)  # the same angles, reduced
    assert np.all(np.isfinite(m.points["B"].x))
    np.testing.assert_allclose(np.hypot(m.points["A"].x, m.points["A"].y), 0.03, rtol=1e-12)
    assert ref.points["B"].x.shape == m.points["B"].x.shape
    for phi in (np.array([0.0, np.inf]), np.array([np.nan]), float("inf")):
        with pytest.raises(MechanismError, match="phi must be finite crank angles"):
            lk.motion(phi)


def test_the_plan_follows_the_structure_and_the_output():
    lk = _six_link()
    phi = ms.cycle(72)
    m = lk.motion(phi, speed=ms.rpm(300))
    assert list(m.sliders)[0] == "N" and m.slider is m.sliders["N"]
    np.testing.assert_array_equal(m.pressure_angle, m.pressure_angles["N"], strict=True)
    assert list(m.points)[: len(lk.points)] == list(lk.points)
    for name in ("O", "D"):  # ground points: tracks of the motion's shape, at rest
        p = m.points[name]
        assert p.x.shape == phi.shape and not np.any(p.vx) and not np.any(p.ay)
    b = lk.with_output("B").motion(phi, speed=ms.rpm(300))
    np.testing.assert_array_equal(b.pressure_angle, b.pressure_angles["B"], strict=True)
    np.testing.assert_array_equal(
        b.raw_transmission_angle, b.raw_transmission_angles["B"], strict=True
    )
    # a renamed linkage and one with other values keep their own plan
    oa = lk.parameters["OA"] * 1.002
    r = lk.rename(OA="crank").with_parameters(crank=oa)
    mr = r.motion(phi, speed=ms.rpm(300), kernel=False)  # the model's plans, bit for bit
    mo = lk(OA=oa).motion(phi, speed=ms.rpm(300), kernel=False)
    for a, c in zip(vars(mr.sliders["N"]).values(), vars(mo.sliders["N"]).values(), strict=True):
        np.testing.assert_array_equal(a, c, strict=True)
    # a linkage growing after a motion: its new group is its output
    lk2 = lk.attach("Q", on="KN", along=0.01)
    assert lk2.motion(phi).points["Q"].x.shape == phi.shape


def test_a_batch_is_still_guarded_and_a_design_of_numbers_is_not_looked_at_twice():
    lk = _six_link()
    assert lk._guarded == {}
    oa, kn = lk.parameters["OA"], lk.parameters["KN"]
    batch = lk(OA=oa * np.array([[1.0], [1.001]]), KN=kn * np.array([[1.0], [1.001], [1.002]]))
    assert batch._guarded is batch._values
    with pytest.raises(MechanismError):  # (2, 1) against (3, 1): they do not broadcast
        batch.motion(ms.cycle(10))
    m = lk(OA=oa * np.array([[1.0], [1.001]])).motion(ms.cycle(10))
    assert m.points["N"].x.shape == (2, 10)


@pytest.mark.parametrize("angle", [0.3, -2.0, np.pi / 2, np.array([[0.3], [1.1]])])
def test_a_shared_height_over_the_guide_gives_the_dyads_own_bit_for_bit(angle):
    from mechsynth.kinematics.linkage_groups import guide_height

    phi = ms.cycle(360)
    c, s = np.cos(phi), np.sin(phi)
    p = PointJet(0.01 + 0.03 * c, -0.0 + 0.03 * s, -0.03 * s, 0.03 * c, -0.03 * c, -0.03 * s)
    for gx, gy in ((0.0, -0.0), (0.05, 0.01)):
        hgt = guide_height(p, gx, gy, angle)
        own = blocks.dyad_rrp(p, 0.1, gx, gy, angle, -1, phi)
        shared = blocks.dyad_rrp(p, 0.1, gx, gy, angle, -1, phi, hgt)
        for x, y in zip(np.concatenate(own), np.concatenate(shared), strict=True):
            np.testing.assert_array_equal(x, y, strict=True)
            assert np.array_equal(np.signbit(x), np.signbit(y))
