"""``mechsynth synthesize motion``: files, JSON, exit codes and one-line errors."""

from __future__ import annotations

import json
import tomllib

import numpy as np
import pytest
from test_motion_generation import POSES5, POSES_0  # noqa: I001

from mechsynth.cli import main
from mechsynth.synthesis.design_file import load_design
from mechsynth.synthesis.linkage_file import load_linkage
from mechsynth.synthesis.motion_generation import pose_errors


def _csv(path, poses, header="x [m],y [m],angle [deg]", deg=True):
    rows = [header]
    for x, y, a in np.asarray(poses, float).tolist():
        rows.append(f"{x!r},{y!r},{float(np.degrees(a)) if deg else a!r}")
    path.write_text("\n".join(rows) + "\n")
    return path


def test_five_poses_write_figure_csv_and_design_files(tmp_path, capsys):
    f = _csv(tmp_path / "poses.csv", POSES5)
    out = tmp_path / "out"
    assert main(["synthesize", "motion", str(f), "--out", str(out), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["success"] is True and len(data["burmester"]["burmester_points"]) == 4
    assert max(data["pose_error"]["position_m"]) < 1e-9
    names = {p.name for p in out.iterdir()}
    assert {"motion.png", "candidates.csv", "linkage.toml", "design.toml", "manifest.json"} <= names
    # the design file is what 'mechsynth animate' reads; the linkage takes the poses
    spec = load_design(out / "design.toml")
    assert spec.trace == ("P",)
    pos, ang = pose_errors(spec.design, POSES5)
    assert pos.max() < 1e-9 and ang.max() < 1e-9
    assert load_linkage(out / "linkage.toml").parameters == spec.design.parameters
    header = (out / "candidates.csv").read_text().splitlines()[0]
    assert header.startswith("rank,kind,defects,grashof,min transmission angle [deg]")
    manifest = json.loads((out / "manifest.json").read_text())
    assert len(manifest["files"]) == 4


def test_text_report_and_units_in_the_header(tmp_path, capsys):
    poses = np.asarray(POSES5).copy()
    poses[:, :2] *= 1000.0
    f = tmp_path / "poses.csv"
    f.write_text(
        "angle_rad,x_mm,y [mm]\n"
        + "".join(f"{a!r},{x!r},{y!r}\n" for x, y, a in poses.tolist())
    )  # fmt: skip
    assert main(["synthesize", "motion", str(f)]) == 0
    out = capsys.readouterr().out
    assert "Burmester points: 4 real" in out and "defects: none" in out


def test_four_poses_with_centres(tmp_path, capsys):
    f = _csv(tmp_path / "poses.csv", POSES5[:4])
    from test_motion_generation import _pivots, FB, PHI5  # noqa: I001

    o1, _, o2, _ = (p.tolist() for p in _pivots(FB, PHI5[0]))
    rc = main(["synthesize", "motion", str(f), "--json",
               "--centres", f"{o1[0]!r},{o1[1]!r}", f"{o2[0]!r},{o2[1]!r}"])  # fmt: skip
    data = json.loads(capsys.readouterr().out)
    assert rc == 0 and len(data["candidates"]) == 2
    assert data["candidates"][0]["defects"] == []


def test_optimize_more_poses_than_the_exact_theory(tmp_path, capsys):
    from test_motion_generation import FB, _poses_of  # noqa: I001

    poses = _poses_of(FB, np.radians([10.0, 55.0, 110.0, 170.0, 230.0, 290.0]))
    poses[5, :2] += 0.02
    f = _csv(tmp_path / "poses.csv", poses)
    out = tmp_path / "out"
    rc = main(["synthesize", "motion", str(f), "--optimize", "--json", "--out", str(out)])
    data = json.loads(capsys.readouterr().out)
    assert rc == 0 and data["optimize"]["mode"] == "error"
    import mechsynth as ms
    from mechsynth.synthesis.motion_generation import pose_error_measure

    start = pose_error_measure(poses).fn(ms.motion_generation(poses[:5]).best.linkage)
    assert data["optimize"]["value"] < 0.5 * start
    tomllib.loads((out / "linkage.toml").read_text())


@pytest.mark.parametrize(
    "text, match",
    [
        ("a,b,c\n1,2,3\n", "unknown column 'a'"),
        ("x,y,angle\n0,0,0\n1,0,1\n", "needs its unit"),
        ("x,y,angle [furlong]\n0,0,0\n", "unknown unit"),
        ("x,y\n0,0\n", "name x, y and angle"),
        ("x,y,angle [deg]\n0,0,0\n1,nan,3\n", "finite"),
        ("x,y,angle [deg]\n0,0,0\n1,abc,3\n", "not numbers"),
        ("x,y,angle [deg]\n0,0,0\n1,2\n", "row 3 has 2 values"),
        ("x,y,angle [deg]\n0,0,0\n", "at least 2"),
        ("x,y,angle [deg]\n0,0,10\n0,0,10\n", "coincide"),
        ("x,y,angle [deg]\n" + "".join(f"{i},{i * i},{10 * i}\n" for i in range(6)), "--optimize"),
        ("", "empty"),
    ],
)
def test_bad_input_exits_1_with_one_line(tmp_path, capsys, text, match):
    f = tmp_path / "poses.csv"
    f.write_text(text)
    assert main(["synthesize", "motion", str(f)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("mechsynth: error:") and match in err[0]


def test_bad_options_exit_1(tmp_path, capsys):
    f = _csv(tmp_path / "poses.csv", POSES5)
    for extra, match in (
        (["--centres", "1;2"], "expected X,Y"),
        (["--candidate", "99"], "--candidate must be 1 to"),
        (["--tol", "-1"], "--tol must be a positive"),
        (["--centres", "50,50", "60,60"], "not a Burmester point"),
    ):
        assert main(["synthesize", "motion", str(f), *extra]) == 1
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and match in err[0], err


def test_no_real_burmester_points_exits_2(tmp_path, capsys):
    f = _csv(tmp_path / "poses.csv", POSES_0)
    assert main(["synthesize", "motion", str(f), "--json"]) == 2
    data = json.loads(capsys.readouterr().out)
    assert data["success"] is False and "0 real Burmester point" in data["message"]


def test_help_lists_the_options(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["synthesize", "motion", "--help"])
    assert exc.value.code == 0
    text = capsys.readouterr().out
    for opt in ("--out", "--json", "--centres", "--optimize", "--candidate"):
        assert opt in text


def test_example_poses_file_gives_back_its_crank_rocker(capsys):
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "examples" / "motion_poses.csv"
    assert main(["synthesize", "motion", str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    # the crank-rocker the file's comment names (its poses written to 1e-6 mm and deg)
    lengths = [sorted(c["parameters"][k] for k in ("OA", "AB", "DB")) for c in data["candidates"]]
    assert any(np.allclose(v, [0.12, 0.30, 0.35], atol=1e-7) for v in lengths)


@pytest.mark.slow
def test_optimize_five_poses_raises_the_transmission_angle(tmp_path, capsys):
    f = _csv(tmp_path / "poses.csv", POSES5)
    out = tmp_path / "out"
    rc = main(["synthesize", "motion", str(f), "--optimize", "--tol", "0.05", "--starts", "1",
               "--json", "--out", str(out)])  # fmt: skip
    data = json.loads(capsys.readouterr().out)
    assert rc == 0 and data["optimize"]["mode"] == "transmission"
    exact = data["candidates"][0]["min_transmission_deg"]
    assert np.degrees(data["optimize"]["value"]) > exact
    # the written design is the refined one and still takes the poses within the tolerance
    from mechsynth.synthesis.motion_generation import pose_error_measure

    refined = load_linkage(out / "linkage.toml")
    assert pose_error_measure(POSES5).fn(refined) <= 0.05 + 1e-6
    start = data["candidates"][0]["parameters"]
    assert max(abs(refined.parameters[k] - v) for k, v in start.items()) > 1e-3
