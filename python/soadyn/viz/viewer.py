"""A 3D viewer on viser (a maintained web viewer: the browser draws, no WebGL of ours).

Two layers:
- `scene_poses(m, q)`: the scene graph at a state, headless — the world pose
  (4x4) of every node the viewer draws, keyed by its viser path:
  ``/bodies/<body>`` (the body frame), ``/frames/<frame>``,
  ``/visuals/<visual>`` (the shape's frame: its frame's pose times its own
  placement), and the two ends of every loop (``/loops/<loop>/a``, ``/b``).
  Bodies come from `forward_kinematics`, frames from `frame_pose`: what is
  drawn is what the dynamics use.
  Attachment frames of flexible bodies are not among the frames: a flexible
  body is drawn by its body frame and its deformed shape (below).
- `flexible_shapes(m, q, exaggeration)`: the world positions of every
  flexible body's nodes, deformed by its modal coordinates times
  `exaggeration` (1: true size; real appendages deflect millimetres, so
  tens to thousands make a mode visible). The viewer draws each as a
  polyline through its nodes in node order (a beam's nodes are its stations)
  with a point per node; a slider sets the exaggeration.
- `Viewer(m)`: a viser server drawing those nodes — each Visual as its shape
  (box, sphere, ellipsoid, cylinder, capsule as a cylinder with end spheres,
  mesh from vertices/faces or a mesh file trimesh can read), body and frame
  axes sized to the model, rods and joint markers for bodies without visuals
  (soadyn.viz.figures), every cut joint as a ball on each side joined by a
  line — moved by `show(q)`. The camera starts framed on the model
  (soadyn.viz.framing; "reset view" frames it again, "follow" keeps a free
  base in view). `play(trajectory, speed, trails)` adds a time slider, a
  play checkbox, a playback-speed slider and the paths of chosen frames.
  `save_png`, `save_movie` render in a headless Chromium (soadyn.viz.headless);
  `save_html` writes a standalone page that replays a trajectory offline.

Decisions: the viewer never runs in a real-time thread; it reads states it is
given. Mesh files are read by trimesh (`read_mesh`: COLLADA through pycollada,
STL, OBJ), scaled, and coloured by the URDF/MJCF material when the file has
no colours of its own; a mesh file that cannot be read is drawn as its
frame's axes and named once in a warning, with the reason.
"""
from __future__ import annotations

import importlib.util
import json
import os
import threading
import time
import warnings

import numpy as np

from .. import scenes
from .._soadyn import forward_kinematics, frame_pose, neutral_configuration
from ..io.mjcf import load_mjcf
from ..io.example_robots import example_robot
from ..io.model_file import load_model
from ..io.urdf import load_urdf
from ..loops import assemble
from ..model import Model
from .figures import link_radius, link_visuals
from .framing import ASPECT, framed_camera, up_direction, visual_corners
from .playback import TRAIL_COLOURS, resample, trail_points, trajectory_arrays
from .visuals import Visual

__all__ = ["MeshError", "Viewer", "flexible_shapes", "read_mesh", "scene_poses"]


LOOP_COLOUR = (220, 40, 40)
AXES_PER_ROD = 8.0  # body axes this many link radii long (soadyn.viz.figures.link_radius)
HEMISPHERE_INTENSITY = 1.5  # about the brightness of the environment map it replaces
FRAMING_STATES = 24  # states of a trajectory the camera is framed on
PLAYBACK_PERIOD = 0.03  # seconds between the play loop's advances of the time slider


def _transform(R, p) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


def _loop_anchors(m: Model) -> list[tuple[str, str, np.ndarray, str, np.ndarray]]:
    """(loop, frame_a, placement_a, frame_b, placement_b) of every loop, from the model-file view."""
    data = json.loads(m._to_json()) if m.nloops else {"loops": []}
    return [(x["name"], x["frame_a"], _transform(x["placement_a"]["rotation"], x["placement_a"]["translation"]),
             x["frame_b"], _transform(x["placement_b"]["rotation"], x["placement_b"]["translation"]))
            for x in data["loops"]]


