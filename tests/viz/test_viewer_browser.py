"""The viewer in a real browser: Debian's Chromium, headless, software WebGL.

A Viewer serves a four-bar with two coloured boxes (one on the world, one on
the crank); Chromium loads the page, runs viser's client, connects over the
websocket and renders. Checked: the server saw the browser connect; the page's
scene tree (the DOM after the client ran) lists our nodes; the screenshot
holds both boxes (blue on the world, green on the crank), so the scene reached WebGL; after show() turns the crank,
a second browser sees the crank's box moved and the world's box not. tests/run_all.sh
installs the `chromium` package (apt-get) when it is missing.
"""
from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest
from PIL import Image

import soadyn
from soadyn.viewer import Viewer

BROWSER_TIMEOUT = 120  # seconds for one headless Chromium run
VIRTUAL_TIME_MS = 15000  # page time Chromium lets pass (timers, websocket) before it captures
# Chromium's page time runs ahead of the wall clock: on a loaded machine the server's websocket
# messages can arrive after the capture. A run is repeated, up to this many times, until the
# server saw a new connection (and, where a test asks, until the capture holds what it needs);
# a viewer that never serves the page, or never sends the scene, fails every attempt.
ATTEMPTS = 4


def chromium() -> str:
    path = shutil.which("chromium") or shutil.which("chromium-browser")
    assert path, "Chromium is needed for the browser test: apt-get install chromium (tests/run_all.sh does it as root)"
    return path


def headless(tmp_path, url: str, *action: str, connected=None, complete=None) -> subprocess.CompletedProcess:
    """One headless Chromium run on `url` (repeated while `connected`, the server's list of
    connections, did not grow, or while `complete(result)` is false)."""
    for _ in range(ATTEMPTS):
        before = None if connected is None else len(connected)
        result = _chromium_once(tmp_path, url, *action)
        if result.returncode != 0:
            return result
        if (connected is None or len(connected) > before) and (complete is None or complete(result)):
            return result
    return result


def _chromium_once(tmp_path, url: str, *action: str) -> subprocess.CompletedProcess:
    command = [chromium(), "--headless", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
               "--enable-unsafe-swiftshader", "--no-first-run", "--disable-dev-shm-usage",
               f"--user-data-dir={tmp_path / 'profile'}", "--window-size=1200,900",
               f"--virtual-time-budget={VIRTUAL_TIME_MS}", *action, url]
    return subprocess.run(command, capture_output=True, text=True, timeout=BROWSER_TIMEOUT)


@pytest.fixture
def served_four_bar():
    m = soadyn.scenes.four_bar()
    m.visuals = [soadyn.Visual("blue_block", "world", "box", size=[0.03, 0.03, 0.03], translation=[0.0, 0.0, -0.04],
                               rgba=[0.0, 0.0, 1.0, 1.0]),
                 soadyn.Visual("green_block", "crank", "box", size=[0.02, 0.02, 0.02], translation=[0.038, 0.0, 0.0],
                               rgba=[0.0, 1.0, 0.0, 1.0])]
    q, _ = soadyn.scenes.four_bar_state(0.5)
    viewer = Viewer(m, port=0, q=q, frames=False)
    viewer.server.initial_camera.position = (0.02, -0.12, 0.15)
    viewer.server.initial_camera.look_at = (0.02, 0.0, -0.01)
    connected = []
    viewer.server.on_client_connect(lambda client: connected.append(client.client_id))
    yield viewer, connected
    viewer.close()


def test_a_real_browser_connects_and_lists_the_scene(served_four_bar, tmp_path):
    viewer, connected = served_four_bar
    nodes = ("bodies", "visuals", "loops")
    result = headless(tmp_path, viewer.url, "--dump-dom", connected=connected,
                      complete=lambda r: all(node in r.stdout for node in nodes))
    assert result.returncode == 0, result.stderr[-2000:]
    assert connected, "the browser never opened the websocket"
    dom = result.stdout
    for node in nodes:
        assert node in dom, f"the page's scene tree does not list /{node}"


def colour_pixels(path) -> dict:
    """{colour: (count, centroid)} of blue and green pixels, told by hue so that a scene still fading in counts
    too; the page's corners with the axes gizmo, the software-rendering notice and the control panel are left
    out (the loops are drawn red, the sticks grey)."""
    hsv = np.asarray(Image.open(path).convert("HSV")).astype(int)  # each channel 0-255
    hue, tinted = hsv[..., 0], hsv[..., 1] >= 12
    scene = np.ones(hue.shape, bool)
    scene[-120:, :120] = False  # the axes gizmo
    scene[:160, :320] = False  # the software-rendering notice
    scene[:360, -340:] = False  # the control panel (blue buttons)
    masks = {"blue": (hue >= 150) & (hue <= 195) & tinted & scene,  # 212-275 degrees
             "green": (hue >= 60) & (hue <= 110) & tinted & scene}  # 85-155 degrees
    out = {}
    for name, mask in masks.items():
        ys, xs = np.nonzero(mask)
        out[name] = (int(mask.sum()), np.array([xs.mean(), ys.mean()]) if mask.any() else None)
    return out


def test_a_real_browser_renders_the_visuals_where_show_puts_them(served_four_bar, tmp_path):
    viewer, connected = served_four_bar
    seen = []
    for crank_angle in (0.5, 2.5):
        viewer.show(soadyn.scenes.four_bar_state(crank_angle)[0])
        shot = tmp_path / f"viewer_{crank_angle}.png"
        result = headless(tmp_path, viewer.url, f"--screenshot={shot}", connected=connected)
        assert result.returncode == 0 and shot.is_file(), result.stderr[-2000:]
        seen.append(colour_pixels(shot))
    assert len(connected) >= 2
    for colours in seen:
        assert colours["blue"][0] >= 500, f"the blue box on the world is not on the screenshot: {colours}"
        assert colours["green"][0] >= 200, f"the green box on the crank is not on the screenshot: {colours}"
    blue_shift = np.linalg.norm(seen[1]["blue"][1] - seen[0]["blue"][1])
    green_shift = np.linalg.norm(seen[1]["green"][1] - seen[0]["green"][1])
    assert green_shift >= 20, f"the crank's box did not move in the browser ({green_shift:.1f} px)"
    assert blue_shift <= 2, f"the world's box moved ({blue_shift:.1f} px)"
