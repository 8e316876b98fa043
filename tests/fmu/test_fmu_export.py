"""Exported FMUs (FMI 3.0 and 2.0 co-simulation) in fmpy: valid, and their trajectories equal soadyn's own
Simulator's bit for bit.

fmpy (an importer nobody here wrote) validates each model description against the standard's schema and
its own consistency rules, loads the binary and steps it. The scenarios: the pendulum chain from a tilted
start; cassini (free flight, its turntable and engine gimbal prescribed, following their acceleration
inputs) with a torque on the scan platform and its hinge locked half-way through the Boolean input
locked.scan_az, then released; the four-bar (a closed loop) from a closed start; a URDF robot (ur5) and an
MJCF model under constant torques; a DOF switched to prescribed through prescribed.<dof>.
"""
from __future__ import annotations

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.validation import validate_fmu

import soadyn
from soadyn.fmu import export_fmu
from support.fmu_runs import FmuSession, Step, run_fmu, run_reference

MJCF = """<mujoco model="arm">
  <worldbody>
    <body name="upper" pos="0 0 1">
      <joint name="shoulder" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.04" mass="1.2"/>
      <body name="lower" pos="0.4 0 0">
        <joint name="elbow" type="hinge" axis="0 1 0"/>
        <joint name="slide" type="slide" axis="1 0 0"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="0.6"/>
      </body>
    </body>
  </worldbody>
</mujoco>"""


def ur5():
    return soadyn.load_urdf(soadyn.io.example_robots.example_robot("ur5_robot"))


def assert_same_trajectory(fmu, reference):
    np.testing.assert_allclose(fmu.t, reference.t, rtol=0, atol=1e-12)  # communication points: sums of h
    assert np.array_equal(fmu.q, reference.q), np.abs(fmu.q - reference.q).max()
    assert np.array_equal(fmu.v, reference.v), np.abs(fmu.v - reference.v).max()


@pytest.mark.parametrize("fmi", [3, 2])
def test_fmus_of_every_kind_of_model_validate(fmi, tmp_path):
    models = {"pendulum": soadyn.scenes.pendulum_chain(3), "cassini": soadyn.scenes.cassini(),
              "four_bar": soadyn.scenes.four_bar(), "ur5": ur5(), "mjcf_arm": soadyn.load_mjcf(MJCF)}
    for name, m in models.items():
        q0 = soadyn.scenes.four_bar_state(0.7)[0] if name == "four_bar" else None
        path = export_fmu(m, tmp_path / f"{name}.fmu", fmi=fmi, step=0.01, q0=q0, name=name)
        assert validate_fmu(str(path)) == [], name


@pytest.mark.parametrize("fmi", [3, 2])
def test_pendulum_fmu_equals_the_simulator_bit_for_bit(fmi, tmp_path):
    m = soadyn.scenes.pendulum_chain(2)
    q0, v0 = np.array([0.4, -0.3]), np.array([0.0, 1.0])
    path = export_fmu(m, tmp_path / "p.fmu", fmi=fmi, step=0.01, q0=q0, v0=v0)
    steps = [Step(0.01, {"link_1": 0.2 * np.sin(k / 10)}) for k in range(100)]
    assert_same_trajectory(run_fmu(path, m, steps), run_reference(m, 0.01, q0, v0, steps))


@pytest.mark.parametrize("fmi", [3, 2])
def test_cassini_lock_up_through_the_boolean_input_equals_the_simulator(fmi, tmp_path):
    m = soadyn.scenes.cassini()
    q0 = soadyn.neutral_configuration(m)
    v0 = np.zeros(m.nv)
    v0[m.dof_index("turntable")] = soadyn.scenes.TURNTABLE_RATE
    path = export_fmu(m, tmp_path / "cassini.fmu", fmi=fmi, step=0.01, substeps=2, q0=q0, v0=v0)
    steps = []
    for k in range(60):  # slew the scan platform; lock it from 0.2 s to 0.4 s; a gimbal rate change
        locked = frozenset({"scan_az"}) if 20 <= k < 40 else frozenset()
        steps.append(Step(0.01, {"scan_az": 2.0, "gimbal_pitch": 0.01 if k >= 30 else 0.0}, locked))
    fmu = run_fmu(path, m, steps)
    assert_same_trajectory(fmu, run_reference(m, 0.005, q0, v0, steps))
    scan = m.dof_index("scan_az")
    assert np.all(fmu.v[21:41, scan] == 0.0) and fmu.v[20, scan] > 0.0  # stopped and held while locked
    turntable = m.dof_index("turntable")
    np.testing.assert_allclose(fmu.v[:, turntable], soadyn.scenes.TURNTABLE_RATE, rtol=0, atol=1e-15)


