"""Declared options of studies and charts: one declaration for --set, --set help, --help and API
calls; bad values and unknown keys are named."""

import pytest

from mechsynth.cli import CHARTS, _chart_function, main
from mechsynth.options import Option, Options, takes_options
from mechsynth.studies import STUDIES, get_study, run_study


def _all_declared():
    yield from ((f"study {n}", get_study(n).run.options) for n in STUDIES)
    yield from ((f"chart {n}", _chart_function(n).options) for n in CHARTS)


def test_every_study_and_chart_declares_options_whose_defaults_pass_their_rules():
    for owner, options in _all_declared():
        assert isinstance(options, Options), owner
        for opt in options:
            assert opt.help, f"{owner}: option {opt.name} has no meaning"
            if not opt.required and opt.default is not None:
                assert opt.read(opt.default, owner) == opt.default, (owner, opt.name)


@pytest.mark.parametrize(
    "kind, name", [("chart", n) for n in CHARTS] + [("study", n) for n in STUDIES]
)
def test_set_help_lists_every_option_with_default_and_rule(kind, name, capsys):
    args = [kind, name] if kind == "chart" else ["study", "run", name]
    assert main([*args, "--set", "help"]) == 0
    text = capsys.readouterr().out
    options = (_chart_function(name) if kind == "chart" else get_study(name).run).options
    for opt in options:
        assert opt.name in text and opt.rule() in text and opt.help in text


@pytest.mark.parametrize("command", [["chart"], ["study", "run"]])
def test_help_lists_the_options_of_every_name(command, capsys):
    with pytest.raises(SystemExit) as exc:
        main([*command, "--help"])
    assert exc.value.code == 0
    text = capsys.readouterr().out
    names = CHARTS if command == ["chart"] else STUDIES
    for name in names:
        assert f"\n{name}" in text
    assert "rod_crank" in text if command == ["chart"] else "scan_step (kg)" in text


@pytest.mark.parametrize(
    "args, message",
    [
        (["chart", "slider-crank", "--set", "n=abc"], "option n must be an integer, got 'abc'"),
        (["chart", "slider-crank", "--set", "n=2"], "option n must be >= 3, got 2"),
        (["chart", "slider-crank", "--set", "n=2.5"], "option n must be an integer"),
        (["chart", "slider-crank", "--set", "stroke=nan"], "option stroke (m) must be a finite"),
        (["chart", "slider-crank", "--set", "rod_crank=5:2"], "LOW:HIGH with LOW < HIGH"),
        (["chart", "slider-crank", "--set", "rod_crank=0.5:2"], "option rod_crank must be"),
        (["chart", "slider-crank", "--set", "nn=3"], "unknown option nn; options: stroke, rpm"),
        (
            ["chart", "dwell", "--set", "gamma_deg=0,,20"],
            "option gamma_deg must be numbers separated by commas",
        ),
        (["chart", "dwell", "--set", "n=100000"], "option n must be <= 1000, got 100000"),
        (["chart", "slider-crank", "--set", "=3"], "--set expects KEY=VALUE"),
        (["study", "run", "nail-header", "--set", "scan_step=0"], "scan_step (kg) must be > 0"),
        (["study", "run", "dwell", "--set", "min_scale=0"], "option min_scale must be >= 0.0001"),
        (["study", "run", "beam-pump", "--set", "starts=true"], "option starts must be an integer"),
        (["study", "run", "extreme-velocity", "--set", "n=3"], "unknown option n; options: none"),
    ],
)
def test_bad_values_name_the_option_and_exit_1(args, message, capsys):
    assert main(args) == 1
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1, err


def test_api_calls_are_checked_by_the_same_declaration():
    with pytest.raises(ValueError, match=r"option scan_step \(kg\) must be > 0, got 0"):
        run_study("nail-header", scan_step=0)
    with pytest.raises(ValueError, match="unknown option speed; options: angles, scan_step"):
        run_study("nail-header", speed=3)
    with pytest.raises(ValueError, match="option starts must be an integer, got True"):
        run_study("beam-pump", starts=True)


def test_reading_values():
    opt = Option("n", (16, 23, 25), "grid", minimum=2)
    assert opt.read("7") == (7,) and opt.read("6,7,8") == (6, 7, 8) and opt.read(5) == (5,)
    assert opt.read([3, 4, 5]) == (3, 4, 5)
    flag = Option("draw", False, "flag")
    assert flag.read("yes") is True and flag.read("0") is False
    span = Option("r", (0.1, 0.2), "range", kind="span")
    assert span.read("-1:2.5") == (-1.0, 2.5) and span.read((1, 2)) == (1.0, 2.0)
    assert Option("x", 1.0, "x", maximum=2.0).read("2") == 2.0
    with pytest.raises(ValueError, match="must be <= 2"):
        Option("x", 1.0, "x", maximum=2.0).read("2.0001")
    with pytest.raises(ValueError, match="one of a, b"):
        Option("m", "a", "mode", choices=("a", "b")).read("c")
    with pytest.raises(ValueError, match="duplicate option names"):
        Options(Option("a", 1, "x"), Option("a", 2, "y"))


def test_takes_options_passes_undeclared_own_arguments_through():
    @takes_options(Option("n", 3, "count", minimum=1), owner="demo")
    def run(out=None, n=3, executor=None):
        return n, executor

    assert run(n="4", executor="pool") == (4, "pool")
    assert run.options["n"].default == 3
    with pytest.raises(ValueError, match="demo: option n must be >= 1, got 0"):
        run(n=0)
