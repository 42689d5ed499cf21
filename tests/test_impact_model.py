"""Paper 001's impact mechanisms as linkages; the printed formulas (1)-(10) against the exact
model; the findings at the special position."""

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.machines.impact import crank_rocker, five_link, six_link, special_angles
from mechsynth.machines.impact.paper001 import (
    check_five_link,
    check_six_link,
    eq4_v_n,
    rho_finding,
    six_link_quantities,
)

PHI = np.linspace(0.0, 2 * np.pi, 361)
W = ms.rpm(2000)


def test_names_and_parameters():
    six = six_link()
    assert isinstance(six, ms.Linkage) and six.name == "six-link"
    for key in (
        "D_x",
        "OA",
        "AB",
        "DB",
        "K_along",
        "K_left",
        "KN",
        "N_guide_offset",
        "N_guide_angle",
    ):
        assert key in six.parameters
    assert abs(six.parameters["N_guide_angle"] - ms.deg(90)) < 1e-15
    base = crank_rocker()
    assert base.default_output == "K" and "N" not in base.points
    five = five_link()
    assert "N_profile_base_radius" in five.parameters


def test_six_link_stroke_and_special_position():
    m = six_link().motion(PHI, speed=W)
    stroke = np.ptp(m.sliders["N"].position)
    assert 0.03 < stroke < 0.05
    phi_s = special_angles(six_link())
    assert phi_s.size == 2
    ms_ = six_link().motion(phi_s)
    k, d = ms_.points["K"], ms_.points["D"]
    assert np.allclose(k.y - d.y, 0.0, atol=1e-13) and np.all(k.x > d.x)


def test_five_link_involute_moves_striker_by_base_radius():
    five = five_link()
    rb = five.parameters["N_profile_base_radius"]
    m = five.motion(PHI, speed=W)
    assert np.max(m.pressure_angle) < 1e-12
    assert np.allclose(m.sliders["N"].velocity, -rb * m.links["DB"].omega, atol=1e-10)
    arc = five_link("arc").motion(PHI, speed=W)
    assert np.max(arc.pressure_angle) > ms.deg(1)  # the arc pushes off the guide's line


@pytest.mark.parametrize("rho", [57.0, 90.0, 123.0])
def test_printed_six_link_formulas(rho):
    """(3), (5), (6), (7) exact as printed for the striker behind K; (4) has the opposite sign;
    (1) is wrong; every correction is exact on both assemblies."""
    rows = {r["formula"]: r for r in check_six_link(six_link(ms.deg(rho)), PHI, W)}
    for f in ("(3)", "(5)", "(6)", "(7)"):
        assert rows[f]["agrees"], rows[f]
    assert not rows["(1)"]["agrees"] and not rows["(4)"]["agrees"]
    q = six_link_quantities(six_link(ms.deg(rho)), PHI, W)
    v4 = eq4_v_n(q["v_k"], q["phi3"], q["rho"], q["eta"])
    assert np.allclose(v4, -q["v_n"], atol=1e-12 * np.abs(q["v_n"]).max())
    for branch in (-1, 1):
        for r in check_six_link(six_link(ms.deg(rho), branch=branch), PHI, W):
            assert r["corrected_deviation"] < 1e-9, r
    ahead = {r["formula"]: r for r in check_six_link(six_link(ms.deg(rho), branch=1), PHI, W)}
    for f in ("(3)", "(5)", "(6)"):
        assert not ahead[f]["agrees"]


def test_printed_five_link_formulas():
    rows = {r["formula"]: r for r in check_five_link(five_link(), PHI, W)}
    assert rows["(8)"]["agrees"]
    for f in ("(9)", "(10)", "(10')"):
        assert not rows[f]["agrees"] and rows[f]["printed_deviation"] > 0.05
        assert rows[f]["corrected_deviation"] < 1e-9


def test_rho_findings_at_the_special_position():
    """rho = 90: V_N = V_K (exact, any rod); 57: V_N > V_K; 123: V_N < V_K with the striker
    behind K (the paper's assembly); reversed with it ahead: the claim is not general."""
    for rho, sense in ((57.0, ">"), (90.0, "="), (123.0, "<")):
        f = rho_finding(six_link(ms.deg(rho)), W)
        assert f["paper"] == sense and f["holds"], f
        assert np.allclose(f["ratio"], f["predicted_ratio"], rtol=1e-12)
    for extra_rod in (0.05, 0.09):
        f = rho_finding(six_link(ms.deg(90), extra_rod=extra_rod), W)
        assert np.allclose(f["ratio"], 1.0, atol=1e-12)
    for rho in (57.0, 123.0):
        f = rho_finding(six_link(ms.deg(rho), branch=1), W)
        assert not f["holds"] and np.allclose(f["ratio"], f["predicted_ratio"], rtol=1e-12)


def test_bad_input():
    with pytest.raises(ms.MechanismError, match="farther from the guide"):
        six_link(ms.deg(57), extra_rod=0.02).motion(PHI)
    with pytest.raises(ms.MechanismError, match="profile"):
        five_link("spline")
    with pytest.raises(ms.MechanismError, match="base_radius"):
        five_link(base_radius=-0.01)


def test_example_file_is_the_representative_six_link():
    from pathlib import Path

    from mechsynth.synthesis.linkage_file import load_linkage

    path = Path(__file__).resolve().parents[1] / "examples" / "impact_six_link.toml"
    lk = load_linkage(path)
    a, b = lk.motion(PHI), six_link().motion(PHI)
    for p in ("A", "B", "K", "N"):
        assert np.allclose(a.points[p].x, b.points[p].x, atol=1e-15)
        assert np.allclose(a.points[p].y, b.points[p].y, atol=1e-15)


def test_builders_name_a_bad_argument():
    """numpy's 'could not convert string to float' and a ufunc TypeError reached the user."""
    for call, match in [
        (lambda: ms.five_link(base_radius="x"), "base_radius must be a number"),
        (lambda: ms.five_link(rho="x"), "rho must be a number"),
        (lambda: ms.five_link(margin=-1.0), "margin must be positive"),
        (lambda: ms.six_link(arm_angle="a"), "arm_angle must be a number"),
    ]:
        with pytest.raises(ms.MechanismError, match=match):
            call()
