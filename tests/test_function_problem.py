"""Problem files for function generators (``mechanism = "function-generator"``): the phases and
the partial input range that a crank-driven linkage cannot say, solved by ``optimize``."""

from __future__ import annotations

import io
import json
import tomllib
from contextlib import redirect_stdout

import numpy as np
import pytest

import mechsynth as ms
import mechsynth.synthesis.function_problem as fp  # registers the mechanism and the measure
from mechsynth.synthesis.problem_file import load_problem

LOG = dict(function="log10(x)", x=(1, 10), input_range=ms.deg(60), output_range=ms.deg(90),
           phases=(ms.deg(120), ms.deg(20)))  # fmt: skip


@pytest.fixture(scope="module")
def exact():
    return ms.function_generation(**LOG)


def _problem(tmp_path, text, name="problem.toml"):
    path = tmp_path / name
    path.write_text(text)
    return load_problem(path)


def test_the_grid_covers_the_range_not_a_turn(exact, tmp_path):
    spec = _problem(tmp_path, exact.problem_toml(angles=17))
    a = spec.problem.base_angles
    assert len(a) == 17 and a[0] == 0.0 and abs(a[-1] - ms.deg(60)) < 1e-15
    fam = spec.problem.mechanism
    assert fam.input_range == (0.0, ms.deg(60)) and fam.periodic is False


def test_the_files_error_is_the_designs(exact, tmp_path):
    """structural_error of the file at the exact design is the design's own error (the same
    ideal output, the same motion), and the file reads back what was written."""
    text = exact.problem_toml()
    data = tomllib.loads(text)
    assert data["function"]["y"] == "log10(x)" and data["fixed"] == {"ground": 1.0}
    spec = _problem(tmp_path, text)
    g = exact.generator()
    design = spec.problem.mechanism(**{k: getattr(g, k) for k in g.parameters})
    t = np.linspace(0.0, ms.deg(60), 401)
    measure = fp._structural_error()
    e = np.asarray(measure.samples(design, design.motion(t)), float)
    assert abs(e.max() - exact.max_error) < 1e-12
    assert np.allclose(e, np.abs(exact.error), atol=1e-12)


@pytest.mark.parametrize("limit", [None, "auto"])
def test_solving_the_file_is_the_min_max_stage(exact, tmp_path, limit):
    """The file's problem, solved, reaches the library's min-max optimum: 0.9237 deg without
    a transmission limit (docs/precision_synthesis.md), and with 30 deg the value of
    function_generation(..., optimize=True) with its default limit."""
    spec = _problem(tmp_path, exact.problem_toml(min_transmission=limit))
    res = spec.problem.solve(starts=1, progress=False)
    assert res.success and res.certification.certified
    if limit is None:
        assert abs(ms.to_deg(res.value) - 0.92369) < 1e-3
    else:
        best = ms.function_generation(**LOG, optimize=True)  # min_transmission 30 deg
        assert abs(res.value - best.max_error) < 1e-6
        assert abs(ms.to_deg(res.value) - 2.4821) < 1e-3
    d = res.design  # a generator: its error recomputed here from the function itself
    t = np.linspace(0.0, ms.deg(60), 2001)
    x = 1.0 + 9.0 * t / ms.deg(60)
    ideal = np.log10(x) * ms.deg(90)
    err = np.asarray(d.output(d.motion(t)), float) - ideal
    assert abs(np.max(np.abs(err)) - res.value) < 1e-6
    assert "target" not in res.values and json.dumps(res.to_dict(), default=float)
    # its figure spans the input range, not a turn, says it is a rotation and fits its title
    from mechsynth.plotting import layout_problems

    fig = res.plot()
    ax = fig.axes[-1]
    assert ax.get_xlim() == pytest.approx((0.0, 60.0)) and "input rotation" in ax.get_xlabel()
    assert "driving slider" not in res.report()
    assert layout_problems(fig) == []


def test_slider_crank_file_in_metres(tmp_path):
    fs = ms.function_generation(
        "x**2", x=(0, 1), input_range=ms.deg(120), output_range=0.5, mechanism="slider-crank",
        phases=(ms.deg(120),), crank=1.0,
    )  # fmt: skip
    text = fs.problem_toml()
    assert 'minimize = "structural_error(slider)"' in text and "constraints" not in text
    spec = _problem(tmp_path, text)
    assert spec.problem.objective.unit == "m"
    g = fs.generator()
    design = spec.problem.mechanism(**{k: getattr(g, k) for k in g.parameters})
    t = np.linspace(0.0, ms.deg(120), 401)
    e = np.asarray(spec.problem.objective.samples(design, design.motion(t)), float)
    assert abs(e.max() - fs.max_error) < 1e-12


