"""What the viewer draws beyond a model's own visuals, and how it replays and frames, headless.

- Link figures (soadyn.viz.figures): on the loop scenes and the pendulum chain
  at a closed state, every rod starts at its body's origin and ends at a child's
  joint origin or a loop's anchor, positions read from forward kinematics and
  the loop frames (scene_poses), or, on the ground, at a world-fixed joint frame
  (a slider's rail at its zero), or, for a body carrying nothing, at twice its
  centre of mass (a uniform rod's tip), so the figure follows the dynamics' geometry.
- The cassini visuals sit on the scene's bodies and frames; a reaction wheel's
  mark turns about the wheel's hinge axis by the wheel's angle (closed-form
  rotation), and the dish is the paraboloid it says it is.
- Framing: every point of a cloud projects inside a pinhole camera's picture
  (perspective projection written out here), and the tightest point sits at the
  margin, for random clouds, gravity directions and aspect ratios.
- Replay: resample picks the latest sample at each frame's time; Trajectory
  save/load round trip; trails, the playback-speed slider and "follow" on a
  viser server; a standalone page is written with its scene embedded; bad
  input (files, speeds, names) is refused by name.
"""
from __future__ import annotations

import numpy as np
import pytest

import soadyn
from soadyn.simulator import Simulator, Trajectory
from soadyn.viewer import scene_poses
from soadyn.viz.figures import link_visuals
from soadyn.viz.framing import MARGIN, framed_camera
from soadyn.viz.playback import resample, trail_points
from soadyn.viz.visuals import revolved_mesh
from support.viewers import four_bar_run, quiet_viewer  # noqa: F401 (a fixture)

LOOP_SCENES = {"four-bar": lambda: soadyn.scenes.four_bar_state(1.1),
               "slider-crank": lambda: soadyn.scenes.slider_crank_state(2.0),
               "delta-robot": lambda: soadyn.scenes.delta_robot_state([0.05, -0.03, -0.6])}


def rod_ends(T, v) -> tuple[np.ndarray, np.ndarray]:
    axis = T[:3, 2] * v.size[1] / 2
    return T[:3, 3] - axis, T[:3, 3] + axis


@pytest.mark.parametrize("scene", [*LOOP_SCENES, "pendulum-chain"])
def test_every_rod_joins_its_body_to_a_joint_or_a_loop_anchor(scene):
    m = soadyn.scenes.SCENES[scene]()
    q = np.asarray(LOOP_SCENES[scene]()[0]) if scene in LOOP_SCENES else np.linspace(0.2, 0.9, m.nq)
    rods = [v for v in link_visuals(m) if "/rod" in v.name or "/ground" in v.name]
    poses = scene_poses(m, q, visuals=rods)
    origins = {name: poses[f"/bodies/{name}"][:3, 3] for name in m.body_names}
    anchors = [T[:3, 3] for path, T in poses.items() if path.startswith("/loops/")]
    neutral = scene_poses(m, soadyn.neutral_configuration(m), loops=[], frames=[], visuals=[])
    rails = [neutral[f"/bodies/{name}"][:3, 3] for name, p in zip(m.body_names, m.parents) if p < 0]  # world-fixed joint frames (a slider's rail)
    leaves = [name for i, name in enumerate(m.body_names) if i not in m.parents]  # a leaf's rod: to twice its com
    tips = [poses[f"/bodies/{n}"][:3, :3] @ (2 * np.asarray(m.get_parameter(f"{n}.com"))) + origins[n] for n in leaves]
    targets = np.array(list(origins.values()) + anchors + rails + tips)
    assert len(rods) >= m.nbodies - 1
    for v in rods:
        start, end = rod_ends(poses[f"/visuals/{v.name}"], v)
        body = v.name.split("/")[0]
        near = start if body == "world" else origins[body]
        assert min(np.linalg.norm(start - near), np.linalg.norm(end - near)) <= 1e-12, v.name
        far = end if np.linalg.norm(start - near) <= 1e-12 else start
        assert np.min(np.linalg.norm(targets - far, axis=1)) <= 1e-12, f"{v.name} ends nowhere"


def test_a_body_with_its_own_visual_gets_no_figure_and_flexible_bodies_none():
    m = soadyn.scenes.four_bar()
    m.visuals = [soadyn.Visual("crank_shape", "crank", "box", size=[0.04, 0.01, 0.01])]
    names = {v.name.split("/")[0] for v in link_visuals(m)}
    assert "crank" not in names and {"coupler", "rocker"} <= names
    cassini = soadyn.scenes.cassini()
    cassini.visuals = []
    drawn = {v.name.split("/")[0] for v in link_visuals(cassini)}
    assert not drawn & {"magnetometer_boom", "plasma_wave_antenna"} and "scan_el" in drawn


