"""Path and function generation in the explorer: the page's logic (:mod:`mechsynth.explore.
synthesis_model`) against the library's engines, the page object driven from Python, and (marked
``browser`` and ``slow``) what a user sees in headless Chromium: clicked and dragged targets and
poses, the ranked path generators (four-bars, slider-cranks, a point of the page's linkage; free
or prescribed crank angles), one previewed and loaded, a function generator's error curve,
design and certified min-max stage, and a linkage file of more than 16 dimensions opened after
the page loaded.
"""

import math
import os
import re
import time

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.errors import MechanismError
from mechsynth.explore import synthesis_model as sm
from mechsynth.explore.model import State
from mechsynth.synthesis.path_cases import exact_case


def exact_result():
    """A path result made without a search: exact_case's crank-rocker at a tenth of its size
    (crank 100 mm) as the one solution through six points of its coupler curve."""
    from mechsynth.synthesis.path_generation import evaluated
    from mechsynth.synthesis.path_result import PathResult

    _, design, angles = exact_case(6)
    vals = {k: v * (1 if k == "angle" else 0.1) for k, v in design.items()}
    sol = evaluated(vals, "open", angles, np.zeros((6, 2)))
    t = sol.trace(angles)
    sol = evaluated(vals, "open", angles, t)
    res = PathResult(
        targets=t, best=sol, solutions=(sol,), timing="free", objective="squares", closed=True,
        min_transmission=math.radians(30), starts=1, distinct=1, status="optimal", seconds=0.0,
        error_definition="",
    )  # fmt: skip
    return sm.PathJob(t, "free", math.radians(30), 1), res


@pytest.fixture(scope="module")
def path_result():
    """The page's default targets (six points on a known crank-rocker's coupler curve, mm)
    searched with 3 starts and a 30 deg minimum transmission angle."""
    st = State.default("slider-crank", units="mm-deg")
    job = sm.PathJob(sm.parse_points(sm.DEFAULT_POINTS, st), "free", math.radians(30), 3)
    seen = []
    res = sm.run_path(job, lambda d, k, n: seen.append((k, n)))
    return job, res, seen


def test_points_and_pairs_are_read_in_the_pages_units_and_bad_lines_named():
    st = State.default("slider-crank", units="mm-deg")
    pts = sm.parse_points(sm.DEFAULT_POINTS, st)
    # the default points are exact_case's, scaled to a 100 mm crank (m inside), to 0.01 mm
    want, _, _ = exact_case(6)
    assert pts == pytest.approx(want * 0.1, abs=1e-5)
    with pytest.raises(MechanismError, match=r"point line 2: give x and y \(2 numbers\), got 3"):
        sm.parse_points("1, 2\n1 2 3\n4, 5", st)
    with pytest.raises(MechanismError, match="point line 1: 'x' is not a number"):
        sm.parse_points("x, 2\n1, 2\n3, 4", st)
    with pytest.raises(MechanismError, match="3 or more target points, got 2"):
        sm.parse_points("1, 2\n3, 4\n# a comment", st)
    pairs = sm.parse_pairs("40, 70\n60 85\n80; 95")
    assert pairs == pytest.approx(np.radians([[40, 70], [60, 85], [80, 95]]))
    with pytest.raises(MechanismError, match="3 or more precision pairs, got 1"):
        sm.parse_pairs("1, 2")
    with pytest.raises(MechanismError, match="timing must be free, shape or prescribed"):
        sm.PathJob(pts, "given")
    with pytest.raises(MechanismError, match="one crank angle per target point: 6 points, got 0"):
        sm.PathJob(pts, "prescribed")
    with pytest.raises(MechanismError, match=r"in \[0, 90\) deg, got 95 deg"):
        sm.PathJob(pts, "free", math.radians(95))


@pytest.mark.slow
def test_a_path_search_reaches_the_points_and_its_solution_loads_as_the_same_linkage(
    path_result,
):
    job, res, seen = path_result
    assert seen and seen[-1] == (3, 3)  # every start reported
    rows = sm.path_rows(res)
    assert res.status == "optimal" and rows[0]["rank"] == 1
    # the points lie on a four-bar's coupler curve: the best passes through them (to the
    # 0.01 mm the points are typed with) with the transmission angle kept
    assert rows[0]["max_distance"] < 1e-6
    assert all(r["transmission"] >= math.radians(30) - 1e-6 for r in rows)
    assert [r["error"] for r in rows] == sorted(r["error"] for r in rows)
    sol = res.solutions[0]
    st = sm.path_state(sol, 1, "mm-deg")
    design, msg = st.check_design()
    assert msg is None and st.kind.title == "Path generation: solution 1"
    # the loaded linkage's P at the solution's crank angles is the solution's coupler point
    m = design.motion(sol.angles)
    p = np.column_stack([m.points["P"].x, m.points["P"].y])
    assert p == pytest.approx(sol.trace(sol.angles), abs=1e-12)
    assert p == pytest.approx(job.targets, abs=1e-6)
    pv = sm.path_preview(sol, n=60)
    assert pv["points"]["P"].shape == (60, 2) and pv["targets_angle"] == pytest.approx(sol.angles)
    assert pv["trace"] == "P" and ["A", "B", "P", "A"] in pv["links"]
    # its dimensions are the page's: lengths in mm, the crank's phase in deg
    assert st.shown(st.values["O1A"], "m") == pytest.approx(sol.crank * 1e3)
    assert st.shown(st.values["phase"], "rad") == pytest.approx(math.degrees(sol.angle))


def test_function_generation_as_the_library_gives_it_and_loaded_when_the_crank_turns():
    job = sm.FunctionJob("log10(x)", (1.0, 10.0), math.radians(60), math.radians(90), ground=0.1)
    fg = sm.run_function(job)
    ref = ms.function_generation(
        "log10(x)", x=(1, 10), input_range=ms.deg(60), output_range=ms.deg(90), ground=0.1,
        require_crank=True,
    )
    assert fg.max_error == pytest.approx(ref.max_error, rel=1e-12)
    assert fg.design.full_turn and fg.design.ground == pytest.approx(0.1)
    st = sm.function_state(fg, "mm-deg")
    design, msg = st.check_design()
    assert msg is None
    # the linkage's rocker angle at the crank angles of the precision points is the
    # generator's: O2 -> B against psi
    phi = np.asarray(fg.precision_points)[:, 0]
    m = design.motion(phi)
    psi = np.arctan2(m.points["B"].y, np.asarray(m.points["B"].x) - fg.design.ground)
    d = np.angle(np.exp(1j * (psi - np.asarray(fg.precision_points)[:, 1])))
    assert np.abs(d).max() < 1e-9
    pv = sm.function_preview(fg, n=30)
    assert set(pv) == {"O1", "A", "B", "O2"} and pv["A"].shape == (30, 2)
    # pairs: a least-squares design whose crank rocks cannot be loaded, and says why
    rocks = sm.run_function(
        sm.FunctionJob(pairs=np.radians([[40, 70], [60, 85], [80, 95], [100, 110]]),
                       require_crank=False)
    )  # fmt: skip
    assert not rocks.design.full_turn
    with pytest.raises(MechanismError, match="crank does not turn fully"):
        sm.function_state(rocks)


