"""The FMU's inputs beyond torques and accelerations, and its parameters beyond the fixed ones, in fmpy:
external wrenches on frames, velocity and position inputs of prescribed DOFs, the integrator and substeps
parameters, and tunable model parameters changed in step mode.

Each run equals soadyn's own Simulator bit for bit (tests/support/fmu_runs.py gives the reference), and
closed-form physics checks what the reference cannot: a velocity input is reached at the end of each
communication step, a position input too (with the velocity continuous), and a rod held at an angle by a
force on a frame at its tip stays there.
"""
from __future__ import annotations

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException
from fmpy.validation import validate_fmu

import soadyn
from soadyn.fmu import FmuError, export_fmu
from support.fmu_runs import FmuSession, Step, run_fmu, run_reference

STEP = 0.01


def assert_same_trajectory(fmu, reference):
    assert np.array_equal(fmu.q, reference.q), np.abs(fmu.q - reference.q).max()
    assert np.array_equal(fmu.v, reference.v), np.abs(fmu.v - reference.v).max()


@pytest.mark.parametrize("fmi", [3, 2])
def test_wrench_inputs_on_bodies_equal_the_simulator_bit_for_bit(fmi, tmp_path):
    m = soadyn.scenes.pendulum_chain(3)
    q0, v0 = np.array([0.3, -0.2, 0.1]), np.zeros(3)
    path = export_fmu(m, tmp_path / "w.fmu", fmi=fmi, step=STEP, q0=q0, v0=v0, wrenches=["link_2", "link_3"])
    assert validate_fmu(str(path)) == []
    steps = [Step(STEP, {"link_1": 0.1}, wrenches={"link_2": [0.2 * np.sin(k / 7), 0, 0, 0, 0.5, -0.3],
                                                   "link_3": [0, 0.1, 0, 1.0 if k > 20 else 0.0, 0, 0]})
             for k in range(60)]
    assert_same_trajectory(run_fmu(path, m, steps), run_reference(m, STEP, q0, v0, steps))


