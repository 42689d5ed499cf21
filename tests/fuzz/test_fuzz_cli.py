"""Fuzz the command line: a table of hostile files and arguments through every command, each
required to end with exit 0, 1 (one line on stderr) or 2 -- never a traceback, never exit 3
(an internal error). Run in process (``mechsynth.cli.main``) for speed; the subprocess exit
codes are tested in ``tests/test_files_and_exit_codes.py``."""

from pathlib import Path

import pytest

from mechsynth.cli import main

ROOT = Path(__file__).resolve().parents[2]
EX = ROOT / "examples"

PROBLEM = (
    'mechanism = "slider-crank"\nminimize = "peak_acceleration(slider)"\nstarts = 1\n'
    "[variables]\ncrank = [0.01, 0.1]\nrod = [0.2, 0.4]\n"
)
DESIGN = 'mechanism = "slider-crank"\n[design]\ncrank = 0.07\nrod = 0.24\n'

#: (name, file text or None for an example file, command with {f} for the file)
FILES = {
    "empty": "",
    "binary": bytes(range(256)),
    "not-toml": "[[[ this is not toml",
    "latin1": "title = 'caf\xe9'\n".encode("latin-1"),
    "deep": "x = " + "[" * 200 + "]" * 200 + "\n",
    "huge-number": "mechanism = 1e999\n",
    "table-as-string": 'mechanism = "slider-crank"\nvariables = "crank"\n',
    "list-mechanism": 'mechanism = ["slider-crank"]\n',
    "objective-42": 'mechanism = "slider-crank"\nminimize = 42\n',
    "both-senses": PROBLEM.replace("starts = 1", 'maximize = "stroke(slider)"'),
    "starts-float": PROBLEM.replace("starts = 1", "starts = 2.5"),
    "starts-true": PROBLEM.replace("starts = 1", "starts = true"),
    "starts-huge": PROBLEM.replace("starts = 1", "starts = 1000000000"),
    "angles-huge": PROBLEM.replace("starts = 1", "angles = 1e9"),
    "angles-list": PROBLEM.replace("starts = 1", "angles = [1, 2]"),
    "speed-length": PROBLEM.replace("starts = 1", 'speed = "600 m"'),
    "speed-inf": PROBLEM.replace("starts = 1", "speed = inf"),
    "stroke-deg": PROBLEM.replace("starts = 1", 'constraints = ["stroke(slider) == 5 deg"]'),
    "angle-mm": PROBLEM.replace("starts = 1", 'constraints = ["max_pressure_angle <= 3 mm"]'),
    "bad-kwarg": PROBLEM.replace("starts = 1", 'constraints = ["stroke(slider, x=1) == 0.1"]'),
    "unknown-measure": PROBLEM.replace("peak_acceleration(slider)", "nope"),
    "slider-of-four-bar": 'mechanism = "four-bar"\nminimize = "peak_acceleration(slider)"\n'
    "[variables]\ncrank = [0.1, 0.3]\ncoupler = [2, 3]\nrocker = [2, 3]\n[fixed]\nground = 3\n",
    "negative-bound": PROBLEM.replace("crank = [0.01, 0.1]", "crank = [-0.1, 0.1]"),
    "reversed-bound": PROBLEM.replace("crank = [0.01, 0.1]", "crank = [0.1, 0.01]"),
    "string-bound": PROBLEM.replace("crank = [0.01, 0.1]", 'crank = ["a", "b"]'),
    "nan-bound": PROBLEM.replace("crank = [0.01, 0.1]", "crank = [nan, 0.1]"),
    "unknown-key": PROBLEM + "colour = 1\n",
    "no-valid-design": PROBLEM.replace("rod = [0.2, 0.4]", "rod = [0.02, 0.04]"),
    "design-bad": DESIGN.replace("0.24", "0.01"),
    "design-string": DESIGN.replace("0.24", '"long"'),
    "design-unknown": DESIGN + "speed = 3\nwhat = 1\n",
    "unit-negative": (EX / "pump_unit_c320.toml").read_text().replace("R = 42.01", "R = -42"),
    "unit-spm": (EX / "pump_unit_c320.toml").read_text().replace("spm = 8.0", "spm = 1e300"),
    "unit-string": (EX / "pump_unit_c320.toml").read_text().replace("A = 155.00", 'A = "x"'),
}

CARDS = {
    "card-text": "position,load\nx,y\n1,2\n",
    "card-short": "0,1\n1,2\n",
    "card-nan": "\n".join(f"{i},{'nan' if i == 3 else 100}" for i in range(20)),
    "card-negative": (EX / "pump_card.csv").read_text().replace("7200.0", "-7200.0"),
    "card-reversed": "\n".join((EX / "pump_card.csv").read_text().splitlines()[:0:-1]),
    "card-three-columns": "0,1,2\n" * 10,
}

COMMANDS = [
    ["optimize", "{f}", "--starts", "1", "--quiet"],
    ["animate", "{f}", "--out", "{out}", "--frames", "4", "--dpi", "20"],
    ["pump", "analyze", "{f}"],
    ["chart", "linkage", "--set", "file={f}", "--set", "n=3"],
    ["synthesize", "function", "--pairs", "{f}"],
    ["synthesize", "motion", "{f}", "--quiet"],
]

