"""A HIL run and Python threads calling the simulator it steps: the run holds
the simulator's lock, so other calls wait for it and no step is lost or
interleaved with the loop's; a second run() of a running runner is refused."""
import threading

import numpy as np
import pytest

from soadyn import Simulator, scenes
from soadyn.hil import HilRunner

STEPS = 3000


def test_steps_from_another_thread_wait_for_the_run_and_none_is_lost():
    sim = Simulator(scenes.pendulum_chain(5), 1e-3)
    sim.set_state(np.full(5, 0.3), np.zeros(5))
    reference = Simulator(scenes.pendulum_chain(5), 1e-3)
    reference.set_state(np.full(5, 0.3), np.zeros(5))
    runner = HilRunner(sim, 1000.0, STEPS, as_fast_as_possible=True)
    started = threading.Event()
    extra = []

    def stepper():
        started.wait()
        for _ in range(200):
            sim.step()
            extra.append(sim.time)

    thread = threading.Thread(target=stepper)
    thread.start()
    started.set()
    runner.run()
    thread.join()
    assert runner.summary().steps == STEPS and len(extra) == 200
    for _ in range(STEPS + 200):  # the same number of steps, one after another
        reference.step()
    assert sim.time == pytest.approx(reference.time, abs=1e-12)
    np.testing.assert_array_equal(sim.q, reference.q)
    np.testing.assert_array_equal(sim.v, reference.v)


def test_a_second_run_of_a_running_runner_is_refused():
    sim = Simulator(scenes.pendulum_chain(3), 1e-3)
    runner = HilRunner(sim, 1000.0, 300, as_fast_as_possible=False)  # paced: 0.3 s
    errors = []
    thread = threading.Thread(target=runner.run)
    thread.start()
    while runner.steps_done == 0:
        pass
    try:
        runner.run()
    except RuntimeError as e:
        errors.append(str(e))
    thread.join()
    assert errors and "already running" in errors[0]
    assert runner.summary().steps == 300
