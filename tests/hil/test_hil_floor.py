"""The machine's floor in a HIL report, and deadline misses split by cause.

After a paced run the runner times register arithmetic calibrated to the
steps' median compute time, paced like the steps (HilRunner, hil_runner.hpp):
the report's `floor_us` gives its percentiles and the ratio of the step's
p99.9 to the floor's. Misses are split into "compute" (the step's own compute
exceeded the period) and "machine" (woken or run late). Values are not judged
here (they are the machine's); their consistency and the classification are.
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


def test_a_paced_run_reports_the_floor_it_measured():
    report = run_hil(chain(), 1000.0, 0.2, progress=False)
    floor = report.floor_us
    assert report.ok and floor["periods"] == 200 and len(report.floor_ns) == 200
    compute = np.sort(report.compute_ns)
    assert floor["target"] == pytest.approx(compute[100] * 1e-3)  # the median step (all 200 sampled)
    ns = np.sort(report.floor_ns)
    for key, p in (("p50", 0.5), ("p99", 0.99), ("p999", 0.999), ("max", 1.0)):
        assert floor[key] == pytest.approx(nearest_rank(ns, p))
    assert floor["tail_ratio"] == pytest.approx(report.compute_us["p999"] / floor["p999"])
    assert report.misses["compute"] + report.misses["machine"] == report.deadline_misses
    assert "machine   us" in format_table(report) and "step p99.9 / floor p99.9" in format_table(report)
    assert report.to_dict()["floor_us"]["periods"] == 200


def test_no_floor_when_unpaced_or_asked_for_none():
    assert run_hil(chain(), 1000.0, 0.05, progress=False, realtime=False).floor_us is None
    report = run_hil(chain(), 1000.0, 0.05, progress=False, floor_periods=0)
    assert report.floor_us is None and report.floor_ns is None
    assert run_hil(chain(), 1000.0, 0.05, progress=False, floor_periods=30).floor_us["periods"] == 30
    with pytest.raises(ValueError, match="floor_periods"):
        run_hil(chain(), 1000.0, 0.05, progress=False, floor_periods=-1)


def test_a_step_slower_than_the_period_is_a_compute_miss():
    sim = chain()

    def slow(t):  # each step's source samples sleep: the step's own compute exceeds 1 ms
        time.sleep(0.0015)
        return 0.0, 0.0, 0.0

    sim.prescribe("link_1", MotionSource.function(slow))
    report = run_hil(sim, 1000.0, 0.02, progress=False, floor_periods=0)
    assert report.ok and report.deadline_misses == 20
    assert report.misses == {"compute": 20, "machine": 0}
    assert "20 compute overran the period" in format_table(report)


def test_cli_floor_periods_is_checked():
    result = subprocess.run([sys.executable, "-m", "soadyn", "hil", "--scene", "pendulum-chain", "--duration", "0.1",
                             "--floor-periods", "-5", "--no-progress"], capture_output=True, text=True, timeout=120)
    assert result.returncode == 2 and "--floor-periods" in result.stderr and "Traceback" not in result.stderr


def test_a_backlog_of_our_own_is_not_blamed_on_the_machine():
    sim = chain()
    calls = []

    def first_step_slow(t):  # step 0's new sample (t = 0.5 ms; t = 0 was taken by prescribe, before the
        if t < 0.0006:       # run) takes 9 ms: it misses, and the steps that catch up after it start late
            time.sleep(0.009)
        return 0.0, 0.0, 0.0

    sim.prescribe("link_1", MotionSource.function(first_step_slow))
    report = run_hil(sim, 1000.0, 0.02, progress=False, floor_periods=0)
    assert report.ok and report.misses["compute"] >= 2
    assert report.misses["compute"] + report.misses["machine"] == report.deadline_misses


def test_no_floor_after_a_failed_run_and_the_buffer_is_bounded_by_the_steps():
    sim = chain()
    sim.prescribe("link_1", MotionSource.function(lambda t: (float("nan") if t > 0.004 else 0.0, 0.0, 0.0)))
    failed = run_hil(sim, 1000.0, 0.05, progress=False)
    assert not failed.ok and failed.floor_us is None
    report = run_hil(chain(), 1000.0, 0.03, progress=False, floor_periods=10**8)  # kept: one per step
    assert report.floor_us["periods"] == 30
