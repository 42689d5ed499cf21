"""``mechsynth synthesize path``: a run with its files (the design TOML read back by the design
and linkage readers), JSON, prescribed timing from a third column, and the one-line errors with
exit 1 on bad input."""

import json

import numpy as np
import pytest

from mechsynth.cli import main
from mechsynth.synthesis.path_cases import CASES, exact_case


def _csv(path, rows, header="x,y"):
    path.write_text(header + "\n" + "\n".join(",".join(repr(float(v)) for v in r) for r in rows))
    return path


def test_run_writes_files_and_a_design_the_readers_accept(tmp_path, capsys):
    f = _csv(tmp_path / "t.csv", CASES["bulatovic-12"].targets)
    out = tmp_path / "out"
    code = main(["synthesize", "path", str(f), "--min-transmission", "30deg", "--starts", "2",
                 "--out", str(out), "--quiet"])  # fmt: skip
    assert code == 0
    text = capsys.readouterr().out
    assert "distinct optima" in text and "path.png" in text
    for name in ("path.png", "solutions.csv", "positions.csv", "design.toml", "linkage.toml",
                 "result.json", "manifest.json"):  # fmt: skip
        assert (out / name).is_file(), name
    res = json.loads((out / "result.json").read_text())
    assert res["success"] and res["best"]["transmission_min"] >= np.deg2rad(30) - 1e-9
    # the TOML files give back the same linkage: same coupler point at the same angles
    from mechsynth.synthesis.design_file import load_design
    from mechsynth.synthesis.linkage_file import load_linkage

    angles = np.asarray(res["best"]["angles"])
    for lk in (load_design(out / "design.toml").design, load_linkage(out / "linkage.toml")):
        m = lk.motion(angles)
        d2 = (m.points["P"].x - CASES["bulatovic-12"].targets[:, 0]) ** 2 + (
            m.points["P"].y - CASES["bulatovic-12"].targets[:, 1]
        ) ** 2
        assert d2.sum() == pytest.approx(res["best"]["sum_squares"], rel=1e-9)
    rows = (out / "solutions.csv").read_text().splitlines()
    assert rows[0].startswith("rank,crank") and len(rows) >= 2


def test_json_and_prescribed_timing(tmp_path, capsys):
    pts, _, angles = exact_case()
    rows = np.column_stack([pts, np.rad2deg(angles)])
    f = _csv(tmp_path / "t.csv", rows, header="x,y,crank angle deg")
    code = main(["synthesize", "path", str(f), "--timing", "prescribed", "--starts", "4",
                 "--json"])  # fmt: skip
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    assert data["timing"] == "prescribed" and data["best"]["sum_squares"] < 1e-26
    np.testing.assert_allclose(np.diff(data["best"]["angles"]), np.diff(angles), atol=1e-12)


@pytest.mark.parametrize(
    "rows, extra, match",
    [
        ([(0, 0), (1, 0)], [], "at least 3 targets"),
        ([(0, 0), (1, 0), (1, 0), (0, 1)], [], "same point"),
        ([(0, 0), (1, float("nan")), (2, 1)], [], "not finite"),
        ([(0, 0, 1), (1, 0, 1), (2, 1, 1)], [], "expected 2 columns"),
        ([(0, 0), (1, 0), (2, 1)], ["--timing", "prescribed"], "expected 3 columns"),
        ([(0, 0), (1, 0), (2, 1)], ["--min-transmission", "30 mm"], "--min-transmission"),
        ([(0, 0), (1, 0), (2, 1)], ["--starts", "0"], "--starts"),
    ],
)
def test_bad_input_one_line_exit_1(tmp_path, capsys, rows, extra, match):
    f = tmp_path / "t.csv"
    f.write_text("x,y\n" + "\n".join(",".join(str(v) for v in r) for r in rows))
    code = main(["synthesize", "path", str(f), *extra])
    err = capsys.readouterr().err.strip()
    assert code == 1
    assert len(err.splitlines()) == 1 and err.startswith("mechsynth: error:") and match in err


