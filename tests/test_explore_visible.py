"""The explorer as a user sees it, in headless Chromium: the drawing's visible range, the values
in the fields, the messages' text, the downloaded files' contents, the layout at 1280 x 800 and
390 x 844, the accessible names, the animation played in the browser.

Skipped, with the reason, where Playwright, Panel or a Chromium executable is missing (see
``tests/test_explore_browser.py``).
"""

import json
import subprocess
import sys
import threading
import tomllib
from pathlib import Path

import pytest
from test_explore_browser import ROOT, chromium

pytestmark = [pytest.mark.browser, pytest.mark.slow]

REFERENCE = ROOT / "examples" / "optimize_centric_slider_crank.toml"
ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
]
# every joint of every frame of the cycle, and the drawing's visible range
CYCLE = """() => { const d = Bokeh.documents[0];
  const F = d.get_model_by_name('frames').data, f = d.get_model_by_name('drawing');
  const M = JSON.parse(d.get_model_by_name('meta').data.json[0]);
  let xs = [], ys = [];
  for (const p of M.points) { xs = xs.concat(F['x:' + p]); ys = ys.concat(F['y:' + p]); }
  return {x0: Math.min(...xs), x1: Math.max(...xs), y0: Math.min(...ys), y1: Math.max(...ys),
          vx0: f.x_range.start, vx1: f.x_range.end, vy0: f.y_range.start, vy1: f.y_range.end,
          w: f.inner_width, h: f.inner_height}; }"""


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    pytest.importorskip("panel", reason="the explorer needs Panel (pip install mechsynth[explore])")
    pytest.importorskip("playwright", reason="browser tests need the playwright package")
    if chromium() is None:
        pytest.skip("no Chromium executable (install Debian's chromium or set MECHSYNTH_CHROMIUM)")
    out = tmp_path_factory.mktemp("explore-visible")
    err = open(out / "server.err", "w")
    proc = subprocess.Popen(
        [sys.executable, "-m", "mechsynth", "explore", str(REFERENCE), "--no-browser", "--json",
         "--units", "mm-deg", "--out", str(out / "exports")],
        cwd=ROOT, stdout=subprocess.PIPE, stderr=err, text=True,
    )  # fmt: skip
    line = []
    reader = threading.Thread(target=lambda: line.append(proc.stdout.readline()), daemon=True)
    reader.start()
    reader.join(timeout=120)
    if not line or not line[0].strip():
        proc.kill()
        pytest.fail("mechsynth explore did not start: " + (out / "server.err").read_text())
    info = json.loads(line[0])
    info.update(out=out, pid=proc.pid, err=out / "server.err")
    yield info
    proc.terminate()
    proc.wait(timeout=30)
    err.close()


@pytest.fixture(scope="module")
def browser(server):
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=chromium(), args=ARGS)
        yield b
        b.close()


def _open(browser, server, width=1280, height=800):
    pg = browser.new_page(viewport={"width": width, "height": height}, accept_downloads=True)
    pg.goto(server["url"])
    pg.wait_for_selector("#stroke", timeout=60_000)
    pg.wait_for_timeout(800)
    return pg


@pytest.fixture
def page(browser, server):
    pg = _open(browser, server)
    yield pg
    pg.close()


def _fill(page, what, value):
    """Type ``value`` into the field labelled ``what`` (or the input of the element ``.css``)
    and press Enter."""
    if what.startswith("."):
        box = page.locator(f"{what} input").first
    else:
        box = page.get_by_label(what, exact=True)
    box.fill(str(value))
    box.press("Enter")


def _select(page, label, option):
    page.get_by_label(label, exact=True).select_option(label=option)


def _shown_fits(page):
    """The drawing shows every joint over the cycle, and the mechanism is not a speck."""
    c = page.evaluate(CYCLE)
    assert c["vx0"] <= c["x0"] and c["x1"] <= c["vx1"], c
    assert c["vy0"] <= c["y0"] and c["y1"] <= c["vy1"], c
    fill = max(
        (c["x1"] - c["x0"]) / (c["vx1"] - c["vx0"]), (c["y1"] - c["y0"]) / (c["vy1"] - c["vy0"])
    )
    assert fill > 0.5, c
    # equal scales: as many units per pixel across as up
    sx, sy = (c["vx1"] - c["vx0"]) / c["w"], (c["vy1"] - c["vy0"]) / c["h"]
    assert sx == pytest.approx(sy, rel=0.02), c
    return c


def _wait_meta(page, before):
    page.wait_for_function(
        "(b) => Bokeh.documents[0].get_model_by_name('meta').data.json[0] !== b", arg=before,
        timeout=30_000,
    )  # fmt: skip
    page.wait_for_timeout(400)


def _meta(page):
    return page.evaluate("() => Bokeh.documents[0].get_model_by_name('meta').data.json[0]")


