"""``mechsynth synthesize function``: files, JSON, exit codes and one-line errors."""

from __future__ import annotations

import json

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.cli import main

LOG = [
    "synthesize", "function", "--function", "log10(x)", "--x", "1", "10",
    "--input-range", "60deg", "--output-range", "90 deg", "--phases", "120deg", "20deg",
]  # fmt: skip


def test_writes_files_and_prints_json(tmp_path, capsys):
    assert main([*LOG, "--out", str(tmp_path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["method"] == "exact" and data["success"] is True
    names = {p.name for p in tmp_path.iterdir()}
    assert {"design.toml", "error.csv", "precision_points.csv", "result.json", "error.png",
            "manifest.json"} <= names  # fmt: skip
    phases = (ms.deg(120), ms.deg(20))
    fg = ms.function_generation(
        "log10(x)", x=(1, 10), input_range=ms.deg(60), output_range=ms.deg(90), phases=phases
    )
    assert data["max_error"] == pytest.approx(fg.max_error, rel=1e-12)
    rows = np.loadtxt(tmp_path / "error.csv", delimiter=",", skiprows=1)
    assert rows.shape == (401, 3) and np.allclose(rows[:, 1], fg.error)


def test_summary_and_optimize(capsys):
    assert main([*LOG, "--points", "4", "--optimize"]) == 0
    out = capsys.readouterr().out
    assert "min-max" in out and "max error before the min-max stage" in out


def test_slider_crank_and_pairs_file(tmp_path, capsys):
    args = ["synthesize", "function", "--function", "x^2", "--x", "0", "1", "--input-range",
            "120deg", "--output-range", "500 mm", "--mechanism", "slider-crank", "--phases",
            "120deg", "--json"]  # fmt: skip
    assert main(args) == 0
    assert json.loads(capsys.readouterr().out)["design"]["crank"] == 1.0
    fb = ms.FourBar(1.0, 3.5, 3.0, 4.0, "open", False)
    phi = np.array([0.3, 0.9, 1.4])
    psi = fb.motion(phi).links["rocker"].angle
    f = tmp_path / "pairs.csv"
    lines = [f"{float(a)!r},{float(b)!r}" for a, b in zip(phi, psi)]
    f.write_text("phi,psi\n" + "\n".join(lines) + "\n")
    assert main(["synthesize", "function", "--pairs", str(f), "--ground", "4", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["design"]["coupler"] == pytest.approx(3.5, 1e-9)


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--function", "log10(x"], "cannot be parsed"),
        (["--function", "open('f')"], "unknown function"),
        (["--x", "0", "10"], "not finite"),
        (["--input-range", "400deg"], "below 360 deg"),
        (["--spacing", "2,2,5"], "two equal precision points"),
        (["--spacing", "2,a"], "--spacing"),
        (["--output-range", "90 mm"], "--output-range"),
        (["--phases", "1deg"], "--phases takes 2 angles"),
        (["--phases", "45deg", "120deg"], "no valid design for these phases"),
    ],
)
def test_bad_input_exits_1_with_one_line(extra, message, capsys):
    args = list(LOG)
    for i in range(0, len(extra), 1):
        if extra[i].startswith("--") and extra[i] in args:
            j = args.index(extra[i])
            k = j + 1
            while k < len(args) and not args[k].startswith("--"):
                k += 1
            del args[j:k]
    assert main([*args, *extra]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("mechsynth: error:") and message in err[0]


def test_missing_and_bad_pairs(tmp_path, capsys):
    assert main(["synthesize", "function", "--x", "1", "2"]) == 1
    assert "--function" in capsys.readouterr().err
    bad = tmp_path / "bad.csv"
    bad.write_text("a,b\n1,2\nx,y\n")
    assert main(["synthesize", "function", "--pairs", str(bad)]) == 1
    assert "line 3" in capsys.readouterr().err
    assert main(["synthesize", "function", "--pairs", str(tmp_path / "none.csv")]) == 1


def test_help(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["synthesize", "function", "--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    assert "--input-range" in out and "--optimize" in out and "--json" in out