def test_missing_file_and_help(tmp_path, capsys):
    assert main(["synthesize", "path", str(tmp_path / "none.csv")]) == 1
    assert "mechsynth: error:" in capsys.readouterr().err
    with pytest.raises(SystemExit) as exc:
        main(["synthesize", "path", "--help"])
    assert exc.value.code == 0
    assert "--min-transmission" in capsys.readouterr().out


SIX_TOML = """
trace = "P"
[linkage]
name = "six-bar"
output = "P"
[ground]
O = [0, 0]
D = [1.0, 0.1]
E = [0.2, 1.2]
[[group]]
type = "crank"
point = "A"
about = "O"
length = 0.25
[[group]]
type = "rrr"
point = "B"
first = ["A", 0.9]
second = ["D", 0.7]
[[group]]
type = "attach"
point = "C"
on = ["A", "B"]
along = 0.4
left = 0.3
[[group]]
type = "rrr"
point = "F"
first = ["C", 0.85]
second = ["E", 0.65]
[[group]]
type = "attach"
point = "P"
on = ["C", "F"]
along = "450 mm"
left = -0.15
[variables]
CF = [0.5, 1.1]
EF = [0.4, 1.0]
P_along = [0, 1]
P_left = [-0.5, 0.5]
E_x = ["-200 mm", 0.6]
"""


def test_linkage_file_mechanism(tmp_path, capsys):
    from mechsynth.synthesis.design_file import load_design

    toml = tmp_path / "six.toml"
    toml.write_text(SIX_TOML)
    import mechsynth as ms

    true = (
        ms.Linkage(ground={"O": (0, 0), "D": (1.0, 0.1), "E": (0.2, 1.2)})
        .crank("A", about="O", length=0.25)
        .rrr("B", ("A", 0.9), ("D", 0.7))
        .attach("C", on=("A", "B"), along=0.4, left=0.3)
        .rrr("F", ("C", 0.8), ("E", 0.7))
        .attach("P", on=("C", "F"), along=0.5, left=-0.2)
    )
    phi = np.array([0.2, 0.9, 1.6, 2.4, 3.1, 3.9, 4.6, 5.3, 5.9])
    m = true.motion(phi)
    f = _csv(tmp_path / "t.csv", np.column_stack([m.points["P"].x, m.points["P"].y]))
    out = tmp_path / "out"
    code = main(["synthesize", "path", str(f), "--mechanism", str(toml), "--starts", "6",
                 "--out", str(out), "--json"])  # fmt: skip
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    assert data["best"]["sum_squares"] < 1e-26 and data["best"]["CF"] == pytest.approx(0.8)
    design = load_design(out / "design.toml").design
    assert design.parameters["EF"] == pytest.approx(0.7)
    assert not (out / "linkage.toml").exists()


def test_linkage_file_without_variables(tmp_path, capsys):
    toml = tmp_path / "six.toml"
    toml.write_text(SIX_TOML.split("[variables]")[0])
    f = _csv(tmp_path / "t.csv", [(0, 0), (1, 0), (1, 1)])
    assert main(["synthesize", "path", str(f), "--mechanism", str(toml)]) == 1
    assert "[variables]" in capsys.readouterr().err
    assert main(["synthesize", "path", str(f), "--mechanism", "cam"]) == 1
    assert "--mechanism must be" in capsys.readouterr().err


def test_measure_constraint_on_the_command_line(tmp_path, capsys):
    f = _csv(tmp_path / "t.csv", CASES["bulatovic-12"].targets)
    code = main(["synthesize", "path", str(f), "--constraint", "max_pressure_angle <= 50 deg",
                 "--starts", "4", "--json"])  # fmt: skip
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    assert data["best"]["transmission_min"] >= np.deg2rad(40) - 1e-6
    assert main(["synthesize", "path", str(f), "--constraint", "stroke <= 3 deg"]) == 1
    assert "mechsynth: error:" in capsys.readouterr().err


def test_shape_timing_on_the_command_line(tmp_path, capsys):
    f = _csv(tmp_path / "t.csv", CASES["bulatovic-12"].targets)
    code = main(["synthesize", "path", str(f), "--timing", "shape", "--starts", "1", "--json"])
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    assert data["timing"] == "shape" and "Fourier" in data["error_definition"]
    assert data["best"]["sum_squares"] < 1e-2  # the polygon of 12 points, not the points