@pytest.fixture
def page():
    pytest.importorskip("panel")
    from mechsynth.explore.app import Explorer

    return Explorer(State.default("slider-crank", units="mm-deg"))


def test_the_page_object_clicks_targets_and_poses_and_loads_solutions(page):
    syn = page.synthesis
    assert len(syn.src_points.data["x"]) == 6  # the default points on the canvas
    syn.points_input.value = ""
    syn.click(10.0, 20.0)
    syn.click(30.0004, 40.0)  # to a thousandth of the canvas's size (here 0.1 mm)
    assert syn.points_input.value == "10, 20\n30, 40"
    assert syn.src_points.data["x"] == [10.0, 30.0] and syn.src_points.data["label"] == ["1", "2"]
    syn.start_path()  # two points: refused with the reason, no worker started
    assert not syn._path_run.running and "3 or more target points, got 2" in syn.path_msg.object
    page.view()
    syn.tasks.active = 0  # the motion generation's sub-tab: poses on the canvas, no points
    assert syn.src_points.data["x"] == [] and syn.fig.title.text.startswith("click to add a pose")
    syn.pose_angle.value = "45"
    n = len(page.poses_input.value.splitlines())
    syn.click(-5.0, 7.5)
    assert page.poses_input.value.splitlines()[-1] == "-5, 7.5, 45"
    assert len(syn.src_poses.data["x"]) == n + 1
    syn.drag(1.0, 2.0, 1.0, 2.0)  # no movement: nothing
    assert len(page.poses_input.value.splitlines()) == n + 1
    syn.drag(1.0, 2.0, 0.0, 3.0)  # up and to the left: a pose at the start at 135 deg
    assert page.poses_input.value.splitlines()[-1] == "1, 2, 135"
    assert syn.pose_angle.value == "135"
    syn.pose_angle.value = "north"
    syn.click(0.0, 0.0)
    assert "angle of a clicked pose, deg: 'north' is not a number" in page.synth_msg.object
    # a finished search: ranked in the table, the best previewed, loaded as the page's design
    job, res = exact_result()
    assert res.solutions[0].max_distance < 1e-12
    syn.tasks.active = 1
    syn.show_path(res, job.targets)
    assert syn.path_table.object.count("<tr>") == len(res.solutions) + 1
    assert "1 four-bar through the 6 points" in syn.path_msg.object
    meta = syn.src_meta.data["json"][0]
    assert '"n": 120' in meta and len(syn.src_frames.data["x:P"]) == 120
    page.units_select.value = "si"  # the table and the preview in metres
    assert "largest distance, m<" in syn.path_table.object
    assert syn.src_frames.data["x:P"][0] == pytest.approx(res.solutions[0].trace([0.0])[0, 0])
    page.units_select.value = "mm-deg"
    assert syn.src_frames.data["x:P"][0] == pytest.approx(
        res.solutions[0].trace([0.0])[0, 0] * 1e3
    )
    syn.load_path()
    assert page.state.kind.title == "Path generation: solution 1"
    assert page.design is not None and page.trace_select.value == ["P"]
    assert page.src_targets.data["x"] == pytest.approx((job.targets[:, 0] * 1e3).tolist())
    # function generation: the error curve, the design, loaded
    syn.tasks.active = 2
    assert syn.src_meta.data["json"][0] == '{"n": 0, "links": [], "pins": []}'  # none yet

    def generate():
        syn.start_function()
        t0 = time.time()
        while syn._function is not None and time.time() - t0 < 60:
            time.sleep(0.05)
            page.poll()

    syn.fn_text.value = "x**2"
    syn.fn_x0.value, syn.fn_x1.value = "0", "1"
    generate()  # no crank that turns fully spans it: the library's reason
    assert "no phases in a 5 deg scan give a design" in syn.fn_msg.object
    syn.fn_x0.value, syn.fn_x1.value = "1", "2"
    generate()
    assert "for y = x**2" in syn.fn_msg.object, syn.fn_msg.object
    ref = ms.function_generation(
        "x**2", x=(1, 2), input_range=ms.deg(60), output_range=ms.deg(90), ground=0.1,
        require_crank=True,
    )
    shown = float(syn.fn_design.object.split("function-max-error'>")[1].split("<")[0])
    assert shown == pytest.approx(math.degrees(ref.max_error), rel=1e-3)
    assert len(syn.src_err.data["x"]) == 401 and len(syn.src_prec.data["x"]) == 3
    assert not syn.fn_load.disabled
    syn.load_function()
    assert page.state.kind.title == "Function generation: y = x**2"
    syn.fn_x1.value = "one"
    syn.start_function()
    assert "x to: 'one' is not a number" in syn.fn_msg.object