def test_cassini_visuals_sit_on_its_bodies_and_the_wheel_marks_turn_with_the_wheels():
    m = soadyn.scenes.cassini()
    frames = set(m.body_names) | set(m.frame_names)
    assert len(m.visuals) >= 20 and all(v.frame in frames for v in m.visuals)
    q0 = np.array(soadyn.neutral_configuration(m))
    for wheel in ("wheel_1", "wheel_4"):
        angle = 0.7
        q = q0.copy()
        q[m.q_index[m.body_index(wheel)]] = angle
        before, after = (scene_poses(m, x) for x in (q0, q))
        T_wheel = before[f"/bodies/{wheel}"]
        axis = T_wheel[:3, 2]  # the hinge axis: z of the wheel frame
        r0 = before[f"/visuals/{wheel}/mark"][:3, 3] - T_wheel[:3, 3]
        r1 = after[f"/visuals/{wheel}/mark"][:3, 3] - T_wheel[:3, 3]
        K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        rodrigues = np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K
        assert np.linalg.norm(r1 - rodrigues @ r0) <= 1e-12 and np.linalg.norm(r0) > 0.05
    dish = next(v for v in m.visuals if v.name == "high_gain_antenna/dish")
    r = np.hypot(dish.vertices[:, 0], dish.vertices[:, 1])
    assert np.abs(dish.vertices[:, 2] - r**2 / (4 * 1.5)).max() <= 1e-12 and abs(r.max() - 2.0) <= 1e-12


def test_revolved_mesh_sweeps_the_profile():
    vertices, faces = revolved_mesh([0.0, 1.0, 2.0], [0.0, 0.5, 0.0], segments=12)
    assert vertices.shape == (36, 3) and faces.shape == (2 * 2 * 12, 3) and faces.max() == 35
    np.testing.assert_allclose(np.hypot(vertices[:, 0], vertices[:, 1]), np.repeat([0.0, 1.0, 2.0], 12), atol=1e-15)
    for bad in (([1.0], [0.0]), ([-1.0, 1.0], [0.0, 1.0]), ([1.0, 2.0], [0.0])):
        with pytest.raises(ValueError, match="profile"):
            revolved_mesh(*bad)


def project(points, position, look_at, up):
    """Pinhole projection: (tan horizontal, tan vertical) of each point's view angle."""
    forward = (look_at - position) / np.linalg.norm(look_at - position)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    screen_up = np.cross(right, forward)
    offsets = points - position
    depth = offsets @ forward
    assert np.all(depth > 0), "a point is behind the camera"
    return offsets @ right / depth, offsets @ screen_up / depth


@pytest.mark.parametrize("seed", range(6))
def test_the_framed_camera_shows_every_point_and_wastes_no_margin(seed):
    rng = np.random.default_rng(seed)
    points = rng.normal(size=(40, 3)) * rng.uniform(0.01, 10.0, size=3) + rng.normal(size=3) * 5
    up = rng.normal(size=3)
    up /= np.linalg.norm(up)
    fov, aspect = rng.uniform(0.5, 1.4), rng.uniform(0.7, 2.0)
    position, look_at = framed_camera(points, up, fov, aspect)
    u, v = project(points, position, look_at, up)
    share = np.maximum(np.abs(u) / (aspect * np.tan(fov / 2)), np.abs(v) / np.tan(fov / 2))
    assert share.max() <= 1.0 + 1e-12
    assert share.max() >= 0.8 / MARGIN  # framed, not lost in the middle of the picture


def test_resample_takes_the_latest_sample_at_each_frame():
    t = np.array([0.0, 0.1, 0.25, 0.3, 1.0])
    q = np.arange(5.0)[:, None]
    times, frames = resample(t, q, 10.0)
    np.testing.assert_allclose(times, np.arange(11) / 10.0, atol=1e-15)
    assert frames[:, 0].tolist() == [0, 1, 1, 3, 3, 3, 3, 3, 3, 3, 4]
    with pytest.raises(ValueError, match="fps"):
        resample(t, q, 0.0)


