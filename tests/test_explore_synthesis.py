"""Path and function generation in the explorer: the page's logic (:mod:`mechsynth.explore.
synthesis_model`) against the library's engines, the page object driven from Python, and (marked
``browser`` and ``slow``) what a user sees in headless Chromium: clicked targets and poses, the
ranked path generators, one previewed and loaded, a function generator's error curve and
design, and a linkage file of more than 16 dimensions opened after the page loaded.
"""

import math
import time

import numpy as np
import pytest

import mechsynth as ms
from mechsynth.errors import MechanismError
from mechsynth.explore import synthesis_model as sm
from mechsynth.explore.model import State
from mechsynth.synthesis.path_cases import exact_case


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
    with pytest.raises(MechanismError, match="timing must be free or shape"):
        sm.PathJob(pts, "prescribed")
    with pytest.raises(MechanismError, match=r"in \[0, 90\) deg, got 95 deg"):
        sm.PathJob(pts, "free", math.radians(95))


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
    assert pv["P"].shape == (60, 2) and pv["targets_angle"] == pytest.approx(sol.angles)
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


def test_the_page_object_clicks_targets_and_poses_and_loads_solutions(page, path_result):
    syn = page.synthesis
    assert len(syn.src_points.data["x"]) == 6  # the default points on the canvas
    syn.points_input.value = ""
    syn.click(10.0, 20.0)
    syn.click(30.0, 40.0)
    assert syn.points_input.value == "10, 20\n30, 40"
    assert syn.src_points.data["x"] == [10.0, 30.0] and syn.src_points.data["label"] == ["1", "2"]
    syn.start_path()  # two points: refused with the reason, no worker started
    assert syn._proc is None and "3 or more target points, got 2" in syn.path_msg.object
    syn.tasks = type("T", (), {"active": 2})()  # the motion generation's sub-tab shown
    syn.pose_angle.value = "45"
    n = len(page.poses_input.value.splitlines())
    syn.click(-5.0, 7.5)
    assert page.poses_input.value.splitlines()[-1] == "-5, 7.5, 45"
    assert len(syn.src_poses.data["x"]) == n + 1
    syn.pose_angle.value = "north"
    syn.click(0.0, 0.0)
    assert "angle of a clicked pose, deg: 'north' is not a number" in page.synth_msg.object
    # a finished search: ranked in the table, the best previewed, loaded as the page's design
    job, res, _ = path_result
    syn.show_path(res, job.targets)
    assert syn.path_table.object.count("<tr>") == len(res.solutions) + 1
    assert "four-bars through the 6 points" in syn.path_msg.object
    meta = syn.src_meta.data["json"][0]
    assert '"n": 120' in meta and len(syn.src_frames.data["x:P"]) == 120
    syn.load_path()
    assert page.state.kind.title == "Path generation: solution 1"
    assert page.design is not None and page.trace_select.value == ["P"]
    assert page.src_targets.data["x"] == pytest.approx((job.targets[:, 0] * 1e3).tolist())
    # function generation: the error curve, the design, loaded
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
