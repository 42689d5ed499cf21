"""The command line: help everywhere, study listing, clear errors."""

import json

import pytest

from mechsynth.cli import build_parser, main
from mechsynth.studies import STUDIES


def test_help_exits_cleanly(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    assert "study" in capsys.readouterr().out


def test_every_subcommand_has_help(capsys):
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    for name in sub.choices:
        with pytest.raises(SystemExit) as exc:
            main([name, "--help"])
        assert exc.value.code == 0, name
    capsys.readouterr()


def test_study_list_json_names_every_registered_study(capsys):
    assert main(["study", "list", "--json"]) == 0
    listed = json.loads(capsys.readouterr().out)
    assert set(listed) == set(STUDIES)


def test_unknown_study_is_a_clear_error(capsys):
    assert main(["study", "run", "no-such-study"]) == 1
    err = capsys.readouterr().err
    assert "unknown study 'no-such-study'" in err and "known studies" in err


def test_study_options_from_the_command_line(capsys):
    assert main(["study", "run", "dwell", "--set", "help"]) == 0
    out = capsys.readouterr().out
    assert "default 0.002" in out and "tolerance" in out and "minimum stroke S_max" in out
    rc = main(
        ["study", "run", "dwell", "--set", "tolerance=0.003", "--set", "stroke=0.35"]
        + ["--set", "n=6,7,7", "--set", "dense=5", "--set", "local=3", "--json"]
    )
    data = json.loads(capsys.readouterr().out)
    assert rc == 0
    assert data["tolerance"] == 0.003 and data["stroke"] == 0.35
    assert data["stages"][0]["evaluations"] == 6 * 7 * 7
    assert data["best"]["deviation"] <= 0.003 and data["best"]["S_max"] >= 0.35


@pytest.mark.parametrize(
    "item, message",
    [
        ("tol=1", "study 'dwell': unknown option tol; options: tolerance, stroke, n"),
        ("n=a,b", "option n must be integers separated by commas, >= 2, <= 200, got 'a,b'"),
        ("min_scale=0", "option min_scale must be >= 0.0001, got 0.0"),
        ("stroke", "--set expects KEY=VALUE"),
        ("stroke=-1", "stroke"),
    ],
)
def test_bad_study_options_are_clear_errors(item, message, capsys):
    assert main(["study", "run", "dwell", "--set", item]) == 1
    assert message in capsys.readouterr().err
