"""Hostile use of exported FMUs in fmpy: missing and corrupted resources, a wrong instantiation token, wrong
value references, non-finite inputs, a DoStep after an error, a step that is not a whole number of
internal steps, rolling back through saved and serialized states, 100 instances at once; and bad
arguments of export_fmu. Every one is a clear FMI error or exception naming the item, never a crash of
the importing process."""
from __future__ import annotations

import shutil
import zipfile

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

import soadyn
from soadyn.fmu import FmuError, export_fmu
from support.fmu_runs import FmuSession


@pytest.fixture(scope="module")
def pendulum_fmu(tmp_path_factory):
    m = soadyn.scenes.pendulum_chain(2)
    return m, export_fmu(m, tmp_path_factory.mktemp("fmu") / "p.fmu", step=0.01, q0=np.array([0.5, 0.0]))


def rewritten(path, tmp_path, name: str, change):
    """A copy of the FMU at `path` with member `name` changed by change(bytes) -> bytes or None (removed)."""
    out = tmp_path / f"changed_{name.replace('/', '_')}.fmu"
    with zipfile.ZipFile(path) as source, zipfile.ZipFile(out, "w") as target:
        for item in source.infolist():
            data = source.read(item)
            if item.filename == name:
                data = change(data)
                if data is None:
                    continue
            target.writestr(item, data)
    return out


