"""The explorer in a real browser: headless Chromium (the system's, e.g. Debian's ``chromium``)
driven by Playwright against ``mechsynth explore`` started as a user starts it.

Skipped, with the reason, where Playwright, Panel or a Chromium executable is missing (CI
installs Debian's ``chromium``; set ``MECHSYNTH_CHROMIUM`` to use another executable).
"""

import json
import math
import os
import shutil
import subprocess
import sys
import threading
from pathlib import Path

import pytest

import mechsynth as ms

pytestmark = [pytest.mark.browser, pytest.mark.slow]

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = ROOT / "examples" / "optimize_centric_slider_crank.toml"
JOINTS = "() => Array.from(Bokeh.documents[0].get_model_by_name('joints').data_source.data.x)"


def chromium() -> str | None:
    """The Chromium executable: ``MECHSYNTH_CHROMIUM`` or one on the PATH."""
    env = os.environ.get("MECHSYNTH_CHROMIUM")
    if env:
        return env if Path(env).exists() else None
    for name in ("chromium", "chromium-browser", "google-chrome", "chrome"):
        found = shutil.which(name)
        if found:
            return found
    return None


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    pytest.importorskip("panel", reason="the explorer needs Panel (pip install mechsynth[explore])")
    pytest.importorskip("playwright", reason="browser tests need the playwright package")
    if chromium() is None:
        pytest.skip("no Chromium executable (install Debian's chromium or set MECHSYNTH_CHROMIUM)")
    out = tmp_path_factory.mktemp("explore-out")
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "mechsynth",
            "explore",
            str(REFERENCE),
            "--no-browser",
            "--json",
            "--units",
            "mm-deg",
            "--out",
            str(out),
        ],
        cwd=ROOT,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    line = []
    reader = threading.Thread(target=lambda: line.append(proc.stdout.readline()), daemon=True)
    reader.start()
    reader.join(timeout=120)
    if not line or not line[0].strip():
        proc.kill()
        pytest.fail(f"mechsynth explore did not start: {proc.stderr.read()[-2000:]}")
    info = json.loads(line[0])
    info["out"] = out
    yield info
    proc.terminate()
    try:
        proc.wait(timeout=20)
    except subprocess.TimeoutExpired:
        proc.kill()


@pytest.fixture(scope="module")
def browser(server):
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=chromium(), args=["--no-sandbox"])
        yield b
        b.close()


@pytest.fixture
def page(browser, server):
    pg = browser.new_page(viewport={"width": 1500, "height": 1000})
    pg.goto(server["url"])
    pg.wait_for_selector("#stroke", timeout=60_000)
    yield pg
    pg.close()


def _fill(page, name, value):
    box = page.get_by_label(f"{name}, mm", exact=True)
    box.fill(str(value))
    box.press("Enter")


def _stroke_mm(page) -> float:
    return float(page.locator("#stroke").inner_text().split()[0])


def test_page_loads_with_the_reference_problem(page, server):
    assert server["url"].startswith("http://127.0.0.1:")
    assert page.locator("text=mechsynth explore").count() >= 1
    # the problem file's box midpoints: crank 50 mm, rod 140 mm, centric: stroke 100 mm
    assert _stroke_mm(page) == pytest.approx(100.0)
    assert page.evaluate(JOINTS) == pytest.approx([50.0, 190.0])
    assert page.locator("#checks .ok").count() == 2  # stroke == 100 mm and the pressure angle


