"""Pictures and movies of a Viewer without a browser session: a headless Chromium runs viser's client.

Chromium (Debian's `chromium` package; another binary through the
SOADYN_CHROMIUM variable) opens the viewer's page with software WebGL
(SwiftShader: no GPU or display needed), and viser's own render request
(`ClientHandle.get_render`) returns what that page draws, so a picture shows
exactly what a user sees in the browser. Chromium is driven over its
DevTools protocol (one websocket); nothing here parses HTML or draws.

- `HeadlessBrowser`: a Chromium process and its DevTools connection;
- `render_png(viewer, path)`: one picture of the shown state, once the page
  has settled (two renders in a row alike: meshes load asynchronously);
- `render_movie(viewer, trajectory, path, fps)`: one picture per frame of
  simulated time, written by imageio (MP4 through imageio-ffmpeg's own
  ffmpeg; GIF through Pillow).
Transparent background pixels are laid on white.
"""
from __future__ import annotations

import base64
import contextlib
import json
import logging
import numbers
import os
import shutil
import signal
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from .playback import resample, trajectory_arrays

__all__ = ["HeadlessBrowser", "chromium_path", "render_png", "render_movie", "rendered_frames"]

TIMEOUT = 120.0  # seconds for Chromium to start, a page to connect, or a render to come back
SETTLE_SECONDS = 0.4  # between the renders compared to tell a settled page
CHROMIUM_NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
MOVIE_EXTENSIONS = (".mp4", ".gif")
BARRIER_SIZE = 16  # pixels a side of the render that lets the page catch up with the poses sent
MOVIE_BLOCK = 16  # video encoders want frame sizes in multiples of 16


def chromium_path() -> str:
    """The Chromium binary: $SOADYN_CHROMIUM, else the first of chromium, chromium-browser, google-chrome on
    PATH. RuntimeError saying how to install it when there is none."""
    named = os.environ.get("SOADYN_CHROMIUM")
    if named:
        if shutil.which(named) is None:
            raise RuntimeError(f"SOADYN_CHROMIUM={named!r} is not an executable")
        return shutil.which(named)
    for name in CHROMIUM_NAMES:
        if shutil.which(name):
            return shutil.which(name)
    raise RuntimeError("pictures and movies need Chromium: apt-get install chromium (Debian/Ubuntu), "
                       "or set SOADYN_CHROMIUM to a Chromium or Chrome binary")