def test_the_view_follows_the_mechanism_its_size_and_the_units(page):
    _shown_fits(page)
    kinds = ("Four-bar", "Beam pumping unit (API 11E dimensions)", "Dwell linkage (paper 003)")
    for option in kinds:
        before = _meta(page)
        _select(page, "Mechanism", option)
        _wait_meta(page, before)
        _shown_fits(page)
    before = _meta(page)
    _select(page, "Display units", "si")
    _wait_meta(page, before)
    c = _shown_fits(page)
    assert c["vx1"] - c["vx0"] < 20  # metres now, not millimetres
    # a much larger design: the view follows
    _select(page, "Mechanism", "Slider-crank")
    page.wait_for_timeout(1500)
    before = _meta(page)
    _fill(page, "rod, m", 0.9)
    _wait_meta(page, before)
    _shown_fits(page)


def test_an_uploaded_file_shows_its_values_and_a_slider_driven_linkage_its_travel(page, tmp_path):
    design = tmp_path / "my_design.toml"
    design.write_text(
        'mechanism = "slider-crank"\nspeed = "300 rpm"\n\n[design]\n'
        'crank = "60 mm"\nrod = "250 mm"\noffset = "10 mm"\n'
    )
    from playwright.sync_api import expect

    page.locator(".upload input[type=file]").set_input_files(str(design))
    expect(page.get_by_label("offset, mm", exact=True)).to_have_value("10", timeout=20_000)
    assert page.get_by_label("crank, mm", exact=True).input_value() == "60"
    assert page.locator(".speed input").first.input_value() == "300"
    _shown_fits(page)
    # the server's Load button (a path on the server's computer) works too
    box = page.get_by_label("or a file's path on the server's computer")
    box.fill(str(ROOT / "examples" / "optimize_cylinder_rocker.toml"))
    page.get_by_role("button", name="Load").click()
    expect(page.get_by_label("Input speed (driving slider), mm/s")).to_have_value(
        "200", timeout=20_000
    )
    assert not page.locator(".design-message").get_by_text("cannot be built").is_visible()
    assert "input displacement" in page.locator("#input-shown").inner_text()
    _shown_fits(page)


def test_refused_input_says_why(page):
    _fill(page, ".speed", -600)
    msg = page.locator(".speed-message").get_by_text("must be positive, or 0 for analogs")
    msg.wait_for(timeout=20_000)
    assert "got -600" in msg.inner_text()
    assert page.locator(".speed input").first.input_value() == "-600"  # not replaced
    _fill(page, "rod, mm", "0.2x")
    rod = page.locator(".msg-rod").get_by_text("is not a number")
    rod.wait_for(timeout=20_000)
    assert "'0.2x' is not a number" in rod.inner_text()
    _fill(page, "rod, mm", "")
    empty = page.locator(".msg-rod").get_by_text("the field is empty")
    empty.wait_for(timeout=20_000)
    assert "nan" not in empty.inner_text()
    _fill(page, "rod, mm", 150)
    page.locator("#stroke").get_by_text("100 mm").wait_for(timeout=20_000)
    assert not page.locator(".msg-rod").get_by_text("not a number").is_visible()


def _download(page, label):
    page.get_by_text("Export", exact=True).click()
    with page.expect_download(timeout=60_000) as dl:
        page.get_by_text(label, exact=True).click()
    return Path(dl.value.path()).read_bytes()


def test_exports_carry_the_design_on_the_page(page):
    _fill(page, "rod, mm", 170)
    page.locator("#stroke").get_by_text("100 mm").wait_for(timeout=20_000)
    page.wait_for_timeout(500)
    data = tomllib.loads(_download(page, "Design file (TOML)").decode())
    assert data["design"]["rod"] == pytest.approx(0.17)
    assert data["design"]["crank"] == pytest.approx(0.05)
    text = _download(page, "Problem file (TOML)").decode()
    assert "#   rod = 0.17" in text and tomllib.loads(text)["variables"]["rod"] == [0.08, 0.2]
    png = _download(page, "Drawing (PNG)")
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    # a chart before a sweep: its button says so and cannot be pressed
    chart = page.get_by_role("button", name="Chart (PNG): sweep a chart first")
    assert chart.is_disabled()


def test_the_first_chart_sweep_shows_progress_then_the_chart(page):
    page.get_by_text("Chart", exact=True).click()
    page.get_by_role("button", name="Sweep").click()
    # the server loaded the kernels when it started: the sweep's progress, or at once its end
    page.locator("#chart-progress, #chart-done").first.wait_for(timeout=10_000)
    page.locator("#chart-done").wait_for(timeout=180_000)
    done = page.locator("#chart-done").inner_text()
    assert "900 designs in" in done
    assert float(done.split(" in ")[1].split()[0]) < 10  # seconds: no compilation behind it
    png = _download(page, "Chart (PNG)")
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10_000


