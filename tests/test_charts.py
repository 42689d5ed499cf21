"""Design charts: vectorized sweeps match direct evaluation, infeasible designs are masked (no
NaN), the slider-crank chart at fixed stroke, figures and tables are written."""

import csv

import numpy as np
import pytest
from scipy.optimize import brentq

import mechsynth as ms
from mechsynth import objectives as ob
from mechsynth.cli import CHARTS, main
from mechsynth.synthesis.charts import Chart, chart_slider_crank, slider_crank_chart, sweep

PHI = ms.cycle(360)


def _direct(mech, measure, speed=None, phi=PHI):
    return float(measure.bind(type(mech)).from_motion(mech, mech.motion(phi, speed=speed)))


def test_sweep_matches_direct_evaluation_and_masks_infeasible():
    crank = np.linspace(0.02, 0.1, 9)
    offset = np.linspace(-0.06, 0.06, 7)
    measures = {
        "a": ob.peak_acceleration("slider"),
        "p": ob.max_pressure_angle(),
        "s": ob.stroke("slider"),
        "vA": ob.peak_velocity("A"),
    }
    ch = sweep(
        ms.SliderCrank,
        {"crank": crank, "offset": offset},
        measures,
        fixed={"rod": 0.13},
        speed=ms.rpm(300),
        chunk=5,
        progress=False,
    )
    assert isinstance(ch, Chart) and ch.shape == (9, 7)
    expected_ok = 0.13 > crank[:, None] + np.abs(offset)[None, :]
    np.testing.assert_array_equal(ch.feasible, expected_ok)
    assert (~ch.feasible).any() and "full turn" in ch.reason
    for i in range(9):
        for j in range(7):
            for label, m in measures.items():
                v = ch.values[label]
                assert not np.isnan(v.data).any()
                if not expected_ok[i, j]:
                    assert v.mask[i, j]
                    continue
                mech = ms.SliderCrank(crank=crank[i], rod=0.13, offset=offset[j])
                assert v[i, j] == pytest.approx(_direct(mech, m, ms.rpm(300)), rel=1e-12)
    assert ch.params["rod"][0, 0] == 0.13 and ch.params["crank"][3, 2] == crank[3]


def test_batches_that_fail_on_construction_are_split_to_the_bad_designs():
    # FourBar without its feasibility hook in play: a grid through non-rotating designs
    class NoHook(ms.FourBar):
        feasibility_constraints = None

    coupler = np.linspace(2.0, 6.0, 13)
    ch = sweep(
        NoHook,
        {"coupler": coupler, "rocker": np.linspace(2.0, 5.0, 5)},
        {"mu": ob.min_transmission_angle()},
        fixed={"crank": 1.0, "ground": 4.0},
        angles=72,
        chunk=16,
        progress=False,
    )
    for i, b in enumerate(coupler):
        for j, c in enumerate(np.linspace(2.0, 5.0, 5)):
            turns = (1.0 + 4.0 < b + c) and abs(4.0 - 1.0) > abs(b - c)
            assert ch.feasible[i, j] == turns
            if turns:
                fb = ms.FourBar(1.0, b, c, 4.0)
                mu = _direct(fb, ob.min_transmission_angle(), phi=ms.cycle(72))
                assert ch.values["mu"][i, j] == pytest.approx(mu, rel=1e-12)
    assert "full turn" in ch.reason


def test_argbest_and_satisfied():
    ch = sweep(
        ms.SliderCrank,
        {"rod": np.linspace(0.12, 0.4, 15), "offset": np.linspace(0, 0.05, 6)},
        {"a": ob.peak_acceleration("slider"), "p": ob.max_pressure_angle()},
        fixed={"crank": 0.05},
        angles=180,
        progress=False,
    )
    lim = {"p": ("<=", ms.deg(12))}
    best = ch.argbest("a", where=lim)
    ok = ch.satisfied(lim)
    data = np.where(ok, ch.values["a"].filled(np.inf), np.inf)
    assert best["values"]["a"] == data.min() and best["values"]["p"] <= ms.deg(12)
    assert best["grid"]["rod"] == ch.grid["rod"][best["index"][0]]
    with pytest.raises(ValueError, match="no feasible grid design"):
        ch.argbest("a", where={"p": ("<=", 0.0)})
    with pytest.raises(ValueError, match="unknown measure"):
        ch.argbest("nope")


def _crank_for_stroke(lam, e_r, H):
    """Crank length giving stroke H, found by root finding on the mechanism's stroke (independent
    of the chart's scaling argument)."""
    return brentq(lambda r: ms.SliderCrank(r, lam * r, e_r * r).stroke - H, 1e-4, H)