class HeadlessBrowser:
    """A headless Chromium with software WebGL and its DevTools websocket (pages attached in flat mode)."""

    def __init__(self, width: int = 1280, height: int = 720, folder=None):
        from websockets.sync.client import connect

        self._folder = None if folder is not None else tempfile.TemporaryDirectory(prefix="soadyn-chromium-")
        folder = Path(folder if folder is not None else self._folder.name)
        profile, log = folder / "profile", folder / "chromium.log"  # its messages go to a file: no pipe to fill
        with log.open("w") as messages:
            self.process = subprocess.Popen(
                [chromium_path(), "--headless", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
                 "--enable-unsafe-swiftshader", "--no-first-run", "--disable-dev-shm-usage", "--hide-scrollbars",
                 f"--user-data-dir={profile}", f"--window-size={int(width)},{int(height)}",
                 "--remote-debugging-port=0", "about:blank"],
                stdout=subprocess.DEVNULL, stderr=messages, start_new_session=True)
        try:
            active_port = profile / "DevToolsActivePort"  # Chromium writes its port and path there once listening
            deadline = time.monotonic() + TIMEOUT
            while len(active_port.read_text().split() if active_port.exists() else ()) < 2:
                if self.process.poll() is not None:
                    raise RuntimeError(f"Chromium exited: {log.read_text()[-2000:]}")
                if time.monotonic() > deadline:
                    raise RuntimeError("Chromium did not open its DevTools port")
                time.sleep(0.05)
            port, path = active_port.read_text().split()
            self.socket = connect(f"ws://127.0.0.1:{port}{path}", max_size=None)
        except BaseException:
            self.kill()
            raise
        self.calls = 0

    def call(self, method: str, session: str | None = None, **params) -> dict:
        """One DevTools command (on page `session` if given): its result; RuntimeError with Chromium's error."""
        self.calls += 1
        message = {"id": self.calls, "method": method, "params": params}
        if session is not None:
            message["sessionId"] = session
        self.socket.send(json.dumps(message))
        while True:  # events of the pages come in between; the reply carries the call's id
            reply = json.loads(self.socket.recv(timeout=TIMEOUT))
            if reply.get("id") == self.calls:
                if "error" in reply:
                    raise RuntimeError(f"Chromium: {method}: {reply['error']}")
                return reply["result"]

    @contextlib.contextmanager
    def page(self, url: str):
        """A new page on `url`, closed after: its DevTools session."""
        target = self.call("Target.createTarget", url=url)["targetId"]
        try:
            yield self.call("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
        finally:
            self.call("Target.closeTarget", targetId=target)

    def dom(self, session: str) -> str:
        """The page's HTML as the browser holds it now, in the tab of `session` ('' before a document)."""
        expression = "document.documentElement ? document.documentElement.outerHTML : ''"
        return self.call("Runtime.evaluate", session, expression=expression, returnByValue=True)["result"].get(
            "value", "")

    def screenshot(self, session: str, path) -> None:
        """The page as Chromium shows it (canvas and controls) in a PNG file."""
        Path(path).write_bytes(base64.b64decode(self.call("Page.captureScreenshot", session, format="png")["data"]))

    def close(self) -> None:
        """Close the DevTools connection and end the browser process (safe to call twice)."""
        with contextlib.suppress(Exception):
            self.socket.close()
        self.kill()

    def kill(self) -> None:
        """Chromium and the processes it started (GPU, renderers: its own process group)."""
        with contextlib.suppress(ProcessLookupError):
            os.killpg(self.process.pid, signal.SIGKILL)
        self.process.wait(TIMEOUT)
        if self._folder is not None:
            self._folder.cleanup()

    def __enter__(self) -> "HeadlessBrowser":
        return self

    def __exit__(self, *_exc) -> None:
        self.close()


def _on_white(rgba: np.ndarray) -> np.ndarray:
    """An (H, W, 3) uint8 picture: the render's transparent background laid on white."""
    rgba = np.asarray(rgba)
    if rgba.shape[-1] == 3:
        return rgba.astype(np.uint8)
    alpha = rgba[..., 3:4].astype(float) / 255.0
    return np.round(rgba[..., :3] * alpha + 255.0 * (1.0 - alpha)).astype(np.uint8)


def camera_wxyz(position, look_at, up) -> np.ndarray:
    """The quaternion (w, x, y, z) of a camera at `position` looking at `look_at` with `up` up on the screen,
    in viser's camera convention (OpenCV: x right, y down, z forward)."""
    from viser import transforms

    forward = np.asarray(look_at, dtype=float) - np.asarray(position, dtype=float)
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    return transforms.SO3.from_matrix(np.column_stack([right, np.cross(forward, right), forward])).wxyz


@contextlib.contextmanager
def rendered_frames(viewer, width: int = 1280, height: int = 720, browser: HeadlessBrowser | None = None,
                    transport: str = "png", states=None):
    """A function render() -> (height, width, 3) uint8 picture of what `viewer` shows, from a headless page
    framed as viewer.camera_view() says (on `states` if given, a movie's frames), a `browser` given reused,
    else one started and closed.
    `transport`: "png" (lossless) or "jpeg" (about twice as fast; movies are lossy anyway)."""
    if not all(isinstance(x, numbers.Integral) and not isinstance(x, bool) and 16 <= x <= 8192
               for x in (width, height)):
        raise ValueError(f"viewer: picture size must be whole numbers of 16 to 8192 pixels a side, got {width!r} x "
                         f"{height!r}")
    width, height = int(width), int(height)
    own = browser is None
    browser = HeadlessBrowser(width, height) if own else browser
    handshakes = logging.getLogger("websockets.server")  # Chromium's probes of the port are not errors
    level = handshakes.level
    handshakes.setLevel(logging.CRITICAL)
    try:
        known = set(viewer.server.get_clients())
        with browser.page(viewer.url):
            deadline = time.monotonic() + TIMEOUT
            while not set(viewer.server.get_clients()) - known:
                if time.monotonic() > deadline:
                    raise RuntimeError(f"the headless page never connected to the viewer at {viewer.url}")
                time.sleep(0.05)
            client = viewer.server.get_clients()[min(set(viewer.server.get_clients()) - known)]
            position, look_at, up = viewer.camera_view(width / height, states)
            wxyz = camera_wxyz(position, look_at, up)

            def render() -> np.ndarray:
                client.flush()
                # The page applies poses it received on its next frame: a tiny render first is that frame.
                client.get_render(BARRIER_SIZE, BARRIER_SIZE, transport_format="jpeg", timeout=TIMEOUT)
                return _on_white(client.get_render(height, width, wxyz=wxyz, position=position,
                                                   transport_format=transport, timeout=TIMEOUT))

            yield render
    finally:
        handshakes.setLevel(level)
        if own:
            browser.close()


def settled(render, timeout: float = TIMEOUT) -> np.ndarray:
    """render() until two pictures SETTLE_SECONDS apart are alike (meshes still loading change them)."""
    deadline = time.monotonic() + timeout
    previous = render()
    while True:
        time.sleep(SETTLE_SECONDS)
        picture = render()
        if np.array_equal(picture, previous) or time.monotonic() > deadline:
            return picture
        previous = picture


def render_png(viewer, path, width: int = 1280, height: int = 720) -> np.ndarray:
    """Write a PNG of what `viewer` shows (framed on the model); returns the picture."""
    from PIL import Image

    with rendered_frames(viewer, width, height) as render:
        picture = settled(render)
    Image.fromarray(picture).save(path)
    return picture


def render_movie(viewer, trajectory, path, fps: float = 30.0, width: int = 1280, height: int = 720,
                 speed: float = 1.0) -> int:
    """Write a movie (MP4, or GIF by its extension) of `trajectory` replayed in `viewer` at `fps` frames per
    second, `speed` seconds of simulated time per second of movie; returns the number of frames.
    The viewer is left showing the state it showed before."""
    import imageio.v2 as imageio

    if not str(path).lower().endswith(MOVIE_EXTENSIONS):
        raise ValueError(f"viewer: a movie is written as {' or '.join(MOVIE_EXTENSIONS)}, not '{path}'")
    if not (np.isfinite(speed) and speed > 0):
        raise ValueError(f"viewer: the movie speed must be a finite number > 0, got {speed}")
    _, frames = resample(*trajectory_arrays(viewer.model, trajectory), fps / speed)
    is_gif = str(path).lower().endswith(".gif")
    if not is_gif:
        width, height = (MOVIE_BLOCK * max(1, round(x / MOVIE_BLOCK)) for x in (width, height))
    shown = viewer.q.copy()
    options = {"duration": 1.0 / fps, "loop": 0} if is_gif else {"fps": fps, "codec": "libx264", "quality": 7,
                                                                  "macro_block_size": MOVIE_BLOCK}
    try:
        with rendered_frames(viewer, width, height, transport="jpeg", states=frames) as render, \
                imageio.get_writer(path, **options) as movie:
            viewer.show(frames[0])
            movie.append_data(settled(render))
            for q in frames[1:]:
                viewer.show(q)
                movie.append_data(render())
    finally:
        viewer.show(shown)
    return len(frames)
