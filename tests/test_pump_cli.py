"""``mechsynth pump analyze`` and the beam-pump optimize example."""

import json
from pathlib import Path

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.cli import main
from mechsynth.machines.pumping_unit import BeamPumpingUnit
from mechsynth.studies.beam_pump import base_design, variants
from mechsynth.synthesis.problem_file import load_problem

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
UNIT = EXAMPLES / "pump_unit_c320.toml"
CARD = EXAMPLES / "pump_card.csv"
GEOM = "units = \"m\"\nA = 3\nC = 2.5\nI = 2.5\nP = 3.2\nR = 0.8\nH = 5\nG = 1.8\n"


def run(capsys, *argv):
    rc = main(list(argv))
    out = capsys.readouterr()
    return rc, out


def test_analyze_json_oilfield_and_si(capsys):
    rc, out = run(capsys, "pump", "analyze", str(UNIT), "--json")
    assert rc == 0
    d = json.loads(out.out)
    u = BeamPumpingUnit.from_api(A=155.0, C=111.06, I=111.02, P=132.01, R=42.01, H=231.97,
                                 G=95.98, units="in")  # fmt: skip
    assert d["units"]["length"] == "in"
    assert d["stroke"] == pytest.approx(ms.to_inch(u.stroke), rel=1e-12)
    assert d["upstroke_span_deg"] + d["downstroke_span_deg"] == pytest.approx(360.0)
    rc, out = run(capsys, "pump", "analyze", str(UNIT), "--json", "--units", "si")
    s = json.loads(out.out)
    assert s["stroke"] == pytest.approx(float(u.stroke), rel=1e-12)
    assert s["max_torque_factor"] == pytest.approx(d["max_torque_factor"] * 0.0254, rel=1e-12)
    assert s["peak_acceleration"] == pytest.approx(d["peak_acceleration"] * 0.0254, rel=1e-12)


def test_analyze_with_card_writes_files(capsys, tmp_path):
    rc, out = run(capsys, "pump", "analyze", str(UNIT), "--card", str(CARD), "--out",
                  str(tmp_path))  # fmt: skip
    assert rc == 0
    assert "optimal counterbalance" in out.out
    d = json.loads((tmp_path / "pump_analysis.json").read_text())
    c = d["card"]
    assert d["success"] and c["counterbalance_status"] == "optimal"
    assert c["scan_peak_net_torque"] == pytest.approx(c["peak_net_torque"], rel=1e-6)
    assert c["peak_net_torque"] < c["peak_torque_without_counterbalance"]
    assert 0 < c["gearbox_loading_percent"] < 100
    curve = c["torque_curve_15deg"]
    assert [r["crank_angle_deg"] for r in curve] == pytest.approx(np.arange(0, 360, 15))
    assert max(abs(r["net_torque"]) for r in curve) <= c["peak_net_torque"] * (1 + 1e-12)
    for name in ("polished_rod.png", "torque.png", "permissible_load.png", "torque_curve.csv",
                 "torque_factor_table.csv"):  # fmt: skip
        assert (tmp_path / name).stat().st_size > 0
    rows = (tmp_path / "torque_factor_table.csv").read_text().splitlines()
    assert len(rows) == 25


@pytest.mark.parametrize(
    "text,match",
    [
        (GEOM + "spm = 5\nfoo = 1\n", "unknown keys"),
        (GEOM + "", "missing spm"),
        (GEOM + "spm = -5\n", "spm must be"),
        (GEOM.replace("A = 3", "A = 'x'") + "spm = 5\n", "A must be"),
        # API 11E tables are in inches: a file without its unit must not be read as metres
        (GEOM.replace('units = "m"\n', "") + "spm = 5\n", "units is required: 'in'"),
        (GEOM.replace('units = "m"', 'units = "mm"') + "spm = 5\n", "units must be 'm' or 'in'"),
    ],
)
def test_bad_unit_files_exit_1(capsys, tmp_path, text, match):
    p = tmp_path / "u.toml"
    p.write_text(text)
    rc, out = run(capsys, "pump", "analyze", str(p))
    assert rc == 1 and match in out.err


def test_bad_card_exits_1(capsys, tmp_path):
    p = tmp_path / "card.csv"
    p.write_text("0,1\n1,2\n")
    rc, out = run(capsys, "pump", "analyze", str(UNIT), "--card", str(p))
    assert rc == 1 and "at least 8" in out.err


def test_help(capsys):
    with pytest.raises(SystemExit) as e:
        main(["pump", "analyze", "--help"])
    assert e.value.code == 0
    assert "--card" in capsys.readouterr().out


def test_study_listed(capsys):
    rc, out = run(capsys, "study", "list", "--json")
    assert "beam-pump" in json.loads(out.out)


def test_optimize_example_beats_the_axial_unit(capsys, tmp_path):
    path = EXAMPLES / "optimize_beam_pump.toml"
    spec = load_problem(path)
    assert spec.problem.mechanism is BeamPumpingUnit
    assert spec.problem.fixed["unit_class"] == "mark-ii"
    assert spec.problem.speed == pytest.approx(ms.spm(6.0))
    rc, out = run(capsys, "optimize", str(path), "--json", "--starts", "2")
    d = json.loads(out.out)
    assert rc == 0 and d["success"]
    # the axial unit of paper 000 meets the same stroke, pressure-angle and TF limits, so the
    # certified optimum can be no worse
    axial = variants(base_design())[0]["axial"]
    m = axial.motion(ms.cycle(2048), speed=ms.spm(6.0))
    assert np.rad2deg(m.pressure_angle.max()) <= 30.0
    assert d["value"] <= np.abs(m.polished_rod.acceleration).max()


def test_inertia_and_speed_fluctuation(capsys, tmp_path):
    p = tmp_path / "u.toml"
    p.write_text(
        UNIT.read_text()
        + "beam_inertia_kgm2 = 60000.0\ncrank_inertia_kgm2 = 15000.0\nspeed_fluctuation = 0.2\n"
    )
    rc, out = run(capsys, "pump", "analyze", str(p), "--card", str(CARD), "--json")
    assert rc == 0
    c = json.loads(out.out)["card"]
    assert c["peak_inertia_torque"] > 0
    assert c["scan_peak_net_torque"] == pytest.approx(c["peak_net_torque"], rel=1e-6)
    p.write_text(UNIT.read_text() + "speed_fluctuation = 3.0\n")
    rc, out = run(capsys, "pump", "analyze", str(p))
    assert rc == 1 and "fluctuation" in out.err
