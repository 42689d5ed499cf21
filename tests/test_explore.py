"""The explorer's logic without a browser: the page's state as a design and a problem, validation
messages, curves against the API, sweeps, exports that `mechsynth optimize` reads, the command
line, and the page object driven from Python (Panel, no server)."""

import json
import math
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.cli import main
from mechsynth.errors import MechanismError
from mechsynth.explore import model
from mechsynth.explore.model import State, checks, curves, kind_names, load_file, to_toml

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"
REFERENCE = EXAMPLES / "optimize_centric_slider_crank.toml"
W600 = 2 * math.pi * 10.0  # 600 rpm, rad/s


def _optimum():
    """Reference optimum: crank 50 mm, rod 200 mm, peak r w^2 (1 + r/l) (crank/rod <= 1/4)."""
    return 0.05 * W600**2 * (1 + 0.05 / 0.2)


@pytest.mark.parametrize("key", list(kind_names()))
def test_every_mechanism_builds_draws_and_measures(key):
    st = State.default(key)
    design, message = st.check_design()
    assert message is None, message
    sk = design.sketch(design.turn_sign * ms.cycle(12))
    assert sk.frames == 12 and sk.bars
    c = curves(st, design)
    for k in ("position", "velocity", "acceleration"):
        assert c[k].shape == (361,) and np.all(np.isfinite(c[k]))
    assert c["pressure"] is not None and np.all(np.isfinite(c["pressure"]))
    assert c["stroke"] > 0
    rows = checks(st, design)
    assert rows[0].objective and np.isfinite(rows[0].value)
    assert len(rows) == 1 + len(st.constraints)
    # its problem is one that `mechsynth optimize` reads
    spec = st.problem()
    assert set(spec.problem.variables) and spec.problem.objective is not None


def test_stroke_is_the_apis():
    st = State.default("slider-crank")
    st.values.update(crank=0.062, rod=0.31, offset=0.021)
    sc = ms.SliderCrank(crank=0.062, rod=0.31, offset=0.021)
    assert curves(st, st.design())["stroke"] == pytest.approx(sc.stroke, rel=1e-12)
    fb = State.default("four-bar")
    swing = ms.objectives.swing_angle("rocker").evaluate(fb.design(), ms.cycle(4096))
    assert curves(fb, fb.design())["stroke"] == pytest.approx(swing, rel=1e-6)
    pu = State.default("beam-pump")
    unit = ms.BeamPumpingUnit.from_api(
        A=155.0, C=111.06, I=111.02, P=132.01, R=42.01, H=231.97, G=95.98, units="in"
    )
    assert curves(pu, pu.design())["stroke"] == pytest.approx(unit.stroke, rel=1e-12)


def test_curves_are_the_motion_of_the_api():
    st = State.default("slider-crank")
    c = curves(st, st.design())
    m = ms.SliderCrank(crank=0.07, rod=0.24).motion(np.deg2rad(c["angle"]), speed=W600)
    np.testing.assert_allclose(c["acceleration"], m.slider.acceleration, rtol=1e-12)
    np.testing.assert_allclose(c["pressure"], m.pressure_angle, rtol=1e-12)


def test_checks_colour_constraints_by_their_values():
    st = State.default("slider-crank")  # stroke 140 mm against == 100 mm; 17 deg <= 30 deg
    rows = {r.name: r for r in checks(st, st.design())}
    assert not rows["stroke(slider)"].ok and rows["stroke(slider)"].value == pytest.approx(0.14)
    assert rows["max_pressure_angle"].ok
    st.values["crank"] = 0.05
    assert {r.name: r.ok for r in checks(st, st.design())}["stroke(slider)"]


def test_impact_machine_is_ms_six_link():
    st = State.default("impact")
    phi = ms.cycle(90)
    a, b = st.design().motion(phi, speed=1.0), ms.six_link().motion(phi, speed=1.0)
    for k in b.points:
        np.testing.assert_allclose(a.points[k].x, b.points[k].x, atol=1e-14)
        np.testing.assert_allclose(a.points[k].vy, b.points[k].vy, atol=1e-14)


