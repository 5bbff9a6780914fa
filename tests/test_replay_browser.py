"""The replay as a user opens it: a short run of the paper's a_3 recorded into a replay page,
opened offline in a real browser (headless Chromium driven by Playwright), paused and sought to
its start, middle and end with Meshcat's own animation API. At each time the car is in view
(hiding it changes many pixels, near the middle of the picture, as many at the end as at the
start: the camera follows), the road is drawn (hiding /drake/road changes most of the
picture, hiding its lane markings changes some), and the console shows no error; the page
loads nothing from the network. The overview camera keeps the car in view too, and Meshcat's
own controls (pause, the time slider) still work.

Needs Debian's ``chromium`` (tools/setup.sh installs it) and Playwright for Python (the test
extra); no ``playwright install``: the system's Chromium is launched. Without Chromium the test
is skipped, except in CI (``CI`` set), where it must run.
"""

import base64
import io
import os
import shutil
import time
from pathlib import Path

import numpy as np
import pytest

from conftest import paper_scene

CHROMIUM = Path(shutil.which("chromium") or "/usr/bin/chromium")
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--enable-unsafe-swiftshader"]
VIEWPORT = {"width": 960, "height": 540}
# a_3 on a 3.5 s timeline: it settles, speeds up (about 25 m down the road) and changes lanes.
# (the rack as given: the shipped calibration's profile, none is calibrated for this timeline)
SHORT = ("manoeuvre: !LaneChange {timeline: {settle_s: 0.2, speed_up_s: 1.5, straight_s: 0.2, "
         "steer_s: 1.2, calm_s: 0.4}, amplitude_m: 0.005908525382359731, "
         "second_lobe: 1.012425560052948}\n")
CAR = ["drake", "visualizer"]  # the car: what Drake's MeshcatVisualizer draws
ROAD = ["drake", "road"]
MARKINGS = ["drake", "road", "markings"]

if not CHROMIUM.exists() and not os.environ.get("CI"):
    pytest.skip("the browser test needs Debian's chromium (/usr/bin/chromium; tools/setup.sh "
                "installs it)", allow_module_level=True)
if os.environ.get("CI"):
    from playwright import sync_api as playwright_api  # in CI it must run: no skip
else:
    playwright_api = pytest.importorskip("playwright.sync_api",
                                         reason="needs playwright (pip install -e .[test])")

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def replays(tmp_path_factory):
    """camera -> (replay page file, the run's history), for a follow and an overview replay."""
    from drake_car.sim.simulate import simulate
    folder = tmp_path_factory.mktemp("replay")
    out = {}
    for camera in ("follow", "overview"):
        run = simulate(paper_scene("a_3", SHORT + f"visualization: !MeshcatReplay "
                                                   f"{{camera: {camera}}}"))
        path = folder / f"{camera}.html"
        path.write_text(run.replay_html)
        out[camera] = (path, run.history)
    return out


@pytest.fixture(scope="module")
def browser():
    with playwright_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=str(CHROMIUM), headless=True, args=ARGS)
        yield b
        b.close()


class Page:
    """A replay page in the browser, with its console errors and any network requests."""

    def __init__(self, browser, path):
        self.page = browser.new_page(viewport=VIEWPORT)
        self.errors, self.remote = [], []
        self.page.on("console", lambda m: m.type == "error" and self.errors.append(m.text))
        self.page.on("pageerror", lambda e: self.errors.append(str(e)))
        self.page.on("request", lambda r: r.url.split(":")[0] not in ("file", "data", "blob")
                     and self.remote.append(r.url))
        self.page.goto(path.resolve().as_uri())
        # The page replays its commands from data: URLs; the animation comes last.
        self.page.wait_for_function("() => window.viewer && viewer.animator && "
                                    "viewer.animator.actions.length > 0", timeout=30_000)
        self.duration = self.page.evaluate("viewer.animator.duration")

    def seek(self, t):
        self.page.evaluate("(t) => { viewer.animator.pause(); viewer.animator.seek(t); }", t)

    def visible(self, path, on):
        self.page.evaluate("([p, on]) => { viewer.scene_tree.find(p).set_property('visible', "
                           "on); viewer.set_dirty(); }", [path, on])

    def pixels(self):
        """The WebGL canvas now (rendered on demand, without the controls' overlay)."""
        from PIL import Image
        url = self.page.evaluate("() => { viewer.render(); "
                                 "return viewer.renderer.domElement.toDataURL('image/png'); }")
        image = Image.open(io.BytesIO(base64.b64decode(url.split(",", 1)[1])))
        return np.asarray(image.convert("RGB")).astype(int)

    def changed_by_hiding(self, path, shown):
        """The pixels that change when ``path`` is hidden (a boolean mask)."""
        self.visible(path, False)
        hidden = self.pixels()
        self.visible(path, True)
        return np.abs(shown - hidden).sum(axis=2) > 30


