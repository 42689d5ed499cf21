"""Take the Synthesis tab's screenshot of docs/explore.md (1280 x 800): path generation through the
page's six default points, the ranked four-bars and the best one previewed over the points (run
from the repository root; needs what ``docs/make_explore_screenshots.py`` needs).
"""

import json
import os
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from make_explore_screenshots import ARGS, FIGURES, REFERENCE, ROOT, chromium  # noqa: E402


def main(out=FIGURES) -> Path:
    from playwright.sync_api import sync_playwright

    out = Path(out)
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
            page = browser.new_page(viewport={"width": 1280, "height": 800})
            page.set_default_timeout(180_000)
            page.goto(url)
            page.wait_for_selector("#stroke")
            page.get_by_text("Synthesis", exact=True).click()
            page.get_by_text("Path (points)", exact=True).click()
            page.get_by_label("Path starts").fill("4")
            page.get_by_label("Path starts").press("Enter")
            page.wait_for_timeout(500)
            page.get_by_role("button", name="Find path generators").click()
            page.locator("#path-table").wait_for()
            page.wait_for_timeout(1500)
            # the preview a third of the way round the cycle, the ranked table in view
            page.evaluate(
                "() => { Bokeh.documents[0].get_model_by_name('synth-frame').value = 40; }"
            )
            page.wait_for_timeout(800)
            page.locator("#path-state").scroll_into_view_if_needed()
            page.evaluate("() => window.scrollTo(0, 0)")
            path = out / "explore_synthesis.png"
            page.screenshot(path=str(path))
            browser.close()
        return path
    finally:
        server.terminate()
        server.wait(timeout=30)


if __name__ == "__main__":
    print(main())
