"""Dwell design charts: they render, and the numbers behind them match direct evaluation."""

import csv

import numpy as np
import pytest

from mechsynth.cli import CHARTS
from mechsynth.machines.dwell.charts import chart_dwell, dwell_chart_data
from mechsynth.machines.dwell.linkage import DwellSliderCrank
from mechsynth.machines.dwell.metrics import dwell_window, relative_stroke, window_deviation


def test_chart_numbers_match_direct_evaluation():
    ch = dwell_chart_data([0.15, 0.3], [0.8, 1.1, 1.4], [0.0, 30.0], 0.002, 60.0, 180)
    phi = np.arange(180) * 2 * np.pi / 180
    for gi, ki, ri in [(0, 1, 0), (1, 2, 1), (1, 0, 0)]:
        m = DwellSliderCrank(ch.r[ri], ch.k[ki], np.deg2rad(ch.gamma_deg[gi]))
        x, y = m.coupler_curve(phi)
        w = dwell_window(phi, x, y, 0.002)
        assert ch.dwell_deg[gi, ki, ri] == pytest.approx(np.rad2deg(w.dwell))
        assert ch.E[gi, ki, ri] == pytest.approx(w.deviation) and w.deviation <= 0.002
        assert ch.S_max[gi, ki, ri] == pytest.approx(relative_stroke(x, y, w.xi))
        best = min(window_deviation(x, y, i, i + 31).width for i in range(180))
        assert ch.width_2E[gi, ki, ri] == pytest.approx(best, rel=1e-9)


def test_chart_cli_renders(tmp_path):
    assert "dwell" in CHARTS
    res = chart_dwell(tmp_path, {"n": "4", "gamma_deg": "0,20", "n_angles": "72"})
    names = {f.name for f in res.files}
    assert {"dwell_chart.png", "dwell_chart.svg", "dwell_chart.csv"} <= names
    assert (tmp_path / "dwell_chart.png").stat().st_size > 10_000
    rows = list(csv.DictReader((tmp_path / "dwell_chart.csv").open()))
    assert len(rows) == 2 * 4 * 4
    with pytest.raises(ValueError, match="unknown option bogus; options: "):
        chart_dwell(None, {"bogus": "1"})


def test_minimum_stroke_filters_the_longest_dwell():
    r, k = np.linspace(0.05, 0.5, 6), np.array([0.5, 0.977, 1.5, 2.0, 2.5])
    loose = dwell_chart_data(r, k, [0.0], 0.002, 90.0, 72, stroke=0.0)
    firm = dwell_chart_data(r, k, [0.0], 0.002, 90.0, 72, stroke=0.3)
    assert loose.best()["dwell_deg"] == pytest.approx(360.0)  # an output that hardly moves
    assert loose.best()["S_max"] < 0.05
    best = firm.best()
    assert best["S_max"] >= 0.3 and best["dwell_deg"] < 360.0
    ok = firm.S_max >= 0.3
    assert best["dwell_deg"] == pytest.approx(firm.dwell_deg[ok].max())
    assert dwell_chart_data(r, k, [20.0], 0.002, 90.0, 72, stroke=5.0).best() is None


def test_dwell_chart_summary_is_a_sentence(tmp_path):
    res = chart_dwell(None, {"n": "5", "gamma_deg": "20", "n_angles": "72", "stroke": "0.3"})
    assert "Longest dwell:" in res.summary and "{" not in res.summary
    assert res.data["best_on_grid"]["S_max"] >= 0.3
    none = chart_dwell(None, {"n": "4", "gamma_deg": "0", "n_angles": "72", "stroke": "9"})
    assert "lower --set stroke" in none.summary
    with pytest.raises(ValueError, match="stroke"):
        chart_dwell(None, {"n": "4", "stroke": "-1"})
