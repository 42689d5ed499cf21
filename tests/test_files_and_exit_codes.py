"""Problem, unit and card files checked against their schema, one-line errors, and the exit
codes of the command line (0 success, 1 bad input or usage, 2 failed solve, 130 Ctrl-C), the
last ones through a real subprocess."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.cli import EXIT_CODES, main
from mechsynth.machines.pumping_unit.torque import DynamometerCard
from mechsynth.synthesis.problem_file import load_problem

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
UNIT = EXAMPLES / "pump_unit_c320.toml"
CARD = EXAMPLES / "pump_card.csv"

BASE = 'mechanism = "slider-crank"\nminimize = "peak_acceleration(slider)"\n'
VARS = "[variables]\ncrank = [0.01, 0.1]\nrod = [0.2, 0.4]\n"


@pytest.mark.parametrize(
    "text, match",
    [
        (BASE + 'variables = "x"\n', "variables must be a table"),
        ('mechanism = "slider-crank"\nminimize = 42\n' + VARS, "minimize must be a string"),
        (BASE + "starts = [1]\n" + VARS, "starts must be a whole number, got \\[1\\]"),
        (BASE + "starts = 2.5\n" + VARS, "starts must be a whole number, got 2.5"),
        (BASE + "starts = true\n" + VARS, "starts must be a whole number, got True"),
        (BASE + "starts = 0\n" + VARS, "starts must be between 1 and"),
        (BASE + "seed = -3\n" + VARS, "seed must be at least 0"),
        (BASE + "angles = [1, 2]\n" + VARS, "angles must be a whole number"),
        (BASE + "angles = 1e9\n" + VARS, "angles must be between 8 and 1000000"),
        (BASE + 'method = "newton"\n' + VARS, "method must be one of 'ipopt'"),
        (BASE + "[variables]\ncrank = [-0.1, 0.1]\nrod = [0.2, 0.4]\n", "is a length"),
        (BASE + "[variables]\ncrank = [0.01, 0.1, 3]\nrod = [0.2, 0.4]\n", "expected \\[lower"),
        (BASE + '[variables]\ncrank = ["1 deg", "2 deg"]\nrod = [0.2, 0.4]\n', "is an angle"),
        (BASE + 'speed = "600 m"\n' + VARS, "'600 m' is a length, expected an angular velocity"),
        (BASE + "speed = nan\n" + VARS, "speed must be finite"),
        (BASE + 'constraints = ["stroke(slider) == 5 deg"]\n' + VARS, "is an angle, expected"),
        (BASE + 'constraints = ["max_pressure_angle <= 30 mm"]\n' + VARS, "expected an angle"),
        (BASE + 'constraints = ["time_ratio >= 1.2 m"]\n' + VARS, "expected a pure number"),
        (BASE + 'constraints = ["stroke(slider, foo=1) == 0.1"]\n' + VARS, "unexpected keyword"),
        (BASE + "constraints = [3]\n" + VARS, "a constraint is a string"),
        (
            BASE
            + '[[constraints]]\nmeasure = "stroke"\nargs = "slider"\nop = "=="\nvalue = 0.1\n'
            + VARS,
            "args must be a list",
        ),
        (
            BASE + '[[constraints]]\nmeasure = "stroke"\nop = "=="\nvalue = "x"\n' + VARS,
            "value must be a number",
        ),
        (BASE + "colour = 1\n" + VARS, "unknown keys \\['colour'\\]; a problem file has"),
        ('mechanism = ["slider-crank"]\n', "mechanism must be one of"),
        ("x = " + "[" * 60 + "1" + "]" * 60 + "\n", "unknown keys"),
    ],
)
def test_problem_file_schema(tmp_path, text, match):
    p = tmp_path / "p.toml"
    p.write_text(text)
    with pytest.raises(ms.MechanismError, match=match):
        load_problem(p)


def test_quantities_with_the_right_dimension_are_converted(tmp_path):
    p = tmp_path / "p.toml"
    p.write_text(
        BASE + 'speed = "600 rpm"\nconstraints = ["stroke(slider) >= 100 mm", '
        '"max_pressure_angle <= 30 deg"]\n[variables]\ncrank = ["10 mm", "10 cm"]\n'
        "rod = [0.2, 0.4]\n"
    )
    spec = load_problem(p)
    assert spec.problem.speed == pytest.approx(20 * np.pi)
    assert spec.problem.variables["crank"] == pytest.approx((0.01, 0.1))
    assert [c.bound for c in spec.problem.constraints] == pytest.approx([0.1, np.pi / 6])


@pytest.mark.parametrize("kind", ["dir", "device", "binary", "missing", "empty-name"])
def test_files_that_are_not_text_files(tmp_path, kind):
    path = {
        "dir": tmp_path,
        "device": Path(os.devnull),
        "missing": tmp_path / "nope.toml",
        "binary": tmp_path / "b.toml",
        "empty-name": "",
    }[kind]
    if kind == "binary":
        path.write_bytes(bytes(range(256)) * 4)
    with pytest.raises(ms.MechanismError, match="directory|not a regular|binary|not found|empty"):
        load_problem(path)


def _card(tmp_path, rows, name="c.csv"):
    p = tmp_path / name
    p.write_text("position_in,load_lb\n" + "\n".join(f"{x},{w}" for x, w in rows) + "\n")
    return p


def _rows():
    rows = []
    for line in CARD.read_text().splitlines()[1:]:
        x, w = line.split(",")
        rows.append((float(x), float(w)))
    return rows


def test_cards_are_one_loop_of_positive_loads_in_recorded_order(tmp_path):
    rows = _rows()
    DynamometerCard.from_csv(_card(tmp_path, rows))  # the example is fine
    neg = [(x, -w) if i == 5 else (x, w) for i, (x, w) in enumerate(rows)]
    with pytest.raises(ms.MechanismError, match="load 6 is negative"):
        DynamometerCard.from_csv(_card(tmp_path, neg))
    shuffled = [rows[i] for i in np.random.default_rng(1).permutation(len(rows))]
    with pytest.raises(ms.MechanismError, match="not one loop in recorded order"):
        DynamometerCard.from_csv(_card(tmp_path, shuffled))
    with pytest.raises(ms.MechanismError, match="runs backwards"):
        DynamometerCard.from_csv(_card(tmp_path, rows[::-1]))
    with pytest.raises(ms.MechanismError, match="is a directory"):
        DynamometerCard.from_csv(tmp_path)
    big = np.tile(np.array(rows), (1000, 1))
    with pytest.raises(ms.MechanismError, match="at most 100000"):
        DynamometerCard(big[:, 0], big[:, 1])


@pytest.mark.parametrize(
    "case, match",
    [
        ("long-card", "times the unit's"),
        ("spm", "spm must be above 0 and at most 60"),
    ],
)
def test_pump_analyze_refuses_absurd_input(tmp_path, capsys, case, match):
    unit, card = UNIT, CARD
    if case == "long-card":
        card = _card(tmp_path, [(100 * x, w) for x, w in _rows()])
    else:
        unit = tmp_path / "u.toml"
        unit.write_text(UNIT.read_text().replace("spm = 8.0", "spm = 1e300"))
    rc = main(["pump", "analyze", str(unit), "--card", str(card)])
    err = capsys.readouterr().err
    assert rc == 1 and match in err and err.count("\n") == 1


# ---------------------------------------------------------------------- exit codes (in process)
def test_usage_errors_exit_1_not_2(capsys):
    for argv in (["--bogus"], ["optimize"], ["chart"], ["animate", "x", "--frames", "many"]):
        with pytest.raises(SystemExit) as exc:
            main(argv)
        assert exc.value.code == 1, argv
    capsys.readouterr()


@pytest.mark.parametrize(
    "argv, hint",
    [
        (["stdy", "list"], "did you mean 'study'?"),
        (["study", "run", "extreme-velocity", "--ot", "x"], "did you mean --out?"),
        (["study", "run", "extreme-velocity", "--jsn"], "did you mean --json?"),
        # the command's own options: --min-transmision is synthesize path's, not optimize's
        (["synthesize", "path", "t.csv", "--min-transmision", "30"], "did you mean --min-trans"),
        (["optimize"], "the following arguments are required: problem"),
    ],
)
def test_usage_errors_are_one_line_with_the_nearest_name(capsys, argv, hint):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    err = capsys.readouterr().err
    assert exc.value.code == 1 and hint in err and err.count("\n") == 1, err
    assert "--help'" in err


def test_no_suggestion_of_another_commands_option_or_of_the_word_itself(capsys):
    # synthesize function has --points; synthesize path does not, and must not suggest it
    with pytest.raises(SystemExit):
        main(["synthesize", "path", "t.csv", "--points", "3"])
    err = capsys.readouterr().err
    assert "unrecognized arguments: --points" in err and "did you mean" not in err, err


@pytest.mark.parametrize(
    "argv, match",
    [
        (["optimize", "{tmp}"], "is a directory"),
        (["optimize", os.devnull], "not a regular file"),
        (["optimize", str(EXAMPLES / "optimize_slider_crank.toml"), "--out", ""], "non-empty"),
        (
            ["optimize", str(EXAMPLES / "optimize_slider_crank.toml"), "--out", "{file}"],
            "is an existing file",
        ),
        (
            ["optimize", str(EXAMPLES / "optimize_slider_crank.toml"), "--out", "{file}/sub"],
            "which is a file",
        ),
        (["pump", "analyze", str(UNIT), "--card", "{tmp}"], "is a directory"),
        # an output folder that cannot be made says which and why (it said only "No such file")
        (["study", "run", "extreme-velocity", "--out", "/proc/nope"], "cannot be created"),
        # --dask '' ran locally without a word; garbage waited 20 s for a traceback
        (["chart", "slider-crank", "--set", "n=5", "--dask", ""], "not a Dask scheduler"),
        (["chart", "slider-crank", "--set", "n=5", "--dask", "garbage"], "not a Dask scheduler"),
        # the explorer names its file's fault (it said "cannot serve on 127.0.0.1:0")
        (["explore", "{tmp}/nosuch.toml", "--no-browser"], "explore file"),
        (["explore", "{tmp}", "--no-browser"], "is a directory"),
        (["explore", os.devnull, "--no-browser"], "not a regular file"),
        (["explore", "{file}", "--no-browser"], "not valid TOML"),
    ],
)
def test_bad_paths_exit_1_with_one_line(tmp_path, capsys, argv, match):
    f = tmp_path / "a_file"
    f.write_text("x")
    argv = [a.format(tmp=tmp_path, file=f) for a in argv]
    rc = main(argv)
    err = capsys.readouterr().err
    assert rc == 1, err
    assert match in err and err.count("\n") == 1 and "Traceback" not in err


def test_help_documents_the_exit_codes(capsys):
    for argv in (["--help"], ["optimize", "--help"], ["pump", "analyze", "--help"]):
        with pytest.raises(SystemExit) as exc:
            main(argv)
        assert exc.value.code == 0
        out = " ".join(capsys.readouterr().out.split())
        assert "exit codes: 0 success; 1 bad input or usage" in out
    assert "130 interrupted" in EXIT_CODES
    readme = (ROOT / "README.md").read_text()
    assert "130" in readme and "exit code" in readme.lower()


# ---------------------------------------------------------------------- exit codes (subprocess)
def _cli(*args, timeout=120, **kwargs):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run(
        [sys.executable, "-m", "mechsynth", *args],
        capture_output=True,
        text=True,
        env=env,
        timeout=timeout,
        cwd=ROOT,
        **kwargs,
    )


def test_subprocess_exit_codes_0_1_2(tmp_path):
    ok = _cli("study", "list")
    assert ok.returncode == 0 and ok.stderr == ""
    usage = _cli("optimize")
    assert usage.returncode == 1 and "Traceback" not in usage.stderr
    bad = tmp_path / "p.toml"
    bad.write_text(BASE + "starts = true\n" + VARS)
    r = _cli("optimize", str(bad))
    assert r.returncode == 1
    assert r.stderr.count("\n") == 1 and "starts must be a whole number" in r.stderr
    infeasible = tmp_path / "i.toml"
    infeasible.write_text(BASE + 'constraints = ["stroke(slider) >= 0.5"]\nstarts = 1\n' + VARS)
    r = _cli("optimize", str(infeasible), "--json")
    assert r.returncode == 2, r.stderr
    # --debug shows the traceback of a bad input
    r = _cli("optimize", str(bad), "--debug")
    assert r.returncode != 0 and "Traceback" in r.stderr


@pytest.mark.skipif(os.name != "posix", reason="SIGINT to a child process")
def test_ctrl_c_exits_130_with_one_line(tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.Popen(
        [sys.executable, "-m", "mechsynth", "study", "run", "extreme-velocity", "--out",
         str(tmp_path / "out"), "--quiet"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
        cwd=ROOT,
    )  # fmt: skip
    # once the command runs (its output folder exists): an interrupt during Python's own
    # start-up, before mechsynth's code, is Python's business
    t0 = time.monotonic()
    while not (tmp_path / "out").exists() and proc.poll() is None and time.monotonic() - t0 < 300:
        time.sleep(0.01)
    time.sleep(0.5)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=120)
    if proc.returncode == 0:  # finished before the signal: nothing to check
        pytest.skip("the command finished before Ctrl-C")
    assert proc.returncode == 130, err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and "interrupted" in lines[0] and "Traceback" not in err
