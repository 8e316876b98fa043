"""A second importer nobody here wrote, libcosim (the Open Simulation Platform's co-simulation library,
libcosimpy), runs the exported FMI 2.0 FMUs: the pendulum chain from a tilted start and cassini with a
torque on its scan platform end where soadyn's Simulator ends, bit for bit. libcosim reads FMI 1.0 and 2.0
FMUs only; the FMI 3.0 ones are run by fmpy (test_fmu_export.py)."""
from __future__ import annotations

import numpy as np
import pytest
from libcosimpy.CosimExecution import CosimExecution
from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
from libcosimpy.CosimManipulator import CosimManipulator
from libcosimpy.CosimObserver import CosimObserver
from libcosimpy.CosimSlave import CosimLocalSlave

import soadyn
from soadyn.fmu import export_fmu
from support.fmu_runs import Step, run_reference

NANOSECONDS = 10**9


def run_in_libcosim(path, m: soadyn.Model, step: float, steps: int, inputs: dict) -> tuple[np.ndarray, np.ndarray]:
    """(q, v) at the end of `steps` communication steps of `step` s with constant `inputs` {DOF: u}."""
    log_output_level(CosimLogLevel.ERROR)
    execution = CosimExecution.from_step_size(step_size=round(step * NANOSECONDS))
    slave = execution.add_local_slave(local_slave=CosimLocalSlave(fmu_path=str(path), instance_name="plant"))
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer=observer)
    manipulator = CosimManipulator.create_override()
    execution.add_manipulator(manipulator=manipulator)
    reference = {v.name.decode(): v.reference for v in execution.slave_variables(slave_index=slave)}
    names = list(inputs)
    manipulator.slave_real_values(slave, [reference[f"u.{n}"] for n in names], [inputs[n] for n in names])
    assert execution.simulate_until(target_time=round(steps * step * NANOSECONDS))
    q = observer.last_real_values(slave_index=slave,
                                  variable_references=[reference[f"q.{c}"] for c in m.coordinate_names])
    v = observer.last_real_values(slave_index=slave, variable_references=[reference[f"v.{d}"] for d in m.dof_names])
    return np.array(q), np.array(v)


@pytest.mark.parametrize("scene", ["pendulum", "cassini"])
def test_libcosim_runs_the_fmi2_fmus_as_the_simulator_does(scene, tmp_path):
    if scene == "pendulum":
        m, inputs = soadyn.scenes.pendulum_chain(3), {"link_2": 0.4}
        q0, v0 = np.array([0.3, -0.2, 0.1]), np.zeros(3)
    else:
        m, inputs = soadyn.scenes.cassini(), {"scan_az": 2.0, "wheel_1": 0.05}
        q0, v0 = soadyn.neutral_configuration(m), np.zeros(m.nv)
        v0[m.dof_index("turntable")] = soadyn.scenes.TURNTABLE_RATE
    path = export_fmu(m, tmp_path / f"{scene}.fmu", fmi=2, step=0.01, q0=q0, v0=v0)
    q, v = run_in_libcosim(path, m, 0.01, 50, inputs)
    reference = run_reference(m, 0.01, q0, v0, [Step(0.01, inputs) for _ in range(50)])
    assert np.array_equal(q, reference.q[-1]), np.abs(q - reference.q[-1]).max()
    assert np.array_equal(v, reference.v[-1])
