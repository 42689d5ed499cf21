"""Take the screenshots of docs/explore.md: start ``mechsynth explore`` on the reference problem,
drive the page in headless Chromium with Playwright and save docs/figures/explore_*.png (run from
the repository root; needs ``mechsynth[explore]``, the playwright package and a Chromium
executable: Debian's ``chromium``, or ``MECHSYNTH_CHROMIUM=/path/to/chrome``).

``--measure``: print the page's speed instead (docs/explore.md, "Speed"): the time from opening
the address to a drawn mechanism, and from a slider's step (a key press on its handle) to the
redrawn mechanism in the browser, over several steps; and the animation's frame rate.
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FIGURES = ROOT / "docs" / "figures"
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


def chromium():
    env = os.environ.get("MECHSYNTH_CHROMIUM")
    if env:
        return env
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return shutil.which(name)
    raise SystemExit("no Chromium executable: install chromium or set MECHSYNTH_CHROMIUM")


def fill(page, name, value):
    box = page.get_by_label(f"{name}, mm", exact=True)
    box.fill(str(value))
    box.press("Enter")


def main(out=FIGURES):
    from playwright.sync_api import expect, sync_playwright

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    exports = tempfile.mkdtemp()
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    server = subprocess.Popen(
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
            exports,
        ],
        cwd=ROOT,
        env=env,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        url = json.loads(server.stdout.readline())["url"]
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=chromium(), args=ARGS)
            page = browser.new_page(viewport={"width": 1280, "height": 800})
            page.goto(url)
            page.wait_for_selector("#stroke", timeout=60_000)
            files = []

            # a design that cannot be built: the message beside the field
            fill(page, "rod", 30)
            page.locator(".msg-rod").get_by_text("not longer").wait_for(timeout=20_000)
            path = out / "explore_invalid.png"
            page.screenshot(path=path, clip={"x": 0, "y": 0, "width": 1280, "height": 560})
            files.append(path)
            fill(page, "rod", 120)
            expect(page.locator("#stroke")).to_have_text("100 mm", timeout=20_000)

            # optimize the reference problem: the sliders move to the optimum
            page.get_by_role("button", name="Optimize").click()
            page.locator("#opt-state").get_by_text("optimal").wait_for(timeout=300_000)
            page.wait_for_timeout(800)
            path = out / "explore_optimized.png"
            page.screenshot(path=path)
            files.append(path)

            # a chart over crank and rod; click a cell to load its design
            page.get_by_text("Chart", exact=True).first.click()
            page.get_by_role("button", name="Sweep").click()
            page.locator(".chart-message").get_by_text("designs in").wait_for(timeout=120_000)
            page.wait_for_timeout(800)
            canvas = page.locator(".bk-Canvas").last
            box = canvas.bounding_box()
            page.mouse.click(box["x"] + 0.45 * box["width"], box["y"] + 0.35 * box["height"])
            page.wait_for_timeout(1200)
            path = out / "explore_chart.png"
            page.screenshot(path=path)
            files.append(path)

            # the impact machine of paper 001 (ms.six_link), animated a while, with its paths
            page.get_by_text("Design", exact=True).first.click()
            page.locator("select").first.select_option(
                label="Impact machine (paper 001, ms.six_link)"
            )
            expect(page.locator("#stroke")).to_have_text("39.0011 mm", timeout=60_000)
            page.get_by_label("KN, mm", exact=True).wait_for(timeout=60_000)
            page.get_by_text("velocity vectors", exact=True).click()
            for _ in range(14):  # 5 deg a step: 70 deg
                page.get_by_role("button", name="Step forward").click()
                page.wait_for_timeout(150)
            page.locator("#input-shown").get_by_text("crank angle 70 deg").wait_for(timeout=30_000)
            page.wait_for_timeout(800)
            path = out / "explore_design.png"
            page.screenshot(path=path)
            files.append(path)

            # on a phone: the drawing first, the controls below it
            phone = browser.new_page(viewport={"width": 390, "height": 844})
            phone.goto(url)
            phone.wait_for_selector("#stroke", timeout=60_000)
            phone.wait_for_timeout(1500)
            path = out / "explore_phone.png"
            phone.screenshot(path=path)
            files.append(path)
            browser.close()
        return files
    finally:
        server.terminate()
        server.wait(timeout=30)


def measure(steps: int = 20) -> dict:
    """The page's speed on this machine (see the module's docstring), in ms and frames/s."""
    import statistics
    import time

    from playwright.sync_api import sync_playwright

    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    server = subprocess.Popen(
        [sys.executable, "-m", "mechsynth", "explore", str(REFERENCE), "--no-browser", "--json",
         "--units", "mm-deg"],
        cwd=ROOT, env=env, stdout=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        url = json.loads(server.stdout.readline())["url"]
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=chromium(), args=ARGS)
            ready = []
            for _ in range(3):
                page = browser.new_page(viewport={"width": 1280, "height": 800})
                t0 = time.perf_counter()
                page.goto(url)
                page.wait_for_function(
                    "() => window.Bokeh && Bokeh.documents.length && Bokeh.documents[0]"
                    ".get_model_by_name('joints').data_source.data.x.length > 0",
                    timeout=60_000,
                    polling=10,
                )
                ready.append(1e3 * (time.perf_counter() - t0))
                if _ < 2:
                    page.close()
            page.wait_for_timeout(1500)
            # the browser notes when the joints' source changes (the server's redraw)
            page.evaluate(
                "() => { const d = Bokeh.documents[0];"
                " const s = d.get_model_by_name('joints').data_source;"
                " window.__redrawn = []; d.on_change((e) => {"
                " if (e.model === s && e.attr === 'data') window.__redrawn.push(performance.now());"
                " }); }"
            )
            handle = page.get_by_label("rod, mm (connecting rod AB)", exact=True)
            handle.focus()
            latency = []
            for k in range(steps):
                n = page.evaluate("() => window.__redrawn.length")
                t0 = page.evaluate("() => performance.now()")
                handle.press("ArrowRight" if k % 2 == 0 else "ArrowLeft")
                page.wait_for_function(f"() => window.__redrawn.length > {n}", timeout=20_000)
                latency.append(page.evaluate(f"() => window.__redrawn[{n}]") - t0)
                page.wait_for_timeout(200)
            page.get_by_role("button", name="Play").click()
            page.wait_for_timeout(3000)
            fps = page.evaluate("() => window.mx_explore.fps")
            page.get_by_role("button", name="Pause").click()
            browser.close()
    finally:
        server.terminate()
        server.wait(timeout=30)
    return {
        "page_ready_ms": [round(t) for t in ready],
        "slider_to_redraw_ms_median": round(statistics.median(latency), 1),
        "slider_to_redraw_ms_max": round(max(latency), 1),
        "animation_frames_per_s": round(fps, 1),
    }


if __name__ == "__main__":
    if "--measure" in sys.argv[1:]:
        print(json.dumps(measure()))
    else:
        for f in main():
            print(f)
