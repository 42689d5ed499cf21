"""``mechsynth optimize``, problem files, and the optimize examples (every one is run)."""

import json
import runpy
from pathlib import Path

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.cli import main
from mechsynth.synthesis.problem_file import (
    load_problem,
    parse_constraint,
    parse_measure,
    parse_quantity,
)

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
TOMLS = sorted(EXAMPLES.glob("optimize_*.toml"))
SCRIPTS = sorted(EXAMPLES.glob("optimize_*.py"))


def test_examples_exist():
    assert len(TOMLS) >= 2 and len(SCRIPTS) >= 2


@pytest.mark.parametrize("path", TOMLS, ids=lambda p: p.name)
def test_example_problem_files(path, tmp_path, capsys):
    rc = main(["optimize", str(path), "--out", str(tmp_path), "--json"])
    data = json.loads(capsys.readouterr().out)
    assert rc == 0, data["message"]
    assert data["success"] and data["status"] == "optimal"
    assert data["certification"]["certified"]
    saved = json.loads((tmp_path / "result.json").read_text())
    assert saved["value"] == pytest.approx(data["value"])
    assert (tmp_path / "optimum.png").stat().st_size > 10_000
    assert "status: optimal" in (tmp_path / "report.txt").read_text()


@pytest.mark.parametrize("path", SCRIPTS, ids=lambda p: p.name)
def test_example_scripts(path, tmp_path, capsys):
    ns = runpy.run_path(str(path))
    out = ns["main"](str(tmp_path))
    res = out[0] if isinstance(out, tuple) else out
    assert res.success
    assert list(tmp_path.glob("*.png"))
    assert "certified: True" in capsys.readouterr().out


def test_toml_and_python_agree():
    spec = load_problem(EXAMPLES / "optimize_slider_crank.toml")
    assert spec.problem.speed == pytest.approx(ms.rpm(600))
    assert spec.problem.variables["rod"] == pytest.approx((0.05, 0.2))
    assert [c.name for c in spec.problem.constraints] == [
        "stroke(slider) == 0.1",
        f"max_pressure_angle <= {np.deg2rad(30):g}",
    ]
    assert spec.solve_options == {"method": "ipopt", "starts": 6, "seed": 1}


def test_infeasible_problem_file_exits_2(tmp_path, capsys):
    f = tmp_path / "p.toml"
    f.write_text(
        'mechanism = "slider-crank"\n'
        'minimize = "peak_velocity(slider)"\n'
        'constraints = ["stroke >= 500 mm"]\n'
        "starts = 2\n"
        "[variables]\n"
        "crank = [0.01, 0.1]\n"
        "rod = [0.3, 0.5]\n"
        "[fixed]\n"
        "offset = 0.0\n"
    )
    rc = main(["optimize", str(f), "--out", str(tmp_path / "out")])
    out = capsys.readouterr().out
    assert rc == 2
    assert "status: infeasible" in out and "stroke(slider) >= 0.5" in out
    data = json.loads((tmp_path / "out" / "result.json").read_text())
    assert data["success"] is False
    assert [c["name"] for c in data["constraints"] if not c["satisfied"]] == [
        "stroke(slider) >= 0.5"
    ]


def test_bad_problem_file_exits_1(tmp_path, capsys):
    f = tmp_path / "p.toml"
    f.write_text(
        'mechanism = "slider-crank"\nminimize = "peak_jerk(slider)"\n'
        "[variables]\ncrank = [0.01, 0.1]\nrod = [0.3, 0.5]\n"
    )
    assert main(["optimize", str(f)]) == 1
    assert "unknown measure 'peak_jerk'" in capsys.readouterr().err


def test_parsers():
    assert parse_quantity("30 deg") == pytest.approx(np.pi / 6)
    assert parse_quantity("100 mm") == pytest.approx(0.1)
    assert parse_quantity(2) == 2.0
    with pytest.raises(ValueError, match="unknown unit"):
        parse_quantity("3 furlong")
    m = parse_measure("peak_velocity(A, direction=90 deg)")
    assert m.point == "A" and m.direction == pytest.approx(np.pi / 2)
    c = parse_constraint(
        {"measure": "stroke", "args": ["slider"], "op": "==", "value": 100, "unit": "mm"}
    )
    assert c.bound == pytest.approx(0.1) and c.op == "=="
    with pytest.raises(ValueError, match="cannot read the constraint"):
        parse_constraint("stroke = 0.1")
    with pytest.raises(ValueError, match="top-level keys first"):
        load_problem({"mechanism": "four-bar", "maximize": "time_ratio", "extra": 1})


def test_help_lists_optimize(capsys):
    with pytest.raises(SystemExit):
        main(["optimize", "--help"])
    assert "--out" in capsys.readouterr().out