def test_trajectory_files_round_trip_and_bad_ones_are_named(tmp_path):
    m = soadyn.scenes.pendulum_chain(2)
    sim = Simulator(m, dt=0.01)
    sim.set_state([0.3, 0.1], [0.0, 0.0])
    trajectory = sim.run(0.05)
    trajectory.save(tmp_path / "run.npz")
    loaded = Trajectory.load(tmp_path / "run.npz")
    for name in ("t", "q", "v", "tau"):
        assert np.array_equal(getattr(loaded, name), getattr(trajectory, name))
    (tmp_path / "text.npz").write_text("not an archive")
    np.savez(tmp_path / "short.npz", t=np.zeros(2))
    for name, reason in (("missing.npz", "No such file"), ("text.npz", "not a .npz archive"),
                         ("short.npz", "lacks q, v, tau")):
        with pytest.raises(ValueError, match=reason) as error:
            Trajectory.load(tmp_path / name)
        assert name in str(error.value)


def test_play_draws_trails_where_the_frames_went_and_refuses_bad_input(quiet_viewer, tmp_path):
    m, trajectory = four_bar_run(0.2)
    viewer = quiet_viewer(m, q=trajectory.q[0])
    viewer.play(trajectory, speed=2.5, trails=["coupler", "rocker"])
    assert viewer.speed_slider.value == 2.5
    for name in ("coupler", "rocker"):
        segments = np.asarray(viewer.handles[f"/trails/{name}"].points)
        origin = [scene_poses(m, qk, loops=[], frames=[], visuals=[])[f"/bodies/{name}"][:3, 3] for qk in trajectory.q]
        assert np.abs(segments[:, 0] - origin[:-1]).max() <= 1e-6 and np.abs(segments[-1, 1] - origin[-1]).max() <= 1e-6
    with pytest.raises(ValueError, match="no body or frame named 'elbow'"):
        trail_points(m, trajectory.q, ["elbow"])
    with pytest.raises(ValueError, match="speed"):
        viewer.play(trajectory, speed=0.0)
    np.savez(tmp_path / "wide.npz", t=np.zeros(3), q=np.zeros((3, 4)))
    with pytest.raises(ValueError, match="3 coordinates per sample"):
        viewer.play(tmp_path / "wide.npz")
    with pytest.raises(ValueError, match=r"\.mp4 or \.gif"):
        viewer.save_movie(tmp_path / "out.avi", trajectory)


def test_follow_keeps_the_camera_on_a_free_base(quiet_viewer):
    m = soadyn.scenes.cassini()
    q = np.array(soadyn.neutral_configuration(m))
    viewer = quiet_viewer(m, q=q, follow=True)
    camera = viewer.server.initial_camera
    before = np.array(camera.look_at), np.array(camera.position)
    moved = q.copy()
    moved[:3] += [1.0, -2.0, 0.5]  # the free joint's translation comes first in q
    viewer.show(moved)
    shift = viewer.handles["/bodies/bus"].position - q[:3]
    assert np.linalg.norm(shift) > 1.0
    np.testing.assert_allclose(np.array(camera.look_at) - before[0], shift, atol=1e-9)
    np.testing.assert_allclose(np.array(camera.position) - before[1], shift, atol=1e-9)
    viewer.follow_checkbox.value = False
    viewer.show(q)
    np.testing.assert_allclose(np.array(camera.look_at) - before[0], shift, atol=1e-9)
    fixed = quiet_viewer(soadyn.scenes.four_bar(), q=soadyn.scenes.four_bar_state(0.5)[0])
    assert fixed.follow_checkbox is None


def embedded_recording(path) -> dict:
    """The scene recording a standalone page carries (viser's format: base64 of a size, then zstd of a
    length-prefixed msgpack header)."""
    import base64
    import re

    import msgspec
    import zstandard

    data = base64.b64decode(re.search(r'window.__VISER_EMBED_DATA__="([^"]*)"', path.read_text()).group(1))
    inner = zstandard.ZstdDecompressor().decompress(data[8:], max_output_size=int.from_bytes(data[:8], "little"))
    header = int.from_bytes(inner[:8], "little")
    return msgspec.msgpack.decode(inner[8:8 + header])


def test_save_html_embeds_the_scene_and_its_replay(quiet_viewer, tmp_path):
    m, trajectory = four_bar_run(0.5)
    q = trajectory.q[0]
    viewer = quiet_viewer(m, q=q)
    viewer.save_html(tmp_path / "still.html")
    viewer.save_html(tmp_path / "replay.html", trajectory, fps=20)
    still, replay = (embedded_recording(tmp_path / name) for name in ("still.html", "replay.html"))
    assert still["durationSeconds"] == 0.0
    assert replay["durationSeconds"] == pytest.approx(11 / 20)  # 0 to 0.5 s at 20 frames per second
    assert len(replay["messages"]) > len(still["messages"]) + 11
    np.testing.assert_array_equal(viewer.q, q)  # the viewer shows what it showed before