def save(pixels, path):
    from PIL import Image
    Image.fromarray(pixels.astype(np.uint8)).save(path)


def test_follow_replay_keeps_the_car_on_the_road_in_view(browser, replays, tmp_path):
    began = time.perf_counter()
    path, history = replays["follow"]
    assert history["x_m"][-1] - history["x_m"][0] > 15.0  # the car really goes down the road
    page = Page(browser, path)
    assert page.duration == pytest.approx(history["t"][-1], abs=0.1)
    area = {}
    height, width = VIEWPORT["height"], VIEWPORT["width"]
    for t in (0.0, page.duration / 2, page.duration):
        page.seek(t)
        shown = page.pixels()
        save(shown, tmp_path / f"follow_{t:04.2f}.png")
        car = page.changed_by_hiding(CAR, shown)
        area[t] = int(car.sum())
        assert area[t] > 0.01 * width * height, f"t = {t:.2f} s: the car is not in view"
        rows, cols = np.nonzero(car)
        assert 0.3 < cols.mean() / width < 0.7 and 0.3 < rows.mean() / height < 0.9, \
            f"t = {t:.2f} s: the car is off the middle ({cols.mean():.0f}, {rows.mean():.0f})"
        road = int(page.changed_by_hiding(ROAD, shown).sum())
        assert road > 0.08 * width * height, f"t = {t:.2f} s: no road ({road} px)"
        markings = int(page.changed_by_hiding(MARKINGS, shown).sum())
        assert markings > 0.002 * width * height, f"t = {t:.2f} s: no lane markings"
    # The camera follows: the car looks as big at the end as at the start (25 m further on, a
    # fixed camera would see it at a fraction of its size).
    assert 0.7 < area[page.duration] / area[0.0] < 1.4, area
    assert page.errors == [], page.errors
    assert page.remote == [], page.remote
    print(f"\nfollow replay in the browser: {time.perf_counter() - began:.1f} s; "
          f"screenshots in {tmp_path}")


def test_overview_replay_and_meshcat_controls(browser, replays, tmp_path):
    path, _ = replays["overview"]
    page = Page(browser, path)
    for t in (0.0, page.duration / 2, page.duration):
        page.seek(t)
        shown = page.pixels()
        save(shown, tmp_path / f"overview_{t:04.2f}.png")
        assert page.changed_by_hiding(CAR, shown).sum() > 50, f"t = {t:.2f} s: no car"
        assert page.changed_by_hiding(ROAD, shown).sum() > 0.05 * shown.shape[0] * shown.shape[1]
    # Meshcat's own controls: play, pause, and the time slider.
    page.seek(0.0)
    page.page.evaluate("viewer.animator.play()")
    page.page.wait_for_timeout(400)
    assert page.page.evaluate("viewer.animator.playing")
    page.page.click("text=Open Controls")
    page.page.click(".dg li.function:has-text('pause')")
    assert not page.page.evaluate("viewer.animator.playing")
    slider = page.page.locator(".dg li.number:has-text('time') .slider").first
    box = slider.bounding_box()
    page.page.mouse.click(box["x"] + 0.75 * box["width"], box["y"] + box["height"] / 2)
    assert page.page.evaluate("viewer.animator.time") == pytest.approx(
        0.75 * page.duration, abs=0.1 * page.duration)
    assert page.errors == [], page.errors
    assert page.remote == [], page.remote
