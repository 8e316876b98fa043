"""Watching a HIL run: the runner's latest-state snapshot, run_hil's on_state and `soadyn hil --view`.

The loop publishes (step, t, q, v) into a sequence-locked snapshot after every
step (cpp/include/soadyn/realtime/state_snapshot.hpp; its allocation-free,
tear-free publication under a concurrent reader is proved by
tests/cpp/test_sim_no_allocation.cpp). Here: what a reader gets is a state
the simulation really passed through, the last one is the final state, a
failing reader never disturbs the run, and the viewer shows the run's state.
"""
from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import soadyn
from soadyn import Simulator, scenes
from soadyn.hil import HilRunner, run_hil, scene_simulator
from soadyn.viewer import Viewer, flexible_shapes

TIMEOUT = 120


def chain(dt=1e-3):
    m = scenes.pendulum_chain(4)
    sim = Simulator(m, dt, "rk4")
    sim.set_state(np.full(m.nq, 0.3), np.zeros(m.nv))
    return m, sim


def test_latest_state_is_none_before_a_run_and_the_final_state_after():
    _, sim = chain()
    runner = HilRunner(sim, 1000.0, 50, as_fast_as_possible=True)
    assert runner.latest_state() is None
    runner.run()
    step, t, q, v = runner.latest_state()
    assert step == 50 and t == sim.time
    assert np.array_equal(q, sim.q) and np.array_equal(v, sim.v)


def test_on_state_sees_states_the_run_passed_through_ending_with_the_final_one():
    m, sim = chain()
    _, reference = chain()
    states = []
    report = run_hil(sim, 1000.0, 0.4, progress=False, on_state=lambda *state: states.append(state),
                     state_interval=0.02)
    assert report.ok and report.report_errors == []
    steps = [s[0] for s in states]
    assert len(states) >= 5 and steps == sorted(set(steps))  # a paced 0.4 s run at 50 Hz: new states only
    assert steps[-1] == 400 and np.array_equal(states[-1][2], sim.q) and np.array_equal(states[-1][3], sim.v)
    by_step = {s[0]: s for s in states}
    for k in range(1, 401):  # replay the same steps: every state seen is the state after its step
        reference.step()
        if k in by_step:
            _, t, q, v = by_step[k]
            assert t == pytest.approx(k * 1e-3, abs=1e-12)
            assert np.array_equal(q, reference.q) and np.array_equal(v, reference.v)


def test_a_failing_on_state_is_named_and_the_run_goes_on():
    _, sim = chain()
    calls = []

    def broken(step, t, q, v):
        calls.append(step)
        raise RuntimeError("display unplugged")

    report = run_hil(sim, 1000.0, 0.2, progress=False, on_state=broken, state_interval=0.01)
    assert report.ok and report.steps == 200 and len(calls) == 1
    assert len(report.report_errors) == 1
    assert "on_state" in report.report_errors[0] and "display unplugged" in report.report_errors[0]
    with pytest.raises(ValueError, match="state_interval"):
        run_hil(sim, 1000.0, 0.1, progress=False, on_state=print, state_interval=0.0)


def test_viewer_follows_a_cassini_run_with_its_booms_deformed():
    sim = scene_simulator("cassini", 500.0)
    m = sim._model
    viewer = Viewer(m, port=0, q=sim.q, exaggeration=200.0)
    try:
        report = run_hil(sim, 500.0, 0.3, progress=False, on_state=lambda step, t, q, v: viewer.show(q))
        assert report.ok and report.report_errors == []
        assert np.array_equal(viewer.q, sim.q)  # the final state is shown
        for name, nodes in flexible_shapes(m, sim.q, 200.0).items():
            assert np.abs(np.asarray(viewer.handles[f"/flexible/{name}/nodes"].points) - nodes).max() <= 1e-5
    finally:
        viewer.close()


def test_cli_hil_view_serves_the_run_and_exits():
    result = subprocess.run(
        [sys.executable, "-m", "soadyn", "hil", "--scene", "cassini", "--rate", "200", "--duration", "0.3",
         "--view", "--view-port", "0", "--view-exaggeration", "50", "--no-progress"],
        capture_output=True, text=True, timeout=TIMEOUT)
    assert result.returncode == 0, result.stderr
    assert "viewer at http://127.0.0.1:" in result.stdout and "deadline misses" in result.stdout


@pytest.mark.parametrize("option, value, culprit", [
    ("--view-port", "70000", "--view-port"),
    ("--view-exaggeration", "-3", "--view-exaggeration"),
    ("--view-exaggeration", "nan", "--view-exaggeration"),
])
def test_cli_hil_view_rejects_bad_options(option, value, culprit):
    result = subprocess.run([sys.executable, "-m", "soadyn", "hil", "--scene", "pendulum-chain", "--duration", "0.1",
                             "--view", option, value, "--no-progress"], capture_output=True, text=True,
                            timeout=TIMEOUT)
    assert result.returncode == 2
    assert culprit in result.stderr and "Traceback" not in result.stderr
