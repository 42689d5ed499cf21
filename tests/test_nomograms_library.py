"""Built-in nomograms of the library's models: each chart's reading, through its geometry,
against the model it stands for (SliderCrank, FourBar, the pumping unit's torque), and the
``mechsynth nomogram`` command."""

import json

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.cli import main
from mechsynth.nomograms import library
from mechsynth.nomograms.library import build, crank_rocker_design, displacement_constant

INCH, LBF, SPM = 0.0254, 4.4482216152605, 2.0 * np.pi / 60.0


def test_displacement_constant_is_derived_and_matches_the_field_value():
    # Q [bbl/d] = C D^2 S N: (pi/4) in^2 x in a stroke, 1440 strokes-minutes a day, 9702 in^3
    # a barrel (42 gal x 231 in^3); the field formula prints 0.1166 (e.g. Takacs, Sucker-Rod
    # Pumping Manual, 2003, the pump displacement PD = 0.1166 S_p N D^2)
    C = displacement_constant()
    assert C == pytest.approx(np.pi / 4 * 1440 / 9702, rel=1e-15)
    assert C == pytest.approx(0.1166, abs=5e-5)


def test_pump_displacement_reads_the_physical_displacement():
    with ms.display_units("oilfield"):
        nm = build("pump-displacement")
        # 2 in plunger, 120 in stroke, 8 spm: 0.11657 x 4 x 120 x 8 = 447.6 bbl/d
        q = nm.read(plunger=2 * INCH, stroke=120 * INCH, speed=8 * SPM)
        bbl_d = 42 * 231 * INCH**3 / 86400
        assert q / bbl_d == pytest.approx(displacement_constant() * 4 * 120 * 8, rel=1e-10)
        assert q / bbl_d == pytest.approx(447.7, abs=0.2)
        acc = nm.accuracy  # against pi/4 D^2 S x strokes a second, SI
        assert acc.unit == "bbl/d" and acc.max_relative < 1e-9 and acc.misses == 0


def test_pump_torque_is_a_z_chart_of_the_units_net_torque():
    from mechsynth.machines.pumping_unit.torque import net_torque

    with ms.display_units("oilfield"):
        nm = build("pump-torque")
        t = nm.read(torque_factor=40 * INCH, load=15000 * LBF)
        assert t == pytest.approx(float(net_torque(40 * INCH, 15000 * LBF)), rel=1e-10)
        assert t / (INCH * LBF) == pytest.approx(600000, rel=1e-10)  # in-lb
        assert nm.accuracy.unit == "in-lb" and nm.accuracy.max_relative < 1e-8
        # the load read back from a torque and a torque factor
        assert nm.read(torque=t, torque_factor=40 * INCH) == pytest.approx(15000 * LBF, rel=1e-9)


def test_slider_crank_chart_reads_stroke_and_time_ratio_of_the_model():
    nm = build("slider-crank")
    acc = nm.accuracies
    # measured: stroke / crank max 0.0062 (0.63 mm), time ratio max 0.0021 (1.7 mm)
    assert acc["stroke_crank"].max_error < 0.01 and acc["stroke_crank"].max_mm < 1.0
    assert acc["time_ratio"].max_error < 0.004 and acc["time_ratio"].max_mm < 2.5
    rng = np.random.default_rng(7)
    lam, eps = rng.uniform(2.5, 6.0, 30), rng.uniform(0.05, 1.0, 30)
    sc = ms.SliderCrank(crank=0.05, rod=0.05 * lam, offset=0.05 * eps)
    k = nm.read(rod_crank=lam, offset_crank=eps)
    assert np.max(np.abs(0.05 * k - sc.stroke)) < 0.05 * acc["stroke_crank"].max_error + 1e-12
    q = nm.isopleth(rod_crank=lam, offset_crank=eps)["time_ratio"]
    assert np.max(np.abs(q - sc.time_ratio)) <= acc["time_ratio"].max_error + 1e-12


