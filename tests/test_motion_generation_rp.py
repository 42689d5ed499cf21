"""RP dyads (a block pinned at a fixed pivot, the coupler sliding through it: the circle point at
infinity) and the inverted slider-cranks they make with an RR crank."""

from __future__ import annotations

import json

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.kinematics.linkage import Linkage
from mechsynth.synthesis.burmester import displace
from mechsynth.synthesis.linkage_file import linkage_from_data, load_linkage
from mechsynth.synthesis.motion_generation import (
    motion_problem,
    pair,
    pose_error_measure,
    pose_errors,
)

O, D, CRANK, OFFSET = (0.0, 0.0), (3.0, 0.5), 1.0, 0.3
P_ON_COUPLER = (1.2, 0.6)  # along, left of the coupler's axis through A (m)
TURN = 0.3  # the pose frame turned from the coupler's axis (rad)
PHI5 = np.radians([10.0, 60.0, 110.0, 170.0, 240.0])


def _known():
    """An inverted slider-crank: crank OA, the coupler pinned at A slides through a block
    pinned at D, its slot 0.3 m to the left of its axis through A."""
    return (
        Linkage(ground={"O": O, "D": D})
        .crank("A", about="O", length=CRANK)
        .rpr("coupler", about="A", through="D", offset=OFFSET, block="block")
        .attach("P", on="coupler", along=P_ON_COUPLER[0], left=P_ON_COUPLER[1])
    )


def _poses(phi=PHI5):
    m = _known().motion(np.asarray(phi, float))
    axis = np.asarray(m.links["coupler"].angle, float)
    return np.column_stack([m.points["P"].x, m.points["P"].y, axis + TURN]), axis


POSES, AXIS = _poses()
# the slot's direction in the pose frame: the coupler's axis is TURN behind the frame's x axis
SLOT = float(np.mod(-TURN, np.pi))


def _slot_distance(dyad, poses):
    """The fixed pivot's distance from the slot placed by each pose, computed here from the
    pose frames (not by the library): the slot passes through ``local`` at ``line_angle``."""
    poses = np.asarray(poses, float)
    through = displace(poses, dyad.circle)  # the slot's point at the pivot in pose 1
    g = dyad.line_angle + poses[:, 2]
    n = np.column_stack([-np.sin(g), np.cos(g)])
    return np.abs(np.einsum("ij,ij->i", np.asarray(dyad.centre) - through, n))


def test_three_poses_any_slot_direction_has_one_pivot():
    bm = ms.burmester(POSES[:3])
    d = bm.rp_point(SLOT)
    assert d.kind == "RP" and d.length is None and d.guide_angle is None
    assert np.allclose(d.centre, D, atol=1e-12)
    assert abs(d.line_angle - SLOT) < 1e-12
    for angle in (0.2, 1.0, 2.5):  # any other direction: its own pivot, checked geometrically
        other = bm.rp_point(angle)
        assert _slot_distance(other, POSES[:3]).max() < 1e-12 and other.residual < 1e-12
    local = np.array(d.local)  # the pivot's place in the moving frame in pose 1
    c, s = np.cos(POSES[0, 2]), np.sin(POSES[0, 2])
    assert np.allclose(np.array([[c, -s], [s, c]]) @ local + POSES[0, :2], d.circle)


def test_four_poses_give_one_rp_dyad_the_known_one():
    bm = ms.burmester(POSES[:4])
    (d,) = bm.rp_dyads()
    assert np.allclose(d.centre, D, atol=1e-12)
    assert abs(d.line_angle - SLOT) < 1e-12
    assert _slot_distance(d, POSES[:4]).max() < 1e-12
    assert bm.as_dict()["rp_dyads"][0]["line_angle"] == d.line_angle
    # the dual of the PR dyad: four poses of any motion have exactly one of each
    assert len(bm.sliders()) == 1


def test_five_poses_of_an_inverted_slider_crank_have_its_rp_dyad():
    bm = ms.burmester(POSES)
    rp = bm.rp_dyads()
    assert len(rp) == 1 and np.allclose(rp[0].centre, D, atol=1e-12)
    rr = [d for d in bm.points if d.kind == "RR"]
    assert any(np.allclose(d.centre, O, atol=1e-12) for d in rr)
    # no RR dyad stands in for the one at infinity (a far circle point in floating point)
    assert all(d.length < 1e3 for d in rr)
    # five generic poses have none
    from test_motion_generation import POSES5

    assert ms.burmester(POSES5).rp_dyads() == ()