def _children(pid):
    out = subprocess.run(
        ["ps", "--ppid", str(pid), "-o", "pid=,stat=,comm="], capture_output=True, text=True
    ).stdout
    return [line.split() for line in out.splitlines() if line.strip()]


def test_a_solve_reports_in_display_units_keeps_the_menu_and_leaves_no_zombie(page, server):
    page.get_by_text("Problem", exact=True).click()
    _fill(page, ".opt-starts", 60)
    page.get_by_text("Design", exact=True).click()
    page.get_by_role("button", name="Optimize").click()
    page.locator("#opt-state").get_by_text("solving").wait_for(timeout=20_000)
    _select(page, "Mechanism", "Four-bar")
    page.locator("#opt-state").get_by_text("cancel the solve to change the mechanism").wait_for(
        timeout=20_000
    )
    menu = page.get_by_label("Mechanism", exact=True)
    assert "from optimize_centric_slider_crank.toml" in menu.evaluate(
        "e => e.options[e.selectedIndex].text"
    )
    assert page.get_by_label("rod, mm", exact=True).is_visible()  # still the slider-crank's
    page.locator("#opt-state").get_by_text("optimal").wait_for(timeout=240_000)
    text = page.locator("#opt-state").inner_text()
    # r w^2 (1 + r/l) = 246.74 m/s^2 shown in the page's units, mm/s^2
    assert "mm/s^2" in text
    assert float(text.split("=")[1].split()[0]) == pytest.approx(246740.1, rel=1e-5)
    page.wait_for_timeout(1000)
    assert not [c for c in _children(server["pid"]) if c[1].startswith("Z")]


@pytest.mark.parametrize("size", [(1280, 800), (390, 844)])
def test_the_layout_fits_and_every_control_has_a_name(browser, server, size):
    pg = _open(browser, server, *size)
    try:
        width = size[0]
        for name in ("drawing",):
            box = pg.evaluate(
                f"() => {{ const f = Bokeh.documents[0].get_model_by_name('{name}');"
                " return [f.outer_width, f.inner_width]; }"
            )
            assert 0 < box[0] <= width
        for role, name in (("button", "Play"), ("button", "Reverse"), ("button", "Optimize")):
            b = pg.get_by_role(role, name=name).bounding_box()
            assert b["x"] >= 0 and b["x"] + b["width"] <= width, (name, b)
        canvas = pg.evaluate(
            "() => { const f = Bokeh.documents[0].get_model_by_name('drawing');"
            " const r = Bokeh.index.find_one(f).canvas_view.el.getBoundingClientRect();"
            " return [r.left, r.right]; }"
        )
        assert canvas[0] >= 0 and canvas[1] <= width + 0.5
        _shown_fits(pg)
        # accessible names: every input, select and slider handle is named
        unnamed = pg.evaluate(
            """() => { const bad = [];
            function walk(root) {
              for (const el of root.querySelectorAll('input, select, textarea, .noUi-handle')) {
                if (el.type === 'hidden') continue;
                const named = el.getAttribute('aria-label') ||
                  (el.labels && [...el.labels].some(l => l.textContent.trim()));
                if (!named) bad.push(el.outerHTML.slice(0, 120));
              }
              for (const el of root.querySelectorAll('*')) if (el.shadowRoot) walk(el.shadowRoot);
            }
            walk(document); return bad; }"""
        )
        assert unnamed == []
    finally:
        pg.close()


def test_the_animation_plays_in_the_browser(page):
    before = page.evaluate("() => window.mx_explore.drawn")
    page.get_by_role("button", name="Play").click()
    page.wait_for_timeout(2000)
    state = page.evaluate("() => [window.mx_explore.fps, window.mx_explore.drawn]")
    page.get_by_role("button", name="Pause").click()
    assert state[0] > 20  # frames drawn per second by the browser, no server round trip
    assert state[1] - before > 30
    # velocity vectors at the current frame
    page.get_by_text("velocity vectors", exact=True).click()
    page.wait_for_timeout(300)
    n = page.evaluate(
        "() => Bokeh.documents[0].get_model_by_name('velocity').data_source.data.xs.length"
    )
    assert n == 2  # A and B of the slider-crank
    # tracing another point: its closed path drawn
    page.locator(".choices__input--cloned").first.click()
    page.locator(".choices__item--choice", has_text="A").first.click()
    page.wait_for_function(
        "() => Bokeh.documents[0].get_model_by_name('paths').data_source.data.xs.length === 2",
        timeout=10_000,
    )


