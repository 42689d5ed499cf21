"""Path and function generation in the explorer: the page's logic (:mod:`mechsynth.explore.
synthesis_model`) against the library's engines, the page object driven from Python, and (marked
``browser`` and ``slow``) what a user sees in headless Chromium: clicked targets and poses, the
ranked path generators, one previewed and loaded, a function generator's error curve and
design, and a linkage file of more than 16 dimensions opened after the page loaded.
"""

import math
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
    with pytest.raises(MechanismError, match="timing must be free or shape"):
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


def test_the_page_object_clicks_targets_and_poses_and_loads_solutions(page):
    syn = page.synthesis
    assert len(syn.src_points.data["x"]) == 6  # the default points on the canvas
    syn.points_input.value = ""
    syn.click(10.0, 20.0)
    syn.click(30.0004, 40.0)  # to a thousandth of the canvas's size (here 0.1 mm)
    assert syn.points_input.value == "10, 20\n30, 40"
    assert syn.src_points.data["x"] == [10.0, 30.0] and syn.src_points.data["label"] == ["1", "2"]
    syn.start_path()  # two points: refused with the reason, no worker started
    assert syn._proc is None and "3 or more target points, got 2" in syn.path_msg.object
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


# ------------------------------------------------------------------------------ in a browser
# (the page as a user sees it; Chromium and the server started once for these tests)
from test_explore_visible import _children, _open, _select, browser, server  # noqa: E402, F401

CANVAS = """([x, y]) => { const d = Bokeh.documents[0], f = d.get_model_by_name('synth-canvas');
  const v = Bokeh.index.find_one(f), r = v.canvas_view.el.getBoundingClientRect();
  return [r.left + v.frame.x_scale.compute(x), r.top + v.frame.y_scale.compute(y)]; }"""
# the largest distance (display units) from a target to the path P takes in the browser
GAP = """() => { const d = Bokeh.documents[0];
  const F = d.get_model_by_name('frames').data, T = d.get_model_by_name('targets').data_source.data;
  let worst = 0;
  for (let i = 0; i < T.x.length; i++) {
    let best = Infinity;
    for (let k = 0; k < F['x:P'].length; k++)
      best = Math.min(best, Math.hypot(F['x:P'][k] - T.x[i], F['y:P'][k] - T.y[i]));
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
        n, gap = page.evaluate(GAP)
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
        # a drag from (0, 100) mm up and to the right: a pose there at 45 deg
        a, b = page.evaluate(CANVAS, [0, 100]), page.evaluate(CANVAS, [40, 140])
        page.mouse.move(*a)
        page.mouse.down()
        page.mouse.move((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, steps=4)
        page.mouse.move(*b, steps=4)
        page.mouse.up()
        expect(poses).to_have_value(re.compile(r", 45$"), timeout=30_000)
        x, y, a = (float(v) for v in poses.input_value().splitlines()[-1].split(","))
        assert (x, y) == (pytest.approx(0, abs=2), pytest.approx(100, abs=2))
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
