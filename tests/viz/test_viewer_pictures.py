"""Pictures, movies and pages of the viewer without a browser session: a headless Chromium runs viser's
client (soadyn.viz.headless), as `soadyn view --screenshot/--movie/--html` does.

- Pictures of cassini, the four-bar, ur5 and talos (example-robot-data) from the command line: not blank
  (3% of the pixels drawn, not a dot), framed (the drawn pixels span most of the picture one way and are
  centred), and for the models with visuals (meshes of ur5 and talos, cassini's primitives) what is drawn
  is their shapes: five times the pixels of a picture of the same model with its axes alone (the flexible
  bodies' beams, drawn alike in both, left out of the count).
- A movie of a replayed trajectory (an .npz file Trajectory.save wrote): one frame per 1/fps of simulated
  time, and in each frame the four-bar's cut joint (its red ball) is where a pinhole projection of the
  joint's position at that frame's state puts it, to 3 pixels: the replay is in order and framed as said.
- A GIF from Viewer.save_movie; a standalone page (save_html) that draws the scene in a browser with the
  viewer's server closed (offline).
tests/run_all.sh installs Chromium (apt-get) when it is missing.
"""
from __future__ import annotations

import time

import imageio.v2 as imageio
import numpy as np
import pytest
from PIL import Image

from soadyn.apps import cli
from soadyn.viewer import Viewer, load_any, scene_poses, start_state
from soadyn.viz.headless import HeadlessBrowser
from soadyn.viz.playback import resample
from support.robots import robot
from support.viewers import four_bar_run

WIDTH, HEIGHT = 640, 360
PICTURED = {"cassini": lambda: "cassini", "four-bar": lambda: "four-bar",
            "ur5": lambda: str(robot("ur5")[0]), "talos": lambda: str(robot("talos")[0])}
PAGE_TIMEOUT = 120


def drawn(picture) -> np.ndarray:
    """Pixels that are not the white background."""
    return np.asarray(picture, dtype=int)[..., :3].min(axis=2) < 245


def shapes(picture) -> np.ndarray:
    """Drawn pixels but the flexible bodies' beams (blue lines, drawn alike with or without visuals)."""
    hsv = np.asarray(Image.fromarray(np.asarray(picture, dtype=np.uint8)).convert("HSV")).astype(int)
    beam_blue = (np.abs(hsv[..., 0] - 152) <= 6) & (hsv[..., 1] >= 150)  # (40, 110, 220): 215 degrees
    return drawn(picture) & ~beam_blue


def axes_only_picture(source: str, path) -> np.ndarray:
    """The same model drawn by its body axes alone (no visuals, no link figures), lit as the command line's
    pictures are."""
    m = load_any(source)
    q = start_state(source, m)[0]
    m.visuals = []
    viewer = Viewer(m, port=0, q=q, links=False, frames=True, environment=False)
    try:
        return viewer.save_png(path, WIDTH, HEIGHT)
    finally:
        viewer.close()


@pytest.mark.parametrize("name", PICTURED)
def test_a_picture_shows_the_model_drawn_and_framed(name, tmp_path):
    source, out = PICTURED[name](), tmp_path / f"{name}.png"
    assert cli.main(["view", source, "--screenshot", str(out), "--width", str(WIDTH), "--height", str(HEIGHT),
                     "--no-axes"]) == 0
    picture = np.asarray(Image.open(out).convert("RGB"))
    assert picture.shape == (HEIGHT, WIDTH, 3)
    mask = drawn(picture)
    ys, xs = np.nonzero(mask)
    span = ((xs.max() - xs.min() + 1) / WIDTH, (ys.max() - ys.min() + 1) / HEIGHT)
    assert max(span) >= 0.6, f"{name}: the model spans only {span[0]:.0%} x {span[1]:.0%} of the picture"
    centre = ((xs.max() + xs.min()) / 2 / WIDTH, (ys.max() + ys.min()) / 2 / HEIGHT)
    assert abs(centre[0] - 0.5) <= 0.15 and abs(centre[1] - 0.5) <= 0.15, f"{name}: off centre at {centre}"
    assert mask.mean() >= 0.03, f"{name}: {mask.mean():.1%} of the picture drawn"
    if name != "four-bar":  # the models with visuals of their own: meshes (ur5, talos), primitives (cassini)
        model, axes = shapes(picture).sum(), shapes(axes_only_picture(source, tmp_path / f"{name}_axes.png")).sum()
        assert model >= 5 * axes, f"{name}: {model} pixels of shapes, {axes} with the axes alone"


