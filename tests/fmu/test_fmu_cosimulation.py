"""A co-simulation of two FMUs: the exported plant (the pendulum chain, FMI 2.0) and a PD controller FMU
written in C against the FMI headers alone (pd_controller.c, compiled here with the system's C compiler),
connected by a master loop in fmpy: at each communication point the controller reads the first link's
angle and rate and its torque drives the plant. The loop tracks the setpoint, and its trajectory equals the
same loop closed in soadyn's Simulator (the PD law computed in Python at the same points) bit for bit."""
from __future__ import annotations

import shutil
import subprocess
import uuid
import zipfile
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

import soadyn
from soadyn.fmu import export_fmu
from support.fmu_runs import FmuSession

HERE = Path(__file__).resolve().parent
FMI_HEADERS = HERE.parents[1] / "third_party" / "fmi"
SETPOINT, KP, KD = 0.6, 40.0, 6.0
STEP, STEPS = 0.005, 800  # 4 s

CONTROLLER_DESCRIPTION = """<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="pd_controller" guid="{guid}" variableNamingConvention="flat"
    numberOfEventIndicators="0">
  <CoSimulation modelIdentifier="pd_controller" canHandleVariableCommunicationStepSize="true"/>
  <ModelVariables>
    <ScalarVariable name="setpoint" valueReference="0" causality="parameter" variability="fixed"><Real start="0"/></ScalarVariable>
    <ScalarVariable name="kp" valueReference="1" causality="parameter" variability="fixed"><Real start="0"/></ScalarVariable>
    <ScalarVariable name="kd" valueReference="2" causality="parameter" variability="fixed"><Real start="0"/></ScalarVariable>
    <ScalarVariable name="position" valueReference="3" causality="input" variability="continuous"><Real start="0"/></ScalarVariable>
    <ScalarVariable name="velocity" valueReference="4" causality="input" variability="continuous"><Real start="0"/></ScalarVariable>
    <ScalarVariable name="torque" valueReference="5" causality="output" variability="continuous"><Real/></ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs><Unknown index="6" dependencies="4 5"/></Outputs>
    <InitialUnknowns><Unknown index="6"/></InitialUnknowns>
  </ModelStructure>
</fmiModelDescription>
"""


@pytest.fixture(scope="module")
def controller_fmu(tmp_path_factory) -> Path:
    compiler = shutil.which("cc") or shutil.which("gcc")
    assert compiler, "a C compiler (cc or gcc) builds the controller FMU"
    folder = tmp_path_factory.mktemp("controller")
    binary = folder / "pd_controller.so"
    subprocess.run([compiler, "-std=c99", "-shared", "-fPIC", "-O2", f"-I{FMI_HEADERS}", str(HERE / "pd_controller.c"),
                    "-o", str(binary)], check=True)
    path = folder / "pd_controller.fmu"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("modelDescription.xml", CONTROLLER_DESCRIPTION.format(guid="{" + str(uuid.uuid4()) + "}"))
        archive.write(binary, "binaries/linux64/pd_controller.so")
    return path


def test_plant_and_controller_fmus_track_the_setpoint_as_the_simulator_does(controller_fmu, tmp_path):
    m = soadyn.scenes.pendulum_chain(2)
    plant = FmuSession(export_fmu(m, tmp_path / "plant.fmu", fmi=2, step=STEP))
    controller = FmuSession(controller_fmu, instance_name="controller")
    for name, value in (("setpoint", SETPOINT), ("kp", KP), ("kd", KD)):
        controller.set_real(name, value)
    sim = soadyn.Simulator(m, dt=STEP)
    angles_fmu, angles_sim = [], []
    for _ in range(STEPS):
        q, v = plant.reals(["q.link_1", "v.link_1"])
        controller.set_real("position", q)
        controller.set_real("velocity", v)
        controller.step(STEP)
        plant.set_real("u.link_1", controller.reals(["torque"])[0])
        plant.step(STEP)
        angles_fmu.append(plant.reals(["q.link_1"])[0])
        sim.set_input("link_1", KP * (SETPOINT - sim.q[0]) - KD * sim.v[0])
        sim.run(STEP)
        angles_sim.append(sim.q[0])
    plant.close()
    controller.close()
    assert np.array_equal(angles_fmu, angles_sim)
    # A PD loop against gravity holds the first link below the setpoint, where kp (setpoint - q) balances the
    # static load of both links with the second hanging straight down: m g (l/2 + l) sin q (closed form); the
    # undamped second link keeps swinging about it.
    equilibrium = brentq(lambda q: KP * (SETPOINT - q) - 9.81 * (0.25 + 0.5) * np.sin(q), 0.0, SETPOINT)
    assert abs(np.mean(angles_fmu[-400:]) - equilibrium) < 2e-3, (np.mean(angles_fmu[-400:]), equilibrium)
