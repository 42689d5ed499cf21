"""The command line's animate command, optimize --animate, --units and --quiet."""

import json
from pathlib import Path

import pytest
from PIL import Image

from mechsynth import display
from mechsynth.cli import main

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.mark.parametrize(
    "name",
    [
        "design_slider_crank",
        "design_dwell",
        "design_nail_header",
        "design_six_link",
        "design_impact_six_link",
        "pump_unit_c320",
    ],
)
def test_animate_writes_a_still_and_a_gif(name, tmp_path, capsys):
    rc = main(
        ["animate", str(EXAMPLES / f"{name}.toml"), "--out", str(tmp_path), "--frames", "6"]
        + ["--dpi", "30", "--json"]
    )
    assert rc == 0
    data = json.loads(capsys.readouterr().out)
    assert data["frames"] == 6
    still, gif = (Path(f) for f in data["files"])
    assert still.suffix == ".png" and still.stat().st_size > 0
    with Image.open(gif) as im:
        assert im.n_frames == 6


def test_animate_prints_in_display_units(tmp_path, capsys):
    rc = main(
        ["animate", str(EXAMPLES / "design_slider_crank.toml"), "--out", str(tmp_path)]
        + ["--frames", "4", "--dpi", "30", "--units", "mm-deg"]
    )
    assert rc == 0
    out = capsys.readouterr().out
    assert "crank 70 mm, rod 240 mm, offset 10 mm" in out and "slowed x" in out
    assert display.current().name == "si"  # the CLI's setting does not leak


@pytest.mark.parametrize(
    "text, message",
    [
        ('mechanism = "slider-crank"\n[design]\ncrank = 0.07\n', "must give rod"),
        ('mechanism = "slider-crank"\n[design]\ncrank = 0.07\nrod = 0.2\nwheel = 1\n', "wheel"),
        ('mechanism = "cam"\n[design]\n', "mechanism must be one of"),
        ('mechanism = "slider-crank"\n[design]\ncrank = 0.2\nrod = 0.1\n', "full turn"),
        ('mechanism = "slider-crank"\ntrace = "B"\n[design]\ncrank = 0.1\nrod = 0.3\n', "trace"),
        ('mechanism = "slider-crank"\nminimize = "stroke"\n', "optimize FILE --animate"),
        ("mechanism = [", "not valid TOML"),
    ],
)
def test_animate_bad_design_files_fail_in_one_line(text, message, tmp_path, capsys):
    f = tmp_path / "d.toml"
    f.write_text(text)
    rc = main(["animate", str(f), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 1 and message in err and len(err.strip().splitlines()) == 1


def test_animate_needs_out_and_sane_options(tmp_path, capsys):
    f = str(EXAMPLES / "design_slider_crank.toml")
    assert main(["animate", f]) == 1
    assert "give --out DIR" in capsys.readouterr().err
    assert main(["animate", f, "--out", str(tmp_path), "--frames", "1"]) == 1
    assert "--frames" in capsys.readouterr().err
    assert main(["animate", str(tmp_path / "missing.toml"), "--out", str(tmp_path)]) == 1


def test_optimize_animate_writes_the_optimum_moving(tmp_path, capsys):
    out = tmp_path / "opt"
    rc = main(
        ["optimize", str(EXAMPLES / "optimize_slider_crank.toml"), "--starts", "1", "--out"]
        + [str(out), "--animate", "--units", "mm-deg", "--quiet"]
    )
    assert rc == 0
    text = capsys.readouterr().out
    assert "stroke(slider) == 100 mm" in text and "max_pressure_angle <= 30 deg" in text
    with Image.open(out / "optimum.gif") as im:
        assert im.n_frames == 48
    assert main(["optimize", str(EXAMPLES / "optimize_slider_crank.toml"), "--animate"]) == 1
    assert "--out" in capsys.readouterr().err
