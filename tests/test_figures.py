"""Figure regression: every figure the studies, charts and commands write is rendered (at low
resolution) and checked for overlapping text, text outside the figure, legends over data and
markers clipped by their axes (mechsynth.plotting.layout_problems)."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from mechsynth.plotting import LINESTYLES, layout_problems  # noqa: E402

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


def _figure(size=(5, 3), **kw):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=size, layout="constrained", **kw)
    for a in np.atleast_1d(ax):
        a.set_xlabel("crank angle, deg")
        a.set_ylabel("force, kN")
    return fig, ax


def test_the_checker_sees_a_curve_hidden_under_a_later_one():
    import matplotlib.pyplot as plt

    x = np.linspace(0.0, 360.0, 181)
    y = np.sin(np.radians(x))
    fig, ax = _figure()
    ax.plot(x, y, label="joint A")
    ax.plot(x, y + 1e-4, label="joint O", ls="--")  # dashed: A shows through its gaps
    ax.plot(x, 0.5 * y, label="joint B", ls=":")
    ax.legend(loc="lower left")
    assert layout_problems(fig) == []
    ax.plot(x, y, label="joint C", ls="-.")
    ax.lines[1].set_linestyle("-")  # now a solid line covers A
    ax.get_legend().remove()
    ax.legend(loc="lower left")
    problems = layout_problems(fig)
    assert any("'joint A'" in p and "hidden" in p for p in problems), problems
    assert not any("'joint B'" in p and "hidden" in p for p in problems)
    plt.close(fig)
    # a wide pale line under a thin one shows on both sides; a translucent line hides nothing
    fig, ax = _figure()
    ax.plot(x, y, color="0.6", lw=3, label="planar unit")
    ax.plot(x, y, lw=1, label="spatial drive")
    ax.plot(x, 0.5 * y, lw=1, ls="--", label="half")
    ax.plot(x, 0.5 * y, lw=3, alpha=0.5, label="half, pale")
    ax.legend(loc="lower left")
    assert not any("hidden" in p for p in layout_problems(fig))
    plt.close(fig)
    # a curve on a zero line drawn after it is hidden too; drawn before, it is in sight
    for first, hidden in ((True, True), (False, False)):
        fig, ax = _figure()
        if not first:
            ax.axhline(0.0, color="k", lw=0.8)
        ax.plot(x, np.zeros_like(x), lw=0.8, label="guide")
        if first:
            ax.axhline(0.0, color="k", lw=0.8)
        ax.set_ylim(-1, 1)
        assert any("'guide'" in p for p in layout_problems(fig)) == hidden
        plt.close(fig)


def test_the_checker_sees_reference_lines_on_the_frame():
    import matplotlib.pyplot as plt

    for pos, on_frame in ((5.0, True), (4.5, False), (6.0, False)):
        fig, ax = _figure()
        ax.plot([0, 360], [1, 4])
        ax.axhline(pos, ls="--", color="k", label="5 % limit")
        ax.set_ylim(0, 5)
        problems = layout_problems(fig)
        assert any("lies on the axes' frame" in p for p in problems) == on_frame, (pos, problems)
        plt.close(fig)
    fig, ax = _figure()
    ax.plot([0, 360], [1, 4])
    ax.plot([0, 360], [0, 0], ls=":")  # a constant series on the lower frame
    ax.axvline(360.0, ls="--")
    ax.set_xlim(0, 360)
    ax.set_ylim(0, 5)
    problems = " | ".join(layout_problems(fig))
    assert "horizontal line" in problems and "vertical line" in problems
    plt.close(fig)


def test_the_checker_sees_series_told_apart_by_colour_only():
    import matplotlib.pyplot as plt

    x = np.linspace(0.0, 1.0, 11)
    fig, ax = _figure()
    ax.plot(x, x, color="r", label="left, 5 %")
    ax.plot(x, 2 * x, color="g", label="right, 5 %")
    ax.plot(x, 3 * x, color="r", ls="--", label="left, 10 %")
    ax.legend(loc="upper left")
    ax.set_ylim(-2, 4)
    problems = layout_problems(fig)
    assert any("'left, 5 %', 'right, 5 %'" in p and "colour only" in p for p in problems)
    plt.close(fig)
    fig, ax = _figure()
    ax.plot(x, x, color="r", label="left")
    ax.plot(x, 2 * x, color="g", ls="--", label="right")
    ax.plot(x, 3 * x, "o", color="b", label="measured")
    ax.plot(x, 4 * x, "s", color="k", mfc="none", label="published")
    ax.plot(x, x - 1.5, color="b", lw=2.6, label="limit")  # as "left" but twice as wide
    ax.set_ylim(-2, 5)
    ax.legend(loc="upper left", ncols=2)
    assert layout_problems(fig) == []
    plt.close(fig)
    fig, ax = _figure(ncols=2)  # a figure-level legend is checked too
    ax[0].plot(x, x, color="r", label="a")
    ax[1].plot(x, x, color="g", label="b")
    fig.legend(loc="outside lower center", ncols=2)
    assert any("the figure's legend" in p for p in layout_problems(fig))
    plt.close(fig)


def test_the_checker_sees_unequal_scales_on_directional_axes():
    import matplotlib.pyplot as plt

    from mechsynth.plotting import equal_axes

    t = np.linspace(0.0, 2.0 * np.pi, 60)
    fig, ax = _figure()
    ax.plot(3.0 * np.cos(t), np.sin(t))
    ax.mechsynth_directional = True  # marked, but scales left free
    problems = layout_problems(fig)
    assert any("x and y scales differ" in p for p in problems), problems
    plt.close(fig)
    for adjustable in ("box", "datalim"):
        fig, ax = _figure((4, 4))
        ax.plot(3.0 * np.cos(t), np.sin(t))
        equal_axes(ax, adjustable)
        ax.margins(0.1)
        assert layout_problems(fig) == []
        plt.close(fig)
    fig, ax = _figure()  # unmarked axes: any scales go
    ax.plot(3.0 * np.cos(t), np.sin(t))
    ax.margins(0.1)
    assert layout_problems(fig) == []
    plt.close(fig)


def test_the_checks_are_fast_on_a_busy_figure():
    import time

    import matplotlib.pyplot as plt

    x = np.linspace(0.0, 360.0, 721)
    fig, ax = _figure()
    for k in range(12):
        ax.plot(x, np.sin(np.radians(x) + 0.3 * k), ls=LINESTYLES[k % 6], lw=1 + k // 6)
    t0 = time.perf_counter()
    layout_problems(fig)
    assert time.perf_counter() - t0 < 2.0
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
    assert (
        main(
            ["animate", str(EXAMPLES / "design_six_link.toml"), "--out", str(tmp_path)]
            + ["--frames", "4", "--dpi", "30"]
        )
        == 0
    )  # two traced paths: told apart by dash
    assert (
        main(
            ["optimize", str(EXAMPLES / "optimize_cylinder_rocker.toml"), "--starts", "2"]
            + ["--out", str(tmp_path / "linear")]
        )
        == 0
    )  # a driving slider: a long title
    assert (
        main(
            ["chart", "slider-crank", "--set", "n=12", "--units", "oilfield", "--quiet"]
            + ["--out", str(tmp_path / "oilfield")]
        )
        == 0
    )  # accelerations of 10,000 in/s^2 and more: in 1000 in/s^2
    assert "optimum.png" in checked and "design_dwell.png" in checked
    assert "design_beam_pump.png" in checked and "design_six_link.png" in checked
    assert "slider_crank_chart.png" in checked
    assert len(checked) >= 7
    _assert_clean(checked, [])