# ------------------------------------------------------------------------------ timing, mechanisms
def test_prescribed_angles_are_read_or_evenly_spaced_and_bad_jobs_named():
    assert sm.parse_angles("0, 60 120\n180;240  # deg\n300", 6) == pytest.approx(
        np.radians([0, 60, 120, 180, 240, 300])
    )
    assert sm.even_angles(4) == pytest.approx([0, math.pi / 2, math.pi, 3 * math.pi / 2])
    with pytest.raises(MechanismError, match="one crank angle per target point: 3 points, got 2"):
        sm.parse_angles("0, 90", 3)
    with pytest.raises(MechanismError, match=r"crank angle \(line 1\), deg: 'x' is not a number"):
        sm.parse_angles("0, x, 90", 3)
    pts = np.zeros((3, 2))
    with pytest.raises(MechanismError, match="shape-only timing is the four-bar's"):
        sm.PathJob(pts, "shape", mechanism="slider-crank")
    with pytest.raises(MechanismError, match="crank angles are given with prescribed timing"):
        sm.PathJob(pts, "free", angles=np.zeros(3))
    with pytest.raises(MechanismError, match="needs its tables, the point to follow"):
        sm.PathJob(pts, mechanism="linkage")
    with pytest.raises(MechanismError, match="mechanism must be one of four-bar, slider-crank"):
        sm.PathJob(pts, mechanism="cam")
    six = State.default("linkage", units="mm-deg")
    var = sm.linkage_variables(six, ["DB", "K_along", "N_guide_angle"], 0.3)
    db, ka = six.values["DB"], six.values["K_along"]
    # a length within 30 % of its value; a signed offset within 30 % of the largest length
    # (the coupler AB, 120 mm); an angle within 30 % of 180 deg
    assert var["DB"] == pytest.approx((0.7 * db, 1.3 * db))
    assert var["K_along"] == pytest.approx((ka - 0.036, ka + 0.036))
    a = six.values["N_guide_angle"]
    assert var["N_guide_angle"] == pytest.approx((a - 0.3 * math.pi, a + 0.3 * math.pi))
    with pytest.raises(MechanismError, match="pick one or more dimensions"):
        sm.linkage_variables(six, [], 0.3)
    with pytest.raises(MechanismError, match=r"in \(0, 1000\] %, got -5 %"):
        sm.linkage_variables(six, ["DB"], -0.05)


@pytest.mark.slow
def test_prescribed_timing_passes_near_the_points_at_their_crank_angles():
    # the default points are exact_case's coupler points (scaled to a 100 mm crank) at its
    # crank angles 0.1, 0.7, ..., 3.8 rad (its four-bar, transmission angle 46 deg or more,
    # passes through them); with those angles prescribed the search finds that four-bar to
    # the points' rounding (0.005 mm a coordinate): 0.0017 mm (shape-matched starts alone
    # ended at a local optimum 0.071 mm away)
    st = State.default("slider-crank", units="mm-deg")
    _, design, angles = exact_case(6)
    job = sm.PathJob(sm.parse_points(sm.DEFAULT_POINTS, st), "prescribed", None, 6,
                     angles=angles[:6])  # fmt: skip
    res = sm.run_path(job)
    sol = res.solutions[0]
    assert res.status == "optimal" and res.timing == "prescribed"
    assert sol.max_distance < 1e-5  # m
    # the solution's crank angles keep the prescribed differences (only the start is free)
    d = np.angle(np.exp(1j * ((sol.angles - sol.angles[0]) - (angles[:6] - angles[0]))))
    assert np.abs(d).max() < 1e-9
    st = sm.path_state(sol, 1, "mm-deg")
    m = st.check_design()[0].motion(sol.angles)
    p = np.column_stack([m.points["P"].x, m.points["P"].y])
    assert p == pytest.approx(sol.trace(sol.angles), abs=1e-12)
    assert np.hypot(*(p - job.targets).T).max() == pytest.approx(sol.max_distance, rel=1e-9)


def test_a_slider_crank_through_the_points_loads_as_the_same_linkage():
    from mechsynth.synthesis.linkage_file import linkage_from_data

    st = State.default("slider-crank", units="mm-deg")
    job = sm.PathJob(sm.parse_points(sm.DEFAULT_POINTS, st), "free", math.radians(30), 2,
                     mechanism="slider-crank")  # fmt: skip
    res = sm.run_path(job)
    rows = sm.path_rows(res)
    sol = res.solutions[0]
    # nine dimensions and six crank angles for twelve coordinates: through the points
    assert res.status == "optimal" and rows[0]["max_distance"] < 1e-9
    assert rows[0]["transmission"] >= math.radians(30) - 1e-6
    assert [n for n, _, _ in rows[0]["dims"]][:4] == ["O_x", "O_y", "OA", "AB"]
    tables = sm.slider_crank_tables(sol)
    assert linkage_from_data(tables).parameters == pytest.approx(sol.linkage.parameters)
    loaded = sm.path_state(sol, 1, "mm-deg")
    assert loaded.kind.title == "Path generation: solution 1" and loaded.kind.trace == ("P",)
    design, msg = loaded.check_design()
    assert msg is None
    m = design.motion(sol.angles)
    assert np.column_stack([m.points["P"].x, m.points["P"].y]) == pytest.approx(
        job.targets, abs=1e-9
    )
    pv = sm.path_preview(sol, n=24)
    assert pv["trace"] == "P" and ["A", "B", "P", "A"] in pv["links"]
    assert pv["points"]["P"] == pytest.approx(sol.trace(np.linspace(0, 2 * np.pi, 24,
                                                                    endpoint=False)))  # fmt: skip


def test_path_generation_over_the_pages_linkage_finds_its_changed_dimension():
    # the six-link's point K at six crank angles with DB 5 % shorter: DB, K's place on its
    # link and the crank varied from the page's design, the angles prescribed
    six = State.default("linkage", units="mm-deg")
    values = dict(six.values, DB=six.values["DB"] * 0.95)
    phi = sm.even_angles(6)
    p = six.kind.build(values).motion(phi).points["K"]
    targets = np.column_stack([p.x, p.y])
    job = sm.PathJob(
        targets, "prescribed", None, 2, angles=phi, mechanism="linkage",
        tables=six.kind.file_data, values=dict(six.values), trace="K",
        variables=sm.linkage_variables(six, ["DB", "K_along", "OA"], 0.3),
    )  # fmt: skip
    res = sm.run_path(job)
    sol = res.solutions[0]
    assert res.status == "optimal" and sol.max_distance < 1e-9
    assert sol.values["DB"] == pytest.approx(values["DB"], rel=1e-7)
    loaded = sm.path_state(sol, 1, "mm-deg", tables=six.kind.file_data)
    assert loaded.kind.trace == ("K",) and loaded.kind.file_data["linkage"]["output"] == "K"
    assert loaded.values["DB"] == sol.values["DB"]  # exact, not the tables' 6 digits
    assert loaded.values["KN"] == six.values["KN"]  # not varied: the page's
    design, msg = loaded.check_design()
    assert msg is None
    m = design.motion(sol.angles)
    assert np.column_stack([m.points["K"].x, m.points["K"].y]) == pytest.approx(
        targets, abs=1e-9
    )
    pv = sm.path_preview(sol, n=12)
    assert pv["pins"] == ["O", "D", "A", "B", "K", "N"] and ["D", "B", "K", "D"] in pv["links"]
    with pytest.raises(MechanismError, match="driven by a slider"):
        rocker = load_cylinder_rocker()
        sm.run_path(sm.PathJob(targets, mechanism="linkage", tables=rocker.kind.file_data,
                               trace="B", variables={"AB": (0.1, 1.0)}))  # fmt: skip


