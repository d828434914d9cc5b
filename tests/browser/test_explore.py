"""`pointshade explore` in headless Chromium (tests/browser/run.sh runs this).

Each test starts the real server (`pointshade explore ... --port 0`), opens the page, acts as a
user would (moves a slider, clicks a pixel, ticks D/G/F) and checks what the page shows against
what pointshade itself computes: the image shown must be, byte for byte, what `pointshade
normalmap` (or `render`) writes for the scene file the page saves. Any console error fails the
test. Screenshots of each view go to target/explore/, and the time from a slider's input event
to the new image on screen to target/explore/timings.csv (a benchmark, never asserted).
"""

import csv
import json
import os
import statistics
import subprocess
import time
import urllib.request
from pathlib import Path

import pytest
from playwright.sync_api import sync_playwright

ROOT = Path(__file__).resolve().parents[2]
CLI = os.environ.get("POINTSHADE_CLI", str(ROOT / "target/release/pointshade"))
OUT = ROOT / "target/explore"
SHARED = ROOT.parent / "shared/data"
TIMINGS = OUT / "timings.csv"


class Explorer:
    """A running `pointshade explore` and its URL."""

    def __init__(self, *args):
        OUT.mkdir(parents=True, exist_ok=True)
        self.log = OUT / "server.log"
        with open(self.log, "a") as log:
            self.process = subprocess.Popen(
                [CLI, "explore", *map(str, args), "--port", "0"], stdout=subprocess.PIPE, stderr=log, text=True
            )
        self.url = self.process.stdout.readline().strip()
        self.contexts = []
        assert self.url.startswith("http://127.0.0.1:"), self.log.read_text()

    def post(self, path, body):
        request = urllib.request.Request(self.url + path.lstrip("/"), data=json.dumps(body).encode(), method="POST")
        with urllib.request.urlopen(request) as reply:
            return reply.read()

    def get(self, path):
        with urllib.request.urlopen(self.url + path.lstrip("/")) as reply:
            return reply.read()

    def stop(self):
        for context in self.contexts:
            context.close()
        self.process.terminate()
        self.process.wait(timeout=10)


@pytest.fixture(scope="module")
def browser():
    OUT.mkdir(parents=True, exist_ok=True)
    with sync_playwright() as p:
        b = p.chromium.launch(
            executable_path="/usr/bin/chromium",
            args=["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--disable-gpu-compositing"],
        )
        yield b
        b.close()


def open_page(browser, explorer, fragment=""):
    """A new page (in a context of its own, closed with the explorer) at the explorer's URL,
    ready, and the list its console errors go to."""
    context = browser.new_context(viewport={"width": 1400, "height": 1050})
    explorer.contexts.append(context)
    page = context.new_page()
    errors = []
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(explorer.url + fragment)
    try:
        page.wait_for_function("window.explore && window.explore.ready", timeout=60000)
    except Exception as e:
        status = page.evaluate(
            "[(document.getElementById('status') || {}).textContent, window.explore && "
            "[explore.renders, !!explore.plot, !!explore.lobe, !!explore.albedo]]"
        )
        raise AssertionError(f"the page never got ready: status, [renders, plot, lobe, albedo] {status!r}, console errors {errors}") from e
    return page, errors


def move_slider(page, selector, value):
    """Sets a range input as a drag would, and returns the renders shown before."""
    before = page.evaluate("explore.renders")
    page.eval_on_selector(
        selector,
        "(el, v) => { el.value = String(v); el.dispatchEvent(new Event('input', {bubbles: true})); }",
        value,
    )
    return before


def wait_for_render(page, before, check="true"):
    page.wait_for_function(f"explore.renders > {before} && ({check})", timeout=60000)


def shown_bytes(page):
    """The bytes of the image element's source, as the browser holds them."""
    data = page.evaluate(
        """async () => {
            const blob = await (await fetch(document.getElementById('render-image').src)).blob();
            return Array.from(new Uint8Array(await blob.arrayBuffer()));
        }"""
    )
    return bytes(data)


