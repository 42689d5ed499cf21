"""The dwell synthesis study: feasible best design, consistent with direct evaluation."""

import json

import numpy as np
import pytest

from mechsynth.cli import main
from mechsynth.jsonutil import dumps
from mechsynth.studies import STUDIES
from mechsynth.studies.dwell import evaluate, run


def test_dwell_study_small(tmp_path):
    assert "dwell" in STUDIES
    res = run(tmp_path, tolerance=0.003, stroke=0.3, n=5, dense=6)
    best = res.data["best"]
    assert res.data["success"] and res.data["certificate"]["passed"]
    assert best["deviation"] <= 0.003 and best["S_max"] >= 0.3
    assert best["dwell_deg"] >= res.data["seed"]["dwell_deg"]
    again = evaluate(best["r"], best["k"], best["gamma_deg"], 0.003)
    assert again == pytest.approx(best)
    assert (tmp_path / "dwell_best.png").stat().st_size > 10_000
    payload = json.loads(dumps(res.data))
    for key in ("r", "k", "gamma_deg", "phi_L_deg", "dwell_deg", "deviation", "xi_deg", "S_max"):
        assert np.isfinite(payload["best"][key])


def test_dwell_study_rejects_bad_tolerance():
    with pytest.raises(ValueError, match="tolerance"):
        run(None, tolerance=-1.0)


def test_chart_cli_json(tmp_path, capsys):
    rc = main(["chart", "dwell", "--set", "n=3", "--set", "n_angles=72", "--json"])
    assert rc == 0
    assert json.loads(capsys.readouterr().out)["tolerance"] == 0.002


def test_infeasible_stroke_reported_and_exits_nonzero(capsys):
    import argparse

    from mechsynth.cli import _print_result

    # no design within the bounds reaches a stroke of 5 rod lengths
    res = run(None, stroke=5.0, n=3, dense=3)
    assert res.data["success"] is False
    assert _print_result(res, argparse.Namespace(json=True)) == 1
    capsys.readouterr()