def load_cylinder_rocker():
    from pathlib import Path

    from mechsynth.explore.model import load_file

    root = Path(__file__).resolve().parents[1]
    return load_file(root / "examples" / "optimize_cylinder_rocker.toml", "mm-deg")


def test_the_min_max_stage_lowers_the_worst_error_and_its_certificate_holds_on_a_dense_grid():
    job = sm.FunctionJob("log10(x)", (1.0, 10.0), math.radians(60), math.radians(90), ground=0.1)
    seen = []
    fg = sm.run_minmax(job, lambda d, k, n: seen.append((k, n)))
    assert seen[-1] == (1, 1)
    start = sm.run_function(job)
    assert fg.method == "min-max" and fg.start_max_error == pytest.approx(start.max_error)
    assert fg.solve.status == "optimal" and fg.solve.certification.certified
    assert fg.max_error < 0.7 * start.max_error  # 8.98 -> 5.57 deg on this machine
    assert fg.design.full_turn and fg.min_transmission_angle >= math.radians(30) * (1 - 1e-6)
    # the certificate checked independently: the loaded linkage's rocker over 20001 inputs
    st = sm.function_state(fg, "mm-deg")
    x = np.linspace(1.0, 10.0, 20001)
    phi = fg.phases[0] + (x - 1.0) / 9.0 * fg.spans[0]
    m = st.check_design()[0].motion(phi)
    psi = np.arctan2(m.points["B"].y, np.asarray(m.points["B"].x) - fg.design.ground)
    ideal = fg.phases[1] + fg.spans[1] * np.log10(x)
    err = np.angle(np.exp(1j * (psi - ideal)))
    assert np.abs(err).max() == pytest.approx(fg.max_error, rel=1e-6)
    words = sm.certificate_words(fg)
    before, after = math.degrees(start.max_error), math.degrees(fg.max_error)
    assert f"{before:.4g} deg before the min-max stage, {after:.4g} deg after" in words
    assert "certified: the worst error is the true one over the whole input range" in words
    with pytest.raises(MechanismError, match="min-max stage needs a function"):
        sm.run_minmax(sm.FunctionJob(pairs=np.radians([[40, 70], [60, 85], [80, 95]])))


def test_the_page_object_drags_targets_and_undoes_the_moves(page):
    syn = page.synthesis
    page.view()
    syn.tasks.active = 1
    syn.points_input.value = "0, 0\n# a comment\n100, 0  # the second\n50, 80"
    assert syn._fitted is not None
    syn.drag(100.5, 0.5, 110.0, 20.0)  # from near point 2 (within 3 % of the view)
    assert syn.points_input.value == "0, 0\n# a comment\n110, 20  # the second\n50, 80"
    assert syn.src_points.data["x"] == [0.0, 110.0, 50.0] and not syn.undo_move.disabled
    syn.drag(60.0, 40.0, 70.0, 50.0)  # from nowhere near a point: nothing
    assert syn.points_input.value.splitlines()[2] == "110, 20  # the second"
    syn.move_target("point", 0, -10.0, 5.0)
    assert syn.points_input.value.splitlines()[0] == "-10, 5"
    syn.undo_target_move()
    syn.undo_target_move()
    assert syn.points_input.value == "0, 0\n# a comment\n100, 0  # the second\n50, 80"
    assert syn.undo_move.disabled
    # poses: moved by their square, turned by their line's end
    syn.tasks.active = 0
    page.poses_input.value = "0, 0, 0\n100, 0, 90"
    syn.drag(100.0, 0.0, 120.0, 10.0)
    assert page.poses_input.value == "0, 0, 0\n120, 10, 90"
    tip = syn.src_poses.data["xs"][1][1], syn.src_poses.data["ys"][1][1]
    assert tip[0] == pytest.approx(120.0) and tip[1] > 10.0  # its line, at 90 deg
    syn.drag(*tip, 120.0 - 30.0, 10.0 + 30.0)  # its line's end dragged up and to the left
    assert page.poses_input.value == "0, 0, 0\n120, 10, 135"
    syn.undo_target_move()
    assert page.poses_input.value == "0, 0, 0\n120, 10, 90"
    n = len(page.poses_input.value.splitlines())
    syn.drag(50.0, 50.0, 50.0, 60.0)  # elsewhere: a new pose, as before
    assert len(page.poses_input.value.splitlines()) == n + 1
    assert page.poses_input.value.splitlines()[-1] == "50, 50, 90"


