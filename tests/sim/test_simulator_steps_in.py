"""Simulator.steps_in: a step count no run could take (a subnormal dt makes it infinite) is a
ValueError naming the duration and dt, never an OverflowError."""
import pytest

from soadyn import scenes
from soadyn.simulator import MAX_RUN_STEPS, Simulator


@pytest.mark.parametrize("dt, duration, fragment", [
    (5e-324, 1.0, "duration 1.0 s is inf steps of dt = 5e-324 s"),
    (1e-300, 1e300, "duration 1e+300 s is inf steps of dt = 1e-300 s"),
    (1e-3, 1e12, "duration 1000000000000.0 s is 1e+15 steps of dt = 0.001 s"),
])
def test_too_many_steps_is_a_value_error_naming_duration_and_dt(dt, duration, fragment):
    sim = Simulator(scenes.pendulum_chain(2), dt)
    for call in (sim.steps_in, sim.run):
        with pytest.raises(ValueError) as error:
            call(duration)
        assert str(error.value).startswith(fragment)
        assert f"at most {MAX_RUN_STEPS} per call" in str(error.value)
    assert sim.time == 0.0 and sim.steps_taken == 0


def test_the_largest_run_is_still_counted():
    sim = Simulator(scenes.pendulum_chain(2), 1.0)
    assert sim.steps_in(float(MAX_RUN_STEPS)) == MAX_RUN_STEPS
    with pytest.raises(ValueError, match="run in pieces"):
        sim.steps_in(float(MAX_RUN_STEPS + 1))