@pytest.mark.parametrize("fmi", [3, 2])
def test_four_bar_fmu_closes_its_loop_as_the_simulator_does(fmi, tmp_path):
    m = soadyn.scenes.four_bar()
    q0, v0 = soadyn.scenes.four_bar_state(0.7, 1.0)
    path = export_fmu(m, tmp_path / "fb.fmu", fmi=fmi, step=0.005, q0=q0, v0=v0)
    steps = [Step(0.005, {"crank": 0.5}) for _ in range(100)]
    fmu = run_fmu(path, m, steps)
    assert_same_trajectory(fmu, run_reference(m, 0.005, q0, v0, steps))
    assert np.abs(soadyn.loop_residual(m, fmu.q[-1])).max() < 1e-9


@pytest.mark.parametrize("fmi", [3, 2])
def test_urdf_and_mjcf_robots_under_torques_equal_the_simulator(fmi, tmp_path):
    for name, m in (("ur5", ur5()), ("arm", soadyn.load_mjcf(MJCF))):
        q0 = soadyn.neutral_configuration(m) + 0.1
        path = export_fmu(m, tmp_path / f"{name}.fmu", fmi=fmi, step=0.002, q0=q0)
        torques = {dof: 0.3 * (k + 1) for k, dof in enumerate(m.dof_names)}
        steps = [Step(0.002, torques) for _ in range(50)]
        assert_same_trajectory(run_fmu(path, m, steps), run_reference(m, 0.002, q0, np.zeros(m.nv), steps))