# ----------------------------------------------------------------------------- validation
def test_design_that_cannot_assemble_names_the_condition():
    st = State.default("slider-crank")
    st.values["rod"] = 0.05
    design, message = st.check_design()
    assert design is None
    assert "rod (0.05 m) not longer than crank + |offset| (0.07 m)" in message
    lk = State.default("linkage")
    lk.values["DB"] = 0.01
    _, message = lk.check_design()
    assert "cannot be assembled" in message and "RRR group B" in message


def test_field_and_bound_messages():
    st = State.default("slider-crank", units="mm-deg")
    st.values["crank"] = -0.01
    assert st.field_messages() == {"crank": "crank must be positive (a length), got -10 mm"}
    st.values["crank"] = float("nan")
    assert "crank must be a number" in st.field_messages()["crank"]
    st.vary = {"rod": (0.3, 0.1), "crank": (0.0, 0.1)}
    bad = st.bound_messages()
    assert bad["rod"] == "rod: lower bound 300 mm is not below the upper bound 100 mm"
    assert "lower bound must be positive, got 0 mm" in bad["crank"]
    with pytest.raises(ValueError, match="rod: lower bound 300 mm"):
        st.problem_data()
    pu = State.default("beam-pump")
    pu.vary["G"] = (1.0, 2.0)
    assert "cannot be an optimization variable" in pu.bound_messages()["G"]


def test_problem_needs_an_objective_and_a_variable():
    st = State.default("slider-crank")
    st.vary = {}
    with pytest.raises(ValueError, match="tick at least one dimension"):
        st.problem_data()
    st = State.default("slider-crank")
    st.objective = " "
    with pytest.raises(ValueError, match="give an objective"):
        st.problem_data()
    st.objective = "peak_jerk(slider)"
    with pytest.raises(ValueError, match="unknown measure 'peak_jerk'"):
        st.problem()


# ----------------------------------------------------------------------------- files
@pytest.mark.parametrize("key", list(kind_names()))
def test_toml_writer_round_trips(key):
    data = State.default(key).problem_data()
    assert tomllib.loads(to_toml(data)) == data