def record(what, values):
    new = not TIMINGS.exists()
    with open(TIMINGS, "a", newline="") as f:
        w = csv.writer(f)
        if new:
            w.writerow(["what", "median_ms", "min_ms", "max_ms", "n"])
        w.writerow([what, f"{statistics.median(values):.1f}", f"{min(values):.1f}", f"{max(values):.1f}", len(values)])
    print(f"{what}: median {statistics.median(values):.1f} ms (min {min(values):.1f}, max {max(values):.1f}, n = {len(values)})")


def test_roughness_slider_shows_what_normalmap_writes(browser, tmp_path):
    explorer = Explorer()
    try:
        page, errors = open_page(browser, explorer)
        page.screenshot(path=str(OUT / "page.png"), full_page=True)
        before = move_slider(page, "#key-normal_map-roughness", 0.3)
        wait_for_render(page, before, "explore.renderState.materials.normal_map.roughness === 0.3")
        shown = shown_bytes(page)
        assert shown == bytes(page.evaluate("Array.from(explore.renderBytes)"))
        state = page.evaluate("explore.renderState")
        # The page's state saved as a scene file, beside the normal image it names.
        (tmp_path / "scene.toml").write_bytes(explorer.post("/api/save", state))
        (tmp_path / "explore-normals.png").write_bytes(explorer.get("/api/normals.png"))
        subprocess.run(
            [CLI, "normalmap", str(tmp_path / "scene.toml"), "-o", str(tmp_path / "cli.png"), "--quiet"],
            check=True,
        )
        assert shown == (tmp_path / "cli.png").read_bytes()
        # The URL's fragment holds the state: a reload shows the same image.
        fragment = page.evaluate("location.hash")
        page2, errors2 = open_page(browser, explorer, fragment)
        assert page2.evaluate("explore.renderState.materials.normal_map.roughness") == 0.3
        assert shown_bytes(page2) == shown
        assert errors == [] and errors2 == []
    finally:
        explorer.stop()


def test_a_clicked_pixel_shows_its_brdf_and_the_plots_follow(browser):
    explorer = Explorer()
    try:
        page, errors = open_page(browser, explorer)
        box = page.locator("#render-image").bounding_box()
        width, height = page.evaluate("[explore.session.width, explore.session.height]")
        # The sphere of the baked scene, above the image's centre.
        x, y = width // 2, int(height * 0.35)
        page.mouse.click(box["x"] + (x + 0.5) * box["width"] / width, box["y"] + (y + 0.5) * box["height"] / height)
        page.wait_for_function("explore.pixel && explore.pixel.hit", timeout=30000)
        pixel = page.evaluate("explore.pixel")
        # The pixel under the pointer (a CSS pixel of the scaled image may straddle two).
        assert abs(pixel["x"] - x) <= 1 and abs(pixel["y"] - y) <= 1, (pixel, x, y)
        state = page.evaluate("explore.renderState")
        direct = json.loads(explorer.post("/api/pixel", {"state": state, "x": pixel["x"], "y": pixel["y"]}))
        assert pixel == direct
        info = page.text_content("#pixel-info")
        assert pixel["material"] in info
        for c in pixel["n"]:
            assert f"{c:.3f}" in info, (c, info)
        page.locator("#pixel-info").screenshot(path=str(OUT / "pixel.png"))
        # D, G and F on demand: the curves drawn are the API's for the current material.
        for term in ["D", "G", "F"]:
            page.check(f"#show-{term}")
        page.wait_for_function("['D', 'G', 'F'].every(k => k in explore.plot.curves)", timeout=30000)
        curves = page.evaluate("explore.plot.curves")
        assert len(curves["D"]) == len(page.evaluate("explore.plot.theta_o"))
        assert max(curves["D"]) > 0 and 0 < max(curves["G"]) <= 1 + 1e-9
        page.uncheck("#show-D")
        page.wait_for_function("!('D' in explore.plot.curves)", timeout=30000)
        for view, selector in [("polar", "#polar"), ("lobe", "#lobe"), ("sphere", "#sphere"), ("albedo", "#albedo")]:
            page.locator(selector).screenshot(path=str(OUT / f"{view}.png"))
        page.click("#pin")
        page.wait_for_function("explore.pins.length === 1", timeout=30000)
        page.click("#copy-python")
        page.wait_for_function("document.getElementById('python-text').value.includes('shade_normal_image')", timeout=30000)
        page.screenshot(path=str(OUT / "page-pixel.png"), full_page=True)
        assert errors == []
    finally:
        explorer.stop()