def test_soadyn_view_refuses_bad_export_requests_by_name(tmp_path, capsys, monkeypatch):
    from soadyn.apps import cli

    (tmp_path / "notes.npz").write_text("not an archive")
    refused = {  # arguments: (exit code, what the message names)
        ("--trajectory", str(tmp_path / "notes.npz")): (1, "not a .npz archive"),
        ("--simulate", "0.01", "--trail", "elbow"): (1, "no body or frame named 'elbow'"),
        ("--movie", str(tmp_path / "m.mp4")): (2, "argument --movie: needs a replay"),
        ("--simulate", "0.01", "--movie", str(tmp_path / "m.avi")): (2, "write a .mp4 or .gif file"),
        ("--screenshot", str(tmp_path / "p.png"), "--width", "10"): (2, "argument --width: must be 16 to 8192"),
        ("--simulate", "0.01", "--movie", str(tmp_path / "m.mp4"), "--fps", "nan"): (2, "argument --fps"),
        ("--screenshot", str(tmp_path / "missing" / "deeper" / "p.png")): (2, "cannot write"),
        ("--trajectory", str(tmp_path / "notes.npz"), "--simulate", "1"): (2, "not both"),
    }
    for arguments, (code, message) in refused.items():
        try:
            result = cli.main(["view", "four-bar", "--port", "0", "--duration", "0", *arguments])
        except SystemExit as exit_info:
            result = exit_info.code
        assert result == code, arguments
        assert message in capsys.readouterr().err, arguments
    monkeypatch.setenv("SOADYN_CHROMIUM", str(tmp_path / "no-such-browser"))
    assert cli.main(["view", "four-bar", "--screenshot", str(tmp_path / "p.png")]) == 1
    assert "SOADYN_CHROMIUM=" in capsys.readouterr().err and not (tmp_path / "p.png").exists()


def test_hostile_replays_and_picture_requests_are_refused_by_name(quiet_viewer, tmp_path):
    m, trajectory = four_bar_run(0.05)
    viewer = quiet_viewer(m, q=trajectory.q[0])
    bad_q = trajectory.q.copy()
    bad_q[2, 1] = np.nan
    backwards = trajectory.t[::-1].copy()
    for t, q, message in ((trajectory.t, bad_q, "non-finite"), (backwards, trajectory.q, "must not decrease"),
                          (trajectory.t[:0], trajectory.q[:0], "coordinates per sample")):
        with pytest.raises(ValueError, match=message):
            viewer.play(type("Replay", (), {"t": t, "q": q})())
    with pytest.raises(ValueError, match="at most"):  # a frame count no movie or page can hold
        resample(np.array([0.0, 1e6]), np.zeros((2, m.nq)), 30.0)
    for size in ((float("nan"), 100), ("wide", 100), (10, 100), (True, 100), (640, 10_000)):
        with pytest.raises(ValueError, match="picture size must be whole numbers of 16 to 8192 pixels"):
            viewer.save_png(tmp_path / "p.png", *size)
    with pytest.raises(OSError):
        viewer.save_html(tmp_path / "no-such-folder" / "page.html", trajectory)
    np.testing.assert_array_equal(viewer.q, trajectory.q[0])  # a failed export leaves the shown state


def test_a_model_without_bodies_is_drawn_and_framed(quiet_viewer):
    viewer = quiet_viewer(soadyn.Model())
    position, look_at, up = viewer.camera_view()
    assert np.all(np.isfinite(position)) and np.linalg.norm(position - look_at) > 0
    assert viewer.visuals == [] and viewer.follow_checkbox is None


def test_show_from_two_threads_keeps_every_pose_whole(quiet_viewer):
    import threading

    m, trajectory = four_bar_run(0.2)
    viewer = quiet_viewer(m, q=trajectory.q[0])
    errors = []

    def replay(rows):
        try:
            for q in rows:
                viewer.show(q)
        except Exception as error:  # any failure of a thread is the test's failure
            errors.append(error)

    threads = [threading.Thread(target=replay, args=(trajectory.q[k::2],)) for k in (0, 1)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    expected = scene_poses(m, viewer.q, visuals=viewer.visuals)  # the last show, whichever thread made it
    for path in ("/bodies/coupler", "/visuals/rocker/rod0"):
        np.testing.assert_allclose(viewer.handles[path].position, expected[path][:3, 3], atol=1e-6)
