"""Units at the edges (display settings), unit-labelled tables of results, result values."""

import csv
import io

import numpy as np
import pytest

import mechsynth as ms
from mechsynth import display, tables
from mechsynth import objectives as ob
from mechsynth.machines.nail_header import NailHeader


def test_presets_and_the_context_manager_restore_the_setting():
    assert display.current().name == "si"
    with ms.display_units("oilfield") as du:
        assert du.length == "in" and du.force == "lbf" and display.current() is du
        with ms.display_units(length="mm"):
            assert display.current().length == "mm" and display.current().force == "lbf"
        assert display.current().length == "in"
    assert display.current().name == "si"
    setting = ms.display_units("mm-deg")
    try:
        assert display.current().length == "mm"  # set at once, without a with block
    finally:
        setting.__exit__()
    assert display.current().name == "si"


def test_conversions_at_the_edges():
    with ms.display_units("oilfield"):
        assert display.convert(0.0254, "m") == pytest.approx((1.0, "in"))
        assert display.convert(4.4482216152605, "N")[0] == pytest.approx(1.0)
        assert display.convert(0.0254 * 4.4482216152605, "N m") == pytest.approx((1.0, "in-lb"))
        assert display.convert(2.0, "m/s^2") == pytest.approx((2.0 / 0.0254, "in/s^2"))
    with ms.display_units("mm-deg"):
        assert display.fmt(0.1, "m") == "100 mm"
        assert display.fmt(ms.deg(30), "rad") == "30 deg"
        assert display.convert(3.0, "m/rad") == pytest.approx((3000.0, "mm/rad"))
        assert display.convert(5.0, "rad/s") == (5.0, "rad/s")  # angular speeds stay in rad/s
        assert display.convert(7.0, "") == (7.0, "")
    with ms.display_units(angle="rad"):
        assert display.fmt(0.5, "rad") == "0.5 rad"


def test_bad_display_units_name_the_choices():
    with pytest.raises(ValueError, match="si, mm-deg, oilfield"):
        ms.display_units("imperial")
    with pytest.raises(ValueError, match="length unit must be one of m, mm"):
        ms.display_units(length="furlong")
    assert display.current().name == "si"


def test_angle_positions_are_in_one_turn():
    assert display.angle_position(2 * np.pi) == 0.0
    assert display.angle_position(2 * np.pi - 1e-12) == 0.0  # never "360.000000 deg"
    assert display.angle_position(-np.pi / 2) == pytest.approx(270.0)
    assert display.angle_position(np.deg2rad(725.0)) == pytest.approx(5.0)
    with ms.display_units(angle="rad"):
        assert display.angle_position(-np.pi / 2) == pytest.approx(1.5 * np.pi)


def test_table_columns_are_unit_labelled_and_never_repeated():
    cols = tables.table([("x", "m", [1.0, 2.0]), ("phi", "rad", [0.0, np.pi])])
    assert list(cols) == ["x [m]", "phi [deg]"] and cols["phi [deg]"][1] == pytest.approx(180)
    with pytest.raises(ValueError, match="appears twice"):
        tables.table([("x", "m", [1.0]), ("x", "m", [2.0])])
    with pytest.raises(ValueError, match="rows"):
        tables.table([("x", "m", [1.0]), ("y", "m", [2.0, 3.0])])
    text = tables.write_csv(
        {"a [m]": np.ma.MaskedArray([1.0, 2.0], [False, True]), "b": [np.nan, 3.0]}
    )
    assert list(csv.reader(io.StringIO(text))) == [["a [m]", "b"], ["1", ""], ["", "3"]]


def _read(text):
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], np.array(rows[1:], dtype=float)


def test_motion_to_csv_and_to_dict():
    sc = ms.SliderCrank(crank=0.07, rod=0.24, offset=0.01)
    phi = ms.cycle(12)
    m = sc.motion(phi, speed=ms.rpm(600))
    head, rows = _read(m.to_csv())
    assert len(head) == len(set(head)) and rows.shape == (12, len(head))
    assert head[0] == "phi [deg]" and np.allclose(rows[:, 0], np.rad2deg(phi))
    i = head.index("slider B acceleration [m/s^2]")
    assert np.allclose(rows[:, i], m.slider.acceleration, rtol=1e-9)
    assert "link rod omega [rad/s]" in head and "pressure angle [deg]" in head
    with ms.display_units("mm-deg"):
        d = m.to_dict()
    assert d["slider B position [mm]"] == pytest.approx(1e3 * m.slider.position)
    analog = sc.motion(phi).to_dict()
    assert "B vx [m/rad]" in analog