@pytest.fixture
def turning_four_bar(tmp_path):
    """The four-bar's crank driven round at 4 rad/s for half a second, and the .npz file of the run."""
    m, trajectory = four_bar_run(0.5, crank_rate=4.0)
    trajectory.save(tmp_path / "four_bar.npz")
    return m, trajectory, tmp_path / "four_bar.npz"


def pixel(point, position, look_at, up, fov, width, height) -> np.ndarray:
    """Where a pinhole camera (vertical field of view fov) puts a world point: (column, row)."""
    forward = (look_at - position) / np.linalg.norm(look_at - position)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    screen_up = np.cross(right, forward)
    offset = point - position
    depth, scale = offset @ forward, height / 2 / np.tan(fov / 2)
    return np.array([width / 2 + scale * (offset @ right) / depth, height / 2 - scale * (offset @ screen_up) / depth])


def red_centroid(frame) -> np.ndarray:
    """(column, row) of the red pixels: the loop's cut-joint ball."""
    rgb = np.asarray(frame, dtype=int)
    red = (rgb[..., 0] > 120) & (rgb[..., 1] < 0.35 * rgb[..., 0]) & (rgb[..., 2] < 0.35 * rgb[..., 0])  # not orange
    assert red.sum() >= 10, "no cut-joint ball in the frame"
    ys, xs = np.nonzero(red)
    return np.array([xs.mean(), ys.mean()])


def test_a_movie_replays_the_trajectory_in_order(turning_four_bar, tmp_path):
    m, trajectory, npz = turning_four_bar
    movie, width, height = tmp_path / "four_bar.mp4", 320, 192
    assert cli.main(["view", "four-bar", "--trajectory", str(npz), "--movie", str(movie), "--fps", "8",
                     "--width", str(width), "--height", str(height), "--no-axes"]) == 0
    frames = [np.asarray(f) for f in imageio.get_reader(movie)]
    assert len(frames) == 5  # 0, 1/8, ..., 4/8 s
    _, states = resample(trajectory.t, trajectory.q, 8.0)
    viewer = Viewer(m, port=0, q=states[0], frames=False)
    try:  # the camera the movie was framed with, and the cut joint's world position at each frame's state
        position, look_at, up = viewer.camera_view(width / height, states)
        fov = float(viewer.server.initial_camera.fov)
    finally:
        viewer.close()
    seen = np.array([red_centroid(f) for f in frames])
    expected = np.array([pixel(scene_poses(m, q)["/loops/coupler_rocker/a"][:3, 3], position, look_at, up, fov,
                               width, height) for q in states])
    assert np.linalg.norm(expected[-1] - expected[0]) >= 20  # the pin travels across the picture
    error = np.linalg.norm(seen - expected, axis=1)
    assert error.max() <= 3.0, f"the cut joint is {error.round(1)} pixels from where each state puts it"


def test_a_gif_and_an_offline_page(turning_four_bar, tmp_path):
    m, trajectory, _ = turning_four_bar
    viewer = Viewer(m, port=0, q=trajectory.q[0], environment=False)
    try:
        assert viewer.save_movie(tmp_path / "four_bar.gif", trajectory, fps=4, width=240, height=160) == 3
        viewer.save_html(tmp_path / "four_bar.html", trajectory, fps=10)
    finally:
        viewer.close()
    assert len(list(imageio.get_reader(tmp_path / "four_bar.gif"))) == 3
    shot = tmp_path / "page.png"
    with HeadlessBrowser(800, 600, folder=tmp_path) as browser, \
            browser.page((tmp_path / "four_bar.html").as_uri()) as page:
        deadline = time.monotonic() + PAGE_TIMEOUT
        while True:  # the page decodes its embedded scene and draws it: poll its screenshot
            browser.screenshot(page, shot)
            hsv = np.asarray(Image.open(shot).convert("HSV")).astype(int)
            orange = (hsv[..., 0] >= 14) & (hsv[..., 0] <= 32) & (hsv[..., 1] >= 90) & (hsv[..., 2] >= 120)
            if orange.sum() >= 100 or time.monotonic() > deadline:
                break
            time.sleep(0.5)
    assert orange.sum() >= 100, "the offline page never drew the four-bar's joints"