ARGS = [
    ["optimize", str(EX / "optimize_slider_crank.toml"), "--starts", "0"],
    ["optimize", str(EX / "optimize_slider_crank.toml"), "--starts", "x"],
    ["optimize", str(EX / "optimize_slider_crank.toml"), "--method", "newton"],
    ["optimize", str(EX / "optimize_slider_crank.toml"), "--out", ""],
    ["optimize", "/nonexistent/file.toml"],
    ["animate", str(EX / "design_slider_crank.toml"), "--frames", "0", "--out", "{out}"],
    ["animate", str(EX / "design_slider_crank.toml"), "--angle", "nan", "--out", "{out}"],
    ["animate", str(EX / "design_slider_crank.toml"), "--dpi", "100000", "--out", "{out}"],
    ["animate", str(EX / "design_slider_crank.toml")],
    ["study", "run", "nope"],
    ["study", "run", "dwell", "--set", "min_scale=0"],
    ["study", "run", "dwell", "--set", "n=-1"],
    ["study", "run", "nail-header", "--set", "scan_step=0"],
    ["study", "run", "beam-pump", "--set", "n_angles=0"],
    ["study", "run", "extreme-velocity", "--set", "=3"],
    ["study", "run", "extreme-velocity", "--set", "noequals"],
    ["chart", "nope"],
    ["chart", "slider-crank", "--set", "n=1,2"],
    ["chart", "slider-crank", "--set", "n=100000000"],
    ["chart", "dwell", "--set", "gamma_deg=nan"],
    ["chart", "linkage"],
    ["pump", "analyze", str(EX / "pump_unit_c320.toml"), "--card", "/nonexistent.csv"],
    ["pump", "analyze", str(EX / "pump_unit_c320.toml"), "--units", "furlongs"],
    ["--units", "si"],
    [],
    ["optimize", "--bogus"],
    ["synthesize", "function", "--function", "log10(x)", "--x", "0", "10", "--input-range",
     "60deg", "--output-range", "90deg"],  # fmt: skip
    ["synthesize", "function", "--function", "x.real", "--x", "1", "2", "--input-range", "1",
     "--output-range", "1"],  # fmt: skip
    ["synthesize", "function", "--function", "__import__('os')", "--x", "1", "2"],
    ["synthesize", "motion", str(EX / "motion_poses.csv"), "--centres", "nan,1"],
    ["synthesize", "motion", str(EX / "motion_poses.csv"), "--candidate", "0"],
    ["synthesize", "motion", str(EX / "motion_poses.csv"), "--tol", "nan"],
    ["synthesize", "motion", "/nonexistent.csv"],
    ["synthesize"],
    ["nomogram", "nope"],
    ["nomogram", "pump-torque", "--set", "load=0:1"],
    ["nomogram", "slider-crank", "--set", "rod_crank=nan:3"],
    ["nomogram", "pump-torque", "--paper", "a3"],
    ["nomogram", "four-bar", "--set", "read=x"],
    ["chart", "slider-crank", "--set", "n=5", "--dask", ""],
    ["explore", "/nonexistent.toml", "--no-browser"],
    ["explore", "/dev/zero", "--no-browser"],
]


def _clean(capsys, argv):
    try:
        rc = main(argv)
    except SystemExit as exc:  # argparse: usage errors and --help
        rc = exc.code
    out = capsys.readouterr()
    assert "Traceback" not in out.err and "Traceback" not in out.out, out.err
    assert rc in (0, 1, 2), (rc, out.err)
    if rc == 1:
        lines = [ln for ln in out.err.splitlines() if ln.strip()]
        assert lines and lines[-1].startswith(("mechsynth: error:", "mechsynth ")), out.err
        assert len([ln for ln in lines if ln.startswith("mechsynth")]) == 1, out.err
    return rc


@pytest.mark.parametrize("name", sorted(FILES))
@pytest.mark.parametrize(
    "command",
    COMMANDS,
    ids=lambda c: c[0] + ("-" + c[1] if c[0] in ("pump", "chart", "synthesize") else ""),
)
def test_hostile_files_through_every_command(tmp_path, capsys, name, command):
    text = FILES[name]
    f = tmp_path / f"{name}.toml"
    f.write_bytes(text if isinstance(text, bytes) else text.encode())
    argv = [a.format(f=f, out=tmp_path / "out") for a in command]
    rc = _clean(capsys, argv)
    if name in ("binary", "not-toml", "latin1", "starts-float", "speed-length", "stroke-deg"):
        assert rc == 1


@pytest.mark.parametrize("name", sorted(CARDS))
def test_hostile_cards(tmp_path, capsys, name):
    card = tmp_path / f"{name}.csv"
    card.write_text(CARDS[name])
    rc = _clean(capsys, ["pump", "analyze", str(EX / "pump_unit_c320.toml"), "--card", str(card)])
    assert rc == 1


@pytest.mark.parametrize("argv", ARGS, ids=lambda a: " ".join(a)[:60] or "empty")
def test_hostile_arguments(tmp_path, capsys, argv):
    argv = [a.format(out=tmp_path / "out") for a in argv]
    assert _clean(capsys, argv) == 1


def test_directories_and_devices_as_files(tmp_path, capsys):
    for argv in (
        ["optimize", str(tmp_path)],
        ["animate", str(tmp_path), "--out", str(tmp_path / "o")],
        ["pump", "analyze", str(tmp_path)],
        ["pump", "analyze", str(EX / "pump_unit_c320.toml"), "--card", str(tmp_path)],
        ["optimize", "/dev/null"],
        ["chart", "linkage", "--set", f"file={tmp_path}"],
    ):
        assert _clean(capsys, argv) == 1, argv
