"""The impact study: its JSON schema, files, findings and figures' layout."""

import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from mechsynth.jsonutil import dumps  # noqa: E402
from mechsynth.plotting import layout_problems  # noqa: E402
from mechsynth.studies import run_study  # noqa: E402


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    out = tmp_path_factory.mktemp("impact")
    found = {}
    original = Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        found[Path(str(fname)).name] = layout_problems(self)
        kwargs["dpi"] = 40
        return original(self, fname, *args, **kwargs)

    Figure.savefig = savefig
    try:
        res = run_study("impact", out=out, angles=180, startup_s=0.3, synthesis=False)
    finally:
        Figure.savefig = original
    return res, found


def test_json_schema(result):
    res, _ = result
    data = json.loads(dumps(res.data))
    assert data["success"] is True  # no synthesis asked for: nothing failed
    six = data["six_link"]
    assert [e["rho_deg"] for e in six] == pytest.approx([57.0, 90.0, 123.0])
    for e in six:
        assert set(e) >= {
            "rho_deg",
            "design",
            "points_at_0",
            "stroke",
            "peak_velocity",
            "peak_acceleration",
            "peak_guide_force",
        }
        d = e["design"]
        assert set(d) >= {
            "O",
            "D",
            "OA",
            "AB",
            "DB",
            "KN",
            "guide_point",
            "guide_angle_deg",
            "speed_rpm",
        }
        assert d["guide_angle_deg"] == pytest.approx(e["rho_deg"])
        assert set(e["points_at_0"]) == {"A", "B", "K", "N"}
        # the guide passes through N at crank angle 0
        n = np.array(e["points_at_0"]["N"]) - np.array(d["guide_point"])
        a = np.radians(d["guide_angle_deg"])
        assert abs(-n[0] * np.sin(a) + n[1] * np.cos(a)) < 1e-12
        assert 0.02 < e["stroke"] < 0.05
    for key in ("five_link", "forces", "blow", "dynamics", "special_position", "paper_formulas"):
        assert key in data


def test_findings_and_dynamics(result):
    res, _ = result
    d = res.data
    assert all(f["holds"] for f in d["special_position"])
    dyn = d["dynamics"]
    assert dyn["stepping_vs_ivp_max_rel"] < 1e-6 and dyn["quartic_positive_roots"] == [1]
    assert abs(dyn["steady_state"]["blows_per_minute"] - 2000.0) < 20.0
    assert dyn["flywheel"]["delta"] == pytest.approx(dyn["flywheel"]["delta_target"], rel=1e-3)
    assert d["forces"]["six"]["transverse_peak_N"] < 0.3 * d["forces"]["base"]["transverse_peak_N"]
    assert (
        d["five_link"]["five"]["peak_guide_force"]
        < 1e-6
        < d["five_link"]["arc"]["peak_guide_force"]
    )
    assert res.errata


def test_files_and_figures(result):
    res, found = result
    names = {Path(f).name for f in res.files}
    assert {
        "impact_kinematics.png",
        "impact_forces.png",
        "impact_guide.png",
        "impact_speed.png",
        "impact_six_link.gif",
        "impact_six_link.csv",
        "impact_forces.csv",
        "impact_steady_state.csv",
    } <= names
    bad = {k: v for k, v in found.items() if v}
    assert not bad, bad


def test_paper_arguments_and_coverage_reported(result):
    res, found = result
    f = res.data["findings"]
    assert f["support_position"]["least_guide_force_rho_deg"] == 90.0
    assert f["extra_rod"]["verdict"]["123.0"]["speed_rises"]
    assert not f["extra_rod"]["verdict"]["57.0"]["speed_rises"]
    assert f["gravity_assist"]["holds_up_to_the_blow"]
    assert f["rocker_profile"]["max_rel_difference"] < 1e-4
    assert "speed and stroke rise at rho 123 deg" in res.summary
    assert "coverage of Paper 001" in res.summary
    assert res.data["coverage"]["study"] == "impact"
    names = {Path(p).name for p in res.files}
    for name in (
        "impact_extra_rod.png",
        "impact_five_link_forces.png",
        "impact_reduced.png",
        "impact_rocker_profile.png",
        "impact_five_link_forces.csv",
        "impact_extra_rod.csv",
        "impact_coverage.csv",
    ):
        assert name in names
    for name in (
        "impact_extra_rod.png",
        "impact_five_link_forces.png",
        "impact_reduced.png",
        "impact_rocker_profile.png",
    ):
        assert found[name] == [], (name, found[name])