def test_paired_with_the_crank_it_gives_the_linkage_back():
    bm = ms.burmester(POSES[:4])
    cand = pair(POSES[:4], bm.circle_point(O), bm.rp_dyads()[0])
    assert cand.kind == "inverted slider-crank" and cand.defect_free
    assert cand.grashof == "full-turn crank" and cand.mechanism is None
    p = cand.linkage.parameters
    assert abs(p["OA"] - CRANK) < 1e-12 and abs(p["coupler_offset"] - OFFSET) < 1e-12
    assert abs(p["D_x"] - D[0]) < 1e-12 and abs(p["D_y"] - D[1]) < 1e-12
    assert abs(p["P_along"] - P_ON_COUPLER[0]) < 1e-12
    assert abs(p["P_left"] - P_ON_COUPLER[1]) < 1e-12
    assert np.allclose(np.mod(cand.crank_angles, 2 * np.pi), PHI5[:4], atol=1e-12)
    pos, ang = pose_errors(cand.linkage, POSES)  # the fifth pose too
    assert pos.max() < 1e-12 and ang.max() < 1e-12
    # its minimum transmission angle is the RPR group's, over the poses' crank travel
    sweep = np.linspace(PHI5[0], PHI5[3], 181)
    mu = np.asarray(_known().motion(sweep).transmission_angles["coupler"], float)
    assert abs(cand.min_transmission - np.min(np.fmin(mu, np.pi - mu))) < 1e-9


def test_pose_error_measure_of_the_slot_is_the_pivots_distance():
    bm = ms.burmester(POSES[:4])
    cand = pair(POSES[:4], bm.circle_point(O), bm.rp_dyads()[0])
    measure = pose_error_measure(POSES, cand.kind)
    assert measure.fn(cand.linkage) < 1e-12
    moved = cand.linkage.with_parameters(D_y=D[1] + 0.01)
    dist = _slot_distance(bm.rp_dyads()[0], POSES)  # 0 for the exact pivot
    assert dist.max() < 1e-12
    # the pivot moved by 0.01 m in y lies 0.01 |cos(slot)| off each pose's slot
    g = SLOT + POSES[:, 2]
    assert abs(measure.fn(moved) - np.max(0.01 * np.abs(np.cos(g)))) < 1e-12


def test_motion_generation_ranks_inverted_slider_cranks_among_the_rest():
    mg = ms.motion_generation(POSES)
    kinds = {c.kind for c in mg.candidates}
    assert kinds == {"four-bar", "inverted slider-crank"}
    best = mg.candidates[0]  # the known one, defect-free with the largest angle
    assert best.kind == "inverted slider-crank" and best.defect_free
    assert np.allclose(best.driven.centre, D, atol=1e-12)
    table = mg.table()
    assert np.isnan(table["coupler [m]"][0]) and np.isnan(table["rocker [m]"][0])
    four = ms.motion_generation(POSES[:4])
    assert sum(c.kind == "inverted slider-crank" for c in four.candidates) == sum(
        d.kind == "RR" for d in four.dyads
    )


def test_linkage_file_round_trip_and_the_error_problem():
    mg = ms.motion_generation(POSES)
    best = mg.candidates[0]
    back = linkage_from_data(best.linkage_data())
    assert back.parameters == best.linkage.parameters
    assert pose_errors(back, POSES)[0].max() < 1e-12
    # a sixth pose off the known linkage: the error problem spreads it over all six
    six, _ = _poses(np.append(PHI5, np.radians(300.0)))
    six[5, :2] += 0.03
    start = pose_error_measure(six, best.kind).fn(best.linkage)
    res = motion_problem(best, six, objective="error", span=0.3).solve(starts=1, progress=False)
    assert res.success and res.value < 0.5 * start


def test_bad_calls_are_named():
    with pytest.raises(ms.MechanismError, match="rp_point.*takes 3 poses"):
        ms.burmester(POSES[:4]).rp_point(0.3)
    with pytest.raises(ms.MechanismError, match="line_angle"):
        ms.burmester(POSES[:3]).rp_point(float("nan"))
    assert ms.burmester(POSES[:3]).rp_dyads() == ()


def test_cli_writes_an_inverted_slider_crank(tmp_path, capsys):
    from mechsynth.cli import main

    f = tmp_path / "poses.csv"
    f.write_text(
        "x [m],y [m],angle [rad]\n" + "".join(f"{x!r},{y!r},{a!r}\n" for x, y, a in POSES.tolist())
    )
    out = tmp_path / "out"
    assert main(["synthesize", "motion", str(f), "--json", "--out", str(out)]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["candidates"][0]["kind"] == "inverted slider-crank"
    assert data["burmester"]["burmester_points"][-1]["kind"] == "RP"
    assert max(data["pose_error"]["position_m"]) < 1e-9
    lk = load_linkage(out / "linkage.toml")
    assert abs(lk.parameters["coupler_offset"] - OFFSET) < 1e-9
