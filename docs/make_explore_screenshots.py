"""Take the screenshots of docs/explore.md: start ``mechsynth explore`` on the reference problem,
drive the page in headless Chromium with Playwright and save docs/figures/explore_*.png (run from
the repository root; needs ``mechsynth[explore]``, the playwright package and a Chromium
executable: Debian's ``chromium``, or ``MECHSYNTH_CHROMIUM=/path/to/chrome``).
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


def chromium():
    env = os.environ.get("MECHSYNTH_CHROMIUM")
    if env:
        return env
    for name in ("chromium", "chromium-browser", "google-chrome"):
        if shutil.which(name):
            return shutil.which(name)
    raise SystemExit("no Chromium executable: install chromium or set MECHSYNTH_CHROMIUM")


def fill(page, name, value):
    box = page.locator(f".dim-{name} input").first
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
            browser = p.chromium.launch(executable_path=chromium(), args=["--no-sandbox"])
            page = browser.new_page(viewport={"width": 1560, "height": 980})
            page.goto(url)
            page.wait_for_selector("#stroke", timeout=60_000)
            files = []

            # a design that cannot be built: the message beside the field
            fill(page, "rod", 30)
            page.locator(".msg-rod").get_by_text("not longer").wait_for(timeout=20_000)
            path = out / "explore_invalid.png"
            page.screenshot(path=path, clip={"x": 0, "y": 0, "width": 1200, "height": 560})
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
            page.locator(".dim-KN input").first.wait_for(timeout=60_000)
            page.locator("input[type=range]").first.fill("14")  # the animation's player
            page.get_by_text("Crank angle 70 deg").wait_for(timeout=30_000)
            page.wait_for_timeout(800)
            path = out / "explore_design.png"
            page.screenshot(path=path)
            files.append(path)
            browser.close()
        return files
    finally:
        server.terminate()
        server.wait(timeout=30)


if __name__ == "__main__":
    for f in main():
        print(f)
