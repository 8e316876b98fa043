"""The machine's floor in a HIL report, the step's own CPU time, and deadline misses split by cause.

The runner times, beside each step's wall time, the loop thread's own CPU time and its involuntary context
switches, and register arithmetic calibrated to the first steps' median compute time, paced like the steps:
interleaved at the midpoint of the steps' own periods (the default) or after the run (HilRunner,
hil_runner.hpp), and in the same periods the dynamics floor (evaluations of the dynamics at the present state
of about the same length). The report's `floor_us` gives their percentiles and the ratios of the step's p99.9
to the floors'; `cpu_us` the CPU time's. Misses are split into "compute" (ours: the step's own CPU time exceeded the
period, or our own backlog) and "machine" (woken or run late, or pre-empted). Values are not judged here (they
are the machine's); their consistency and the classification are.
"""
from __future__ import annotations

import subprocess
import sys
import time

import numpy as np
import pytest

from soadyn import MotionSource, Simulator, scenes
from soadyn.hil import format_table, run_hil


def chain():
    m = scenes.pendulum_chain(3)
    sim = Simulator(m, 1e-3, "rk4")
    sim.set_state(np.full(m.nq, 0.3), np.zeros(m.nv))
    return sim


def nearest_rank(sorted_ns, p):
    return sorted_ns[max(int(np.ceil(p * len(sorted_ns))), 1) - 1] * 1e-3


def assert_percentiles(values_ns, summary_us):
    ns = np.sort(values_ns)
    for key, p in (("p50", 0.5), ("p99", 0.99), ("p999", 0.999), ("max", 1.0)):
        assert summary_us[key] == pytest.approx(nearest_rank(ns, p))


def test_an_interleaved_floor_is_timed_in_the_steps_own_periods():
    report = run_hil(chain(), 1000.0, 0.2, progress=False)
    floor = report.floor_us
    # The first tenth of the 200 steps sets the length; then at most one floor period per step, from the period
    # of the 20th step on.
    assert report.ok and floor["mode"] == "interleaved" and 0 < floor["periods"] <= 181
    assert len(report.floor_ns) == floor["periods"]
    assert floor["target"] == pytest.approx(np.sort(report.compute_ns[:20])[10] * 1e-3)
    assert_percentiles(report.floor_ns, floor)
    assert floor["tail_ratio"] == pytest.approx(report.compute_us["p999"] / floor["p999"])
    assert report.misses["compute"] + report.misses["machine"] == report.deadline_misses
    table = format_table(report)
    assert "machine   us" in table and "floor, interleaved" in table and "step p99.9 / floor p99.9" in table
    assert report.to_dict()["floor_us"]["periods"] == floor["periods"]
    assert_dynamics_floor(report)


def assert_dynamics_floor(report):
    """The dynamics floor of the report's floor periods: one time per period, its percentiles and ratios."""
    floor = report.floor_us
    dynamics = floor["dynamics"]
    assert dynamics["evaluations"] >= 1 and len(report.dynamics_floor_ns) == floor["periods"]
    assert np.all(report.dynamics_floor_ns > 0)
    assert_percentiles(report.dynamics_floor_ns, dynamics)
    assert dynamics["spread"] == pytest.approx(dynamics["p999"] / dynamics["p50"])
    assert dynamics["tail_ratio"] == pytest.approx(report.compute_us["p999"] / dynamics["p999"])
    assert f"dynamics floor: {dynamics['evaluations']} evaluations" in format_table(report)
    assert report.to_dict()["floor_us"]["dynamics"] == dynamics


def test_an_after_run_floor_is_timed_over_as_many_periods_after_the_steps():
    report = run_hil(chain(), 1000.0, 0.2, progress=False, floor="after")
    floor = report.floor_us
    assert report.ok and floor["mode"] == "after" and floor["periods"] == 200 and len(report.floor_ns) == 200
    assert floor["target"] == pytest.approx(np.sort(report.compute_ns)[100] * 1e-3)  # the median step (all sampled)
    assert_percentiles(report.floor_ns, floor)
    assert_dynamics_floor(report)


@pytest.mark.parametrize("floor, spin_us", [("interleaved", 0.0), ("interleaved", 400.0), ("after", 400.0)])
def test_the_dynamics_floor_changes_nothing_the_steps_compute(floor, spin_us):
    """Its evaluations (at the present state, between steps) leave the run's states the same bit for bit as a
    run without a floor, on cassini (flexible booms, driven gimbals and wheels) and on a chain with a prescribed
    DOF following a source."""
    def cassini():
        sim = Simulator(scenes.cassini(), 1e-3, "rk4")
        scenes.drive_cassini(sim)
        return sim

    def chain_with_a_source():
        sim = chain()
        sim.prescribe("link_2", MotionSource.cycloidal(0.0, 0.5, 0.0, 0.04))
        return sim

    for make in (cassini, chain_with_a_source):
        runs = []
        for floor_periods in (None, 0):
            sim = make()
            report = run_hil(sim, 1000.0, 0.06, progress=False, spin_us=spin_us, floor=floor,
                             floor_periods=floor_periods)
            assert report.ok
            runs.append((sim.q, sim.v, report.q, report.v, report.floor_us))
        (q, v, rq, rv, timed), (q0, v0, rq0, rv0, untimed) = runs
        assert timed["periods"] > 0 and timed["dynamics"]["evaluations"] >= 1 and untimed is None
        assert np.array_equal(q, q0) and np.array_equal(v, v0)
        assert np.array_equal(rq, rq0) and np.array_equal(rv, rv0)


