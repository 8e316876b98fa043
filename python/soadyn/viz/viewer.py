"""A 3D viewer on viser (a maintained web viewer: the browser draws, no WebGL of ours).

`Viewer(m)`: a viser server drawing the nodes of the scene graph
(soadyn.viz.scene_graph) — each Visual as its shape (box, sphere, ellipsoid,
cylinder, capsule as a cylinder with end spheres, mesh from vertices/faces or
a mesh file read by soadyn.viz.meshes), body and frame axes sized to the
model, rods and joint markers for bodies without visuals (soadyn.viz.figures),
every cut joint as a ball on each side joined by a line, flexible bodies as
polylines through their deformed nodes — moved by `show(q)`. The camera
starts framed on the model (soadyn.viz.framing; "reset view" frames it
again, "follow" keeps a free base in view). `play(trajectory, speed, trails)`
adds a time slider, a play checkbox, a playback-speed slider and the paths of
chosen frames. `save_png`, `save_movie` render in a headless Chromium
(soadyn.viz.headless); `save_html` writes a standalone page that replays a
trajectory offline.

Decisions: the viewer never runs in a real-time thread; it reads states it is
given. A mesh file that cannot be read is drawn as its frame's axes and named
once in a warning, with the reason.
"""
from __future__ import annotations

import threading
import time
import warnings

import numpy as np

from .._soadyn import neutral_configuration
from ..model import Model
from .figures import link_radius, link_visuals
from .framing import ASPECT, framed_camera, up_direction, visual_corners
from .meshes import MeshError, read_mesh
from .playback import TRAIL_COLOURS, resample, trail_points, trajectory_arrays
from .scene_graph import drawn_frames, flexible_blocks, flexible_shapes, loop_anchors, scene_poses
from .sources import BUILT_IN_SCENES, load_any, start_state

__all__ = ["BUILT_IN_SCENES", "MeshError", "Viewer", "drawn_frames", "flexible_shapes", "load_any", "read_mesh",
           "scene_poses", "start_state"]

LOOP_COLOUR = (220, 40, 40)
AXES_PER_ROD = 8.0  # body axes this many link radii long (soadyn.viz.figures.link_radius)
HEMISPHERE_INTENSITY = 1.5  # about the brightness of the environment map it replaces
FRAMING_STATES = 24  # states of a trajectory the camera is framed on
PLAYBACK_PERIOD = 0.03  # seconds between the play loop's advances of the time slider


def _wxyz(R) -> np.ndarray:
    from viser import transforms
    return transforms.SO3.from_matrix(np.asarray(R)).wxyz


def _colour(rgba) -> tuple:
    return tuple(int(round(255 * c)) for c in np.clip(rgba[:3], 0, 1))