def test_a_dof_prescribed_through_its_boolean_input_follows_its_acceleration(tmp_path):
    m = soadyn.scenes.pendulum_chain(2)
    q0 = np.array([0.2, 0.1])
    path = export_fmu(m, tmp_path / "p.fmu", step=0.01, q0=q0)
    steps = [Step(0.01, {"link_1": 0.5}, prescribed=frozenset({"link_1"}) if k < 50 else frozenset())
             for k in range(80)]
    fmu = run_fmu(path, m, steps)
    assert_same_trajectory(fmu, run_reference(m, 0.01, q0, np.zeros(2), steps))
    # while prescribed, link_1 moves at 0.5 rad/s^2 from rest: q = q0 + a t^2 / 2 (closed form)
    t = fmu.t[:51]
    np.testing.assert_allclose(fmu.q[:51, 0], 0.2 + 0.25 * t**2, rtol=0, atol=1e-12)
    # its drive torque at the communication points equals the hybrid dynamics' (every DOF's tau output)
    prescribed = m.copy()
    prescribed.set_prescribed(["link_1"])
    _, tau = soadyn.hybrid_dynamics(prescribed, fmu.q[10], fmu.v[10], np.array([0.5, 0.0]))
    np.testing.assert_allclose(fmu.tau[9], tau, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("fmi", [3, 2])
def test_model_parameters_set_before_the_initialization_change_the_run_as_set_parameter_does(fmi, tmp_path):
    m = soadyn.scenes.pendulum_chain(2)
    q0 = np.array([0.4, -0.3])
    path = export_fmu(m, tmp_path / "p.fmu", fmi=fmi, step=0.01, q0=q0)
    session_names = {v.name for v in read_model_description(str(path)).modelVariables}
    assert {"link_1.mass", "link_2.com[2]", "link_1.inertia[0,1]", "link_2.placement[2,3]",
            "gravity[2]"} <= session_names
    changes = {"link_2.mass": 2.5, "link_2.com[2]": -0.3, "gravity[2]": -3.7}
    session = FmuSession(path, parameters=changes)
    q = []
    for _ in range(50):
        session.step(0.01)
        q.append(session.reals(["q.link_1", "q.link_2"]))
    assert session.reals(["link_2.mass"])[0] == 2.5
    session.close()
    changed = m.copy()
    changed.set_parameter("link_2.mass", 2.5)
    changed.set_parameter("link_2.com", [0.0, 0.0, -0.3])
    changed.gravity = [0.0, 0.0, -3.7]
    sim = soadyn.Simulator(changed, dt=0.01)
    sim.set_state(q0, np.zeros(2))
    run = sim.run(0.5)
    assert np.array_equal(np.array(q), run.q[1:])


def driven_state(session: FmuSession, m: soadyn.Model, dof: str, u: float, steps: int, h: float):
    """(q, v) of the FMU after `steps` steps of `h` with input u.<dof> = u."""
    session.set_real(f"u.{dof}", u)
    for _ in range(steps):
        session.step(h)
    return session.reals([f"q.{c}" for c in m.coordinate_names]), session.reals([f"v.{d}" for d in m.dof_names])


@pytest.mark.parametrize("fmi", [3, 2])
def test_frame_outputs_are_the_frames_pose_velocities_and_acceleration(fmi, tmp_path):
    m = soadyn.scenes.stanford_arm()
    q0 = soadyn.stanford_arm.MOTION_START
    path = export_fmu(m, tmp_path / "arm.fmu", fmi=fmi, step=0.01, q0=q0, outputs=["frame.tool"])
    assert validate_fmu(str(path)) == []
    session = FmuSession(path)
    q, v = driven_state(session, m, "joint_1", 1.5, 20, 0.01)
    qdd = session.reals([f"qdd.{d}" for d in m.dof_names])
    out = dict(zip(["x", "y", "z", "qx", "qy", "qz", "qw", "wx", "wy", "wz", "vx", "vy", "vz", "ax", "ay", "az"],
                   session.reals([f"frame.tool.{k}" for k in ("x", "y", "z", "qx", "qy", "qz", "qw", "wx", "wy", "wz",
                                                              "vx", "vy", "vz", "ax", "ay", "az")])))
    session.close()
    pose = soadyn.frame_pose(m, q, "tool")
    np.testing.assert_allclose([out["x"], out["y"], out["z"]], pose[:3, 3], rtol=0, atol=1e-12)
    x, y, z, w = out["qx"], out["qy"], out["qz"], out["qw"]
    rotation = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    np.testing.assert_allclose(rotation, pose[:3, :3], rtol=0, atol=1e-12)
    velocity = soadyn.frame_velocity(m, q, v, "tool", "local")
    np.testing.assert_allclose([out[k] for k in ("wx", "wy", "wz", "vx", "vy", "vz")], velocity, rtol=0, atol=1e-12)
    acceleration = soadyn.frame_acceleration(m, q, v, qdd, "tool", "local", classical=True)
    np.testing.assert_allclose([out[k] for k in ("ax", "ay", "az")], acceleration[3:], rtol=0, atol=1e-11)
    assert np.linalg.norm(velocity) > 0.1  # the arm moves
    with pytest.raises(soadyn.FmuError, match="'frame.nowhere'|nowhere"):
        export_fmu(m, tmp_path / "bad.fmu", outputs=["frame.nowhere"])
    with pytest.raises(soadyn.FmuError, match="is not 'frame.<name>'"):
        export_fmu(m, tmp_path / "bad.fmu", outputs=["tool"])


def test_loop_wrench_outputs_are_constrained_dynamics_loop_wrenches(tmp_path):
    m = soadyn.scenes.four_bar()
    q0, v0 = soadyn.scenes.four_bar_state(0.7, 1.0)
    path = export_fmu(m, tmp_path / "fb.fmu", step=0.005, q0=q0, v0=v0)
    session = FmuSession(path)
    q, v = driven_state(session, m, "crank", 0.5, 40, 0.005)
    wrench = session.reals([f"loop.coupler_rocker.{k}" for k in ("tx", "ty", "tz", "fx", "fy", "fz")])
    session.close()
    _, _, expected = soadyn.constrained_dynamics(m, q, v, np.array([0.5, 0.0, 0.0]))
    np.testing.assert_allclose(wrench, expected[0], rtol=1e-10, atol=1e-10 * np.abs(expected).max())
    assert np.abs(expected[0][3:]).max() > 1.0  # the pin carries the links' weight


def test_inputs_set_before_the_initialization_survive_a_parameter_change(tmp_path):
    m = soadyn.scenes.pendulum_chain(2)
    path = export_fmu(m, tmp_path / "p.fmu", step=0.01)
    session = FmuSession(path, parameters={"link_1.mass": 1.5, "u.link_1": 0.8})
    for _ in range(30):
        session.step(0.01)
    q = session.reals(["q.link_1", "q.link_2"])
    session.close()
    changed = m.copy()
    changed.set_parameter("link_1.mass", 1.5)
    sim = soadyn.Simulator(changed, dt=0.01)
    sim.set_input("link_1", 0.8)
    sim.run(0.3)
    assert np.array_equal(q, sim.q) and abs(q[0]) > 1e-3