def test_the_steps_own_cpu_time_is_reported_beside_the_wall_time():
    report = run_hil(chain(), 1000.0, 0.1, progress=False)
    cpu, wall = report.cpu_ns, report.compute_ns
    assert len(cpu) == len(wall) == 100 and np.all(cpu > 0)
    assert np.all(cpu <= wall + 1000)  # the CPU clock reads inside the wall window (1 us: the clocks' reading)
    assert_percentiles(cpu, report.cpu_us)
    assert report.cpu_us["spread"] == pytest.approx(report.cpu_us["p999"] / report.cpu_us["p50"])
    assert report.preempted_steps >= 0 and report.involuntary_switches >= 0
    data = report.to_dict()
    assert {"cpu_us", "preempted_steps", "involuntary_switches"} <= set(data)
    assert "cpu       us" in format_table(report) and "pre-empted" in format_table(report)


def test_no_floor_when_unpaced_or_asked_for_none():
    assert run_hil(chain(), 1000.0, 0.05, progress=False, realtime=False).floor_us is None
    report = run_hil(chain(), 1000.0, 0.05, progress=False, floor_periods=0)
    assert report.floor_us is None and report.floor_ns is None and report.dynamics_floor_ns is None
    assert "dynamics floor" not in format_table(report)
    assert run_hil(chain(), 1000.0, 0.1, progress=False, floor_periods=30).floor_us["periods"] == 30
    assert run_hil(chain(), 1000.0, 0.05, progress=False, floor_periods=30, floor="after").floor_us["periods"] == 30
    with pytest.raises(ValueError, match="floor_periods"):
        run_hil(chain(), 1000.0, 0.05, progress=False, floor_periods=-1)
    with pytest.raises(ValueError, match="floor 'sometimes'"):
        run_hil(chain(), 1000.0, 0.05, progress=False, floor="sometimes")
    with pytest.raises(ValueError, match="preemption_margin_us"):
        run_hil(chain(), 1000.0, 0.05, progress=False, preemption_margin_us=-1.0)


def busy(seconds: float) -> None:
    """Spend `seconds` of this thread's CPU time."""
    start = time.thread_time()
    while time.thread_time() - start < seconds:
        pass


def test_a_step_whose_own_cpu_time_exceeds_the_period_is_our_miss():
    sim = chain()

    def slow(t):  # each step's source sample computes for 1.5 ms: the step's own CPU time exceeds 1 ms
        busy(0.0015)
        return 0.0, 0.0, 0.0

    sim.prescribe("link_1", MotionSource.function(slow))
    report = run_hil(sim, 1000.0, 0.02, progress=False, floor_periods=0)
    assert report.ok and report.deadline_misses == 20
    assert report.misses["compute"] == 20 and report.misses["machine"] == 0
    assert "20 ours: CPU time over the period" in format_table(report)


def test_a_step_that_waited_without_running_is_the_machines_miss():
    sim = chain()

    def stalled(t):  # each step is held up 1.5 ms without running (as a pre-empted thread is)
        time.sleep(0.0015)
        return 0.0, 0.0, 0.0

    sim.prescribe("link_1", MotionSource.function(stalled))
    report = run_hil(sim, 1000.0, 0.02, progress=False, floor_periods=0)
    assert report.ok and report.deadline_misses == 20
    assert report.misses == {"compute": 0, "machine": 20, "machine_preempted": 20}
    assert report.preempted_steps == 20 and np.all(report.compute_ns - report.cpu_ns > 1_000_000)


def test_cli_floor_periods_is_checked():
    result = subprocess.run([sys.executable, "-m", "soadyn", "hil", "--scene", "pendulum-chain", "--duration", "0.1",
                             "--floor-periods", "-5", "--no-progress"], capture_output=True, text=True, timeout=120)
    assert result.returncode == 2 and "--floor-periods" in result.stderr and "Traceback" not in result.stderr


def test_a_backlog_of_our_own_is_not_blamed_on_the_machine():
    sim = chain()
    calls = []

    def first_step_slow(t):  # step 0's new sample (t = 0.5 ms; t = 0 was taken by prescribe, before the
        if t < 0.0006:       # run) computes for 9 ms: it misses, and the steps that catch up after it start late
            busy(0.009)
        return 0.0, 0.0, 0.0

    sim.prescribe("link_1", MotionSource.function(first_step_slow))
    report = run_hil(sim, 1000.0, 0.02, progress=False, floor_periods=0)
    assert report.ok and report.misses["compute"] >= 2
    assert report.misses["compute"] + report.misses["machine"] == report.deadline_misses


def test_no_after_run_floor_after_a_failed_run_and_the_buffer_is_bounded_by_the_steps():
    def failing():
        sim = chain()
        sim.prescribe("link_1", MotionSource.function(lambda t: (float("nan") if t > 0.04 else 0.0, 0.0, 0.0)))
        return sim

    failed = run_hil(failing(), 1000.0, 0.05, progress=False, floor="after")
    assert not failed.ok and failed.floor_us is None
    interleaved = run_hil(failing(), 1000.0, 0.05, progress=False)  # the periods timed before the failure count
    assert not interleaved.ok and 0 < interleaved.floor_us["periods"] <= interleaved.steps
    report = run_hil(chain(), 1000.0, 0.03, progress=False, floor_periods=10**8, floor="after")  # one per step
    assert report.floor_us["periods"] == 30
