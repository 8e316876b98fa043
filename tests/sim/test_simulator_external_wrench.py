"""Simulator.set_external_wrench: the wrench enters the dynamics as forward_dynamics' f_ext, and hostile
arguments are refused by name with the simulator unchanged."""
from __future__ import annotations

import threading

import numpy as np
import pytest

import soadyn


def test_a_wrench_gives_the_accelerations_forward_dynamics_gives_with_it():
    m = soadyn.scenes.pendulum_chain(3)
    q, v = np.array([0.3, -0.5, 0.2]), np.array([0.1, 0.0, -0.4])
    wrench = np.array([0.2, -0.1, 0.3, 1.5, -2.0, 0.7])
    f_ext = np.zeros((m.nbodies, 6))
    f_ext[m.body_index("link_2")] = wrench
    sim = soadyn.Simulator(m, dt=1e-3, integrator="euler")  # one semi-implicit step: v1 = v0 + dt qdd
    sim.set_state(q, v)
    sim.set_external_wrench("link_2", wrench)
    assert np.array_equal(sim.external_wrenches, f_ext)
    sim.step()
    qdd = soadyn.forward_dynamics(m, q, v, np.zeros(m.nv), f_ext)
    np.testing.assert_allclose((sim.v - v) / 1e-3, qdd, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("body, wrench, message", [
    ("nowhere", np.zeros(6), "body 'nowhere' is not a body of the model"),
    (7, np.zeros(6), "body 7 is not a body of the model"),
    ("link_1", np.zeros(5), "wrench"),
    ("link_1", [0, 0, float("nan"), 0, 0, 0], "wrench"),
    ("link_1", [0, 0, 0, float("inf"), 0, 0], "wrench"),
])
def test_a_bad_body_or_wrench_is_refused_by_name(body, wrench, message):
    sim = soadyn.Simulator(soadyn.scenes.pendulum_chain(2), dt=1e-3)
    with pytest.raises(ValueError, match=message):
        sim.set_external_wrench(body, wrench)
    assert not sim.external_wrenches.any()


def test_wrenches_set_from_another_thread_during_a_run_wait_for_it():
    sim = soadyn.Simulator(soadyn.scenes.pendulum_chain(2), dt=1e-3)
    errors = []

    def setter():
        try:
            for k in range(200):
                sim.set_external_wrench("link_1", [0.01 * k, 0, 0, 0, 0, 0])
        except Exception as error:  # noqa: BLE001 - reported below
            errors.append(error)

    thread = threading.Thread(target=setter)
    thread.start()
    sim.run(0.2)
    thread.join()
    assert not errors and sim.external_wrenches[0, 0] == pytest.approx(1.99)
    assert np.all(np.isfinite(sim.q))