def test_paper_004_chart_reads_table_1():
    nm = build("extreme-velocity")
    # paper 004, Table 1: b/a = 2, centric: S'_v = 1.1232079 (our maximum of dx_B/dphi)
    v = nm.read(rod_crank=2.0, offset_crank=0.0)
    assert abs(v - 1.1232079) <= nm.accuracy.max_error
    assert nm.accuracy.max_error < 1e-3 and nm.accuracy.max_mm < 1.0  # measured 5.5e-4, 0.51
    assert abs(nm.read(rod_crank=6.0, offset_crank=0.0) - 1.0138038) <= nm.accuracy.max_error
    ev = ms.SliderCrank(crank=1.0, rod=3.0, offset=-0.5).extreme_velocity()
    assert abs(nm.read(rod_crank=3.0, offset_crank=0.5) - ev.maximum.value) < 1e-3


def test_crank_rocker_design_is_what_the_four_bar_model_says():
    mu, a, b, c = crank_rocker_design(ms.deg(np.array([45.0, 60.0, 75.0])),
                                      np.array([1.2, 1.1, 1.3]))
    fb = ms.FourBar(crank=a[:, None], coupler=b[:, None], rocker=c[:, None], ground=1.0)
    assert ms.to_deg(fb.swing_angle).ravel() == pytest.approx([45.0, 60.0, 75.0], abs=1e-6)
    assert fb.time_ratio.ravel() == pytest.approx([1.2, 1.1, 1.3], abs=1e-7)
    t = fb.motion(ms.cycle(7200)).transmission_angle
    assert np.min(np.minimum(t, np.pi - t), axis=-1) == pytest.approx(mu, abs=1e-6)
    # a finer search of the family (12001 candidates a side) gains less than 0.01 deg
    fine = crank_rocker_design(ms.deg(45.0), 1.2, n=12001)[0]
    assert 0 <= ms.to_deg(fine - mu[0]) < 0.01
    assert ms.to_deg(mu[0]) == pytest.approx(44.58, abs=0.01)


@pytest.mark.parametrize(
    "read, k, bound", [("crank", 1, 0.003), ("coupler", 2, 0.004), ("rocker", 3, 0.005)]
)
def test_four_bar_charts_read_the_best_design(read, k, bound):
    nm = build("four-bar", read=read)
    acc = nm.accuracy  # measured: crank 0.0019 (0.94 mm), coupler 0.0027, rocker 0.0036
    assert acc.max_error < bound and acc.max_mm < 1.5 and acc.misses == 0
    v = nm.read(swing=ms.deg(60.0), time_ratio=1.2)
    assert v == pytest.approx(float(crank_rocker_design(ms.deg(60.0), 1.2)[k]), abs=acc.max_error)


def test_options_are_checked_and_unknown_names_listed():
    with pytest.raises(ms.MechanismError, match="unknown nomogram 'nope'"):
        build("nope")
    with pytest.raises(ms.MechanismError, match="unknown option"):
        build("pump-torque", speed="1:2")
    with pytest.raises(ms.MechanismError, match="offset/crank must start above 0"):
        build("slider-crank", offset_crank="0:0.5")
    with pytest.raises(ms.MechanismError, match="paper must be"):
        build("pump-torque", paper="a3")
    assert set(library.NOMOGRAMS) == {"slider-crank", "slider-crank-acceleration",
                                      "extreme-velocity", "four-bar", "pump-displacement",
                                      "pump-torque"}


def test_peak_acceleration_compound_chart_against_the_motion():
    nm = build("slider-crank-acceleration")
    acc = nm.accuracy  # against SliderCrank(...).motion(3600 angles, speed) peaks
    assert acc.max_relative < 0.005 and acc.misses == 0  # measured 0.019 %
    a = nm.read(rod_crank=4.0, offset_crank=0.5, crank=0.05, speed=ms.rpm(600))
    m = ms.SliderCrank(crank=0.05, rod=0.2, offset=0.025).motion(ms.cycle(3600),
                                                                  speed=ms.rpm(600))
    assert a == pytest.approx(np.abs(m.slider.acceleration).max(), rel=acc.max_relative + 1e-9)
    assert sum(s.scale.turning for s in nm.scales.values()) == 2


