"""The viewer (soadyn.viewer): its scene graph headless, and a real viser server.

- scene_poses: the world pose of every body, frame and visual equals
  Pinocchio's forward kinematics of the same URDF (oMf of the links and
  frames) to 1e-12, and a visual's pose is its frame's pose times its own
  placement; a closed loop's two ends coincide at an assembled state.
- Viewer: a viser server on a free port holds one node per body, frame and
  visual, placed at those poses after show(q); play(trajectory) adds a time
  slider whose value shows the matching sample; bad input is refused by name.
- Flexible bodies: drawn through their nodes deformed by the modal
  coordinates times an exaggeration factor; a cantilever's drawn deflection
  has the closed-form Euler-Bernoulli first mode shape, and the viser
  polyline follows the factor set on its slider.
- `soadyn view` serves a scene, simulates and exits after --duration.
"""
from __future__ import annotations

import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

import soadyn
from soadyn.viewer import Viewer, drawn_frames, flexible_shapes, load_any, scene_poses
from support.robots import robot_with_oracle
from support.viewers import quiet_viewer  # noqa: F401 (a fixture)


def test_scene_graph_matches_pinocchio_forward_kinematics():
    m, oracle = robot_with_oracle("panda", False)
    pin = oracle.pin
    m = m.copy()
    m.visuals = [soadyn.Visual("hand_box", "panda_hand", "box", size=[0.1, 0.2, 0.05],
                               rotation=np.array([[0, -1.0, 0], [1.0, 0, 0], [0, 0, 1.0]]), translation=[0, 0, 0.03])]
    frames = drawn_frames(m)
    assert "panda_hand_tcp" in frames
    checked = 0
    for seed in range(3):
        q = soadyn.random_configuration(m, seed)
        poses = scene_poses(m, q)
        pin.framesForwardKinematics(oracle.model, oracle.data, oracle.q(q))
        for name in m.body_names:  # the link frames
            expected = oracle.data.oMf[oracle.model.getFrameId(name)].homogeneous
            assert np.abs(poses[f"/bodies/{name}"] - expected).max() <= 1e-12
            checked += 1
        for name in [f for f in frames if oracle.model.existFrame(f)]:
            expected = oracle.data.oMf[oracle.model.getFrameId(name)].homogeneous
            assert np.abs(poses[f"/frames/{name}"] - expected).max() <= 1e-12, name
            checked += 1
        hand = oracle.data.oMf[oracle.model.getFrameId("panda_hand")].homogeneous
        local = np.eye(4)
        local[:3, :3], local[:3, 3] = m.visuals[0].rotation, m.visuals[0].translation
        assert np.abs(poses["/visuals/hand_box"] - hand @ local).max() <= 1e-12
    assert checked >= 3 * (m.nbodies + 4)


def test_loop_ends_coincide_at_a_closed_state():
    m = soadyn.scenes.four_bar()
    q, _ = soadyn.scenes.four_bar_state(0.7)
    poses = scene_poses(m, q)
    (loop,) = m.loop_names
    assert np.abs(poses[f"/loops/{loop}/a"][:3, 3] - poses[f"/loops/{loop}/b"][:3, 3]).max() <= 1e-12


def test_flexible_bodies_are_drawn_by_their_body_frame():
    m = soadyn.scenes.cassini()
    frames = drawn_frames(m)
    assert all(":" not in f or f.split(":")[0] not in m.body_names for f in frames)
    poses = scene_poses(m, soadyn.random_configuration(m, 2))
    assert len([k for k in poses if k.startswith("/bodies/")]) == m.nbodies


def clamped_free_first_mode(x, length):
    """Euler-Bernoulli cantilever, first bending mode (closed form): beta L = 1.87510407."""
    beta = 1.87510407 / length
    sigma = (np.cosh(beta * length) + np.cos(beta * length)) / (np.sinh(beta * length) + np.sin(beta * length))
    return np.cosh(beta * x) - np.cos(beta * x) - sigma * (np.sinh(beta * x) - np.sin(beta * x))


