"""Figure regression: every figure the studies, charts and commands write is rendered (at low
resolution) and checked for overlapping text, text outside the figure, legends over data and
markers clipped by their axes (mechsynth.plotting.layout_problems)."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import pytest  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from mechsynth.plotting import layout_problems  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.fixture
def checked(monkeypatch):
    """Every ``savefig`` runs the layout checks first and writes at 40 dpi; returns
    ``{file name: [problems]}``."""
    found = {}
    original = Figure.savefig

    def savefig(self, fname, *args, **kwargs):
        found[Path(str(fname)).name] = layout_problems(self)
        kwargs["dpi"] = 40
        return original(self, fname, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", savefig)
    return found


def _assert_clean(found, expected):
    missing = set(expected) - set(found)
    assert not missing, f"figures not written: {sorted(missing)}"
    bad = {name: p for name, p in found.items() if p}
    assert not bad, bad


def test_the_checker_sees_overlaps_clipped_markers_and_hidden_data():
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(4, 3))
    ax.text(0.5, 0.5, "one label", transform=ax.transAxes)
    ax.text(0.52, 0.5, "another label", transform=ax.transAxes)
    ax.plot([0, 1], [0, 1], "*", ms=16, label="best")
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    ax.plot([0.05, 0.1, 0.15], [0.95, 0.95, 0.95], label="data under the legend")
    ax.legend(loc="upper left")
    problems = " | ".join(layout_problems(fig))
    assert "overlap" in problems and "clipped" in problems and "hides" in problems
    plt.close(fig)


def test_the_checker_sees_raw_parameter_names_and_five_digit_ticks():
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 3), layout="constrained")
    ax.plot([0, 1], [0, 200000])
    ax.set_xlabel("N_guide_angle, deg")
    ax.set_ylabel("acceleration, mm/s^2")
    problems = " | ".join(layout_problems(fig))
    assert "'N_guide_angle, deg' is a raw parameter name" in problems
    assert "needs more than four digits" in problems
    plt.close(fig)


def test_layout_checker_passes_a_clean_figure():
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 3), layout="constrained")
    ax.plot([0, 1], [0, 1], "o-", label="line")
    ax.margins(0.1)
    ax.set_xlabel("x, m")
    ax.legend(loc="lower right")
    assert layout_problems(fig) == []
    plt.close(fig)


@pytest.mark.slow
def test_extreme_velocity_study_figures(checked, tmp_path):
    from mechsynth.studies import run_study

    run_study("extreme-velocity", out=tmp_path)
    _assert_clean(checked, ["velocity_analogs.png", "extreme_velocity_chart.png"])


@pytest.mark.slow
def test_nail_header_study_figures(checked, tmp_path):
    from mechsynth.studies import run_study

    run_study("nail-header", out=tmp_path, angles=360, scan_step=5.0)
    _assert_clean(
        checked,
        [
            "nail_header_reactions.png",
            "nail_header_hodographs.png",
            "nail_header_slider_mass.png",
            "nail_header_speed.png",
            "nail_header_balance.png",
        ],
    )
    assert (tmp_path / "nail_header.gif").stat().st_size > 0


@pytest.mark.slow
def test_beam_pump_study_figures(checked, tmp_path):
    from mechsynth.studies import run_study

    run_study("beam-pump", out=tmp_path, n_angles=181, pareto_points=3, starts=1)
    _assert_clean(
        checked,
        [
            "beam_pump_kinematics.png",
            "beam_pump_torque.png",
            "beam_pump_pressure_angle.png",
            "beam_pump_pareto.png",
            "beam_pump_pitman_force.png",
            "beam_pump_pareto_velocity.png",
            "beam_pump_speed_acceleration.png",
        ],
    )
    assert (tmp_path / "beam_pump.gif").stat().st_size > 0


@pytest.mark.slow
def test_dwell_study_figures(checked, tmp_path):
    from mechsynth.studies import run_study

    run_study("dwell", out=tmp_path, n=(5, 6, 7), starts=2, dense=(5, 5, 5), local=3)
    _assert_clean(checked, ["dwell_best.png"])
    assert (tmp_path / "dwell_best.gif").stat().st_size > 0


@pytest.mark.slow
def test_chart_figures(checked, tmp_path):
    from mechsynth.machines.dwell.charts import chart_dwell
    from mechsynth.synthesis.charts import chart_slider_crank
    from mechsynth.synthesis.pareto import chart_pareto_slider_crank

    chart_slider_crank(tmp_path, {"n": "15", "n_angles": "90"})
    chart_dwell(tmp_path, {"n": "8", "n_angles": "72", "gamma_deg": "0,20"})
    chart_pareto_slider_crank(tmp_path, {"n": "3", "starts": "1", "anchor_starts": "2"})
    _assert_clean(checked, ["slider_crank_chart.png", "dwell_chart.png", "slider_crank_pareto.png"])


@pytest.mark.slow
def test_command_figures(checked, tmp_path):
    from mechsynth.cli import main

    assert (
        main(
            ["optimize", str(EXAMPLES / "optimize_crank_rocker.toml"), "--starts", "2"]
            + ["--out", str(tmp_path / "opt")]
        )
        == 0
    )
    unit, card = EXAMPLES / "pump_unit_c320.toml", EXAMPLES / "pump_card.csv"
    assert (
        main(
            ["pump", "analyze", str(unit), "--card", str(card), "--out"] + [str(tmp_path / "pump")]
        )
        == 0
    )
    assert (
        main(
            ["animate", str(EXAMPLES / "design_dwell.toml"), "--out", str(tmp_path)]
            + ["--frames", "4", "--dpi", "30"]
        )
        == 0
    )
    assert (
        main(
            ["animate", str(EXAMPLES / "design_beam_pump.toml"), "--out", str(tmp_path)]
            + ["--frames", "4", "--dpi", "30"]
        )
        == 0
    )  # a long design name: the title was cut at the top
    assert "optimum.png" in checked and "design_dwell.png" in checked
    assert "design_beam_pump.png" in checked
    assert len(checked) >= 4
    _assert_clean(checked, [])