@pytest.mark.slow
def test_the_page_object_searches_its_linkage_and_runs_the_min_max(page):
    syn = page.synthesis
    page.view()
    syn.tasks.active = 1
    syn.path_mech.value = "linkage"  # the page shows the slider-crank: refused, with why
    assert "the page shows the Slider-crank, not a linkage" in syn.path_msg.object
    assert syn.path_linkage_row.visible
    page.kind_select.value = "linkage"
    page.poll()  # the options follow the page's linkage
    assert syn.path_trace.options == ["A", "B", "K", "N"] and syn.path_trace.value == "N"
    assert "phase" not in syn.path_vary.value and "DB" in syn.path_vary.value
    syn.path_trace.value = "K"
    syn.points_from_linkage()
    k = page.state.kind.build(dict(page.state.values)).motion(sm.even_angles(6)).points["K"]
    shown = np.array(
        [[float(v) for v in line.split(",")] for line in syn.points_input.value.splitlines()]
    )
    assert shown == pytest.approx(np.column_stack([k.x, k.y]) * 1e3, abs=1e-3)
    syn.timing.value = "prescribed"
    assert syn.path_angles_row.visible
    syn.even_angles()
    assert syn.path_angles.value == "0, 60, 120, 180, 240, 300"
    syn.path_vary.value = ["DB", "OA"]
    job = syn.path_job()
    assert job.mechanism == "linkage" and job.trace == "K" and set(job.variables) == {"DB", "OA"}
    assert job.angles == pytest.approx(sm.even_angles(6))
    syn.path_angles.value = "0, 60"
    syn.start_path()
    assert not syn._path_run.running
    assert "6 points, got 2 angles" in syn.path_msg.object
    # a linkage driven by a slider: refused before any process starts, with why
    page._load_state(load_cylinder_rocker(), "optimize_cylinder_rocker.toml")
    page.poll()
    syn.timing.value = "free"
    syn.start_path()
    assert not syn._path_run.running
    assert "is driven by a slider: path generation turns a crank" in syn.path_msg.object
    # the function generator, then its min-max stage in a worker process
    syn.tasks.active = 2
    assert syn.fn_minmax.disabled  # nothing to start from yet
    syn.start_function()
    t0 = time.time()
    while syn._function is not None and time.time() - t0 < 60:
        time.sleep(0.05)
        page.poll()
    assert not syn.fn_minmax.disabled and syn.src_err_before.data["y"] == []
    start = syn._fg
    syn.start_minmax()
    syn.cancel_minmax()  # at once: the process ends, reaped, the button back
    assert not syn._mm_run.running and "min-max cancelled" in syn.fn_cert.object
    assert not syn.fn_minmax.disabled and syn._fg is start
    syn.fn_text.value = "x**2"  # edited after: the min-max is of the generator shown
    syn.start_minmax()
    assert syn._mm_run.running and syn.fn_minmax.disabled and not syn.fn_mm_cancel.disabled
    t0 = time.time()
    while syn._mm_run.running and time.time() - t0 < 120:
        time.sleep(0.1)
        page.poll()
    fg = syn._fg
    assert fg.method == "min-max" and fg.function == "log10(x)", syn.fn_cert.object
    assert fg.start_max_error == pytest.approx(start.max_error)
    assert "certified: the worst error is the true one" in syn.fn_cert.object
    assert syn.src_err_before.data["y"] == pytest.approx(np.degrees(start.error).tolist())
    assert max(abs(v) for v in syn.src_err.data["y"]) == pytest.approx(
        math.degrees(fg.max_error)
    )
    assert syn.fn_minmax.disabled  # done: again would find the same
    syn.load_function()
    assert page.state.values["O1A"] == pytest.approx(fg.design.crank)
    assert not [c for c in _children(os.getpid()) if c[1].startswith("Z")]  # reaped


# ------------------------------------------------------------------------------ in a browser
# (the page as a user sees it; Chromium and the server started once for these tests)
from test_explore_visible import _children, _open, _select, browser, server  # noqa: E402, F401

CANVAS = """([x, y]) => { const d = Bokeh.documents[0], f = d.get_model_by_name('synth-canvas');
  const v = Bokeh.index.find_one(f), r = v.canvas_view.el.getBoundingClientRect();
  return [r.left + v.frame.x_scale.compute(x), r.top + v.frame.y_scale.compute(y)]; }"""
# the largest distance (display units) from a target to the path P takes in the browser
GAP = """(p) => { const d = Bokeh.documents[0];
  const F = d.get_model_by_name('frames').data, T = d.get_model_by_name('targets').data_source.data;
  let worst = 0;
  for (let i = 0; i < T.x.length; i++) {
    let best = Infinity;
    for (let k = 0; k < F['x:' + p].length; k++)
      best = Math.min(best, Math.hypot(F['x:' + p][k] - T.x[i], F['y:' + p][k] - T.y[i]));
    worst = Math.max(worst, best);
  }
  return [T.x.length, worst]; }"""


def _menu_shows(page, text, timeout=120.0):
    """Wait until the mechanism menu shows ``text``; return what it shows."""
    menu = page.get_by_label("Mechanism", exact=True)
    t0, shown = time.time(), None
    while time.time() - t0 < timeout:
        shown = menu.evaluate("e => e.options[e.selectedIndex].text")
        if shown == text:
            break
        page.wait_for_timeout(200)
    return shown


def _data(page, name, col):
    return page.evaluate(
        "([n, c]) => Array.from(Bokeh.documents[0].get_model_by_name(n).data[c] || [])",
        [name, col],
    )


@pytest.mark.browser
@pytest.mark.slow
def test_in_the_browser_clicked_points_ranked_path_generators_previewed_and_one_loaded(
    browser, server  # noqa: F811 - the fixtures imported above
):
    from playwright.sync_api import expect

    page = _open(browser, server)
    page.set_default_timeout(120_000)  # a new mechanism on a loaded machine: tens of s
    try:
        page.get_by_text("Synthesis", exact=True).click()
        page.get_by_text("Path (points)", exact=True).click()
        points = page.get_by_label("Target points of the coupler point, one a line: x, y (mm)")
        expect(points).to_have_value(sm.DEFAULT_POINTS, timeout=30_000)
        page.wait_for_function(  # drawn on the canvas
            "() => Bokeh.documents[0].get_model_by_name('synth-points').data.x.length === 6",
            timeout=20_000,
        )
        # a click on the canvas at (0, 100) mm adds a point there, drawn as the 7th
        page.mouse.click(*page.evaluate(CANVAS, [0, 100]))
        page.wait_for_function(
            "() => Bokeh.documents[0].get_model_by_name('synth-points').data.x.length === 7",
            timeout=20_000,
        )
        expect(points).to_have_value(re.compile(r"36\.55\n[^\n]+$"), timeout=30_000)  # a 7th
        x, y = (float(v) for v in points.input_value().splitlines()[-1].split(","))
        assert (x, y) == (pytest.approx(0, abs=0.5), pytest.approx(100, abs=0.5))
        # many starts, then Cancel: the search's process ends, no zombie behind it
        page.get_by_label("Path starts").fill("200")
        page.get_by_role("button", name="Find path generators").click()
        page.locator("#path-state").get_by_text("searching").wait_for(timeout=20_000)
        page.get_by_role("button", name="Cancel the search").click()
        page.locator("#path-state").get_by_text("cancelled").wait_for(timeout=20_000)
        page.wait_for_timeout(500)
        assert not [c for c in _children(server["pid"]) if c[1].startswith("Z")]
        # the six points on a crank-rocker's coupler curve, 3 starts: found and ranked
        points.fill(sm.DEFAULT_POINTS)
        page.get_by_label("Path starts").fill("3")
        page.get_by_label("Path starts").press("Enter")
        page.wait_for_timeout(500)
        page.get_by_role("button", name="Find path generators").click()
        page.locator("#path-table").wait_for(timeout=180_000)
        state = page.locator("#path-state").inner_text()
        assert "four-bars through the 6 points" in state, state
        rows = page.locator("#path-table tr")
        assert rows.count() >= 2
        first = rows.nth(1).locator("td").all_inner_texts()
        assert first[0] == "1" and float(first[1]) < 1e-3  # largest distance, mm
        assert float(first[3]) >= 30.0 - 1e-6  # the transmission angle asked for
        # the preview: the four-bar moves (Play) and its P's curve passes the points
        page.wait_for_function(
            "() => Bokeh.documents[0].get_model_by_name('synth-curve').data.x.length > 100",
            timeout=20_000,
        )
        before = _data(page, "synth-links", "xs")
        page.get_by_role("button", name="Play preview").click()
        page.wait_for_timeout(600)
        assert _data(page, "synth-links", "xs") != before
        page.get_by_role("button", name="Pause preview").click()
        # loaded: the page's mechanism, drawn over the targets its P passes through
        page.get_by_role("button", name="Load the path generator").click()
        assert _menu_shows(page, "Path generation: solution 1") == "Path generation: solution 1"
        page.wait_for_function(
            "() => Bokeh.documents[0].get_model_by_name('targets').data_source.data.x.length"
            " === 6",
            timeout=30_000,
        )
        page.wait_for_timeout(800)
        n, gap = page.evaluate(GAP, "P")
        assert n == 6 and gap < 3.0  # mm: within the spacing of the 180 frames sent
        expect(page.get_by_label("O1A, mm", exact=True)).to_be_visible(timeout=30_000)
    finally:
        page.close()