def test_a_torque_wrench_on_a_link_equals_the_joint_torques_it_implies():
    # A pure torque tau about x on link_2 (hinges about parallel x axes) is the generalized force (tau, tau).
    m = soadyn.scenes.pendulum_chain(2)
    q0, v0 = np.array([0.4, -0.6]), np.array([0.0, 0.5])
    runs = []
    for through_wrench in (False, True):
        sim = soadyn.Simulator(m, dt=1e-3)
        sim.set_state(q0, v0)
        if through_wrench:
            sim.set_external_wrench("link_2", [1.5, 0, 0, 0, 0, 0])
        else:
            sim.set_input("link_1", 1.5)
            sim.set_input("link_2", 1.5)
        runs.append(sim.run(0.5))
    np.testing.assert_allclose(runs[1].q, runs[0].q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(runs[1].v, runs[0].v, rtol=0, atol=1e-11)
    assert np.abs(runs[0].q[-1] - q0).max() > 0.1  # the torque moved it


ROD = """<robot name="rod">
  <link name="base"/>
  <link name="rod">
    <inertial><origin xyz="0 0 -0.25"/><mass value="2.0"/>
      <inertia ixx="0.0416666667" iyy="0.0416666667" izz="0.0001" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="hinge" type="continuous"><parent link="base"/><child link="rod"/><axis xyz="1 0 0"/></joint>
  <link name="tip"/>
  <joint name="tip_weld" type="fixed"><parent link="rod"/><child link="tip"/><origin xyz="0 0 -0.5"/></joint>
</robot>"""


@pytest.mark.parametrize("fmi", [3, 2])
def test_a_force_on_the_tip_frame_holds_the_rod_where_gravity_would_swing_it(fmi, tmp_path):
    # Statics: a rod of mass m and length L at angle theta is held by a force m g sin(theta) / 2 at its tip,
    # along the tip frame's y axis (perpendicular to the rod).
    urdf = tmp_path / "rod.urdf"
    urdf.write_text(ROD)
    m = soadyn.load_urdf(str(urdf))
    assert "tip" in m.frame_names
    theta = 0.7
    path = export_fmu(m, tmp_path / "rod.fmu", fmi=fmi, step=STEP, q0=[theta], wrenches=["tip"])
    force = 2.0 * 9.81 * np.sin(theta) / 2.0
    held = run_fmu(path, m, [Step(STEP, wrenches={"tip": [0, 0, 0, 0, force, 0]}) for _ in range(100)])
    assert np.abs(held.q[:, 0] - theta).max() < 1e-12 and np.abs(held.v).max() < 1e-11
    free = run_fmu(path, m, [Step(STEP) for _ in range(10)])
    assert abs(free.q[-1, 0] - theta) > 1e-2  # without it, the rod swings


def prescribed_chain():
    m = soadyn.scenes.pendulum_chain(3)
    m.set_prescribed([False, True, False])
    return m


def run_kind(fmi, tmp_path, kind: str, substeps: int, steps: list[Step]):
    """The prescribed chain's FMU with link_2's input of `kind` through `steps`, checked bit for bit against
    the Simulator; returns the FMU's run."""
    m = prescribed_chain()
    q0, v0 = np.array([0.2, 0.0, -0.1]), np.zeros(3)
    path = export_fmu(m, tmp_path / f"{kind}.fmu", fmi=fmi, step=STEP, substeps=substeps, q0=q0, v0=v0,
                      input_kinds={"link_2": kind})
    assert validate_fmu(str(path)) == []
    fmu = run_fmu(path, m, steps)
    assert_same_trajectory(fmu, run_reference(m, STEP / substeps, q0, v0, steps, input_kinds={"link_2": kind}))
    return fmu


@pytest.mark.parametrize("fmi", [3, 2])
def test_a_velocity_input_is_reached_at_the_end_of_each_communication_step(fmi, tmp_path):
    command = [0.5 * np.sin(k / 5) for k in range(50)]
    fmu = run_kind(fmi, tmp_path, "velocity", 4, [Step(STEP, {"link_2": u, "link_1": 0.05}) for u in command])
    assert np.abs(fmu.v[1:, 1] - command).max() < 1e-12  # reached: (u - v) / h over h


@pytest.mark.parametrize("fmi", [3, 2])
def test_a_position_input_is_reached_with_the_velocity_continuous_and_no_ringing(fmi, tmp_path):
    command = [0.3] * 20 + [0.3 + 0.02 * k for k in range(1, 31)]  # a step, held, then a ramp of 2 rad/s
    fmu = run_kind(fmi, tmp_path, "position", 5, [Step(STEP, {"link_2": u}) for u in command])
    assert np.abs(fmu.q[1:, 1] - command).max() < 1e-12
    # The end velocity of each step is the mean rate over it: 30 rad/s after the step in the command, 0 while
    # held (no oscillation about the held position), 2 rad/s on the ramp.
    assert abs(fmu.v[1, 1] - 0.3 / STEP) < 1e-9
    assert np.abs(fmu.v[2:21, 1]).max() < 1e-9 and np.abs(fmu.v[22:, 1] - 2.0).max() < 1e-9


@pytest.mark.parametrize("fmi", [3, 2])
def test_the_integrator_and_substeps_parameters_equal_a_simulator_with_them(fmi, tmp_path):
    m = soadyn.scenes.pendulum_chain(2)
    q0, v0 = np.array([0.5, -0.4]), np.zeros(2)
    path = export_fmu(m, tmp_path / "i.fmu", fmi=fmi, step=STEP, q0=q0, v0=v0)
    steps = [Step(STEP, {"link_1": 0.3}) for _ in range(40)]
    for integrator, number, substeps in (("euler", 2, 4), ("dopri5", 3, 1), ("rk4", 1, 3)):
        session = FmuSession(path, integers={"integrator": number, "substeps": substeps})
        q = []
        for step in steps:
            session.set_real("u.link_1", step.inputs["link_1"])
            session.step(step.h)
            q.append(session.reals(["q.link_1", "q.link_2"]))
        session.close()
        reference = run_reference(m, STEP / substeps, q0, v0, steps, integrator=integrator)
        assert np.array_equal(np.array(q), reference.q[1:]), integrator


@pytest.mark.parametrize("fmi", [3, 2])
def test_a_tunable_mass_changed_in_step_mode_changes_the_run_from_then_on(fmi, tmp_path):
    m = soadyn.scenes.pendulum_chain(2)
    q0, v0 = np.array([0.5, -0.4]), np.zeros(2)
    path = export_fmu(m, tmp_path / "t.fmu", fmi=fmi, step=STEP, q0=q0, v0=v0)
    session = FmuSession(path)
    q = []
    for k in range(60):
        if k == 30:
            session.set_real("link_2.mass", 3.0)
            session.set_real("gravity[2]", -3.7)
        session.step(STEP)
        q.append(session.reals(["q.link_1", "q.link_2"]))
    session.close()
    first = soadyn.Simulator(m, dt=STEP)
    first.set_state(q0, v0)
    first.run(30 * STEP)
    changed = m.copy()
    changed.set_parameter("link_2.mass", 3.0)
    changed.gravity = [0.0, 0.0, -3.7]
    second = soadyn.Simulator(changed, dt=STEP)
    second.set_state(first.q, first.v, first.time)
    reference = np.vstack([first.run(0).q[-1:], second.run(30 * STEP).q[1:]])  # q at 0.3 s, then the rest
    assert np.array_equal(np.array(q)[29:], reference)


def test_a_saved_state_holds_the_tunable_parameters(tmp_path):
    m = soadyn.scenes.pendulum_chain(2)
    path = export_fmu(m, tmp_path / "s.fmu", step=STEP, q0=[0.5, -0.4])
    session = FmuSession(path)
    state = session.fmu.getFMUState()
    trajectory = []
    for _ in range(20):
        session.step(STEP)
        trajectory.append(session.reals(["q.link_1", "q.link_2"]))
    session.set_real("link_2.mass", 7.0)
    session.fmu.setFMUState(state)
    session.time = 0.0
    assert session.reals(["link_2.mass"])[0] == 1.0
    again = []
    for _ in range(20):
        session.step(STEP)
        again.append(session.reals(["q.link_1", "q.link_2"]))
    assert np.array_equal(np.array(again), np.array(trajectory))
    session.fmu.freeFMUState(state)
    session.close()


def test_hostile_uses_of_the_new_inputs_and_parameters_are_fmi_errors(tmp_path):
    m = prescribed_chain()
    path = export_fmu(m, tmp_path / "h.fmu", step=STEP, wrenches=["link_3"], input_kinds={"link_2": "position"})
    messages = []
    session = FmuSession(path, logger=messages.append)
    for name, value, message in (("link_2.placement[1,3]", 0.2, "the parameter 'link_2.placement[1,3]' is fixed"),
                                 ("wrench.link_3.fx", float("nan"), "the value of 'wrench.link_3.fx' is not finite"),
                                 ("link_3.mass", -1.0, "link_3")):
        with pytest.raises(FMICallException):
            session.set_real(name, value)
        assert message in messages[-1], messages[-1]
        session.fmu.reset()
        session.fmu.enterInitializationMode()
        session.fmu.exitInitializationMode()
        session.time = 0.0
    with pytest.raises(FMICallException):
        session.set_integer("substeps", 2)  # fixed: before the initialization only
    assert "the parameter 'substeps' is fixed" in messages[-1]
    session.close()
    with pytest.raises(FMICallException):
        FmuSession(path, logger=messages.append, integers={"integrator": 7})
    assert "integrator must be 1 (rk4), 2 (euler) or 3 (dopri5), got 7" in messages[-1]


@pytest.mark.parametrize("arguments, message", [
    (dict(wrenches=["nowhere"]), "wrenches: 'nowhere' is not a body or frame of the model"),
    (dict(input_kinds={"link_9": "velocity"}), "input_kinds: 'link_9' is not a DOF of the model"),
    (dict(input_kinds={"link_1": "jerk"}), "input_kinds\\['link_1'\\] must be one of acceleration, velocity, position"),
    (dict(input_kinds=["link_1"]), "input_kinds must be a dict"),
])
def test_export_names_a_bad_wrench_frame_or_input_kind(tmp_path, arguments, message):
    with pytest.raises(FmuError, match=message):
        export_fmu(soadyn.scenes.pendulum_chain(2), tmp_path / "x.fmu", **arguments)


def test_the_command_line_exports_wrench_inputs_and_input_kinds(tmp_path):
    from soadyn.apps.cli import main

    out = tmp_path / "c.fmu"
    assert main(["fmu", "cassini", "--out", str(out), "--wrench", "scan_el", "--input-kind",
                 "gimbal_pitch=position", "--input-kind", "turntable=velocity"]) == 0
    session = FmuSession(out)
    names = set(session.vr)
    assert {f"wrench.scan_el.{c}" for c in ("tx", "ty", "tz", "fx", "fy", "fz")} <= names
    description = {v.name: v.description for v in session.description.modelVariables}
    assert "its position when prescribed (rad)" in description["u.gimbal_pitch"]
    assert "its velocity when prescribed (rad/s)" in description["u.turntable"]
    session.close()


def test_the_command_line_names_a_malformed_input_kind(tmp_path, capsys):
    from soadyn.apps.cli import main

    with pytest.raises(SystemExit) as exit_info:
        main(["fmu", "cassini", "--out", str(tmp_path / "c.fmu"), "--input-kind", "gimbal_pitch"])
    assert exit_info.value.code == 2 and "--input-kind 'gimbal_pitch': expected DOF=KIND" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["fmu", "cassini", "--out", str(tmp_path / "c.fmu"), "--input-kind", "gimbal_pitch=jerk"])
    assert "must be one of acceleration, velocity, position" in capsys.readouterr().err