def test_slider_crank_chart_matches_direct_evaluation():
    H, speed = 0.1, ms.rpm(600)
    lam = np.linspace(1.5, 6.0, 10)
    e_r = np.linspace(0.0, 1.5, 7)
    ch = slider_crank_chart(H, lam, e_r, speed=speed, angles=360, progress=False)
    np.testing.assert_array_equal(ch.feasible, lam[:, None] > 1.0 + e_r[None, :])
    rng = np.random.default_rng(3)
    feasible = np.argwhere(ch.feasible)
    for i, j in feasible[rng.choice(len(feasible), 8, replace=False)]:
        r = _crank_for_stroke(lam[i], e_r[j], H)
        mech = ms.SliderCrank(r, lam[i] * r, e_r[j] * r)
        assert ch.params["crank"][i, j] == pytest.approx(r, rel=1e-9)
        a = _direct(mech, ob.peak_acceleration("slider"), speed)
        p = _direct(mech, ob.max_pressure_angle(), speed)
        assert ch.values["peak slider acceleration"][i, j] == pytest.approx(a, rel=1e-9)
        assert ch.values["max pressure angle"][i, j] == pytest.approx(p, rel=1e-9)
        assert ch.values["time ratio"][i, j] == pytest.approx(mech.time_ratio, rel=1e-12)
    assert (
        ch.units["peak slider acceleration"] == "m/s^2" and ch.units["max pressure angle"] == "rad"
    )


def test_slider_crank_chart_best_approaches_the_certified_optimum():
    """With pressure angle <= 30 deg and rod <= 0.2 m the chart's best grid design approaches the
    certified IPOPT optimum of tests/test_synthesis_validation.py (243.2411566 m/s^2 at crank
    48.176 mm, rod 200 mm, offset 51.824 mm) from above."""
    ch = slider_crank_chart(
        0.1, np.linspace(3.8, 4.4, 25), np.linspace(0.9, 1.2, 25), progress=False
    )
    best = ch.argbest(
        "peak slider acceleration",
        where={"max pressure angle": ("<=", ms.deg(30)), "rod length": ("<=", 0.2)},
    )
    value = best["values"]["peak slider acceleration"]
    assert 243.2411566 * (1 - 1e-6) <= value <= 243.2411566 * 1.003
    assert best["params"]["crank"] == pytest.approx(0.048176, rel=0.01)


def test_chart_tables_and_figure(tmp_path):
    ch = slider_crank_chart(
        0.1, np.linspace(1.5, 5.0, 8), np.linspace(0, 1.5, 6), angles=120, progress=False
    )
    path = ch.to_csv(tmp_path / "c.csv")
    rows = list(csv.DictReader(path.open()))
    assert len(rows) == 48
    bad = [r for r in rows if r["feasible"] == "0"]
    assert bad and all(r["peak slider acceleration [m/s^2]"] == "" for r in bad)
    good = [r for r in rows if r["feasible"] == "1"]
    k = int(np.argmax(ch.feasible.ravel()))
    assert float(good[0]["peak slider acceleration [m/s^2]"]) == pytest.approx(
        ch.values["peak slider acceleration"].ravel()[k], rel=1e-9
    )
    z = np.load(ch.to_npz(tmp_path / "c.npz"))
    np.testing.assert_array_equal(z["feasible"], ch.feasible)
    np.testing.assert_allclose(
        z["value/max pressure angle"], ch.values["max pressure angle"].filled(0.0)
    )
    assert not np.isnan(z["value/peak slider acceleration"]).any()
    fig = ch.plot(limits={"max pressure angle": ("<=", ms.deg(30))})
    fig.savefig(tmp_path / "c.png", dpi=60)
    assert (tmp_path / "c.png").stat().st_size > 10_000
    ax = fig.axes[0]
    assert "rod / crank" in ax.get_xlabel() and "offset / crank" in ax.get_ylabel()
    texts = [t.get_text() for t in fig.legends[0].get_texts()]
    assert any("infeasible" in t for t in texts) and any("> 30 deg" in t for t in texts)
    assert any("best grid design" in t for t in texts)


def test_chart_cli(tmp_path, capsys):
    assert "slider-crank" in CHARTS
    assert (
        main(
            [
                "chart",
                "slider-crank",
                "--set",
                "n=6",
                "--set",
                "n_angles=90",
                "--out",
                str(tmp_path),
            ]
        )
        == 0
    )
    out = capsys.readouterr().out
    assert "Lowest peak slider acceleration" in out
    for name in ("slider_crank_chart.png", "slider_crank_chart.csv", "slider_crank_chart.npz"):
        assert (tmp_path / name).stat().st_size > 1000
    with pytest.raises(ValueError, match="unknown option bogus; options: "):
        chart_slider_crank(None, {"bogus": "1"})


