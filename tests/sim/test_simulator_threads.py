"""Simulator calls from several Python threads: each call holds the simulator's lock,
so concurrent calls run one after another and give the results of some serial order."""
import threading
import time

import numpy as np
import pytest

from soadyn import DynamicsError, MotionSource, Simulator, scenes

RACE_SECONDS = 2.0


def run_threads(*targets):
    """Runs the targets in threads; returns the exceptions they raised."""
    errors = []

    def guarded(target):
        try:
            target()
        except BaseException as e:  # noqa: BLE001 - reported to the test
            errors.append(e)

    threads = [threading.Thread(target=guarded, args=(t,)) for t in targets]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=120)
        assert not t.is_alive(), "a thread hung"
    return errors


def test_prescribe_while_running_equals_the_same_calls_in_one_thread():
    """Each prescribe samples its source once on the prescribing thread, under the
    simulator's lock, at the simulator's time: that sample logs when it took effect."""
    m = scenes.pendulum_chain(3)
    sim = Simulator(m, 1e-3, "rk4")
    sim.set_state(np.full(3, 0.2), np.zeros(3))
    log, steps_run = [], []
    prescriber = {}

    def source(k):
        rate = 0.5 if k % 2 else -0.5

        def fn(t):
            if threading.get_ident() == prescriber.get("id"):
                log.append((t, k))
            return (rate * t, rate, 0.0)
        return fn

    stop = time.monotonic() + RACE_SECONDS

    def runner():
        while time.monotonic() < stop:
            steps_run.append(len(sim.run(0.01).t) - 1)

    def prescribe_loop():
        prescriber["id"] = threading.get_ident()
        k = 0
        while time.monotonic() < stop:
            sim.prescribe("link_2", MotionSource.function(source(k)))
            k += 1
            time.sleep(0.001)

    assert run_threads(runner, prescribe_loop) == []
    assert sum(steps_run) == sim.steps_taken == 10 * len(steps_run) > 0
    assert len(log) > 10

    replay = Simulator(m, 1e-3, "rk4")
    replay.set_state(np.full(3, 0.2), np.zeros(3))
    prescriber["id"] = None  # the replay logs nothing
    for t, k in log:
        while replay.time < t:
            replay.step()
        assert replay.time == t
        replay.prescribe("link_2", MotionSource.function(source(k)))
    while replay.steps_taken < sim.steps_taken:
        replay.step()
    np.testing.assert_array_equal(replay.q, sim.q)
    np.testing.assert_array_equal(replay.v, sim.v)
    assert replay.time == sim.time


def test_prescribe_and_release_of_cpp_sources_while_running():
    """C++ sources swapped while another thread runs (this crashed before the simulator had a lock)."""
    m = scenes.pendulum_chain(4)
    sim = Simulator(m, 1e-3, "rk4")
    sim.set_state(np.full(4, 0.3), np.zeros(4))
    steps_run, swaps = [], []
    stop = time.monotonic() + RACE_SECONDS

    def runner():
        while time.monotonic() < stop:
            steps_run.append(len(sim.run(0.02).t) - 1)

    def swapper():
        k = 0
        while time.monotonic() < stop:
            sim.prescribe("link_3", MotionSource.constant_velocity(0.25 * (k % 3)))
            if k % 4 == 3:
                sim.release("link_3")
            sim.set_input("link_1", 0.1 * (k % 5))
            k += 1
        sim.prescribe("link_3", MotionSource.constant_velocity(0.75))
        swaps.append(k)

    assert run_threads(runner, swapper) == []
    assert sum(steps_run) == sim.steps_taken == 20 * len(steps_run) > 0 and swaps[0] > 10
    assert np.all(np.isfinite(sim.q)) and np.all(np.isfinite(sim.v))
    assert sim.v[m.dof_index("link_3")] == 0.75 and sim.prescribed[m.dof_index("link_3")]


@pytest.mark.parametrize("integrator", ["rk4", "dopri5"])
def test_two_threads_stepping_lose_no_step(integrator):
    m = scenes.pendulum_chain(30)  # above the size where the model's calls release the GIL
    sim = Simulator(m, 1e-3, integrator)
    q0 = np.full(m.nq, 0.05)
    sim.set_state(q0, np.zeros(m.nv))
    counts = [0, 0]
    stop = time.monotonic() + RACE_SECONDS

    def stepper(i):
        def loop():
            while time.monotonic() < stop:
                sim.step()
                counts[i] += 1
        return loop

    def reader():
        while time.monotonic() < stop:
            q, v, t = sim.q, sim.v, sim.time
            assert np.all(np.isfinite(q)) and np.all(np.isfinite(v)) and t >= 0

    assert run_threads(stepper(0), stepper(1), reader) == []
    assert sim.steps_taken == sum(counts) and min(counts) > 0
    replay = Simulator(m, 1e-3, integrator)
    replay.set_state(q0, np.zeros(m.nv))
    replay.run(sum(counts) * 1e-3)
    np.testing.assert_array_equal(replay.q, sim.q)
    np.testing.assert_array_equal(replay.v, sim.v)
    assert replay.time == sim.time


def test_a_source_calling_its_own_simulator_is_refused_not_deadlocked():
    sim = Simulator(scenes.pendulum_chain(2), 1e-3)
    sim.prescribe("link_1", MotionSource.constant_velocity(0.0))
    sim.prescribe("link_2", MotionSource.function(lambda t: (sim.time, 1.0, 0.0) if t > 0 else (0.0, 1.0, 0.0)))
    with pytest.raises(DynamicsError, match="DOF 'link_2'") as info:
        sim.step()
    assert isinstance(info.value.__cause__, RuntimeError)
    assert "in use by this thread" in str(info.value.__cause__)
    assert sim.steps_taken == 0