def test_motion_generation_shows_ranked_linkages_and_loads_one_over_its_targets(page):
    page.get_by_text("Synthesis", exact=True).click()
    page.get_by_role("button", name="Find linkages").click()
    from playwright.sync_api import expect

    page.locator("#synth-table").wait_for(timeout=60_000)
    expect(page.locator("#synth-state")).to_contain_text("linkages through the 5 poses")
    assert page.locator("#synth-table tr").count() == 13  # the header and 12 solutions
    page.get_by_role("button", name="Load into the editor").click()
    menu = page.get_by_label("Mechanism", exact=True)
    page.wait_for_function(
        "() => Bokeh.documents[0].get_model_by_name('targets').data_source.data.x.length === 5",
        timeout=30_000,
    )
    assert menu.evaluate("e => e.options[e.selectedIndex].text") == (
        "Motion generation: solution 1"
    )
    page.wait_for_timeout(800)
    # the coupler point P's path, as the browser holds it, passes through every target
    gap = page.evaluate(
        """() => { const d = Bokeh.documents[0];
        const F = d.get_model_by_name('frames').data;
        const T = d.get_model_by_name('targets').data_source.data;
        let worst = 0;
        for (let i = 0; i < T.x.length; i++) {
          let best = Infinity;
          for (let k = 0; k < F['x:P'].length; k++)
            best = Math.min(best, Math.hypot(F['x:P'][k] - T.x[i], F['y:P'][k] - T.y[i]));
          worst = Math.max(worst, best);
        }
        return worst; }"""
    )
    assert gap < 3.0  # mm: within the spacing of the 180 frames sent
    _shown_fits(page)


SCREEN = """(name) => { const d = Bokeh.documents[0], f = d.get_model_by_name('drawing');
  const v = Bokeh.index.find_one(f), G = d.get_model_by_name('ground').data_source.data;
  const i = G.name.indexOf(name), r = v.canvas_view.el.getBoundingClientRect();
  return [r.left + v.frame.x_scale.compute(G.x[i]), r.top + v.frame.y_scale.compute(G.y[i]),
          G.x[i], G.y[i]]; }"""


# the drawing's place on the screen, its ranges and the fixed pivots it shows
VIEW = """() => { const d = Bokeh.documents[0], f = d.get_model_by_name('drawing');
  const r = Bokeh.index.find_one(f).canvas_view.el.getBoundingClientRect();
  const G = d.get_model_by_name('ground').data_source.data;
  return [r.left, r.top, r.width, r.height, f.x_range.start, f.x_range.end, f.y_range.start,
          f.y_range.end, G.name.join()]; }"""


def _settled(page, name):
    """Wait until the drawing shows the fixed pivot ``name`` and has not moved for 0.4 s."""
    page.wait_for_function(
        "(n) => Bokeh.documents[0].get_model_by_name('ground').data_source.data.name"
        ".includes(n)", arg=name, timeout=60_000,
    )  # fmt: skip
    last = None
    for _ in range(100):
        now = page.evaluate(VIEW)
        if now == last:
            return
        last = now
        page.wait_for_timeout(400)
    raise AssertionError(f"the drawing did not settle: {last}")


def _drag(page, name, dx):
    x, y, _, _ = page.evaluate(SCREEN, name)
    page.mouse.click(x, y)
    page.mouse.move(x, y)
    page.mouse.down()
    page.mouse.move(x + dx / 2, y, steps=5)
    page.mouse.move(x + dx, y, steps=5)
    page.mouse.up()


def test_dragging_a_fixed_pivot_moves_it_or_snaps_back_saying_why(page):
    from playwright.sync_api import expect

    _select(page, "Mechanism", "Impact machine (paper 001, ms.six_link)")
    expect(page.get_by_label("D_x, mm", exact=True)).to_have_value("80", timeout=30_000)
    moved_js = "() => Bokeh.documents[0].get_model_by_name('ground').data_source.data.x[1] < 80"
    # a few pixels: the six-link still assembles. The press must land on the pivot: the
    # drawing shows the six-link's pivots and has stopped moving (the view fitted to the new
    # mechanism, the page laid out again around its dimension rows); a press read from the
    # view before it settled missed the pivot, and the drag was not taken
    _settled(page, "D")
    _drag(page, "D", -6)
    page.wait_for_function(moved_js, timeout=20_000)
    page.wait_for_timeout(800)
    moved = page.evaluate(SCREEN, "D")[2]
    assert float(page.get_by_label("D_x, mm", exact=True).input_value()) == pytest.approx(
        moved, rel=1e-5
    )
    assert moved < 80
    _shown_fits(page)
    # far away: the dyad cannot reach, the pivot returns and the page says why
    _drag(page, "D", 300)
    page.locator(".design-message").get_by_text("cannot move D there").wait_for(timeout=20_000)
    page.wait_for_timeout(800)
    assert page.evaluate(SCREEN, "D")[2] == pytest.approx(moved)
    assert float(page.get_by_label("D_x, mm", exact=True).input_value()) == pytest.approx(
        moved, rel=1e-5
    )
