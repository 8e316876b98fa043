"""Runs of exported FMUs in fmpy (an importer nobody here wrote), step by step with inputs, and the same
scenario on soadyn's own Simulator, for bit-for-bit comparisons.

A scenario is a list of communication steps, each (h, inputs, locked, prescribed, wrenches): the step size,
{DOF: u} (torque of a regular DOF; acceleration, velocity or position of a prescribed one, per the export's
input_kinds; held over the step), the sets of DOFs locked and prescribed during it, and {body: wrench} (the
external wrench on a body's own frame). The reference applies what the FMU does at each communication
point (embed::Plant::apply_inputs): locks first (Simulator.lock), then each prescribed DOF follows the
motion its input gives over the step from where it is (Simulator.prescribe with
MotionSource.constant_acceleration, or for a position input the cubic MotionSource.polynomial), then
releases and torques (Simulator.release, set_input), the wrenches (Simulator.set_external_wrench), then
Simulator.run(h).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from fmpy import extract, read_model_description
from fmpy import fmi2
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave, fmi3LogMessageCallback

import soadyn


@dataclass
class Step:
    h: float
    inputs: dict = field(default_factory=dict)
    locked: frozenset = frozenset()
    prescribed: frozenset | None = None  # None: the model's prescribed DOFs
    wrenches: dict = field(default_factory=dict)  # {body name: (6,) [torque; force]}


@dataclass
class FmuRun:
    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    tau: np.ndarray | None  # the FMU's tau.<dof> at each communication point after the start


class FmuSession:
    """One instance of an FMU in fmpy, its variables by name; `logger(message: str)` receives what the FMU
    logs (errors, and everything with logging on); `parameters` {name: value} are set before the
    initialization."""

    def __init__(self, path, instance_name: str = "plant", start_time: float = 0.0, logger=None,
                 parameters: dict | None = None, integers: dict | None = None):
        self.directory = extract(str(path))
        self.description = read_model_description(self.directory)
        self.version = int(self.description.fmiVersion[0])
        self.vr = {v.name: v.valueReference for v in self.description.modelVariables}
        kind = FMU3Slave if self.version == 3 else FMU2Slave
        token = self.description.instantiationToken if self.version == 3 else self.description.guid
        self.fmu = kind(guid=token, unzipDirectory=self.directory, instanceName=instance_name,
                        modelIdentifier=self.description.coSimulation.modelIdentifier)
        self._callback = None
        if logger is None:
            self.fmu.instantiate()
        elif self.version == 3:
            self._callback = fmi3LogMessageCallback(lambda env, status, category, message: logger(message.decode()))
            self.fmu.instantiate(logMessage=self._callback)
        else:
            self._callback = fmi2.fmi2CallbackFunctions()
            self._callback.logger = fmi2.fmi2CallbackLoggerTYPE(
                lambda env, name, status, category, message: logger(message.decode()))
            self._callback.allocateMemory = fmi2.fmi2CallbackAllocateMemoryTYPE(fmi2.calloc)
            self._callback.freeMemory = fmi2.fmi2CallbackFreeMemoryTYPE(fmi2.free)
            self.fmu.instantiate(callbacks=self._callback)
        for name, value in (parameters or {}).items():  # fixed parameters: before the initialization
            self.set_real(name, value)
        for name, value in (integers or {}).items():
            self.set_integer(name, value)
        if self.version == 3:
            self.fmu.enterInitializationMode(startTime=start_time)
        else:
            self.fmu.setupExperiment(startTime=start_time)
            self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        self.time = start_time

    def set_real(self, name: str, value: float) -> None:
        (self.fmu.setFloat64 if self.version == 3 else self.fmu.setReal)([self.vr[name]], [float(value)])

    def set_integer(self, name: str, value: int) -> None:
        """An Int32 (substeps) or Enumeration (integrator) parameter."""
        if self.version == 2:
            self.fmu.setInteger([self.vr[name]], [int(value)])
        elif name == "integrator":
            self.fmu.setInt64([self.vr[name]], [int(value)])
        else:
            self.fmu.setInt32([self.vr[name]], [int(value)])

    def set_bool(self, name: str, value: bool) -> None:
        self.fmu.setBoolean([self.vr[name]], [bool(value)])

    def reals(self, names) -> np.ndarray:
        get = self.fmu.getFloat64 if self.version == 3 else self.fmu.getReal
        return np.array(get([self.vr[n] for n in names]))

    def step(self, h: float) -> None:
        self.fmu.doStep(currentCommunicationPoint=self.time, communicationStepSize=h)
        self.time += h

    def close(self) -> None:
        self.fmu.terminate()
        self.fmu.freeInstance()


def run_fmu(path, m: soadyn.Model, steps: list[Step]) -> FmuRun:
    """The FMU at `path` (of model m) through `steps`: the state and forces at every communication point."""
    session = FmuSession(path)
    q_names = [f"q.{c}" for c in m.coordinate_names]
    v_names = [f"v.{d}" for d in m.dof_names]
    tau_names = [f"tau.{d}" for d in m.dof_names]
    lockable = {d for d in m.dof_names if f"locked.{d}" in session.vr}
    sourceable = {d for d in m.dof_names if f"prescribed.{d}" in session.vr}
    model_prescribed = {d for d, p in zip(m.dof_names, m.prescribed) if p}
    t, q, v, tau = [0.0], [session.reals(q_names)], [session.reals(v_names)], []
    for step in steps:
        prescribed = model_prescribed if step.prescribed is None else step.prescribed
        for dof in m.dof_names:
            session.set_real(f"u.{dof}", step.inputs.get(dof, 0.0))
        for dof in lockable:
            session.set_bool(f"locked.{dof}", dof in step.locked)
        for dof in sourceable:
            session.set_bool(f"prescribed.{dof}", dof in prescribed)
        for body, wrench in step.wrenches.items():
            for name, value in zip(WRENCH_COMPONENTS, wrench):
                session.set_real(f"wrench.{body}.{name}", value)
        session.step(step.h)
        t.append(session.time)
        q.append(session.reals(q_names))
        v.append(session.reals(v_names))
        tau.append(session.reals(tau_names))
    session.close()
    return FmuRun(np.array(t), np.array(q), np.array(v), np.array(tau))


WRENCH_COMPONENTS = ("tx", "ty", "tz", "fx", "fy", "fz")


def input_source(kind: str, u: float, q: float, v: float, t: float, horizon: float) -> soadyn.MotionSource:
    """The motion a prescribed DOF at (q, v) follows over `horizon` from its input u of `kind` (embed::Plant)."""
    if kind == "acceleration":
        return soadyn.MotionSource.constant_acceleration(u, v, q, t)
    if kind == "velocity":
        return soadyn.MotionSource.constant_acceleration((u - v) / horizon, v, q, t)
    mean_rate = (u - q) / horizon  # position: the cubic Hermite to (u, mean_rate)
    a, jerk = 4.0 * (mean_rate - v) / horizon, 6.0 * (v - mean_rate) / (horizon * horizon)
    if jerk == 0.0:
        return soadyn.MotionSource.constant_acceleration(a, v, q, t)
    return soadyn.MotionSource.polynomial([q, v, a / 2.0, jerk / 6.0], t)


def run_reference(m: soadyn.Model, dt: float, q0, v0, steps: list[Step], integrator: str = "rk4",
                  input_kinds: dict | None = None) -> FmuRun:
    """The same scenario on soadyn.Simulator (`integrator`, internal step dt)."""
    regular = m.copy()
    regular.set_prescribed([False] * m.nv)
    sim = soadyn.Simulator(regular, dt=dt, integrator=integrator)
    sim.set_state(np.asarray(q0, float), np.asarray(v0, float))
    model_prescribed = {d for d, p in zip(m.dof_names, m.prescribed) if p}
    coordinate = {d: m.coordinate_names.index(d) for d in m.dof_names if d in m.coordinate_names}
    locked_now: set = set()
    t, q, v = [0.0], [sim.q], [sim.v]
    for step in steps:
        prescribed = model_prescribed if step.prescribed is None else step.prescribed
        for k, dof in enumerate(m.dof_names):
            u = step.inputs.get(dof, 0.0)
            if dof in step.locked:
                if dof not in locked_now:
                    sim.lock(dof)
                    locked_now.add(dof)
            elif dof in prescribed and dof in coordinate:
                locked_now.discard(dof)
                horizon = round(step.h / dt) * dt
                kind = (input_kinds or {}).get(dof, "acceleration")
                sim.prescribe(dof, input_source(kind, u, sim.q[coordinate[dof]], sim.v[k], sim.time, horizon))
            else:
                if sim.prescribed[k]:
                    sim.release(dof)
                locked_now.discard(dof)
                sim.set_input(dof, u)
        for body, wrench in step.wrenches.items():
            sim.set_external_wrench(body, wrench)
        sim.run(step.h)
        t.append(sim.time)
        q.append(sim.q)
        v.append(sim.v)
    return FmuRun(np.array(t), np.array(q), np.array(v), None)