def test_flexible_beam_is_drawn_in_its_closed_form_mode_shape():
    length = 2.0
    m = soadyn.scenes.cantilever_beam(length, 50.0, 0.5, 2)
    q = np.zeros(m.nq)
    q[m.dof_names.index("beam:mode1")] = 0.01
    rest = flexible_shapes(m, q, 0.0)["beam"]
    assert np.abs(rest - m.flexible_body("beam").nodes).max() == 0.0  # clamped at the world origin
    for exaggeration in (1.0, 25.0):
        deflection = flexible_shapes(m, q, exaggeration)["beam"] - rest
        assert np.abs(deflection[:, 0]).max() <= 1e-15  # linear modes: transverse only
        w = np.linalg.norm(deflection[:, 1:], axis=1)
        x = rest[:, 0]
        assert w[-1] > 0
        assert np.abs(w / w[-1] - clamped_free_first_mode(x, length) / clamped_free_first_mode(length, length)).max() <= 1e-9
        if exaggeration == 1.0:
            true_tip = w[-1]
    assert w[-1] == pytest.approx(25.0 * true_tip, rel=1e-12)


def test_flexible_shapes_follow_the_body_pose_on_cassini():
    m = soadyn.scenes.cassini()
    q = soadyn.random_configuration(m, 3)
    shapes = flexible_shapes(m, q, 40.0)
    assert set(shapes) == {"magnetometer_boom", "plasma_wave_antenna"}
    poses = scene_poses(m, q)
    for name, nodes in shapes.items():
        body = m.flexible_body(name)
        b = m.body_names.index(name)
        start = m.q_index[b + 1] - body.n_modes
        T = poses[f"/bodies/{name}"]
        for j in (0, body.n_nodes // 2, body.n_nodes - 1):
            local = body.node_pose(j, 40.0 * q[start:start + body.n_modes])[:3, 3]
            assert np.abs(nodes[j] - (T[:3, :3] @ local + T[:3, 3])).max() <= 1e-12
    with pytest.raises(ValueError, match="exaggeration"):
        flexible_shapes(m, q, -1.0)


def test_viewer_nodes_sit_at_the_scene_graph_poses(quiet_viewer):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", soadyn.MjcfIgnoredWarning)
        import gymnasium
        m = soadyn.load_mjcf(os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets", "ant.xml"))
    viewer = quiet_viewer(m)
    assert viewer.url.startswith("http://127.0.0.1:")
    q = soadyn.random_configuration(m, 5)
    viewer.show(q)
    poses = scene_poses(m, q)
    assert {f"/visuals/{v.name}" for v in m.visuals} <= set(viewer.handles)
    assert {f"/bodies/{b}" for b in m.body_names} <= set(viewer.handles)
    for path, T in poses.items():
        handle = viewer.handles[path]
        assert np.abs(np.asarray(handle.position) - T[:3, 3]).max() <= 1e-6  # viser stores float32
        R = soadyn_rotation(np.asarray(handle.wxyz))
        assert np.abs(R - T[:3, :3]).max() <= 1e-6


def soadyn_rotation(wxyz):
    w, x, y, z = wxyz
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def test_trajectory_slider_shows_the_matching_sample(quiet_viewer):
    m = soadyn.scenes.four_bar()
    q, v = soadyn.scenes.four_bar_state(0.3, 2.0)
    sim = soadyn.Simulator(m, dt=1e-3)
    sim.set_state(q, v)
    trajectory = sim.run(0.2)
    viewer = quiet_viewer(m, q=q)
    slider = viewer.play(trajectory)
    assert np.array_equal(viewer.q, trajectory.q[0])
    slider.value = float(trajectory.t[120])
    assert np.array_equal(viewer.q, trajectory.q[120])
    crank = viewer.handles["/bodies/crank"]
    assert np.abs(soadyn_rotation(np.asarray(crank.wxyz)) -
                  soadyn.forward_kinematics(m, trajectory.q[120])[0][0][:3, :3]).max() <= 1e-6


def test_viewer_draws_flexible_bodies_deformed_with_an_adjustable_exaggeration(quiet_viewer):
    m = soadyn.scenes.cassini()
    q = soadyn.random_configuration(m, 4)
    viewer = quiet_viewer(m, q=q, exaggeration=10.0)
    for factor in (10.0, 300.0):
        if factor != viewer.exaggeration:
            viewer.exaggeration_slider.value = factor  # as a user dragging the slider
        assert viewer.exaggeration == factor
        for name, nodes in flexible_shapes(m, q, factor).items():
            segments = np.asarray(viewer.handles[f"/flexible/{name}"].points)
            assert segments.shape == (len(nodes) - 1, 2, 3)
            assert np.abs(segments[:, 0] - nodes[:-1]).max() <= 1e-5  # float32 in viser
            assert np.abs(segments[-1, 1] - nodes[-1]).max() <= 1e-5
            assert np.abs(np.asarray(viewer.handles[f"/flexible/{name}/nodes"].points) - nodes).max() <= 1e-5
    with pytest.raises(ValueError, match="exaggeration"):
        viewer.exaggeration = float("nan")
    viewer.exaggeration = 5000.0  # beyond the slider's initial range: the slider follows
    assert viewer.exaggeration_slider.value == 5000.0 and viewer.exaggeration_slider.max >= 5000.0
    nodes = flexible_shapes(m, q, 5000.0)["magnetometer_boom"]
    assert np.abs(np.asarray(viewer.handles["/flexible/magnetometer_boom/nodes"].points) - nodes).max() <= 1e-4
    assert quiet_viewer(soadyn.scenes.four_bar()).exaggeration_slider is None  # nothing flexible to exaggerate


def test_bad_input_is_refused_by_name(quiet_viewer):
    m = soadyn.scenes.four_bar()
    viewer = quiet_viewer(m)
    with pytest.raises(ValueError, match="3 finite numbers"):
        viewer.show([0.0, np.nan, 0.0])
    with pytest.raises(ValueError, match="3 finite numbers"):
        viewer.show(np.zeros(5))
    with pytest.raises(ValueError, match="trajectory"):
        viewer.play(type("T", (), {"t": np.zeros(2), "q": np.zeros((2, 7))})())
    with pytest.raises(TypeError, match="soadyn.Model"):
        Viewer("four-bar", port=0)
    with pytest.raises(ValueError, match="not a built-in scene"):
        load_any("robot.stl")


def test_soadyn_view_serves_and_exits(tmp_path):
    path = tmp_path / "chain.json"
    soadyn.save_model(soadyn.scenes.pendulum_chain(4), path)
    for model in ("delta-robot", str(path)):
        result = subprocess.run([sys.executable, "-m", "soadyn", "view", model, "--port", "0", "--duration", "0.3",
                                 "--simulate", "0.05"], capture_output=True, text=True, timeout=120)
        assert result.returncode == 0, result.stderr
        assert "soadyn view:" in result.stdout and "http://127.0.0.1:" in result.stdout
    result = subprocess.run([sys.executable, "-m", "soadyn", "view", "four-bar", "--port", "70000"],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 2 and "--port" in result.stderr
    # a loop model whose neutral configuration cannot be assembled: one line, exit code 1
    soadyn.save_model(soadyn.scenes.four_bar(), tmp_path / "four_bar.json")
    result = subprocess.run([sys.executable, "-m", "soadyn", "view", str(tmp_path / "four_bar.json"), "--port", "0"],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 1 and "cannot start" in result.stderr and "Traceback" not in result.stderr


def test_a_one_node_flexible_body_is_drawn_as_its_point(quiet_viewer):
    body = soadyn.FlexibleBody(positions=[[0.5, 0.0, 0.0]], masses=[2.0], rotary_inertias=[np.eye(3) * 0.01],
                               mode_shapes=[[[0.0], [0.0], [0.0], [0.0], [1.0], [0.0]]], stiffness=[[40.0]])
    m = soadyn.Model()
    m.add_flexible_body("blob", None, body, soadyn.Joint.revolute([0, 0, 1]))
    q = np.array([0.3, 0.02])
    viewer = quiet_viewer(m, q=q, exaggeration=10.0)
    assert "/flexible/blob" not in viewer.handles
    point = np.asarray(viewer.handles["/flexible/blob/nodes"].points)
    assert point.shape == (1, 3) and np.abs(point - flexible_shapes(m, q, 10.0)["blob"]).max() <= 1e-6