@pytest.mark.parametrize("member, change, message", [
    ("resources/model.json", lambda b: None, "model.json"),
    ("resources/model.json", lambda b: b[: len(b) // 2], "model.json"),
    ("resources/soadyn_fmu.txt", lambda b: None, "soadyn_fmu.txt"),
    ("resources/soadyn_fmu.txt", lambda b: b.replace(b"step 0.01", b"step -1"), "the step must be > 0"),
    ("resources/soadyn_fmu.txt", lambda b: b.replace(b"integrator rk4", b"integrator magic"), "unknown integrator"),
])
def test_missing_or_corrupted_resources_refuse_to_instantiate(pendulum_fmu, tmp_path, member, change, message):
    _, path = pendulum_fmu
    broken = rewritten(path, tmp_path, member, change)
    messages = []
    with pytest.raises(Exception, match="instantiate"):
        FmuSession(broken, logger=messages.append)
    assert any(message in m for m in messages), messages


def test_a_wrong_token_is_refused(pendulum_fmu, tmp_path):
    _, path = pendulum_fmu
    broken = rewritten(path, tmp_path, "modelDescription.xml",
                       lambda b: b.replace(b'instantiationToken="{', b'instantiationToken="{0'))
    messages = []
    with pytest.raises(Exception):
        FmuSession(broken, logger=messages.append)
    assert any("instantiation token" in m for m in messages), messages


def test_bad_calls_are_fmi_errors_and_a_failed_instance_refuses_to_step(pendulum_fmu):
    m, path = pendulum_fmu
    messages = []
    session = FmuSession(path, logger=messages.append)
    with pytest.raises(FMICallException):
        session.fmu.setFloat64([10_000], [1.0])
    assert "no variable has value reference 10000" in messages[-1]
    session.fmu.reset()
    session.fmu.enterInitializationMode()
    session.fmu.exitInitializationMode()
    session.time = 0.0
    with pytest.raises(FMICallException):
        session.set_real("u.link_1", float("nan"))
    assert "the value of 'u.link_1' is not finite" in messages[-1]
    with pytest.raises(FMICallException):
        session.step(0.01)
    assert "DoStep after an error" in messages[-1]
    session.fmu.reset()
    session.fmu.enterInitializationMode()
    session.fmu.exitInitializationMode()
    with pytest.raises(FMICallException):
        session.fmu.doStep(currentCommunicationPoint=0.0, communicationStepSize=0.0105)
    assert "not a whole number of the FMU's internal step" in messages[-1]
    session.close()


def test_rollback_through_saved_and_serialized_states_repeats_the_steps_bit_for_bit(pendulum_fmu):
    _, path = pendulum_fmu
    session = FmuSession(path)
    session.set_real("u.link_2", 0.3)
    for _ in range(10):
        session.step(0.01)
    state = session.fmu.getFMUState()
    serialized = session.fmu.serializeFMUState(state)
    first = []
    for _ in range(20):
        session.step(0.01)
        first.append(session.reals(["q.link_1", "q.link_2", "v.link_1"]))
    session.fmu.setFMUState(state)
    session.time = 0.1
    again = []
    for _ in range(20):
        session.step(0.01)
        again.append(session.reals(["q.link_1", "q.link_2", "v.link_1"]))
    assert np.array_equal(first, again)
    restored = session.fmu.deserializeFMUState(serialized)
    session.fmu.setFMUState(restored)
    session.time = 0.1
    session.step(0.01)
    assert np.array_equal(session.reals(["q.link_1", "q.link_2", "v.link_1"]), first[0])
    with pytest.raises(Exception):
        session.fmu.deserializeFMUState(serialized[:-3])
    session.fmu.freeFMUState(state)
    session.fmu.freeFMUState(restored)
    session.close()


def test_a_hundred_instances_at_once(pendulum_fmu):
    _, path = pendulum_fmu
    sessions = [FmuSession(path, instance_name=f"p{k}") for k in range(100)]
    for k, session in enumerate(sessions):
        session.set_real("u.link_1", 0.01 * k)
        session.step(0.01)
    q = np.array([s.reals(["q.link_1"])[0] for s in sessions])
    assert np.all(np.isfinite(q)) and len(set(q)) == 100
    for session in sessions:
        session.close()


@pytest.mark.parametrize("arguments, error, message", [
    (dict(fmi=1), FmuError, "fmi must be 3 or 2"),
    (dict(step=0.0), FmuError, "step must be a finite number of seconds > 0"),
    (dict(step=float("nan")), FmuError, "step must be"),
    (dict(substeps=0), FmuError, "substeps must be a whole number"),
    (dict(integrator="magic"), FmuError, "integrator must be one of"),
    (dict(q0=[0.0]), FmuError, "q0 must be 2 finite numbers"),
    (dict(v0=[0.0, float("inf")]), FmuError, "v0 must be 2 finite numbers"),
])
def test_export_names_a_bad_argument(tmp_path, arguments, error, message):
    with pytest.raises(error, match=message):
        export_fmu(soadyn.scenes.pendulum_chain(2), tmp_path / "x.fmu", **arguments)


def test_export_refuses_a_start_state_the_simulator_refuses_and_an_unwritable_path(tmp_path):
    m = soadyn.scenes.cassini()
    q0 = soadyn.neutral_configuration(m)
    q0[3:7] = [0.0, 0.0, 0.0, 2.0]  # a quaternion of norm 2
    with pytest.raises(FmuError, match="quaternion of joint 'bus'"):
        export_fmu(m, tmp_path / "c.fmu", q0=q0)
    with pytest.raises(OSError, match="the FMU '/proc/x.fmu'"):
        export_fmu(soadyn.scenes.pendulum_chain(1), "/proc/x.fmu")
    with pytest.raises(TypeError, match="needs a soadyn.Model"):
        export_fmu(42, tmp_path / "n.fmu")
    shutil.rmtree(tmp_path)


def test_a_parameter_out_of_range_or_set_after_the_initialization_is_refused(pendulum_fmu):
    _, path = pendulum_fmu
    messages = []
    with pytest.raises(FMICallException):
        FmuSession(path, logger=messages.append, parameters={"link_2.mass": -1.0})
    assert any("link_2" in m and "mass" in m for m in messages), messages
    session = FmuSession(path, logger=messages.append)
    with pytest.raises(FMICallException):
        session.set_real("link_2.placement[1,3]", 0.3)  # masses are tunable, placements fixed
    assert "the parameter 'link_2.placement[1,3]' is fixed" in messages[-1]
    session.close()


def test_instances_stepped_from_two_threads_at_once_equal_their_runs_alone(pendulum_fmu):
    """fmpy's calls release the GIL: two instances of one FMU step concurrently, each from its own thread, and
    each ends where it ends when run alone (instances share nothing; errors are per instance)."""
    import threading

    _, path = pendulum_fmu

    def run(torque: float, out: dict) -> None:
        session = FmuSession(path, instance_name=f"t{torque}")
        session.set_real("u.link_1", torque)
        for _ in range(300):
            session.step(0.01)
        out[torque] = session.reals(["q.link_1", "q.link_2", "v.link_1", "v.link_2"])
        session.close()

    alone, together = {}, {}
    for torque in (0.3, -0.7):
        run(torque, alone)
    threads = [threading.Thread(target=run, args=(torque, together)) for torque in (0.3, -0.7)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    for torque in (0.3, -0.7):
        assert np.array_equal(together[torque], alone[torque])
    assert not np.array_equal(alone[0.3], alone[-0.7])