def test_a_scene_refines_in_passes_to_what_render_writes(browser, tmp_path):
    """The Cornell box (4 spp): an edit shows a 1-spp pass, then the film's; the last is, byte
    for byte, `pointshade render` of the saved scene file."""
    explorer = Explorer(ROOT / "scenes/cornell-box.toml")
    try:
        page, errors = open_page(browser, explorer)
        assert page.evaluate("[explore.session.mode, explore.session.spp]") == ["scene", 4]
        # The first image is traced: a 1-spp pass is shown first, then the film's 4 spp. (Later
        # edits re-shade kept points, quick enough to skip the coarse pass.)
        assert page.evaluate("[explore.passes, explore.renders, explore.shownSpp]") == [2, 1, 4]
        before = move_slider(page, "#exposure", 1.5)
        wait_for_render(page, before, "explore.renderState.exposure === 1.5")
        assert page.evaluate("explore.shownSpp") == 4
        shown = shown_bytes(page)
        # Saved where the scene's relative mesh path ("../meshes/…") still leads to the mesh.
        (tmp_path / "scenes").mkdir()
        (tmp_path / "meshes").symlink_to(ROOT / "meshes")
        saved = tmp_path / "scenes/scene.toml"
        saved.write_bytes(explorer.post("/api/save", page.evaluate("explore.renderState")))
        subprocess.run([CLI, "render", str(saved), "-o", str(tmp_path / "cli.png"), "--quiet"], check=True)
        assert shown == (tmp_path / "cli.png").read_bytes()
        # Edits faster than the renders: the series in flight is abandoned, the last edit shown.
        for v in [0.25, 0.5, 0.75, 1.0]:
            move_slider(page, "#exposure", v)
        page.wait_for_function("explore.renderState.exposure === 1.0 && explore.shownSpp === 4", timeout=60000)
        assert errors == []
    finally:
        explorer.stop()


MITSUBA = ROOT / "validation/.venv/bin/python"


@pytest.mark.skipif(not MITSUBA.exists(), reason="needs Mitsuba 3 (validation/install.sh)")
def test_the_mitsuba_button_compares_the_edited_scene(browser):
    explorer = Explorer(ROOT / "scenes/validation/conductor-sphere.toml")
    try:
        page, errors = open_page(browser, explorer)
        assert page.evaluate("explore.session.mitsuba.available")
        before = move_slider(page, "#key-copper-roughness", 0.5)
        wait_for_render(page, before, "explore.renderState.materials.copper.roughness === 0.5")
        page.click("#mitsuba")
        page.wait_for_function("explore.mitsuba !== undefined", timeout=300000)
        result = page.evaluate("explore.mitsuba")
        # The validation's requirement for a scene Mitsuba renders exactly.
        assert result["available"] and result["differences"] == [], result["message"]
        assert result["within"] >= 0.999 and result["mean_relative_error"] <= 1e-4, result
        assert page.is_visible("#mitsuba-heatmap")
        assert "% of the pixels within" in page.text_content("#mitsuba-within")
        page.locator("#mitsuba-panel").screenshot(path=str(OUT / "mitsuba.png"))
        assert errors == []
    finally:
        explorer.stop()