@pytest.mark.browser
@pytest.mark.slow
def test_in_the_browser_a_function_generator_and_clicked_and_dragged_poses(
    browser, server  # noqa: F811
):
    from playwright.sync_api import expect

    page = _open(browser, server)
    page.set_default_timeout(120_000)  # a new mechanism on a loaded machine: tens of s
    try:
        page.get_by_text("Synthesis", exact=True).click()
        page.get_by_text("Function (y = f(x))", exact=True).click()
        page.get_by_role("button", name="Generate the function").click()
        page.locator("#function-design").wait_for(timeout=60_000)
        ref = ms.function_generation(
            "log10(x)", x=(1, 10), input_range=ms.deg(60), output_range=ms.deg(90), ground=0.1,
            require_crank=True,
        )  # fmt: skip
        shown = float(page.locator("#function-max-error").inner_text())
        assert shown == pytest.approx(math.degrees(ref.max_error), rel=1e-3)
        err = _data(page, "function-error-curve", "y")
        assert len(err) == 401
        assert max(abs(v) for v in err) == pytest.approx(math.degrees(ref.max_error), rel=1e-6)
        assert "crank <b>" in page.locator("#function-design").inner_html()
        # a click on the function's tab places nothing; on the motion's it places a pose
        page.get_by_text("Motion (poses)", exact=True).click()
        page.get_by_label("Angle of a clicked pose, deg").fill("30")
        page.get_by_label("Angle of a clicked pose, deg").press("Enter")
        page.wait_for_timeout(500)
        poses = page.get_by_label(
            "Target poses of the coupler, one a line: x, y (mm), angle (deg)", exact=True
        )
        n = len(poses.input_value().splitlines())
        page.mouse.click(*page.evaluate(CANVAS, [0, 100]))
        page.wait_for_function(
            f"() => Bokeh.documents[0].get_model_by_name('synth-poses').data.x.length === {n + 1}",
            timeout=20_000,
        )
        expect(poses).to_have_value(re.compile(r", 30$"), timeout=30_000)  # at 30 deg
        x, y, a = (float(v) for v in poses.input_value().splitlines()[-1].split(","))
        assert (x, y, a) == (pytest.approx(0, abs=1), pytest.approx(100, abs=1), 30.0)
        # a drag from that pose's square moves it; from its line's end turns it
        _drag(page, page.evaluate(CANVAS, [0, 100]), page.evaluate(CANVAS, [40, 140]))
        expect(poses).not_to_have_value(re.compile(r"\n0, 100, 30$"), timeout=30_000)
        x, y, a = (float(v) for v in poses.input_value().splitlines()[-1].split(","))
        assert (x, y, a) == (pytest.approx(40, abs=2), pytest.approx(140, abs=2), 30.0)
        page.wait_for_timeout(500)
        tip = page.evaluate(
            f"() => {{ const P = Bokeh.documents[0].get_model_by_name('synth-poses').data;"
            f" return [P.xs[{n}][1], P.ys[{n}][1]]; }}"
        )
        _drag(page, page.evaluate(CANVAS, tip), page.evaluate(CANVAS, [x, tip[1] + 30]))
        expect(poses).to_have_value(re.compile(r", 90$"), timeout=30_000)  # straight up
        x2, y2, _ = (float(v) for v in poses.input_value().splitlines()[-1].split(","))
        assert (x2, y2) == (x, y)
        page.get_by_role("button", name="Undo the pose move").click()
        expect(poses).to_have_value(re.compile(r", 30$"), timeout=30_000)
        # a drag from an empty place (up and to the right): a new pose there at 45 deg
        _drag(page, page.evaluate(CANVAS, [0, 100]), page.evaluate(CANVAS, [40, 140]))
        expect(poses).to_have_value(re.compile(r", 45$"), timeout=30_000)
        x, y, a = (float(v) for v in poses.input_value().splitlines()[-1].split(","))
        assert (x, y) == (pytest.approx(0, abs=2), pytest.approx(100, abs=2))
        assert len(poses.input_value().splitlines()) == n + 2
        # back to the function generator, loaded into the page
        page.get_by_text("Function (y = f(x))", exact=True).click()
        page.get_by_role("button", name="Load the function generator").click()
        title = "Function generation: y = log10(x)"
        assert _menu_shows(page, title) == title
        expect(page.get_by_label("O1A, mm", exact=True)).to_have_value(
            f"{ref.design.crank * 1e3:.6g}", timeout=30_000
        )
    finally:
        page.close()


