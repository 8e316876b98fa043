"""The cache warm-up of a spinning HIL loop (HilRunner::set_warm_up): an evaluation of the dynamics shortly
before each deadline that changes nothing the step reads. The run's states are the same bit for bit with and
without it, on a model with a prescribed DOF following a source, a flexible body and a loop."""
from __future__ import annotations

import numpy as np
import pytest

from soadyn import MotionSource, Simulator, scenes
from soadyn.hil import format_table, run_hil


def cassini():
    sim = Simulator(scenes.cassini(), 1e-3, "rk4")
    scenes.drive_cassini(sim)
    return sim


def four_bar():
    m = scenes.four_bar()
    sim = Simulator(m, 1e-3, "rk4")
    q, v = scenes.four_bar_state(0.7, 1.0)
    sim.set_state(q, v)
    return sim


def chain_with_a_source():
    sim = Simulator(scenes.pendulum_chain(3), 1e-3, "rk4")
    sim.set_state(np.full(3, 0.3), np.zeros(3))
    sim.prescribe("link_2", MotionSource.cycloidal(0.0, 0.5, 0.0, 0.04))
    return sim


@pytest.mark.parametrize("make", [cassini, four_bar, chain_with_a_source])
def test_the_warm_up_changes_nothing_the_steps_compute(make):
    runs = {}
    for warm_up in (True, False):
        sim = make()
        report = run_hil(sim, 1000.0, 0.06, progress=False, spin_us=400.0, warm_up=warm_up, floor_periods=0)
        assert report.ok and report.scheduling["warm_up"] is warm_up
        runs[warm_up] = (sim.q, sim.v, report.q)
    assert all(np.array_equal(a, b) for a, b in zip(runs[True], runs[False]))


def test_the_warm_up_needs_a_spin_window():
    report = run_hil(cassini(), 1000.0, 0.02, progress=False, floor_periods=0)  # sleeping: nothing to warm in
    assert report.scheduling["warm_up"] is False
    spinning = run_hil(cassini(), 1000.0, 0.02, progress=False, floor_periods=0, spin_us=300.0)
    assert spinning.scheduling["warm_up"] is True and "caches warmed before each deadline" in format_table(spinning)