def test_exported_problem_solves_with_optimize(tmp_path, capsys):
    st = load_file(REFERENCE)
    st.values.update(crank=0.03, rod=0.15)  # the page moved away: the problem is the same
    path = tmp_path / "problem.toml"
    path.write_text(st.problem_toml())
    assert main(["optimize", str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["status"] == "optimal"
    assert data["value"] == pytest.approx(_optimum(), rel=1e-7)


def test_linkage_problem_exports_inline_and_reads_back(tmp_path):
    st = load_file(EXAMPLES / "optimize_six_link.toml")
    assert st.vary["KN"] == pytest.approx((0.06, 0.2))
    assert st.speed == pytest.approx(ms.rpm(1500))
    path = tmp_path / "six.toml"
    path.write_text(st.problem_toml())
    again = load_file(path)
    for k, bounds in st.vary.items():
        assert again.vary[k] == pytest.approx(bounds)
    assert again.constraints == st.constraints
    assert again.values == pytest.approx(st.values)


def test_load_files_of_every_kind():
    sc = load_file(EXAMPLES / "design_slider_crank.toml", units="mm-deg")
    assert sc.kind.key == "slider-crank" and sc.values["offset"] == pytest.approx(0.01)
    assert sc.speed == pytest.approx(ms.rpm(600))
    assert load_file(EXAMPLES / "design_six_link.toml").values["DB"] == pytest.approx(0.08)
    assert load_file(EXAMPLES / "six_link.toml").kind.key == "linkage"
    assert load_file(EXAMPLES / "design_dwell.toml").values["k"] == pytest.approx(1.2109)
    pu = load_file(EXAMPLES / "optimize_beam_pump.toml")
    # Mark II: the crankshaft in front of the centre bearing, pivot_x = -I; pivot_y = H - G
    assert pu.kind.text["unit_class"] == "mark-ii"
    data = pu.problem_data()
    assert data["variables"]["pivot_x"] == pytest.approx([-7.5, -2.5])
    assert data["variables"]["pivot_y"] == pytest.approx([3.0, 5.0])
    unit = pu.design()
    assert unit.pivot_x == pytest.approx(-5.0) and unit.pivot_y == pytest.approx(4.0)
    with pytest.raises(ValueError, match="mechanism = 'nail-header'"):
        load_file(EXAMPLES / "design_nail_header.toml")
    with pytest.raises(FileNotFoundError):
        load_file(EXAMPLES / "no_such_file.toml")


def test_solution_parameters_map_back_to_api_dimensions():
    pu = State.default("beam-pump")
    back = pu.values_of({"crank": 1.1, "pivot_x": 2.5, "pivot_y": 3.0})
    assert back["R"] == 1.1 and back["I"] == 2.5
    assert back["H"] - back["G"] == pytest.approx(3.0)


# ----------------------------------------------------------------------------- chart, solve
def test_sweep_cells_are_the_designs_they_load():
    st = State.default("slider-crank")
    ch = model.sweep_chart(st, "crank", "rod", n=12)
    assert ch.shape == (12, 12)
    i, j = 4, 9
    crank, rod = ch.grid["crank"][i], ch.grid["rod"][j]
    sc = ms.SliderCrank(crank=crank, rod=rod, offset=0.0)
    if ch.feasible[i, j]:
        assert ch.values["stroke(slider)"][i, j] == pytest.approx(sc.stroke, rel=1e-9)
    assert not ch.feasible[-1, 0]  # the longest crank on the shortest rod cannot turn
    with pytest.raises(ValueError, match="two different"):
        model.sweep_chart(st, "rod", "rod")


def test_solve_data_reports_progress_and_reaches_the_optimum():
    import queue

    q = queue.Queue()
    out = model.solve_data(load_file(REFERENCE).problem_data(), q)
    assert out["status"] == "optimal"
    assert out["value"] == pytest.approx(_optimum(), rel=1e-7)
    assert out["variables"]["crank"] == pytest.approx(0.05, rel=1e-7)
    steps = []
    while not q.empty():
        steps.append(q.get())
    assert steps[0][0] == "progress" and steps[-1][2:] == (2, 2)


def test_progress_observe_follows_manual_updates():
    seen = []
    with ms.progress.observe(lambda d, k, n: seen.append((d, k, n))):
        b = ms.progress.bar(total=3, desc="sweep", enabled=False)
        b.update()
        b.update(2)
        b.close()
    assert seen == [("sweep", 0, 3), ("sweep", 1, 3), ("sweep", 3, 3)]
    b = ms.progress.bar(total=1, enabled=False)
    b.update()  # no observer: a plain bar
    assert not hasattr(b, "_tell")


# ----------------------------------------------------------------------------- command line
def test_import_and_help_stay_light():
    code = (
        "import sys, mechsynth, mechsynth.explore, mechsynth.explore.model\n"
        "from mechsynth.cli import build_parser\n"
        "try:\n    build_parser().parse_args(['explore', '--help'])\nexcept SystemExit:\n    pass\n"
        "assert 'panel' not in sys.modules and 'bokeh' not in sys.modules, 'panel imported'\n"
    )
    r = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "--no-browser" in r.stdout and "--port" in r.stdout and "--json" in r.stdout


def test_missing_panel_is_one_line_and_exit_1(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "panel", None)  # import panel -> ImportError
    assert main(["explore", "--no-browser"]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "pip install 'mechsynth[explore]'" in err


def test_bad_file_and_port_fail_before_serving(capsys):
    pytest.importorskip("panel")
    assert main(["explore", str(EXAMPLES / "nothing.toml"), "--no-browser"]) == 1
    assert "nothing.toml not found" in capsys.readouterr().err
    assert main(["explore", "--port", "70000", "--no-browser"]) == 1
    assert "--port must be 0 to 65535" in capsys.readouterr().err


# ----------------------------------------------------------------------------- the page object
@pytest.fixture
def page():
    pytest.importorskip("panel")
    from mechsynth.explore.app import Explorer

    return Explorer(State.default("slider-crank", units="mm-deg"))


def test_page_shows_the_apis_stroke_and_moves_the_drawing(page):
    slider = page.dim_widgets["crank"][0]
    from mechsynth.explore.app import label_of

    assert label_of(slider) == "crank, mm (crank OA)" and slider.value == pytest.approx(70.0)
    assert label_of(page.dim_fields["crank"]) == "crank, mm"
    assert page.dim_fields["crank"].value == "70"
    x_before = list(page.src_joints.data["x"])
    slider.value = 80.0
    assert "160 mm" in page.stats.object
    assert page.src_joints.data["x"] != x_before
    sk = ms.SliderCrank(crank=0.08, rod=0.24).sketch(np.array([0.0]))
    assert page.src_joints.data["x"][-1] == pytest.approx(sk.points["B"][0][0] * 1e3)


def test_page_puts_the_message_next_to_the_field(page):
    page.dim_widgets["rod"][0].value = 50.0
    msg = page.dim_widgets["rod"][4]
    assert msg.visible and "not longer than crank + |offset|" in msg.object
    assert not page.dim_widgets["crank"][4].visible
    assert "invalid design" in page.stats.object
    page.dim_widgets["rod"][0].value = 240.0
    assert not msg.visible and "140 mm" in page.stats.object
    _, vary, lo, hi, msg = page.dim_widgets["offset"]
    lo.value = "50"
    hi.value = "-50"
    assert msg.visible and "lower bound 50 mm is not below the upper bound -50 mm" in msg.object


def test_page_loads_a_chart_cell_and_exports(page, tmp_path):
    page.out = tmp_path
    page._chart_state = page.state
    page._chart = model.sweep_chart(page.state, "crank", "rod", n=8)
    page._draw_chart()
    assert len(page.chart_src.data["x"]) == 64
    page.load_cell(2, 6)
    assert page.state.values["crank"] == pytest.approx(page._chart.grid["crank"][2])
    assert page.dim_widgets["rod"][0].value == pytest.approx(page._chart.grid["rod"][6] * 1e3)
    page._export_toml()
    spec = ms.synthesis.problem_file.load_problem(tmp_path / "problem.toml")
    assert spec.problem.variables["rod"] == pytest.approx((0.05, 0.2))
    for f in (page._export_drawing, page._export_curves, page._export_chart):
        assert f().getvalue()[:8] == b"\x89PNG\r\n\x1a\n"
    assert {p.name for p in tmp_path.iterdir()} == {
        "problem.toml",
        "mechanism.png",
        "curves.png",
        "chart.png",
    }


@pytest.mark.parametrize("key", ["linkage", "impact"])
def test_linkage_sweeps(key):
    st = State.default(key)
    ch = model.sweep_chart(st, "AB", "DB", n=4, angles=90)
    assert ch.shape == (4, 4) and ch.feasible.any()


def test_page_follows_the_display_units_and_the_mechanism(page):
    from mechsynth.explore.app import label_of

    slider = page.dim_widgets["crank"][0]
    page.units_select.value = "si"
    assert label_of(page.dim_fields["crank"]) == "crank, m"
    assert page.dim_widgets["crank"][0].value == pytest.approx(0.07)
    assert "0.14 m" in page.stats.object and slider is page.dim_widgets["crank"][0]
    page.kind_select.value = "four-bar"
    assert set(page.dim_widgets) == {"crank", "coupler", "rocker", "ground"}
    assert "swing" in page.stats.object and "deg" in page.stats.object
    page.kind_select.value = "impact"
    assert "of N" in page.stats.object


def test_page_runs_a_solve_in_a_worker_process(page):
    import time

    page.state = load_file(REFERENCE, units="mm-deg")
    page._rebuild_dims()
    page._refresh(None)
    page._on_optimize()
    assert page._solve.running and page.opt_button.disabled
    t0 = time.perf_counter()
    while page._solve.running and time.perf_counter() - t0 < 300:
        page.poll()
        time.sleep(0.2)
    assert "optimal" in page.opt_status.object
    assert page.dim_widgets["rod"][0].value == pytest.approx(200.0)
    assert page.last_result["value"] == pytest.approx(_optimum(), rel=1e-7)


@pytest.mark.slow
@pytest.mark.parametrize("key", list(kind_names()))
def test_every_default_problem_solves(key):
    """What Optimize runs on each mechanism the page starts with ends certified optimal."""
    out = model.solve_data(State.default(key).problem_data())
    assert out["status"] == "optimal", out["message"]
    assert out["certification"]["certified"]


def test_command_serves_the_page_and_prints_its_address(tmp_path):
    """`mechsynth explore --no-browser --json`: one JSON line once serving; the page answers."""
    import os
    import threading
    import urllib.request

    pytest.importorskip("panel")
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "mechsynth",
            "explore",
            "--mechanism",
            "four-bar",
            "--no-browser",
            "--json",
            "--out",
            str(tmp_path),
        ],
        cwd=ROOT,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        line = []
        reader = threading.Thread(target=lambda: line.append(proc.stdout.readline()))
        reader.start()
        reader.join(timeout=120)
        assert line and line[0].strip(), proc.stderr.read() if proc.poll() is not None else ""
        info = json.loads(line[0])
        assert info["host"] == "127.0.0.1" and info["url"] == f"http://127.0.0.1:{info['port']}/"
        assert info["out"] == str(tmp_path)
        with urllib.request.urlopen(info["url"], timeout=60) as r:
            html = r.read().decode()
        assert r.status == 200 and "mechsynth explore" in html
    finally:
        proc.terminate()
        proc.wait(timeout=30)


def test_page_loads_a_file_by_its_path_and_names_a_bad_one(page):
    page.file_input.value = str(EXAMPLES / "nope.toml")
    page._on_load()
    assert page.file_msg.visible and "nope.toml not found" in page.file_msg.object
    page.file_input.value = str(EXAMPLES / "optimize_six_link.toml")
    page._on_load()
    assert not page.file_msg.visible
    assert page.kind_select.value == "__file__"
    assert "Linkage from optimize_six_link.toml" in page.kind_select.options
    assert set(page.state.vary) == {"OA", "DB", "K_along", "KN"}
    assert page.dim_widgets["KN"][1].value  # its vary box is ticked
    assert "of N" in page.stats.object


def test_solve_worker_reports_failures_as_text():
    import queue

    q = queue.Queue()
    model.solve_worker({"mechanism": "nope"}, q)
    kind, text = q.get_nowait()
    assert kind == "error" and "Error: mechanism must be one of" in text


def test_page_exports_a_png_that_says_why_when_no_design_is_valid(tmp_path):
    pytest.importorskip("panel")
    from mechsynth.explore.app import Explorer

    st = State.default("slider-crank", units="mm-deg")
    st.values["rod"] = 0.05  # shorter than the crank: nothing valid to draw
    page = Explorer(st, out=tmp_path)
    assert page.design is None and page.design_msg.visible
    png = page._export_drawing().getvalue()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 1000
    assert "No valid design to draw" in page.export_msg.object
    chart = page._export_chart().getvalue()  # before any sweep: a PNG that says so
    assert chart[:8] == b"\x89PNG\r\n\x1a\n" and "press Sweep" in page.export_msg.object
    assert page.dl_chart.disabled


def test_fields_refuse_text_and_negative_speeds():
    st = State.default("slider-crank", units="mm-deg")
    with pytest.raises(MechanismError, match="'0.2x' is not a number"):
        model.parse_number("0.2x", "rod, mm")
    with pytest.raises(MechanismError, match="the field is empty"):
        model.parse_number("  ", "rod, mm")
    with pytest.raises(MechanismError, match="must be positive, or 0 for analogs.*got -600"):
        st.set_speed("-600")
    assert st.speed == pytest.approx(2 * np.pi * 10)  # unchanged
    st.set_speed("0")
    assert st.speed is None


def test_a_slider_driven_linkage_runs_over_its_travel():
    st = load_file(EXAMPLES / "optimize_cylinder_rocker.toml", units="mm-deg")
    design, message = st.check_design()
    assert message is None
    assert st.speed_field() == ("Input speed (driving slider), mm/s", 200.0)
    c = model.curves(st, design)
    lo, hi = design.input_range
    assert c["input_unit"] == "m" and c["angle"][0] == lo and c["angle"][-1] == hi


def test_motion_generation_in_the_page_loads_a_linkage_through_the_poses():
    pytest.importorskip("panel")
    import time

    from mechsynth.explore.app import Explorer

    page = Explorer(State.default("slider-crank", units="mm-deg"))
    page.poses_input.value = "0, 0\n"
    page._on_synthesize()
    while page._synth is not None:
        time.sleep(0.05)
        page.poll()
    assert "pose line 1: give x, y and angle (3 numbers), got 2" in page.synth_msg.object
    lines = (EXAMPLES / "motion_poses.csv").read_text().splitlines()[4:]
    page.poses_input.value = "\n".join(lines)  # five poses, mm and deg
    page._on_synthesize()
    while page._synth is not None:
        time.sleep(0.05)
        page.poll()
    assert "12 linkages through the 5 poses" in page.synth_msg.object
    page._on_load_candidate()
    assert page.state.kind.title == "Motion generation: solution 1"
    assert page.src_targets.data["x"][0] == pytest.approx(117.060890)
    # the loaded linkage's coupler point P passes through every target at the candidate's
    # crank angles (the library's own result, here through the page's state)
    cand = page._candidates[0]
    design = page.state.design()
    m = design.motion(np.asarray(cand.crank_angles))
    poses = np.loadtxt(EXAMPLES / "motion_poses.csv", delimiter=",", skiprows=4)
    assert np.asarray(m.points["P"].x) * 1e3 == pytest.approx(poses[:, 0], abs=1e-6)
    assert np.asarray(m.points["P"].y) * 1e3 == pytest.approx(poses[:, 1], abs=1e-6)


def test_a_dragged_fixed_pivot_moves_its_dimensions_or_snaps_back():
    pytest.importorskip("panel")
    from mechsynth.explore.app import Explorer

    page = Explorer(State.default("impact", units="mm-deg"))

    def drag(name, dx):
        data = {k: list(v) for k, v in page._ground_shown.items()}
        data["x"][data["name"].index(name)] += dx
        page.src_ground.data = data

    drag("D", -2.0)  # mm
    assert page.state.values["D_x"] == pytest.approx(0.078)
    assert page.dim_fields["D_x"].value == "78" and not page.design_msg.visible
    drag("D", 300.0)  # the dyad cannot reach: back where it was, with the reason
    assert page.state.values["D_x"] == pytest.approx(0.078)
    assert page.src_ground.data["x"][1] == pytest.approx(78.0)
    assert page.design_msg.visible and "cannot move D there: RRR group B" in (
        page.design_msg.object
    )
    drag("O", 5.0)  # O places the linkage's origin too: it is a dimension of the linkage
    assert page.state.values["O_x"] == pytest.approx(0.005)
    sc = Explorer(State.default("slider-crank", units="mm-deg"))
    data = {k: list(v) for k, v in sc._ground_shown.items()}
    data["x"][0] += 5.0
    sc.src_ground.data = data
    assert "O is the frame's origin of the Slider-crank: it stays" in sc.design_msg.object
    assert sc.src_ground.data["x"] == [0.0]
