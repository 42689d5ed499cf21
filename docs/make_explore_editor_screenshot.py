"""Take the editor's screenshot of docs/explore.md (docs/figures/explore_editor.png, 1280 x 800):
start ``mechsynth explore``, build a six-bar by clicks in headless Chromium ("New linkage":
two ground points, a crank, an RRR group, a point on its coupler and an RRP slider driven from
it) and save the page. Run from the repository root; needs what
``docs/make_explore_screenshots.py`` needs.
"""

import json
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from make_explore_screenshots import ARGS, FIGURES, ROOT, chromium  # noqa: E402

SCREEN_AT = """([x, y]) => { const d = Bokeh.documents[0], f = d.get_model_by_name('drawing');
  const v = Bokeh.index.find_one(f), r = v.canvas_view.el.getBoundingClientRect();
  return [r.left + v.frame.x_scale.compute(x), r.top + v.frame.y_scale.compute(y)]; }"""
PLACE = """() => { const f = Bokeh.documents[0].get_model_by_name('drawing');
  const r = Bokeh.index.find_one(f).canvas_view.el.getBoundingClientRect();
  return [r.left, r.top, f.x_range.start, f.x_range.end, f.y_range.start, f.y_range.end]; }"""


def still(page):
    last = None
    for _ in range(60):
        now = page.evaluate(PLACE)
        if now == last:
            return
        last = now
        page.wait_for_timeout(400)


def click(page, x, y):
    still(page)
    page.mouse.click(*page.evaluate(SCREEN_AT, [x, y]))
    page.wait_for_timeout(800)


def main(out=FIGURES):
    from playwright.sync_api import expect, sync_playwright

    server = subprocess.Popen(
        [sys.executable, "-m", "mechsynth", "explore", "--no-browser", "--json", "--units",
         "mm-deg"],
        cwd=ROOT, stdout=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        url = json.loads(server.stdout.readline())["url"]
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=chromium(), args=ARGS)
            page = browser.new_page(viewport={"width": 1280, "height": 800})
            page.goto(url)
            page.wait_for_selector("#stroke", timeout=90_000)
            page.get_by_role("button", name="New linkage").click()
            adds = page.get_by_label("A click on the drawing adds", exact=True)
            adds.wait_for(timeout=60_000)
            click(page, 0, 0)
            click(page, 100, 0)
            steps = [
                ("crank (on a ground point)", {}, (0, 30)),
                ("RRR group (two links)", {"first point": "A", "second point": "O2"}, (60, 80)),
                ("attached point", {"on the link from": "A", "towards": "B"}, (20, 100)),
            ]
            for step, picks, at in steps:
                adds.select_option(label=step)
                for label, option in picks.items():
                    box = page.get_by_label(label, exact=True)
                    box.wait_for(timeout=60_000)
                    box.select_option(option)
                page.wait_for_timeout(800)
                click(page, *at)
            expect(page.locator("#editor-message")).to_contain_text(
                "the linkage assembles", timeout=60_000
            )
            adds.select_option(label="RRP group (rod and slider)")
            page.get_by_label("rod from", exact=True).select_option("C")
            page.wait_for_timeout(800)
            click(page, 150, 110)
            expect(page.get_by_label("CD, mm", exact=True)).to_be_visible(timeout=60_000)
            page.wait_for_timeout(1500)
            page.get_by_role("button", name="Step forward").click()
            page.wait_for_timeout(1500)
            page.evaluate("() => window.scrollTo(0, 0)")
            page.screenshot(path=str(Path(out) / "explore_editor.png"))
            browser.close()
    finally:
        server.terminate()
        server.wait(timeout=30)


if __name__ == "__main__":
    main()