@pytest.mark.slow
@pytest.mark.parametrize(
    "name, options",
    [(n, {}) for n in library.NOMOGRAMS]
    + [("four-bar", {"read": r}) for r in ("coupler", "rocker", "transmission")]
    + [("extreme-velocity", {"extreme": "min"})],
)
@pytest.mark.parametrize("paper", ["a4", "letter"])
def test_every_sheet_reads_cleanly(name, options, paper):
    from mechsynth.plotting import layout_problems

    with ms.display_units(library.preferred_units(name)):
        nm = build(name, paper=paper, **options)
        fig = nm.draw()
        assert layout_problems(fig) == []
        w, h = fig.get_size_inches() * 25.4
        assert (w, h) == pytest.approx((nm.paper.width, nm.paper.height))
        for s in nm.scales.values():  # every labelled scale carries labels, at least 4
            if not s.scale.turning:
                assert s.length() > 40.0
        labels = [t for t in fig.axes[0].texts if t.get_gid() == "mechsynth-nomogram-tick"]
        assert len(labels) >= 4 * len(nm.inputs)


# ------------------------------------------------------------------------------ command line
def test_cli_lists_nomograms_and_their_options(capsys):
    with pytest.raises(SystemExit):
        main(["nomogram", "--help"])
    out = capsys.readouterr().out
    assert all(name in out for name in library.NOMOGRAMS)
    assert main(["nomogram", "pump-torque", "--set", "help"]) == 0
    assert "torque_factor (in)" in capsys.readouterr().out


@pytest.mark.slow
def test_cli_writes_pdf_svg_png_json_and_prints_the_report(tmp_path, capsys):
    out = tmp_path / "n"
    assert main(["nomogram", "pump-torque", "--out", str(out), "--json", "--paper",
                 "letter"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["paper"] == "letter" and data["units"] == "oilfield"
    assert data["accuracy"]["unit"] == "in-lb" and data["accuracy"]["max_relative"] < 1e-8
    names = {p.name for p in out.iterdir()}
    assert {"nomogram_pump_torque.pdf", "nomogram_pump_torque.svg", "nomogram_pump_torque.png",
            "nomogram_pump_torque.json", "manifest.json"} <= names
    assert main(["nomogram", "pump-displacement", "--units", "si"]) == 0
    assert "m^3/d" in capsys.readouterr().out


@pytest.mark.parametrize("args, message", [
    (["pump-displacement", "--set", "plunger=0:1"], "> 0"),
    (["slider-crank-acceleration", "--set", "rpm=0:1"], "> 0"),
    (["pump-torque", "--set", "load=1e300:1e301"], "<= 1e+07"),
    (["slider-crank", "--set", "rod_crank=nan:3"], "LOW:HIGH"),
    (["slider-crank", "--set", "rod_crank=1.2:3"], "rod > crank + offset"),
    (["four-bar", "--set", "swing_deg=5:150", "--set", "time_ratio=1.001:3"], "no crank-rocker"),
    (["four-bar", "--set", "read=x"], "one of"),
])
def test_cli_hostile_options_end_in_one_line(args, message, capsys):
    assert main(["nomogram", *args]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert message in err[-1] and err[-1].startswith(("mechsynth: error:", "mechsynth nomogram:"))
    assert not any("Traceback" in line or "Warning" in line for line in err)


def test_cli_bad_input_is_one_line_and_exit_1(capsys):
    assert main(["nomogram", "nope"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("mechsynth: error: unknown nomogram")
    assert main(["nomogram", "pump-torque", "--set", "load=3"]) == 1
    assert "LOW:HIGH" in capsys.readouterr().err
    with pytest.raises(SystemExit) as stop:  # argparse's usage errors exit 1 too
        main(["nomogram", "pump-torque", "--paper", "a3"])
    assert stop.value.code == 1 and "invalid choice" in capsys.readouterr().err