BIG = """[linkage]
name = "eight-link"
output = "C"

[ground]
O = [0, 0]
D = ["120 mm", "50 mm"]
E = ["200 mm", "150 mm"]

[[group]]
type = "crank"
point = "A"
about = "O"
length = "30 mm"

[[group]]
type = "rrr"
point = "B"
first = ["A", "120 mm"]
second = ["D", "80 mm"]

[[group]]
type = "attach"
point = "K"
on = ["D", "B"]
along = "-50 mm"

[[group]]
type = "rrp"
point = "N"
rod = ["K", "100 mm"]
guide = { through = ["120 mm", 0], angle = "57 deg" }

[[group]]
type = "rrr"
point = "C"
first = ["B", "100 mm"]
second = ["E", "123 mm"]
"""


@pytest.mark.browser
@pytest.mark.slow
def test_in_the_browser_a_file_of_18_dimensions_opened_later_shows_every_row(
    browser, server, tmp_path  # noqa: F811
):
    from playwright.sync_api import expect

    from mechsynth.explore.app import MIN_ROWS
    from mechsynth.explore.model import load_file

    path = tmp_path / "eight_link.toml"
    path.write_text(BIG)
    dims = load_file(path, "mm-deg").kind.dims
    assert len(dims) == 18 > MIN_ROWS
    page = _open(browser, server)
    page.set_default_timeout(120_000)  # a new mechanism on a loaded machine: tens of s
    try:
        page.locator(".upload input[type=file]").set_input_files(str(path))
        # the rows beyond the ones made with the page: shown, labelled, with the file's values
        expect(page.get_by_label("EC, mm", exact=True)).to_have_value("123", timeout=120_000)
        expect(page.get_by_label("BC, mm", exact=True)).to_have_value("100", timeout=60_000)
        for d in dims:
            unit = "deg" if d.unit == "rad" else "mm"
            field = page.get_by_label(f"{d.name}, {unit}", exact=True)
            expect(field).to_be_visible(timeout=120_000)
        # and a row past the 16th works: its field moves the design
        before = page.evaluate("() => Bokeh.documents[0].get_model_by_name('meta').data.json[0]")
        page.get_by_label("EC, mm", exact=True).fill("130")
        page.get_by_label("EC, mm", exact=True).press("Enter")
        page.wait_for_function(
            "(b) => Bokeh.documents[0].get_model_by_name('meta').data.json[0] !== b",
            arg=before, timeout=120_000,
        )  # fmt: skip
        _select(page, "Mechanism", "Four-bar")  # fewer dimensions: the rest hidden
        expect(page.get_by_label("ground, mm", exact=True)).to_be_visible(timeout=120_000)
        assert page.get_by_label("EC, mm", exact=True).count() == 0
    finally:
        page.close()