def test_sweep_input_errors():
    with pytest.raises(ValueError, match="finite"):
        sweep(
            ms.SliderCrank,
            {"crank": [np.nan]},
            {"p": ob.max_pressure_angle()},
            fixed={"rod": 1.0},
            progress=False,
        )
    with pytest.raises(ValueError, match="no feasible design"):
        sweep(
            ms.SliderCrank,
            {"crank": [2.0, 3.0]},
            {"p": ob.max_pressure_angle()},
            fixed={"rod": 1.0},
            progress=False,
        )
    with pytest.raises(TypeError, match="Measure"):
        sweep(ms.SliderCrank, {"crank": [0.1]}, {"p": 3.0}, fixed={"rod": 1.0}, progress=False)
    for key in ("feasible", "design"):  # were "'int' object is not callable" mid-sweep
        with pytest.raises(ms.MechanismError, match=f"{key} must be a function"):
            sweep(ms.SliderCrank, {"crank": [0.1]}, {"p": ob.max_pressure_angle()},
                  fixed={"rod": 1.0}, progress=False, **{key: 3})  # fmt: skip
    with pytest.raises(ms.MechanismError, match="fixed must be a dict"):
        sweep(ms.SliderCrank, {"crank": [0.1]}, {"p": ob.max_pressure_angle()}, fixed=[1.0])


def test_parallel_chunks_give_the_same_chart():
    lam, e_r = np.linspace(1.5, 8.0, 30), np.linspace(0.0, 2.0, 20)
    one = slider_crank_chart(0.1, lam, e_r, angles=90, progress=False, workers=1)
    two = slider_crank_chart(0.1, lam, e_r, angles=90, progress=False, workers=2, chunk=37)
    np.testing.assert_array_equal(one.feasible, two.feasible)
    for label in one.values:
        np.testing.assert_array_equal(one.values[label].filled(0), two.values[label].filled(0))


def test_four_bar_chart_masks_designs_whose_crank_cannot_turn():
    """The four-bar's feasibility hook (Grashof full turn of the crank) sets the mask."""
    coupler, rocker = np.linspace(1.5, 6.0, 16), np.linspace(1.5, 5.0, 12)
    ch = sweep(
        ms.FourBar,
        {"coupler": coupler, "rocker": rocker},
        {"mu": ob.min_transmission_angle(), "swing": ob.swing_angle()},
        fixed={"crank": 1.0, "ground": 4.0},
        angles=90,
        progress=False,
    )
    b, c = np.meshgrid(coupler, rocker, indexing="ij")
    turns = (1.0 + 4.0 < b + c) & (np.abs(4.0 - 1.0) > np.abs(b - c))
    np.testing.assert_array_equal(ch.feasible, turns)
    i, j = np.argwhere(turns)[3]
    fb = ms.FourBar(1.0, coupler[i], rocker[j], 4.0)
    assert ch.values["swing"][i, j] == pytest.approx(fb.swing_angle, rel=1e-12)
    assert not np.isnan(ch.values["mu"].data).any()


def test_chart_table_names_each_column_once_with_its_unit():
    grid = {"rod": np.linspace(0.12, 0.3, 4), "offset": np.linspace(0.0, 0.05, 3)}
    ch = sweep(
        ms.SliderCrank,
        grid,
        {"p": ob.max_pressure_angle()},
        fixed={"crank": 0.05},
        angles=60,
        progress=False,
    )
    head = ch.to_csv().splitlines()[0].split(",")
    assert head == ["rod [m]", "offset [m]", "crank [m]", "feasible", "p [deg]"]
    cols = ch.to_dict()
    assert cols["p [deg]"][0] == pytest.approx(np.rad2deg(ch.values["p"][0, 0]))
    with ms.display_units("mm-deg"):
        assert "rod [mm]" in ch.to_dict()


def test_best_design_on_the_grid_edge_is_flagged(tmp_path):
    res = chart_slider_crank(tmp_path, {"n": "8", "n_angles": "60"})
    best = res.data["best_on_grid"]
    assert best["on_edge"] == {"rod/crank": "upper", "offset/crank": "upper"}
    assert res.data["best_on_edge"] and "grid's edge" in res.summary
    inner = chart_slider_crank(None, {"n": "9", "n_angles": "60", "rod_crank": "3:5"})
    assert "grid's edge" not in inner.summary.split("WARNING")[0]