class _Poser:
    """World poses of named bodies and frames at one state (forward kinematics once)."""

    def __init__(self, m: Model, q):
        self.m, self.q = m, np.asarray(q, dtype=float)
        self.bodies = forward_kinematics(m, self.q)
        self.bodies = self.bodies[0] if isinstance(self.bodies, tuple) else self.bodies
        self.index = {name: i for i, name in enumerate(m.body_names)}

    def __call__(self, name: str) -> np.ndarray:
        if name in ("world", "", None):
            return np.eye(4)
        if name in self.index:
            return self.bodies[self.index[name]]
        return frame_pose(self.m, self.q, name)


def drawn_frames(m: Model) -> list[str]:
    """The frames the viewer draws: every frame that is not a body, except attachment frames of flexible
    bodies (their nodes move with the modal coordinates, which frame_pose does not follow)."""
    q0, bodies = neutral_configuration(m), set(m.body_names)
    drawn = []
    for name in m.frame_names:
        if name in bodies:
            continue
        try:
            frame_pose(m, q0, name)
        except ValueError:  # carried by a flexible body
            continue
        drawn.append(name)
    return drawn


def scene_poses(m: Model, q, loops=None, frames=None, visuals=None) -> dict[str, np.ndarray]:
    """World pose (4x4) of every node the viewer draws at configuration q, keyed by viser path
    (`visuals`: the visuals drawn, m.visuals by default)."""
    pose = _Poser(m, q)
    out = {f"/bodies/{name}": pose.bodies[i] for i, name in enumerate(m.body_names)}
    for name in drawn_frames(m) if frames is None else frames:
        out[f"/frames/{name}"] = pose(name)
    for v in m.visuals if visuals is None else visuals:
        out[f"/visuals/{v.name}"] = pose(v.frame) @ _transform(v.rotation, v.translation)
    for name, frame_a, Xa, frame_b, Xb in (_loop_anchors(m) if loops is None else loops):
        out[f"/loops/{name}/a"] = pose(frame_a) @ Xa
        out[f"/loops/{name}/b"] = pose(frame_b) @ Xb
    return out


def _flexible_blocks(m: Model) -> list[tuple[str, int, object, slice]]:
    """(name, body index, FlexibleBody, slice of its modal coordinates in q) of every flexible body."""
    out = []
    for b, name in enumerate(m.body_names):
        if m.n_modes[b] == 0:
            continue
        end = m.q_index[b + 1] if b + 1 < m.nbodies else m.nq
        out.append((name, b, m.flexible_body(name), slice(end - m.n_modes[b], end)))
    return out


def flexible_shapes(m: Model, q, exaggeration: float = 1.0, blocks=None) -> dict[str, np.ndarray]:
    """{body: (N, 3) world positions of its nodes} for every flexible body at q, the modal coordinates
    scaled by `exaggeration` (the body frame itself stays where q puts it)."""
    if not (np.isfinite(exaggeration) and exaggeration >= 0):
        raise ValueError(f"viewer: the exaggeration must be a finite number >= 0, got {exaggeration}")
    q = np.asarray(q, dtype=float)
    poses = None
    out = {}
    for name, b, body, modal in _flexible_blocks(m) if blocks is None else blocks:
        if poses is None:
            poses = _Poser(m, q).bodies
        eta = exaggeration * q[modal]
        local = np.array([body.node_pose(j, eta)[:3, 3] for j in range(body.n_nodes)])
        out[name] = local @ poses[b][:3, :3].T + poses[b][:3, 3]
    return out


class MeshError(ValueError):
    """A visual's mesh file that cannot be drawn; the message names the visual, the file and why."""