def _drag(page, a, b):
    """A mouse drag on the page from ``a`` to ``b`` (pixels)."""
    page.mouse.move(*a)
    page.mouse.down()
    page.mouse.move((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, steps=4)
    page.mouse.move(*b, steps=4)
    page.mouse.up()


def _loaded(page, title, n, point):
    """Wait until the page shows ``title`` with ``n`` targets on its drawing; return the
    largest distance (mm) from a target to the path of ``point`` sent to the browser."""
    assert _menu_shows(page, title) == title
    page.wait_for_function(
        f"() => Bokeh.documents[0].get_model_by_name('targets').data_source.data.x.length"
        f" === {n}",
        timeout=30_000,
    )
    page.wait_for_timeout(800)
    shown, gap = page.evaluate(GAP, point)
    assert shown == n
    return gap


@pytest.mark.browser
@pytest.mark.slow
def test_in_the_browser_a_dragged_point_and_slider_cranks_free_and_at_prescribed_angles(
    browser, server  # noqa: F811
):
    from playwright.sync_api import expect

    page = _open(browser, server)
    page.set_default_timeout(120_000)
    try:
        page.get_by_text("Synthesis", exact=True).click()
        page.get_by_text("Path (points)", exact=True).click()
        points = page.get_by_label("Target points of the coupler point, one a line: x, y (mm)")
        expect(points).to_have_value(sm.DEFAULT_POINTS, timeout=30_000)
        page.wait_for_function(
            "() => Bokeh.documents[0].get_model_by_name('synth-points').data.x.length === 6",
            timeout=20_000,
        )
        # point 1 (61.42, 166.96) mm dragged to (45, 190): its line and its mark follow
        _drag(page, page.evaluate(CANVAS, [61.42, 166.96]), page.evaluate(CANVAS, [45, 190]))
        expect(points).not_to_have_value(sm.DEFAULT_POINTS, timeout=30_000)
        lines = points.input_value().splitlines()
        x, y = (float(v) for v in lines[0].split(","))
        assert (x, y) == (pytest.approx(45, abs=1), pytest.approx(190, abs=1))
        assert lines[1:] == sm.DEFAULT_POINTS.splitlines()[1:]
        page.wait_for_function(
            "() => Math.abs(Bokeh.documents[0].get_model_by_name('synth-points').data.x[0]"
            " - 45) < 1", timeout=20_000,
        )  # fmt: skip
        page.get_by_role("button", name="Undo the target move").click()
        expect(points).to_have_value(sm.DEFAULT_POINTS, timeout=30_000)
        expect(page.get_by_role("button", name="Undo the target move")).to_be_disabled()
        # a slider-crank through the six points, free timing
        page.get_by_label("Mechanism to synthesize").select_option(
            label="slider-crank: a point on its rod"
        )
        page.get_by_label("Path starts").fill("2")
        page.get_by_label("Path starts").press("Enter")
        page.wait_for_timeout(500)
        page.get_by_role("button", name="Find path generators").click()
        state = page.locator("#path-state")
        state.get_by_text(re.compile(r"slider-cranks? through the 6")).wait_for(timeout=180_000)
        head = page.locator("#path-table tr").nth(0).locator("th").all_inner_texts()
        assert head[4:8] == ["O_x, mm", "O_y, mm", "OA, mm", "AB, mm"]
        assert "guide_angle, deg" in head
        first = page.locator("#path-table tr").nth(1).locator("td").all_inner_texts()
        assert first[0] == "1" and float(first[1]) < 1e-3 and float(first[3]) >= 30 - 1e-6
        page.wait_for_function(  # the preview's path over the points
            "() => Bokeh.documents[0].get_model_by_name('synth-curve').data.x.length > 100",
            timeout=20_000,
        )
        page.get_by_role("button", name="Load the path generator").click()
        gap = _loaded(page, "Path generation: solution 1", 6, "P")
        assert gap < 3.0  # mm: within the spacing of the frames sent
        expect(page.get_by_label("AB, mm", exact=True)).to_have_value(
            f"{float(first[7]):.6g}", timeout=30_000
        )
        # a four-bar at prescribed crank angles, evenly spaced by the button
        page.get_by_text("Synthesis", exact=True).click()
        page.get_by_label("Mechanism to synthesize").select_option(
            label="four-bar: its coupler point"
        )
        page.get_by_label("Timing").select_option(
            label="prescribed: the crank angle at each point given"
        )
        angles = page.get_by_label(
            "Crank angle at each point, deg (only their differences count)"
        )
        page.get_by_role("button", name="Evenly spaced angles").click()
        expect(angles).to_have_value("0, 60, 120, 180, 240, 300", timeout=30_000)
        page.get_by_role("button", name="Find path generators").click()
        state.get_by_text(re.compile(r"four-bars? through the 6 points, at the crank angles "
                                     "given")).wait_for(timeout=180_000)  # fmt: skip
        head = page.locator("#path-table tr").nth(0).locator("th").all_inner_texts()
        assert head[4:8] == ["crank, mm", "coupler, mm", "rocker, mm", "ground, mm"]
        # 21.0 mm at best at these angles (2 starts); the points' own angles are not even
        first = page.locator("#path-table tr").nth(1).locator("td").all_inner_texts()
        assert 1.0 < float(first[1]) < 50.0
    finally:
        page.close()


@pytest.mark.browser
@pytest.mark.slow
def test_in_the_browser_a_point_of_the_six_link_synthesized_and_a_certified_min_max(
    browser, server  # noqa: F811
):
    from playwright.sync_api import expect

    page = _open(browser, server)
    page.set_default_timeout(120_000)
    try:
        _select(page, "Mechanism", "Linkage (six-link of paper 001, or a TOML file)")
        expect(page.get_by_label("KN, mm", exact=True)).to_be_visible(timeout=120_000)
        page.get_by_text("Synthesis", exact=True).click()
        page.get_by_text("Path (points)", exact=True).click()
        page.get_by_label("Mechanism to synthesize").select_option(
            label="the page's linkage: a point of it"
        )
        trace = page.get_by_label("Point to follow")
        expect(trace).to_be_visible(timeout=30_000)
        trace.select_option("K")
        page.wait_for_timeout(500)
        page.get_by_role("button", name="Six points of the followed point's path").click()
        points = page.get_by_label("Target points of the coupler point, one a line: x, y (mm)")
        expect(points).not_to_have_value(sm.DEFAULT_POINTS, timeout=30_000)
        six = State.default("linkage", units="mm-deg")
        k = six.kind.build(six.values).motion(sm.even_angles(6)).points["K"]
        want = np.column_stack([k.x, k.y]) * 1e3
        got = np.array([[float(v) for v in r.split(",")] for r in points.input_value().split("\n")])
        assert got == pytest.approx(want, abs=1e-3)
        # the first point dragged 4 mm towards the others' centre: no longer on K's path
        page.wait_for_function(  # the points drawn, the view fitted to them
            """([x, y]) => { const d = Bokeh.documents[0];
              const P = d.get_model_by_name('synth-points').data;
              const f = d.get_model_by_name('synth-canvas');
              return P.x.length === 6 && Math.abs(P.x[0] - x) < 0.01
                && f.x_range.start < x && x < f.x_range.end
                && f.y_range.start < y && y < f.y_range.end; }""",
            arg=want[0].tolist(), timeout=20_000,
        )  # fmt: skip
        page.wait_for_timeout(1000)
        towards = want.mean(axis=0) - want[0]
        end = want[0] + 4.0 * towards / np.hypot(*towards)
        _drag(page, page.evaluate(CANVAS, want[0].tolist()), page.evaluate(CANVAS, end.tolist()))
        expect(points).not_to_have_value(points.input_value(), timeout=30_000)
        moved = [float(v) for v in points.input_value().split("\n")[0].split(",")]
        assert moved == [pytest.approx(end[0], abs=1), pytest.approx(end[1], abs=1)]
        page.get_by_label("Path starts").fill("2")
        page.get_by_label("Path starts").press("Enter")
        page.wait_for_timeout(500)
        page.get_by_role("button", name="Find path generators").click()
        state = page.locator("#path-state")
        state.get_by_text(re.compile(r"designs? through the 6 points")).wait_for(timeout=180_000)
        head = page.locator("#path-table tr").nth(0).locator("th").all_inner_texts()
        assert "DB, mm" in head and "phase, deg" not in head  # the phase is not varied
        first = page.locator("#path-table tr").nth(1).locator("td").all_inner_texts()
        assert float(first[1]) < 1.0  # mm: the dimensions around the design reach the point
        page.get_by_role("button", name="Load the path generator").click()
        gap = _loaded(page, "Path generation: solution 1", 6, "K")
        assert gap < float(first[1]) + 3.0  # mm: its distance, and the frames' spacing
        # the function generator and its certified min-max stage
        page.get_by_text("Synthesis", exact=True).click()
        page.get_by_text("Function (y = f(x))", exact=True).click()
        page.get_by_role("button", name="Generate the function").click()
        page.locator("#function-design").wait_for(timeout=60_000)
        page.get_by_role("button", name="Minimize the worst error (certified min-max)").click()
        cert = page.locator("#function-certificate")
        cert.get_by_text("certified: the worst error is the true one").wait_for(timeout=180_000)
        ref = ms.function_generation(
            "log10(x)", x=(1, 10), input_range=ms.deg(60), output_range=ms.deg(90), ground=0.1,
            require_crank=True, optimize=True,
        )  # fmt: skip
        words = cert.inner_text()
        before, after = math.degrees(ref.start_max_error), math.degrees(ref.max_error)
        assert f"{before:.4g} deg before the min-max stage, {after:.4g} deg after" in words
        shown = float(page.locator("#function-max-error").inner_text())
        assert shown == pytest.approx(after, rel=1e-3)
        assert len(_data(page, "function-error-before", "y")) == 401
        err = _data(page, "function-error-curve", "y")
        assert max(abs(v) for v in err) == pytest.approx(after, rel=1e-6)
        page.get_by_role("button", name="Load the function generator").click()
        title = "Function generation: y = log10(x)"
        assert _menu_shows(page, title) == title
        expect(page.get_by_label("O1A, mm", exact=True)).to_have_value(
            f"{ref.design.crank * 1e3:.6g}", timeout=30_000
        )
    finally:
        page.close()
