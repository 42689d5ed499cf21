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