def test_the_mitsuba_button_says_why_it_cannot_run(browser):
    explorer = Explorer("--mitsuba-dir", ROOT / "target/no-such-validation")
    try:
        page, errors = open_page(browser, explorer)
        assert not page.evaluate("explore.session.mitsuba.available")
        page.click("#mitsuba")
        page.wait_for_function("explore.mitsuba !== undefined", timeout=30000)
        assert "install.sh" in page.text_content("#mitsuba-message")
        assert page.is_hidden("#mitsuba-heatmap")
        assert errors == []
    finally:
        explorer.stop()


def timed_slider_moves(page, selector, values):
    """Moves a slider through `values`, waiting for each image; the page's own timings (input
    event to the image's load event) of those renders, in ms."""
    for v in values:
        before = move_slider(page, selector, v)
        wait_for_render(page, before)
    return page.evaluate(f"explore.timings.render.slice(-{len(values)})")


@pytest.mark.skipif(not (SHARED / "normalmaps/normal.png").exists(), reason="needs ../shared/data (the assignment's image)")
def test_speed_on_the_assignments_image(browser):
    explorer = Explorer(SHARED / "normalmaps/normal.png")
    try:
        page, errors = open_page(browser, explorer)
        assert page.evaluate("[explore.session.width, explore.session.height]") == [768, 451]
        renders = timed_slider_moves(page, "#key-normal_map-roughness", [0.2 + 0.05 * i for i in range(12)])
        record("slider to image, assignment's 768x451 normal image (tp)", renders[2:])
        before = page.evaluate("explore.timings.polar.length")
        for t in range(10, 80, 5):
            page.eval_on_selector("#theta-i", "(el, v) => { el.value = String(v); el.dispatchEvent(new Event('input', {bubbles: true})); }", t)
            page.wait_for_function(f"explore.timings.polar.length > {before}", timeout=30000)
            before = page.evaluate("explore.timings.polar.length")
        record("polar plot update", page.evaluate("explore.timings.polar.slice(-10)"))
        assert errors == []
    finally:
        explorer.stop()


@pytest.mark.skipif(not (SHARED / "meshes/stanford-dragon.obj").exists(), reason="needs ../shared/data (the Stanford dragon)")
def test_speed_on_the_dragon(browser):
    explorer = Explorer(ROOT / "scenes/shared/dragon-copper.toml")
    try:
        started = time.perf_counter()
        page, errors = open_page(browser, explorer)
        first = page.evaluate("explore.timings.render.length ? explore.timings.render[0] : null")
        print(f"dragon: page ready {1000 * (time.perf_counter() - started):.0f} ms after the page was asked for")
        assert page.evaluate("explore.session.mode") == "scene"
        material = page.evaluate("Object.keys(explore.state.materials)[0]")
        renders = timed_slider_moves(page, f"#key-{material}-roughness", [0.1 + 0.03 * i for i in range(12)])
        record("slider to image, dragon-copper 512x512 4 spp (re-shade)", renders[2:])
        if first is not None:
            record("dragon's first 4-spp image (page load to image)", [first])
        first_pass = page.evaluate("explore.timings.firstPass[0]")
        record("first preview of the dragon, 1-spp pass (page load to image)", [first_pass])
        page.screenshot(path=str(OUT / "dragon.png"), full_page=True)
        assert errors == []
    finally:
        explorer.stop()
    # A fresh server each time, its page opened in the browser already running (as a user
    # opens the printed link): the browser's own start-up no longer shares the two cores with
    # the first trace.
    again, server = [], []
    for _ in range(5):
        explorer = Explorer(ROOT / "scenes/shared/dragon-copper.toml")
        try:
            page, errors = open_page(browser, explorer)
            again.append(page.evaluate("explore.timings.firstPass[0]"))
            server.append(page.evaluate("explore.timings.firstPassServer[0]"))
            assert errors == []
        finally:
            explorer.stop()
    record("first preview of the dragon, 1-spp pass, a fresh server, the browser running", again)
    record("the same, the server's answer (Server-Timing) within it", server)