def read_mesh(v: Visual):
    """The trimesh.Trimesh of mesh visual `v` (its mesh_file, COLLADA, STL, OBJ or any format trimesh reads),
    scaled by v.size; a mesh without colours of its own takes the visual's rgba (the URDF material).
    Raises MeshError naming the visual, the file and the reason."""
    import trimesh

    if not isinstance(v, Visual) or v.mesh_file is None:
        raise MeshError(f"read_mesh needs a Visual with a mesh_file, got {getattr(v, 'name', type(v).__name__)!r}")
    where = f"'{v.name}' ({v.mesh_file})"
    if not os.path.isfile(v.mesh_file):
        raise MeshError(f"{where}: no such file")
    if v.mesh_file.lower().endswith(".dae") and importlib.util.find_spec("collada") is None:
        raise MeshError(f"{where}: COLLADA files need pycollada (pip install 'soadyn[view]')")
    try:
        mesh = trimesh.load(v.mesh_file, force="mesh")
    except Exception as error:  # trimesh's own reason, whatever its type
        raise MeshError(f"{where}: {type(error).__name__}: {' '.join(str(error).split()) or 'unreadable'}") from None
    if len(mesh.faces) == 0:
        raise MeshError(f"{where}: no triangles read{_collada_reason(v.mesh_file)}")
    mesh.apply_scale(v.size if v.size.size == 3 else 1.0)
    if mesh.visual.kind is None:
        mesh.visual.face_colors = np.round(255 * np.clip(v.rgba, 0, 1)).astype(np.uint8)
    return mesh


def _collada_reason(path: str) -> str:
    """Why trimesh read no triangles from a COLLADA file: the first error pycollada reports ("" if none).
    A primitive whose material the file references but does not hold is dropped with it."""
    if not path.lower().endswith(".dae"):
        return ""
    import collada

    errors = collada.common
    try:
        document = collada.Collada(path, ignore=[errors.DaeError])
    except Exception as error:
        return f"; pycollada: {' '.join(str(error).split())}"
    return f"; pycollada: {' '.join(str(document.errors[0]).split())}" if document.errors else ""


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
        self._loops = _loop_anchors(m)
        self._flexible = _flexible_blocks(m)
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
        self.server.stop()


def _scene_builders() -> dict:
    return {"cassini": scenes.cassini, "four-bar": scenes.four_bar, "slider-crank": scenes.slider_crank,
            "delta-robot": scenes.delta_robot}


BUILT_IN_SCENES = tuple(_scene_builders())  # the scene names `soadyn view` takes


def load_any(source: str) -> Model:
    """A model from a built-in scene name, a model file (.json), an MJCF (.xml), a URDF (.urdf), or the name of
    an example-robot-data URDF (`soadyn robots` lists them: ur5_robot, talos_reduced, ...)."""
    builders = _scene_builders()
    if source in builders:
        return builders[source]()
    extension = os.path.splitext(source)[1].lower()
    if extension == ".json":
        return load_model(source)
    if extension == ".xml":
        return load_mjcf(source)
    if extension == ".urdf":
        return load_urdf(source)
    if extension == "" and os.sep not in source:
        try:
            return load_urdf(example_robot(source))
        except ValueError as error:
            raise ValueError(f"'{source}': not a built-in scene ({', '.join(builders)}) nor a .json, .xml or .urdf "
                             f"file; {error}") from None
    raise ValueError(f"'{source}': not a built-in scene ({', '.join(builders)}) nor a .json, .xml or .urdf file")


def start_state(source: str, m: Model) -> tuple[np.ndarray, np.ndarray]:
    """The state `soadyn view` shows first: the loop scenes closed, every other model at rest in q0."""
    closed = {"four-bar": lambda: scenes.four_bar_state(0.5), "slider-crank": lambda: scenes.slider_crank_state(0.5),
              "delta-robot": lambda: scenes.delta_robot_state([0.0, 0.0, -0.6])}
    if source in closed:
        q, v = closed[source]()
        return np.asarray(q, dtype=float), np.asarray(v, dtype=float)
    q = neutral_configuration(m)
    if m.nloops:  # any other loop model: closed from q0 by Gauss-Newton
        q = assemble(m, q)
    return q, np.zeros(m.nv)