def test_cli_writes_the_file_and_optimize_solves_it(tmp_path):
    from mechsynth.cli import main

    out = tmp_path / "fg"
    with redirect_stdout(io.StringIO()):
        rc = main(["synthesize", "function", "--function", "log10(x)", "--x", "1", "10",
                   "--input-range", "60deg", "--output-range", "90deg", "--phases", "120deg",
                   "20deg", "--out", str(out), "--json"])  # fmt: skip
    assert rc == 0 and (out / "problem.toml").exists()
    buf = io.StringIO()
    with redirect_stdout(buf):
        rc = main(["optimize", str(out / "problem.toml"), "--json", "--starts", "1"])
    data = json.loads(buf.getvalue())
    assert rc == 0 and data["status"] == "optimal"
    assert abs(ms.to_deg(data["value"]) - 2.4821) < 1e-3


def test_pairs_have_no_problem_file():
    known = ms.FourBar(crank=1.0, coupler=3.5, rocker=3.0, ground=4.0, full_turn=False)
    phi = np.array([0.3, 0.9, 1.4])
    pairs = np.column_stack([phi, known.motion(phi).links["rocker"].angle])
    with pytest.raises(ms.MechanismError, match="precision pairs"):
        ms.function_generation(pairs=pairs, ground=4.0).problem_toml()


GOOD = """mechanism = "function-generator"
minimize = "structural_error"
[function]
y = "x**2"
x = [0, 1]
input_range = "90 deg"
output_range = "90 deg"
[variables]
crank = [0.1, 1.0]
[fixed]
coupler = 2.0
rocker = 1.0
ground = 2.0
phi0 = "140 deg"
psi0 = "245 deg"
"""


@pytest.mark.parametrize(
    "old, new, match",
    [
        ('y = "x**2"', 'y = "x**2"\nspan = 1', r"unknown keys \['span'\]"),
        ('y = "x**2"\n', "", r"missing \['y'\]"),
        ("x = [0, 1]", "x = [1, 0]", "need x0 < x1"),
        ('output_range = "90 deg"', 'output_range = "400 deg"', "less than a turn"),
        ('input_range = "90 deg"', 'input_range = "90 mm"', "expected an angle"),
        ("rocker = 1.0\n", "", "give rocker as a variable or fixed"),
        ('y = "x**2"', 'y = "sqrt(x) + foo"', "unknown name"),
        ("[function]", '[function]\nmechanism = "six-bar"', "mechanism must be one of"),
        ('minimize = "structural_error"', 'minimize = "structural_error(C)"', "'rocker' or"),
    ],
)
def test_bad_files_are_named(tmp_path, old, new, match):
    assert old in GOOD
    with pytest.raises(ms.MechanismError, match=match):
        _problem(tmp_path, GOOD.replace(old, new, 1))


def test_the_good_file_loads_and_other_mechanisms_have_no_target(tmp_path):
    spec = _problem(tmp_path, GOOD)
    assert spec.problem.names == ("crank",)
    with pytest.raises(ms.MechanismError, match="function generator"):
        _problem(tmp_path, 'mechanism = "four-bar"\nminimize = "structural_error"\n'
                 "[variables]\ncrank = [0.1, 1]\n[fixed]\ncoupler = 3\nrocker = 3\n"
                 "ground = 4\n", "other.toml")  # fmt: skip
    with pytest.raises(ms.MechanismError, match=r"needs a \[function\] table"):
        _problem(tmp_path, GOOD.split("[function]")[0], "nofunction.toml")


def test_optimize_names_a_bad_function_table_in_one_line(tmp_path, capsys):
    from mechsynth.cli import main

    path = tmp_path / "bad.toml"
    path.write_text(GOOD.replace('y = "x**2"', 'y = "log10(x)"'))  # log10(0): not finite
    assert main(["optimize", str(path), "--json"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("mechsynth: error: ")
    assert "bad.toml" in err[0] and "finite" in err[0]
