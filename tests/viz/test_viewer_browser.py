"""The viewer in a real browser: Debian's Chromium, headless, software WebGL.

A Viewer serves a four-bar with two coloured boxes (one on the world, one on
the crank); Chromium loads the page, runs viser's client, connects over the
websocket and renders. Checked: the server saw the browser connect; the page's
scene tree (the DOM after the client ran) lists our nodes; the screenshot
holds both boxes (blue on the world, green on the crank), so the scene reached WebGL; after show() turns the crank,
a second page (a new client) sees the crank's box moved and the world's box not. tests/run_all.sh
installs the `chromium` package (apt-get) when it is missing.

Chromium is driven over the DevTools protocol (soadyn.viz.headless.HeadlessBrowser): each page is read and captured as soon as it holds
what the test looks for (polled against a deadline), rather than after a fixed page time per run.
The scene has no environment map (viser's default lighting, an HDR image that software WebGL spends
seconds per page filtering): the test looks at where the boxes are, not at their shading.
"""
from __future__ import annotations

import time

import numpy as np
import pytest
from PIL import Image

import soadyn
from soadyn.viewer import Viewer
from soadyn.viz.headless import HeadlessBrowser

BROWSER_TIMEOUT = 120  # seconds for a page to hold what a test waits for
POLL_SECONDS = 0.2


def poll(read, holds, what: str):
    """read() until holds(its value), within BROWSER_TIMEOUT seconds: the last value."""
    deadline = time.monotonic() + BROWSER_TIMEOUT
    while True:
        value = read()
        if holds(value):
            return value
        assert time.monotonic() < deadline, f"the page never {what}"
        time.sleep(POLL_SECONDS)


@pytest.fixture
def served_four_bar():
    m = soadyn.scenes.four_bar()
    m.visuals = [soadyn.Visual("blue_block", "world", "box", size=[0.03, 0.03, 0.03], translation=[0.0, 0.0, -0.04],
                               rgba=[0.0, 0.0, 1.0, 1.0]),
                 soadyn.Visual("green_block", "crank", "box", size=[0.02, 0.02, 0.02], translation=[0.038, 0.0, 0.0],
                               rgba=[0.0, 1.0, 0.0, 1.0])]
    q, _ = soadyn.scenes.four_bar_state(0.5)
    viewer = Viewer(m, port=0, q=q, frames=False, links=False)  # the two boxes alone
    viewer.server.initial_camera.position = (0.02, -0.12, 0.15)
    viewer.server.initial_camera.look_at = (0.02, 0.0, -0.01)
    viewer.server.scene.configure_environment_map(hdri=None)
    connected = []
    viewer.server.on_client_connect(lambda client: connected.append(client.client_id))
    yield viewer, connected
    viewer.close()


@pytest.fixture
def browser(served_four_bar, tmp_path):
    """A Chromium, closed before the viewer (its open connections would hold the server's shutdown)."""
    chrome = HeadlessBrowser(1200, 900, folder=tmp_path)
    yield chrome
    chrome.close()


def test_a_real_browser_connects_and_lists_the_scene(browser, served_four_bar):
    viewer, connected = served_four_bar
    nodes = ("bodies", "visuals", "loops")
    with browser.page(viewer.url) as page:
        dom = poll(lambda: browser.dom(page), lambda text: all(node in text for node in nodes),
                   f"listed /{', /'.join(nodes)} in its scene tree")
    # viser counts a client as connected at its first camera message, which the
    # page sends once it renders: possibly after the scene tree is listed.
    poll(lambda: list(connected), bool, "connected as a client (its first camera message)")
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


def test_a_real_browser_renders_the_visuals_where_show_puts_them(browser, served_four_bar, tmp_path):
    viewer, connected = served_four_bar
    seen = []
    for crank_angle in (0.5, 2.5):
        viewer.show(soadyn.scenes.four_bar_state(crank_angle)[0])
        clients, shot = len(connected), tmp_path / f"viewer_{crank_angle}.png"
        with browser.page(viewer.url) as page:
            poll(lambda: len(connected), lambda count: count > clients, "connected to the viewer")

            def capture():
                browser.screenshot(page, shot)
                return colour_pixels(shot)

            poll(capture, lambda colours: colours["blue"][0] > 0 and colours["green"][0] > 0, "drew the two boxes")
            time.sleep(1.0)  # the scene has arrived: a second for it to settle, then the capture judged
            seen.append(capture())
    assert len(connected) >= 2
    for colours in seen:
        assert colours["blue"][0] >= 500, f"the blue box on the world is not on the screenshot: {colours}"
        assert colours["green"][0] >= 200, f"the green box on the crank is not on the screenshot: {colours}"
    blue_shift = np.linalg.norm(seen[1]["blue"][1] - seen[0]["blue"][1])
    green_shift = np.linalg.norm(seen[1]["green"][1] - seen[0]["green"][1])
    assert green_shift >= 20, f"the crank's box did not move in the browser ({green_shift:.1f} px)"
    assert blue_shift <= 2, f"the world's box moved ({blue_shift:.1f} px)"