def test_motion_table_of_a_batch_asks_for_one_design(tmp_path):
    m = ms.SliderCrank(crank=np.array([[0.05], [0.06]]), rod=0.3).motion(ms.cycle(4))
    with pytest.raises(ValueError, match="one design"):
        m.to_csv(tmp_path / "m.csv")


def test_force_result_to_csv(tmp_path):
    f = NailHeader().forces(ms.cycle(16))
    path = f.to_csv(tmp_path / "forces.csv")
    head, rows = _read(path.read_text())
    assert len(head) == len(set(head))
    assert np.allclose(rows[:, head.index("R32 magnitude [N]")], f.magnitude("R32"), rtol=1e-9)
    assert np.allclose(rows[:, head.index("balancing torque [N m]")], f.torque, rtol=1e-9)
    assert "R30 normal force [N]" in head
    with ms.display_units("oilfield"):
        assert "R10 x [lbf]" in f.to_dict()


def test_motion_plot_of_a_four_bar_and_of_a_point():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    m = ms.FourBar(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2).motion(ms.cycle(90))
    fig = m.plot()  # the rocker: no "this mechanism has no slider"
    assert fig.axes[0].get_ylabel() == "angle, deg"
    fig2 = m.plot("B")
    assert [t.get_text() for t in fig2.axes[0].get_legend().get_texts()] == ["B x, m", "B y, m"]
    assert fig2.axes[1].get_ylabel() == "speed |v|, m/rad"
    with pytest.raises(ValueError, match="no slider"):
        m.plot("slider")
    plt.close("all")


def _problem():
    prob = ms.Problem(
        ms.SliderCrank,
        variables={"crank": (0.01, 0.2), "rod": (0.05, 0.2), "offset": (-0.1, 0.1)},
        speed=ms.rpm(600),
    )
    prob.minimize(ob.peak_acceleration("slider"))
    prob.subject_to(ob.stroke("slider") == 0.10, ob.max_pressure_angle() <= ms.deg(30))
    return prob


def test_result_values_rebuild_the_design_and_bounds_are_flagged():
    res = _problem().solve(starts=2)
    assert res.success
    again = ms.SliderCrank(**res.values)
    assert again == res.design
    assert res.on_bounds() == {"rod": "upper"}  # the README's problem: the rod limit binds
    text = res.report()
    assert "ON ITS UPPER BOUND 0.2 m" in text and "max_pressure_angle <= 30 deg" in text
    assert "[ok, active]" in text and "0.523599" not in text
    with ms.display_units("mm-deg"):
        mm = res.report()
    assert "crank = 48.176" in mm and "stroke(slider) == 100 mm" in mm
    data = res.to_dict()
    assert data["values"] == res.values and data["on_bounds"] == {"rod": "upper"}
    assert data["units"]["max_pressure_angle"] == "rad"


def test_peak_angles_are_reported_in_one_turn():
    res = _problem().solve(starts=1)
    for line in res.report().splitlines():
        if line.strip().startswith("peak "):
            angle = float(line.split("at crank angle ")[1].split(" deg")[0])
            assert 0.0 <= angle < 360.0


def test_four_bar_result_values_keep_the_branch():
    fb = ms.FourBar(crank=1.0, coupler=4.3, rocker=3.0, ground=5.2, branch="crossed")
    assert ms.FourBar(**fb.as_dict()) == fb


def test_progress_bars_only_on_a_terminal_and_never_when_quiet(capsys):
    from mechsynth import progress

    assert progress.bar(range(3), desc="x").disable  # pytest's stderr is not a terminal
    assert not progress.bar(range(3), enabled=True).disable
    with progress.quiet():
        assert progress.is_quiet() and progress.bar(range(3), enabled=True).disable
    assert not progress.is_quiet()
    with progress.Stages("study", ["first", "second"], enabled=True) as st:
        st.next("first")
        st.next("second")
    assert "study: second" in capsys.readouterr().err


def test_measure_names_in_words():
    from mechsynth.plotting import readable

    assert readable("peak_acceleration(slider)", "polished rod") == (
        "peak acceleration of the polished rod"
    )
    assert readable("max_pressure_angle") == "max pressure angle"
    assert readable("peak_velocity(C, direction=1.5708)") == (
        "peak velocity of C (direction=1.5708)"
    )


def test_thousands_keeps_tick_labels_to_four_digits():
    from mechsynth import display

    v, u = display.thousands(np.array([-300000.0, 5.0, np.nan]), "mm/s^2")
    assert u == "m/s^2" and np.nanmax(np.abs(v)) == 300.0
    assert display.thousands(np.array([2.5e5]), "N")[1] == "kN"
    assert display.thousands(np.array([2.5e5]), "in-lb")[1] == "1000 in-lb"
    same = np.array([9999.0])
    assert display.thousands(same, "mm")[0] is same  # below 10,000: unchanged
