"""A Python motion source that raises inside the HIL loop, and a report whose
end-of-run measurements fail: the runner is usable afterwards and the report
keeps what was measured."""
import json
import threading

import numpy as np
import pytest

import soadyn
from soadyn import MotionSource, Simulator, scenes
from soadyn.hil import HilRunner, format_table, run_hil


def raising_after(t_fail):
    def fn(t):
        if t >= t_fail:
            raise ZeroDivisionError(f"source failed at t = {t:g}")
        return (0.0, 0.0, 0.0)
    return fn


def held_chain(t_fail):
    m = scenes.pendulum_chain(2)
    sim = Simulator(m, 1e-3, "euler")  # one source sample per step, at the step's end time
    sim.prescribe("link_1", MotionSource.function(raising_after(t_fail)))
    return m, sim


def test_a_raising_source_propagates_and_the_runner_is_not_left_running():
    _, sim = held_chain(0.0055)
    runner = HilRunner(sim, 1000.0, 100, as_fast_as_possible=True, record_every=1)
    with pytest.raises(soadyn.DynamicsError, match="link_1") as raised:  # as Simulator.step raises it
        runner.run()
    assert isinstance(raised.value.__cause__, ZeroDivisionError) and "source failed" in str(raised.value.__cause__)
    s = runner.summary()  # used to fail: "the HIL runner is running"
    assert s.status == "exception in a step" and s.exception_step == s.steps
    assert 1 <= s.steps < 100 and not s.stopped
    t, q, _ = runner.trajectory()  # the start and every completed step
    assert len(runner.compute_ns) == s.steps and len(t) == s.steps + 1 and np.isfinite(q).all()
    with pytest.raises(soadyn.DynamicsError):  # the runner can be run again (and fails the same way)
        runner.run()
    assert runner.summary().exception_step == 0


def test_run_hil_reports_a_raising_source():
    _, sim = held_chain(0.0055)
    report = run_hil(sim, 1000.0, 0.1, progress=False, realtime=False)
    assert not report.ok and report.status == "exception in a step"
    assert report.failed_step == report.steps and 1 <= report.steps < 100
    assert report.error.startswith("DynamicsError: ") and "caused by ZeroDivisionError: source failed at t = " in report.error
    assert isinstance(report.exception, soadyn.DynamicsError) and isinstance(report.exception.__cause__, ZeroDivisionError)
    assert len(report.compute_ns) == report.steps
    data = json.loads(report.to_json())
    assert data["status"] == "exception in a step" and data["error"] == report.error
    assert "ZeroDivisionError" in format_table(report).splitlines()[-1]


def test_a_report_whose_end_measurements_fail_keeps_what_was_measured(monkeypatch):
    """The energy and momentum at the end cannot be measured (the calls that
    measure them raise after the run): the report says so instead of being lost."""
    m = scenes.pendulum_chain(2)
    sim = Simulator(m, 1e-3, "euler")
    measured = []

    def kinetic_energy(model, q, v):
        measured.append(q)
        if len(measured) > 1:
            raise soadyn.DynamicsError("kinetic_energy is not finite: body 'link_2' ...")
        return 0.0

    def momentum(model, q, v):
        if len(measured) > 1:
            raise soadyn.DynamicsError("momentum is not finite: body 'link_2' ...")
        return np.zeros(6)

    monkeypatch.setattr(soadyn.hil.core, "kinetic_energy", kinetic_energy)
    monkeypatch.setattr(soadyn.hil.core, "momentum", momentum)
    report = run_hil(sim, 1000.0, 0.05, progress=False, realtime=False)
    assert report.ok and report.steps == 50
    assert report.energy["start"] is not None and report.energy["end"] is None
    assert report.momentum["end"] is None
    assert [e.split(":")[0] for e in report.report_errors] == ["energy at end", "momentum at end"]
    table = format_table(report)
    assert "not measured (see report_errors)" in table
    data = json.loads(report.to_json())
    assert data["energy"]["end"] is None and len(data["report_errors"]) == 2


def test_the_simulator_keeps_its_own_model():
    """Changing the model after the simulator was built changes neither its
    names nor the energies a HIL report measures."""
    m = scenes.pendulum_chain(2)
    sim = Simulator(m, 1e-3)
    m.add_body("extra", "link_2", soadyn.Joint.revolute([1, 0, 0]), mass=1.0, inertia=[0.1, 0.1, 0.1])
    m.gravity = [0.0, 0.0, 0.0]
    sim.set_input("link_2", 0.5)
    with pytest.raises(ValueError, match="extra"):
        sim.set_input("extra", 0.5)
    report = run_hil(sim, 1000.0, 0.01, progress=False, realtime=False)
    assert report.ok and not report.report_errors
    assert report.energy["start"] == pytest.approx(soadyn.potential_energy(scenes.pendulum_chain(2), np.zeros(2)))


def test_non_finite_report_values_become_null_in_strict_json():
    m = scenes.pendulum_chain(2)
    sim = Simulator(m, 1e-3)
    report = run_hil(sim, 1000.0, 0.01, progress=False, realtime=False, command_limits=float("inf"))
    assert report.commands["limits"] == {"link_1": float("inf"), "link_2": float("inf")}
    data = json.loads(report.to_json())  # allow_nan=False: would raise on inf
    assert data["commands"]["limits"] == {"link_1": None, "link_2": None}


def test_summary_while_running_is_refused_by_name():
    m = scenes.pendulum_chain(2)
    sim = Simulator(m, 1e-3)
    runner = HilRunner(sim, 1000.0, 10**6)
    worker = threading.Thread(target=runner.run)
    worker.start()
    try:
        while runner.steps_done < 5:
            pass
        with pytest.raises(RuntimeError, match="summary: the HIL runner is running"):
            runner.summary()
        for name in ("cpu_ns", "floor_ns", "dynamics_floor_ns"):  # the per-step and per-period arrays too
            with pytest.raises(RuntimeError, match=f"{name}: the HIL runner is running"):
                getattr(runner, name)
    finally:
        runner.request_stop()
        worker.join(60)
    assert runner.summary().stopped and np.isfinite(sim.q).all()
