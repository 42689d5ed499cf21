"""Pareto fronts by the epsilon-constraint method: an analytic front, the slider-crank compromise
between peak slider acceleration and pressure angle, anchors, non-dominance, outputs."""

import csv

import numpy as np
import pytest
from scipy.optimize import brentq

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth.synthesis.pareto import ParetoFront, _dominance, pareto_front, true_value


def test_analytic_front_of_the_centric_slider_crank():
    """Centric slider-crank with a fixed rod b and the crank r free: stroke = 2 r and max
    pressure angle = asin(r / b), so the front (min pressure angle, max stroke) is exactly
    pressure = asin(stroke / (2 b)) for r in its bounds."""
    b = 0.3
    prob = ms.Problem(ms.SliderCrank, {"crank": (0.02, 0.1)}, fixed={"rod": b, "offset": 0.0})
    fr = pareto_front(
        prob, ob.max_pressure_angle(), ob.stroke("slider"), n=5, senses=("min", "max"), starts=2
    )
    assert isinstance(fr, ParetoFront) and fr.success.all() and fr.nondominated.all()
    np.testing.assert_allclose(fr.first, np.arcsin(fr.second / (2 * b)), rtol=1e-9)
    # anchors: crank at its bounds; the points spread over the whole front
    assert fr.second[0] == pytest.approx(0.04, rel=1e-7)
    assert fr.second[-1] == pytest.approx(0.2, rel=1e-6)
    np.testing.assert_allclose(np.sort(fr.second), np.linspace(0.04, 0.2, 5), rtol=1e-6)


def _slider_crank_problem():
    prob = ms.Problem(
        ms.SliderCrank,
        variables={"crank": (0.01, 0.2), "rod": (0.05, 0.2), "offset": (-0.1, 0.1)},
        speed=ms.rpm(600),
    )
    return prob.subject_to(ob.stroke("slider") == 0.1)


@pytest.fixture(scope="module")
def slider_crank_front():
    prob = _slider_crank_problem()
    fr = pareto_front(
        prob,
        ob.peak_acceleration("slider"),
        ob.max_pressure_angle(),
        eps=ms.deg([40.0, 30.0, 20.0]),
        starts=3,
    )
    return prob, fr


def test_front_points_are_feasible_and_nondominated(slider_crank_front):
    prob, fr = slider_crank_front
    assert fr.n_points == 5 and fr.success.all() and fr.nondominated.all()
    for i, r in enumerate(fr.results):
        assert r.status == "optimal" and not r.violated
        d = r.design
        assert d.stroke == pytest.approx(0.1, rel=1e-6)
        assert d.rod > d.crank + abs(d.offset)  # the crank turns fully
        # the front's values are the true peaks at the design
        assert fr.first[i] == pytest.approx(true_value(prob, ob.peak_acceleration("slider"), d))
        assert fr.second[i] <= fr.eps[i] * (1 + 1e-6)
    # along the front one measure improves as the other worsens
    order = np.argsort(fr.second)
    assert np.all(np.diff(fr.first[order]) < 0)
    # the 30 deg point is the certified optimum of tests/test_synthesis_validation.py
    i30 = int(np.argmin(np.abs(fr.eps - ms.deg(30))))
    assert fr.first[i30] == pytest.approx(243.2411566, rel=1e-6)