class Viewer:
    """A viser server drawing model `m` (see the module documentation); open `viewer.url` in a browser.

    `links`: draw rods and joint markers for bodies without visuals (soadyn.viz.figures); `follow`: keep the
    camera on a free-floating root body as it moves (also a checkbox in the page); `environment`: viser's
    image-based lighting (an HDR environment map), or with False a hemisphere light, which the command
    line's pictures and movies use: software WebGL (a headless browser) spends seconds per page filtering
    the map, and the hemisphere light shades about as well."""

    def __init__(self, m: Model, host: str = "127.0.0.1", port: int = 8080, q=None, frames: bool = True,
                 exaggeration: float = 1.0, links: bool = True, follow: bool = False, environment: bool = True):
        import viser

        if not isinstance(m, Model):
            raise TypeError(f"Viewer needs a soadyn.Model, got {type(m).__name__}")
        self.model = m
        self.server = viser.ViserServer(host=host, port=port, verbose=False)
        self._loops = loop_anchors(m)
        self._flexible = flexible_blocks(m)
        flexible_shapes(m, neutral_configuration(m), exaggeration, [])  # checks the factor
        self._exaggeration = float(exaggeration)
        self._lock = threading.Lock()
        self.handles: dict = {}
        self.visuals = list(m.visuals) + (link_visuals(m) if links else [])
        self._corners: dict[str, np.ndarray] = {}
        if not environment:
            self.server.scene.configure_environment_map(hdri=None)
            self.server.scene.add_light_hemisphere("/lighting", sky_color=(255, 255, 255), ground_color=(90, 90, 100),
                                                   intensity=HEMISPHERE_INTENSITY)
        self._add_nodes(frames)
        self.q = None
        self.exaggeration_slider = self._add_exaggeration_slider() if self._flexible else None
        self._followed = m.body_names[0] if m.nbodies and m.joint_types[0] == "free" else None
        self.follow_checkbox = (self.server.gui.add_checkbox(f"follow {self._followed}", initial_value=bool(follow))
                                if self._followed else None)
        self.server.gui.add_button("reset view").on_click(lambda _event: self.frame_view())
        self.show(np.asarray(q, dtype=float) if q is not None else neutral_configuration(m))
        self.frame_view()

    @property
    def exaggeration(self) -> float:
        """The factor on the flexible bodies' modal coordinates when drawing them (1: true size)."""
        return self._exaggeration

    @exaggeration.setter
    def exaggeration(self, value: float) -> None:
        flexible_shapes(self.model, self.q, value, [])  # checks the factor
        self._exaggeration = float(value)
        slider = self.exaggeration_slider
        if slider is not None and slider.max < self._exaggeration:
            slider.max = self._exaggeration  # the slider grows to any factor set from Python
        if slider is not None and slider.value != self._exaggeration:
            slider.value = self._exaggeration  # redraws through the slider's callback
        elif self.q is not None:
            self.show(self.q)

    def _add_exaggeration_slider(self):
        slider = self.server.gui.add_slider("flexible exaggeration", min=0.0, max=max(1000.0, self._exaggeration),
                                            step=1.0, initial_value=self._exaggeration)

        @slider.on_update
        def _(_event) -> None:
            self._exaggeration = float(slider.value)
            if self.q is not None:
                self.show(self.q)
        return slider

    @property
    def url(self) -> str:
        """The address a browser opens to see the viewer (http://host:port)."""
        return f"http://{self.server.get_host()}:{self.server.get_port()}"

    def _add_nodes(self, frames: bool) -> None:
        scene = self.server.scene
        unreadable = []
        rod = link_radius(self.model)  # axes and markers in proportion to the model
        for name in self.model.body_names:
            self.handles[f"/bodies/{name}"] = scene.add_frame(f"/bodies/{name}", show_axes=frames,
                                                              axes_length=AXES_PER_ROD * rod, axes_radius=0.3 * rod)
        self._frames = drawn_frames(self.model)
        for name in self._frames:
            self.handles[f"/frames/{name}"] = scene.add_frame(f"/frames/{name}", show_axes=frames,
                                                              axes_length=AXES_PER_ROD * rod / 2, axes_radius=0.15 * rod)
        for v in self.visuals:
            try:
                handle = self._add_visual(v)
            except MeshError as error:  # drawn as its frame's axes; every such mesh named once, with why
                unreadable.append(str(error))
                handle = scene.add_frame(f"/visuals/{v.name}", axes_length=AXES_PER_ROD * rod / 2,
                                         axes_radius=0.15 * rod)
                self._corners[v.name] = np.zeros((1, 3))
            self.handles[f"/visuals/{v.name}"] = handle
        marker = self._marker_radius = 1.4 * rod
        for name, *_ in self._loops:  # each cut joint: a ball on either side, joined by a line
            for side in ("a", "b"):
                self.handles[f"/loops/{name}/{side}"] = scene.add_icosphere(f"/loops/{name}/{side}", radius=marker,
                                                                            color=LOOP_COLOUR)
        if unreadable:
            warnings.warn("viewer: meshes that cannot be read are drawn as axes: " + "; ".join(unreadable),
                          stacklevel=3)

    def _add_visual(self, v):
        scene, path, colour = self.server.scene, f"/visuals/{v.name}", _colour(v.rgba)
        look = {"color": colour, "opacity": float(v.rgba[3]) if v.rgba[3] < 1 else None}
        mesh = None
        if v.shape == "box":
            handle = scene.add_box(path, dimensions=tuple(v.size), **look)
        elif v.shape in ("sphere", "ellipsoid"):
            scale = (v.size[0],) * 3 if v.shape == "sphere" else tuple(v.size)
            handle = scene.add_icosphere(path, radius=1.0, scale=scale, **look)
        elif v.shape in ("cylinder", "capsule"):
            handle = scene.add_cylinder(path, radius=float(v.size[0]), height=float(v.size[1]), **look)
            if v.shape == "capsule":
                for end, z in (("top", 0.5), ("bottom", -0.5)):
                    scene.add_icosphere(f"{path}/{end}", radius=float(v.size[0]), position=(0.0, 0.0, z * float(v.size[1])),
                                        **look)
        elif v.shape == "plane":
            size = [s if s > 0 else 10.0 for s in v.size[:2]]
            handle = scene.add_box(path, dimensions=(size[0], size[1], 1e-3), **look)
        elif v.vertices is not None:
            handle = scene.add_mesh_simple(path, vertices=v.vertices.astype(np.float32), faces=v.faces.astype(np.uint32),
                                           side="double", **look)
        else:
            mesh = read_mesh(v)
            handle = scene.add_mesh_trimesh(path, mesh)
        self._corners[v.name] = visual_corners(v, mesh)
        return handle

    def drawn_points(self, q=None) -> np.ndarray:
        """(N, 3) world points that bound everything drawn at configuration q (the shown one by default): body
        and frame origins, loop ends, the corners of every visual's box, flexible nodes."""
        q = self.q if q is None else np.asarray(q, dtype=float)
        poses = scene_poses(self.model, q, self._loops, self._frames, self.visuals)
        clouds = [np.array([T[:3, 3] for path, T in poses.items() if not path.startswith("/visuals/")]).reshape(-1, 3)]
        balls = np.array([T[:3, 3] for path, T in poses.items() if path.startswith("/loops/")]).reshape(-1, 3)
        clouds += [balls + offset for offset in self._marker_radius * np.vstack([np.eye(3), -np.eye(3)])]
        for v in self.visuals:
            T = poses[f"/visuals/{v.name}"]
            clouds.append(self._corners[v.name] @ T[:3, :3].T + T[:3, 3])
        clouds += list(flexible_shapes(self.model, q, self._exaggeration, self._flexible).values())
        cloud = np.concatenate(clouds)
        return cloud if len(cloud) else np.zeros((1, 3))

    def camera_view(self, aspect: float = ASPECT, states=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(position, look_at, up) of the camera framing the model on a picture `aspect` times as wide as tall
        (soadyn.viz.framing): at the shown state, or at every configuration of `states` (a movie's frames;
        at most FRAMING_STATES of them, evenly picked)."""
        up = up_direction(self.model)
        if states is None:
            points = self.drawn_points()
        else:
            states = np.asarray(states, dtype=float).reshape(-1, self.model.nq)
            picked = states[np.unique(np.linspace(0, len(states) - 1, FRAMING_STATES).round().astype(int))]
            points = np.concatenate([self.drawn_points(q) for q in picked])
        position, look_at = framed_camera(points, up, float(self.server.initial_camera.fov), aspect)
        return position, look_at, up

    def frame_view(self) -> None:
        """Frame the model: the camera of every page, and of pages opened later, on its bounding box."""
        position, look_at, up = self.camera_view()
        camera = self.server.initial_camera
        camera.position, camera.look_at, camera.up = tuple(position), tuple(look_at), tuple(up)
        for client in self.server.get_clients().values():
            with client.atomic():
                client.camera.up_direction = tuple(up)
                client.camera.position, client.camera.look_at = tuple(position), tuple(look_at)

    def show(self, q) -> None:
        """Move every node to its pose at configuration q."""
        q = np.asarray(q, dtype=float)
        if q.shape != (self.model.nq,) or not np.all(np.isfinite(q)):
            raise ValueError(f"viewer: q must be {self.model.nq} finite numbers, got shape {q.shape}")
        poses = scene_poses(self.model, q, self._loops, self._frames, self.visuals)
        with self._lock, self.server.atomic():
            moved = self._followed_shift(poses)
            for path, T in poses.items():
                handle = self.handles.get(path)
                if handle is not None:
                    handle.wxyz, handle.position = _wxyz(T[:3, :3]), T[:3, 3]
            self._draw_loop_lines(poses)
            self._draw_flexible(q)
            self.q = q.copy()
        if moved is not None:
            self._move_cameras(moved)

    def _followed_shift(self, poses):
        """How far the followed base moved since the last show (None when not following)."""
        if self.follow_checkbox is None or not self.follow_checkbox.value or self.q is None:
            return None
        before = self.handles[f"/bodies/{self._followed}"].position
        return poses[f"/bodies/{self._followed}"][:3, 3] - np.asarray(before, dtype=float)

    def _move_cameras(self, shift) -> None:
        camera = self.server.initial_camera
        camera.position, camera.look_at = (tuple(np.asarray(camera.position) + shift),
                                           tuple(np.asarray(camera.look_at) + shift))
        for client in self.server.get_clients().values():
            with client.atomic():
                client.camera.position = tuple(np.asarray(client.camera.position) + shift)
                client.camera.look_at = tuple(np.asarray(client.camera.look_at) + shift)

    def _draw_loop_lines(self, poses) -> None:
        for name, *_ in self._loops:
            a, b = poses[f"/loops/{name}/a"][:3, 3], poses[f"/loops/{name}/b"][:3, 3]
            self.handles[f"/loops/{name}"] = self.server.scene.add_line_segments(
                f"/loops/{name}", points=np.array([[a, b]], dtype=np.float32), colors=LOOP_COLOUR, thickness=4.0,
                thickness_units="screen")

    def _draw_flexible(self, q) -> None:
        for name, nodes in flexible_shapes(self.model, q, self._exaggeration, self._flexible).items():
            points = nodes.astype(np.float32)
            if len(points) > 1:  # a one-node body is its point alone
                self.handles[f"/flexible/{name}"] = self.server.scene.add_line_segments(
                    f"/flexible/{name}", points=np.stack([points[:-1], points[1:]], axis=1), colors=(40, 110, 220),
                    thickness=6.0, thickness_units="screen")
            self.handles[f"/flexible/{name}/nodes"] = self.server.scene.add_point_cloud(
                f"/flexible/{name}/nodes", points=points, colors=(20, 60, 160), point_size=0.01, precision="float32")

    def play(self, trajectory, speed: float = 1.0, trails=()):
        """A time slider, a play checkbox and a playback-speed slider over `trajectory` (a soadyn.Trajectory,
        an object with t and q, or a .npz file of them); `trails`: bodies or frames whose paths are drawn.
        Returns the time slider."""
        t, qs = trajectory_arrays(self.model, trajectory)
        if not (np.isfinite(speed) and speed > 0):
            raise ValueError(f"viewer: the playback speed must be a finite number > 0, got {speed}")
        self._draw_trails(qs, list(trails))
        gui = self.server.gui
        slider = gui.add_slider("time (s)", min=float(t[0]), max=float(max(t[-1], t[0] + 1e-9)),
                                step=float(np.min(np.diff(t))) if len(t) > 1 else 1.0, initial_value=float(t[0]))
        playing = gui.add_checkbox("play", initial_value=False)
        self.speed_slider = gui.add_slider("playback speed", min=0.05, max=max(10.0, float(speed)), step=0.05,
                                           initial_value=float(speed))

        @slider.on_update
        def _(_event) -> None:
            self.show(qs[min(int(np.searchsorted(t, slider.value)), len(t) - 1)])

        def run() -> None:
            while True:
                time.sleep(PLAYBACK_PERIOD)
                if playing.value:
                    advanced = slider.value + PLAYBACK_PERIOD * float(self.speed_slider.value)
                    slider.value = float(t[0]) if slider.value >= t[-1] else min(advanced, float(t[-1]))

        threading.Thread(target=run, daemon=True).start()
        self.show(qs[0])
        return slider

    def _draw_trails(self, qs, names) -> None:
        for k, (name, points) in enumerate(trail_points(self.model, qs, names).items()):
            if len(points) > 1:
                points = points.astype(np.float32)
                self.handles[f"/trails/{name}"] = self.server.scene.add_line_segments(
                    f"/trails/{name}", points=np.stack([points[:-1], points[1:]], axis=1),
                    colors=TRAIL_COLOURS[k % len(TRAIL_COLOURS)], thickness=3.0, thickness_units="screen")

    def save_html(self, path, trajectory=None, fps: float = 30.0) -> None:
        """Write a standalone web page of the scene (viser's client and the scene in one file, no server);
        with `trajectory`, the page replays it at `fps` frames per second of simulated time, with a timeline."""
        frames = None
        if trajectory is not None:
            times, frames = resample(*trajectory_arrays(self.model, trajectory), fps)
        shown = self.q.copy()
        serializer = self.server.get_scene_serializer()
        try:
            for qk in frames if frames is not None else ():
                self.show(qk)
                serializer.insert_sleep(1.0 / fps)
            page = serializer.as_html()
        finally:
            self.show(shown)
        with open(path, "w", encoding="utf-8") as out:
            out.write(page)

    def save_png(self, path, width: int = 1280, height: int = 720) -> np.ndarray:
        """Write a PNG of the shown state, framed on the model, rendered by a headless Chromium running the
        viewer's own page (soadyn.viz.headless); returns the (height, width, 3) picture."""
        from .headless import render_png
        return render_png(self, path, width, height)

    def save_movie(self, path, trajectory, fps: float = 30.0, width: int = 1280, height: int = 720,
                   speed: float = 1.0) -> int:
        """Write a movie (.mp4, or .gif) of `trajectory` at `fps` frames per second, `speed` seconds of
        simulated time per second of movie, rendered as save_png does; returns the number of frames."""
        from .headless import render_movie
        return render_movie(self, trajectory, path, fps, width, height, speed)

    def close(self) -> None:
        """Stop the viewer's server: its page goes blank and the port is free again."""
        self.server.stop()