def test_moving_a_slider_redraws_and_gives_the_apis_stroke(page):
    from playwright.sync_api import expect

    _fill(page, "offset", 10)
    expect(page.locator("#stroke")).not_to_have_text("100 mm", timeout=20_000)
    before = page.evaluate(JOINTS)
    handle = page.get_by_label("crank, mm (crank OA)", exact=True)
    box = handle.bounding_box()
    y = box["y"] + box["height"] / 2
    page.mouse.move(box["x"] + box["width"] / 2, y)
    page.mouse.down()
    page.mouse.move(box["x"] + 50, y, steps=5)
    page.mouse.up()
    page.wait_for_function(
        "(b) => { const x = Array.from(Bokeh.documents[0].get_model_by_name('joints')"
        ".data_source.data.x); return x[0] !== b[0]; }",
        arg=before,
        timeout=20_000,
    )
    page.wait_for_timeout(500)
    crank = float(page.get_by_label("crank, mm", exact=True).input_value()) * 1e-3
    assert crank > 0.05
    sc = ms.SliderCrank(crank=crank, rod=0.14, offset=0.01)
    assert _stroke_mm(page) == pytest.approx(sc.stroke * 1e3, rel=1e-5)
    # the drawing: A and B at crank angle 0 where the API's sketch puts them
    sk = sc.sketch([0.0])
    drawn = page.evaluate(JOINTS)
    assert drawn == pytest.approx([sk.points["A"][0][0] * 1e3, sk.points["B"][0][0] * 1e3])


def test_invalid_field_shows_its_message_and_recovers(page):
    from playwright.sync_api import expect

    _fill(page, "rod", 30)
    msg = page.locator(".msg-rod").get_by_text("not longer than crank + |offset|")
    msg.wait_for(timeout=20_000)
    assert "rod (0.03 m) not longer than crank + |offset| (0.05 m)" in msg.inner_text()
    assert page.locator(".msg-crank").get_by_text("not longer").count() == 0
    _fill(page, "rod", 140)
    expect(page.locator("#stroke")).to_have_text("100 mm", timeout=20_000)
    expect(msg).to_be_hidden()
    # a reversed bound
    lo = page.get_by_label("crank lower bound", exact=True)
    lo.fill("90")
    lo.press("Enter")
    bound = page.locator(".msg-crank").get_by_text("is not below the upper bound")
    bound.wait_for(timeout=20_000)
    assert "lower bound 90 mm is not below the upper bound 80 mm" in bound.inner_text()


def _slow_solve(page, starts=400):
    """Enough starts that the solve outlasts what the test does meanwhile (one start of the
    reference problem takes some 20 ms in the worker)."""
    page.get_by_text("Problem", exact=True).click()  # the tab that holds the solve's options
    box = page.locator(".opt-starts input").first
    box.fill(str(starts))
    box.press("Enter")
    page.get_by_text("Design", exact=True).click()
    page.wait_for_timeout(300)


def test_optimize_reaches_the_known_optimum_and_the_page_stays_live(page):
    from playwright.sync_api import expect

    _slow_solve(page)
    page.get_by_role("button", name="Optimize").click()
    page.locator("#opt-state").get_by_text("solving").wait_for(timeout=20_000)
    # the page answers while the solver runs in its own process
    _fill(page, "offset", 5)
    expect(page.locator("#stroke")).not_to_have_text("100 mm", timeout=10_000)
    assert "solving" in page.locator("#opt-state").inner_text()
    page.locator("#opt-state").get_by_text("optimal").wait_for(timeout=240_000)
    text = page.locator("#opt-state").inner_text()
    value, unit = text.split("=")[1].split()[:2]
    optimum = 0.05 * (2 * math.pi * 10) ** 2 * (1 + 0.05 / 0.2)  # r w^2 (1 + r/l) = 246.74
    assert unit == "mm/s^2"  # the page's display units (mm-deg)
    assert float(value) * 1e-3 == pytest.approx(optimum, rel=1e-5)
    # the sliders moved to the optimum: crank 50 mm, rod 200 mm
    page.wait_for_timeout(500)
    assert float(page.get_by_label("crank, mm", exact=True).input_value()) == pytest.approx(50.0)
    assert float(page.get_by_label("rod, mm", exact=True).input_value()) == pytest.approx(200.0)
    assert "certified: True" in page.locator("#opt-report").inner_text()


def test_optimize_can_be_cancelled(page):
    _slow_solve(page)
    page.get_by_role("button", name="Optimize").click()
    page.locator("#opt-state").get_by_text("solving").wait_for(timeout=20_000)
    page.get_by_role("button", name="Cancel").click()
    page.locator("#opt-state").get_by_text("cancelled").wait_for(timeout=20_000)
    assert page.get_by_role("button", name="Optimize").is_enabled()