def test_anchors_equal_the_single_objective_optima(slider_crank_front):
    prob, fr = slider_crank_front
    # the anchors use 8 starts (anchor_starts), as Problem.solve does by default
    a = prob.copy().minimize(ob.peak_acceleration("slider")).solve(starts=8, progress=False)
    p = prob.copy().minimize(ob.max_pressure_angle()).solve(starts=8, progress=False)
    assert a.success and p.success
    assert fr.first[0] == pytest.approx(a.value, rel=1e-9)
    assert fr.second[-1] == pytest.approx(p.value, rel=1e-6)
    # the centric design with the longest rod has the smallest pressure angle: asin(r / b)
    assert p.value == pytest.approx(np.arcsin(0.05 / 0.2), rel=1e-7)
    # independent check of the first anchor: brute force along the offset bound (where it lies),
    # crank from the stroke, true peaks on 8192 angles. The minimum over this 1-D slice is an
    # upper bound of the optimum; the multi-start local solver lands within 0.2 % of it (its
    # certified local optima differ by about 0.1 % between start sets on this multi-modal
    # problem).
    rods = np.linspace(0.16, 0.2, 81)
    peaks = []
    for rod in rods:
        r = brentq(
            lambda c, rod=rod: ms.SliderCrank(c, rod, 0.1).stroke - 0.1, 0.01, rod - 0.1 - 1e-9
        )
        m = ms.SliderCrank(r, rod, 0.1)
        peaks.append(ob.peak_acceleration("slider").evaluate(m, ms.cycle(8192), speed=ms.rpm(600)))
    assert fr.first[0] <= min(peaks) * (1 + 2e-3)
    assert fr.first[0] >= min(peaks) * (1 - 2e-3)


def test_outputs(slider_crank_front, tmp_path):
    _, fr = slider_crank_front
    rows = list(csv.DictReader(fr.to_csv(tmp_path / "front.csv").open()))
    assert len(rows) == 5 and {"crank [m]", "rod [m]", "offset [m]"} <= set(rows[0])
    assert float(rows[0]["peak_acceleration(slider) [m/s^2]"]) == pytest.approx(fr.first[0])
    fig = fr.plot()
    fig.savefig(tmp_path / "front.png", dpi=60)
    assert (tmp_path / "front.png").stat().st_size > 5000
    assert "deg" in fig.axes[0].get_xlabel()
    d = fr.to_dict()
    assert len(d["points"]) == 5 and d["points"][0]["status"] == "optimal"
    f1, f2 = fr.front()
    assert np.all(np.diff(f2) > 0)


def test_dominance_filter():
    f1 = np.array([1.0, 2.0, 1.5, 3.0, 0.5])
    f2 = np.array([3.0, 1.0, 3.5, 2.0, 4.0])
    ok = np.array([True, True, True, True, False])
    nd = _dominance(f1, f2, ok, ("min", "min"))
    # (1.5, 3.5) is dominated by (1, 3); (3, 2) by (2, 1); the failed point is never on it
    np.testing.assert_array_equal(nd, [True, True, False, False, False])
    # maximizing the second: (1, 3) and (1.5, 3.5) trade off; (1, 3) dominates (2, 1), (3, 2)
    nd = _dominance(f1, f2, ok, ("min", "max"))
    np.testing.assert_array_equal(nd, [True, False, True, False, False])


def test_failed_anchor_is_reported_not_raised():
    prob = ms.Problem(ms.SliderCrank, {"crank": (0.01, 0.05), "rod": (0.2, 0.3)})
    prob.subject_to(ob.stroke("slider") == 0.5)  # needs a crank of 0.25 m
    fr = pareto_front(prob, ob.peak_acceleration("slider"), ob.max_pressure_angle(), n=4, starts=1)
    assert not fr.success.any() and fr.results[0].status == "infeasible"
    assert not np.isnan(fr.first.data).any()
    with pytest.raises(ValueError, match="n must be"):
        pareto_front(prob, ob.max_pressure_angle(), ob.stroke("slider"), n=1)


