"""A HIL run and Python threads calling the simulator it steps: the run holds
the simulator's lock for its whole length, so another thread's call waits
until the run has ended, and nothing interleaves with the loop's steps; a
second run() of a running runner is refused."""
import threading
import time

import numpy as np
import pytest

from soadyn import Simulator, scenes
from soadyn.hil import HilRunner

STEPS = 1000  # paced at 1 kHz: 1 s


def wait_for_first_step(runner, thread, timeout=30.0):
    deadline = time.monotonic() + timeout
    while runner.steps_done == 0:
        assert thread.is_alive() and time.monotonic() < deadline, "the run did not start"
        time.sleep(0.0005)


def test_a_step_from_another_thread_waits_for_the_whole_run():
    sim = Simulator(scenes.pendulum_chain(5), 1e-3)
    sim.set_state(np.full(5, 0.3), np.zeros(5))
    runner = HilRunner(sim, 1000.0, STEPS)
    thread = threading.Thread(target=runner.run)
    thread.start()
    wait_for_first_step(runner, thread)
    sim.step()  # started during the run: must not run before the run has ended
    done_when_our_step_ran = runner.steps_done
    thread.join()
    assert done_when_our_step_ran == STEPS and runner.summary().steps == STEPS
    reference = Simulator(scenes.pendulum_chain(5), 1e-3)
    reference.set_state(np.full(5, 0.3), np.zeros(5))
    for _ in range(STEPS + 1):  # the run's steps, then ours: one after another
        reference.step()
    assert sim.time == pytest.approx(reference.time, abs=1e-12)
    np.testing.assert_array_equal(sim.q, reference.q)
    np.testing.assert_array_equal(sim.v, reference.v)


def test_a_second_run_of_a_running_runner_is_refused():
    sim = Simulator(scenes.pendulum_chain(3), 1e-3)
    runner = HilRunner(sim, 1000.0, STEPS)
    thread = threading.Thread(target=runner.run)
    thread.start()
    wait_for_first_step(runner, thread)
    with pytest.raises(RuntimeError, match="already running"):
        runner.run()
    thread.join()
    assert runner.summary().steps == STEPS
