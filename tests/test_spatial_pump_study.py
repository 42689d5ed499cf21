"""Study spatial-pump (paper 002) at reduced settings, through the command line."""

import json
import shutil

import pytest

from mechsynth.cli import main
from mechsynth.studies.spatial_pump import CARD_FILE, OPTION_UNITS, unit_7sk12

REDUCED = dict(
    n_angles=72, sweep_angles=36, sweep_points=3, chart_points=3, design_points=3,
    sizing_angles=24,
    stiffness_factors="1,4",
)  # fmt: skip


def test_the_unit_has_the_7sk12_stroke():
    u = unit_7sk12()
    assert abs(u.stroke - 2.5) < 1e-9
    assert u.unit_class == "conventional"


def test_study_run_reduced(tmp_path, capsys, monkeypatch):
    from pathlib import Path

    from matplotlib.figure import Figure

    from mechsynth.plotting import layout_problems

    found, original = {}, Figure.savefig

    def savefig(self, fname, *a, **kw):
        found[Path(str(fname)).name] = layout_problems(self)
        return original(self, fname, *a, **kw)

    monkeypatch.setattr(Figure, "savefig", savefig)
    card = tmp_path / "card.csv"
    shutil.copy(CARD_FILE, card)
    out = tmp_path / "out"
    args = ["study", "run", "spatial-pump", "--json", "--out", str(out), "--set", f"card={card}"]
    for k, v in REDUCED.items():
        args += ["--set", f"{k}={v}"]
    assert main(args) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["success"] is True
    ch = data["checks"]
    # the ideal drive is the planar unit; the power balance closes; 5 and 0 self-stress states
    for joints in ("revolute", "spherical"):
        assert ch[f"ideal_{joints}_torque_vs_planar"] < 1e-9
        assert ch[f"ideal_{joints}_split"] < 1e-9
        assert ch[f"ideal_{joints}_rod_motion_vs_planar"] < 1e-9
        assert ch[f"power_balance_{joints}_built"] < 1e-9
        assert ch[f"loop_closure_{joints}_built_m"] < 1e-12
    assert (ch["self_stress_states_revolute"], ch["self_stress_states_spherical"]) == (5, 0)
    # as built: the redundant drive splits the load, the rational one only by its lever rule
    split = data["pitman_split_as_built"]
    assert split["revolute_peak"] > 0.03 and split["rational_peak"] < 0.01
    # the 10 kN between the pitmans needs under a degree of phase mismatch
    assert 0.3 < data["phase_mismatch_for_10kN_deg"] < 1.5
    assert abs(data["phase_mismatch_for_10kN_check_kN"] - 10.0) < 0.1
    # tolerances: every deviation limited in the redundant drive but the shaft's skew; in the
    # rational drive only the off-centre equalizer bearing (lever rule: w * limit / 4)
    tol = data["tolerances"]
    for name in ("phase_mismatch", "crank_difference", "pitman_difference", "shaft_tilt"):
        assert tol[name]["revolute"] is not None and tol[name]["rational"] is None
        assert abs(tol[name]["revolute_split"] - 0.05) < 1e-3
    assert abs(tol["equalizer_offset"]["rational"] - 1.2 * 0.05 / 4) < 1e-3
    # the counterbalance: certified optimum, loading under the 5600 kgf m rating
    for s in data["counterbalance"].values():
        assert s["success"] and s["certified"]
    assert all(0.3 < v < 1.0 for v in data["gearbox_loading"].values())
    names = {p.name for p in out.iterdir()}
    for f in ("card", "pitman_forces", "reactions", "torque", "elastic", "split_vs_deviation",
              "tolerance_chart", "design_chart"):  # fmt: skip
        assert f"spatial_pump_{f}.png" in names
    for f in ("cycle", "tolerances", "sweep", "tolerance_chart", "design_chart"):
        assert f"spatial_pump_{f}.csv" in names
    assert "spatial_pump.json" in names and "spatial_pump.gif" in names
    assert len(data["errata"]) >= 13
    assert any("Conclusion 2 contradicts the body" in e for e in data["errata"])
    # the paper's stated values are the ideal drive's: R12z = 0 and M_R12x = 0 to round-off
    st = data["paper_stated_values"]
    assert st["max_R12z_kN"]["ideal"] < 1e-9 and st["max_M_R12x_Nm"]["ideal"] < 1e-6
    assert abs(st["max_M_R12x_Nm"]["as_built"] - 525.6) < 1.0  # as built: 526 N m
    assert abs(st["max_R12z_kN"]["as_built"] - 0.458) < 0.002
    # wear clearance: a few mrad of play frees the pins; then the drive is the rational one
    c = data["clearance"]
    # the equalizer pins' 4.28 mrad (the crank pins' 0.69), as docs/spatial.md states
    assert abs(c["play_for_rational_mrad"] - 4.28) < 0.01
    assert abs(c["misfit_mrad"]["R12"] - 0.69) < 0.01
    assert abs(c["clearance_for_rational_mm"] - 0.428) < 0.001
    assert abs(c["freed_split"] - c["split_rational"]) < 1e-3
    assert c["freed_torque_vs_rational_Nm"] < 1.0
    assert c["splits"][0] > c["splits"][-1]
    assert (
        c["play_for_limit_mrad"] is None or c["play_for_limit_mrad"] < c["play_for_rational_mrad"]
    )
    for f in ("polished_rod", "clearance"):
        assert f"spatial_pump_{f}.png" in names
        assert found[f"spatial_pump_{f}.png"] == []
    assert "spatial_pump_coverage.csv" in names
    assert data["coverage"]["study"] == "spatial-pump"


@pytest.mark.parametrize(
    "setting, message",
    [
        ("card=/no/such/card.csv", "not found"),
        ("limit=1.5", "limit must be a fraction"),
        ("n_angles=2", "option n_angles must be >= 3, got 2"),
        ("phase_mismatch_deg=30", "not a small deviation"),
        ("spm=abc", "option spm (strokes/min) must be a finite number, got 'abc'"),
        ("sweep_points=1e9", "option sweep_points must be an integer"),
        ("stiffness_factors=1,-2", "must be positive"),
    ],
)
def test_bad_options_exit_1(setting, message, capsys):
    assert main(["study", "run", "spatial-pump", "--set", setting]) == 1
    assert message in capsys.readouterr().err


def test_options_are_listed(capsys):
    assert main(["study", "run", "spatial-pump", "--set", "help"]) == 0
    text = capsys.readouterr().out
    for opt in OPTION_UNITS:
        assert opt in text