def test_pareto_chart_cli(tmp_path, capsys):
    from mechsynth.cli import CHARTS, main

    assert "slider-crank-pareto" in CHARTS
    argv = ["chart", "slider-crank-pareto", "--set", "n=3", "--set", "starts=2"]
    assert main([*argv, "--set", "anchor_starts=4", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "Pareto front" in out and out.count("optimal") == 3
    assert (tmp_path / "slider_crank_pareto.png").stat().st_size > 10_000
    assert len(list(csv.DictReader((tmp_path / "slider_crank_pareto.csv").open()))) == 3
    assert '"status": "optimal"' in (tmp_path / "slider_crank_pareto.json").read_text()
    assert main(["chart", "slider-crank-pareto", "--set", "bogus=1"]) == 1


def test_an_anchor_beaten_by_a_sweep_point_is_solved_again_from_it():
    """Multi-start anchors are local optima: when a point of the sweep beats the first anchor in
    its own objective (here maximized) or the second anchor in the second (minimized), the
    anchor is re-solved from that point's design and replaced only if the new solve is better."""
    from types import SimpleNamespace

    from mechsynth.synthesis.pareto import _polish_anchors

    def res(x, ok=True):
        return SimpleNamespace(success=ok, variables={"x": x})

    # (first: max, second: min); point 2 beats anchor 0 in `first`, point 1 beats the last
    # anchor in `second`
    vals = [(10.0, 50.0), (9.0, 5.0), (12.0, 30.0), (8.0, 10.0)]
    results = [res(0.0), res(1.0), res(2.0), res(3.0)]
    eps = [50.0, 40.0, 30.0, 10.0]
    calls = []

    def anchor1(x0):
        calls.append(("first", x0["x"]))
        return res(9.9), (13.0, 31.0)

    def anchor2(x0):
        calls.append(("second", x0["x"]))
        return res(9.8), (8.5, 6.0)  # not better than the 5.0 that beat it, but than 10.0

    _polish_anchors(results, vals, eps, anchor1, anchor2, ("max", "min"))
    assert calls == [("first", 2.0), ("second", 1.0)]
    assert vals[0] == (13.0, 31.0) and results[0].variables["x"] == 9.9 and eps[0] == 31.0
    assert vals[3] == (8.5, 6.0) and eps[3] == 6.0
    # a re-solve that fails or is worse leaves the anchor as it was
    vals2 = [(10.0, 50.0), (12.0, 30.0), (8.0, 10.0)]
    results2 = [res(0.0), res(2.0), res(3.0)]
    _polish_anchors(
        results2,
        vals2,
        [0, 0, 0],
        lambda x0: (res(7.0, ok=False), (20.0, 1.0)),
        None,
        ("max", "min"),
    )
    assert vals2[0] == (10.0, 50.0) and results2[0].variables["x"] == 0.0


def test_a_failed_inner_point_is_solved_again_from_the_next_solved_one():
    """The sweep starts each inner point from the previous solved one; a point that fails is
    tried once more from the next solved point towards the second anchor (last to first, so a
    recovered point seeds the one before it); a retry that fails too stays a failure."""
    from types import SimpleNamespace

    from mechsynth.synthesis.pareto import _retry_failed

    def res(x, ok=True):
        return SimpleNamespace(success=ok, variables={"x": x})

    results = [res(0.0), res(1.0), res(None, False), res(None, False), res(4.0)]
    vals = [(10.0, 50.0), (9.0, 40.0), (np.nan, np.nan), (np.nan, np.nan), (5.0, 10.0)]
    eps = [50.0, 40.0, 30.0, 20.0, 10.0]
    calls = []

    def point(e, x0):
        calls.append((e, x0["x"]))
        return res(e), (e / 4.0, e)

    _retry_failed(results, vals, eps, point)
    assert calls == [(20.0, 4.0), (30.0, 20.0)]
    assert vals[3] == (5.0, 20.0) and vals[2] == (7.5, 30.0) and results[2].variables["x"] == 30.0
    results = [res(0.0), res(None, False), res(4.0)]
    vals = [(10.0, 50.0), (np.nan, np.nan), (5.0, 10.0)]
    _retry_failed(results, vals, [50.0, 30.0, 10.0], lambda e, x0: (res(e, False), (1.0, e)))
    assert not results[1].success and np.isnan(vals[1][0])
