"""Simulator hardening: validated state and sources, a simulator unchanged by a failed call,
one error type per cause, run() durations, the event queue and dopri5's sub-step bound."""
import math

import numpy as np
import pytest

import soadyn
from soadyn import DynamicsError, MotionSource, Simulator, scenes
from support.bodies import tumbling_body


def ghost_arm():
    """A regular massless DOF ('ghost') after a massive one: its articulated inertia is singular."""
    m = soadyn.Model()
    m.add_body("arm", None, soadyn.Joint.revolute([0, 0, 1]), mass=1.0, com=[0.5, 0, 0])
    m.add_body("ghost", "arm", soadyn.Joint.revolute([1, 0, 0]), placement=[1, 0, 0])
    return m


def snapshot(sim):
    return (sim.q.copy(), sim.v.copy(), sim.time, sim.prescribed.copy(), sim.steps_taken, sim.energy_lost,
            sim.pending_events)


def assert_unchanged(sim, before):
    after = snapshot(sim)
    for a, b in zip(before, after):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("norm", [2.0, 0.0, 1.0 + 1e-4])
def test_set_state_refuses_a_non_unit_quaternion_and_changes_nothing(norm):
    m = tumbling_body()
    sim = Simulator(m, 1e-3)
    sim.set_state(soadyn.neutral_configuration(m), [1.0, 0, 0, 0, 0, 0], 0.5)
    before = snapshot(sim)
    q = soadyn.neutral_configuration(m)
    q[3:7] = norm * np.array([0.0, 0.0, 0.6, 0.8])
    with pytest.raises(ValueError, match="quaternion of joint 'body' has norm"):
        sim.set_state(q, np.zeros(6))
    assert_unchanged(sim, before)
    q[3:7] = np.array([0.0, 0.0, 0.6, 0.8]) * (1 + 1e-9)  # within the tolerance: accepted as given
    sim.set_state(q, np.zeros(6))
    np.testing.assert_array_equal(sim.q, q)


def test_set_state_refuses_non_finite_values_and_time():
    m = scenes.pendulum_chain(2)
    sim = Simulator(m, 1e-3)
    before = snapshot(sim)
    with pytest.raises(ValueError, match="link_2"):
        sim.set_state([0.0, np.nan], [0.0, 0.0])
    with pytest.raises(ValueError, match="link_1"):
        sim.set_state([0.0, 0.0], [np.inf, 0.0])
    with pytest.raises(ValueError, match="t is not finite"):
        sim.set_state([0.0, 0.0], [0.0, 0.0], math.inf)
    assert_unchanged(sim, before)


def nan_after(t_bad):
    return MotionSource.function(lambda t: (0.1 * t, 0.1, 0.0) if t < t_bad else (math.nan, 0.1, 0.0))


def test_a_source_returning_nan_stops_the_run_by_name_and_leaves_the_last_good_state():
    m = scenes.pendulum_chain(3)
    sim = Simulator(m, 1e-3, "rk4")
    sim.set_state(np.full(3, 0.2), np.zeros(3))
    sim.prescribe("link_2", nan_after(0.0505))
    with pytest.raises(DynamicsError, match=r"motion source returned a non-finite value \(DOF 'link_2'\)") as info:
        sim.run(0.1)
    tr = info.value.trajectory
    assert len(tr.t) == 51 and sim.steps_taken == 50 and sim.time == tr.t[-1]
    np.testing.assert_array_equal(sim.q, tr.q[-1])
    np.testing.assert_array_equal(sim.v, tr.v[-1])
    assert np.all(np.isfinite(sim.q)) and np.all(np.isfinite(sim.v))
    with pytest.raises(DynamicsError, match="non-finite value"):  # the same cause again, from step()
        sim.step()
    assert sim.steps_taken == 50
    sim.release("link_2")  # the cause removed, the run goes on: no false singularity
    sim.run(0.1)
    assert sim.steps_taken == 150 and np.all(np.isfinite(sim.q))


@pytest.mark.parametrize("integrator", ["euler", "rk4", "dopri5"])
def test_a_source_that_raises_is_the_named_cause_of_the_dynamics_error(integrator):
    m = scenes.pendulum_chain(2)
    sim = Simulator(m, 1e-3, integrator)

    def source(t):
        if t > 0.0035:
            raise ZeroDivisionError("sensor table ended")
        return (0.0, 0.0, 0.0)

    sim.prescribe("link_1", MotionSource.function(source))
    with pytest.raises(DynamicsError, match="DOF 'link_1'") as info:
        sim.run(0.01)
    assert isinstance(info.value.__cause__, ZeroDivisionError)
    assert "sensor table ended" in str(info.value.__cause__)
    assert sim.steps_taken == len(info.value.trajectory.t) - 1 == 3
    with pytest.raises(DynamicsError) as info:
        sim.step()
    assert isinstance(info.value.__cause__, ZeroDivisionError)


def test_a_source_returning_the_wrong_type_is_a_type_error_cause():
    sim = Simulator(scenes.pendulum_chain(2), 1e-3)
    with pytest.raises(DynamicsError, match="DOF 'link_1'") as info:
        sim.prescribe("link_1", MotionSource.function(lambda t: "fast"))
    assert isinstance(info.value.__cause__, TypeError)
    assert not sim.prescribed.any()
    with pytest.raises(ZeroDivisionError):  # sample() re-raises the source's own exception
        MotionSource.function(lambda t: 1 / 0).sample(0.0)


def test_a_failing_prescribe_leaves_the_dof_as_it_was():
    m = scenes.pendulum_chain(3)
    sim = Simulator(m, 1e-3)
    sim.set_state(np.full(3, 0.2), [0.5, -0.3, 0.1])
    before = snapshot(sim)
    with pytest.raises(DynamicsError, match=r"prescribe: motion source returned a non-finite value \(DOF 'link_2'\)"):
        sim.prescribe("link_2", nan_after(-1.0))
    assert_unchanged(sim, before)
    reference = Simulator(m, 1e-3)
    reference.set_state(np.full(3, 0.2), [0.5, -0.3, 0.1])
    np.testing.assert_array_equal(sim.run(0.05).q, reference.run(0.05).q)


def test_set_state_checks_the_sources_at_the_new_time():
    sim = Simulator(scenes.pendulum_chain(2), 1e-3)
    sim.prescribe("link_1", nan_after(1.0))
    before = snapshot(sim)
    with pytest.raises(DynamicsError, match="set_state: motion source returned a non-finite value"):
        sim.set_state([0.1, 0.2], [0.0, 0.0], 2.0)
    assert_unchanged(sim, before)


def test_dynamics_failures_are_dynamics_errors_everywhere():
    m = ghost_arm()
    sim = Simulator(m, 1e-3)
    with pytest.raises(DynamicsError, match=r"singular articulated inertia \(DOF 'ghost'\)") as info:
        sim.step()
    assert not isinstance(info.value, ValueError)
    with pytest.raises(DynamicsError, match=r"singular articulated inertia \(DOF 'ghost'\)"):
        sim.run(0.01)
    assert sim.steps_taken == 0 and sim.time == 0.0
    # lock: the impulse needs the ghost's articulated inertia
    sim.set_state([0.0, 0.0], [1.0, 0.0])
    before = snapshot(sim)
    with pytest.raises(DynamicsError, match=r"singular articulated inertia \(DOF 'ghost'\)"):
        sim.lock("arm")
    assert_unchanged(sim, before)
    with pytest.raises(ValueError, match="invalid DOF"):  # a bad argument stays a ValueError
        sim._lock(7)
    with pytest.raises(ValueError, match="invalid DOF"):
        sim._release(-1)


@pytest.mark.parametrize("duration, error, message", [
    (math.inf, ValueError, "finite"), (math.nan, ValueError, "finite"), (-0.01, ValueError, ">= 0"),
    (0.0105, ValueError, "not a whole number"), ("1", TypeError, "real number"), (1e30, ValueError, "in pieces"),
])
def test_run_refuses_bad_durations(duration, error, message):
    sim = Simulator(scenes.pendulum_chain(2), 1e-3)
    with pytest.raises(error, match=message):
        sim.run(duration)
    assert sim.time == 0.0 and sim.steps_taken == 0


def test_run_accepts_decimal_multiples_of_dt():
    sim = Simulator(scenes.pendulum_chain(2), 0.1)
    assert len(sim.run(0.3).t) == 4  # 0.3 / 0.1 = 2.9999999999999996 steps
    sim = Simulator(scenes.pendulum_chain(2), 1e-3)
    assert len(sim.run(0.0).t) == 1 and sim.steps_in(0.011) == 11


def test_events_at_one_time_fire_in_scheduling_order_and_past_events_at_the_next_step():
    m = scenes.pendulum_chain(2)
    sim = Simulator(m, 1e-3)
    sim.set_state([0.3, 0.0], [0.0, 0.0])
    sim.run(0.01)
    sim.schedule(0.02, "lock", "link_1")
    sim.schedule(0.02, "release", "link_1")  # same time, later: ends regular
    sim.schedule(0.03, "release", "link_2")
    sim.schedule(0.03, "lock", "link_2")  # ends locked
    sim.schedule(0.005, "lock", "link_1")  # already past: fires at the next step
    assert sim.pending_events == 5
    sim.step()
    assert sim.prescribed.tolist() == [True, False] and sim.pending_events == 4
    sim.release("link_1")
    sim.run(0.03)
    assert sim.prescribed.tolist() == [False, True] and sim.pending_events == 0


def test_scheduled_events_equal_the_same_calls_made_at_the_step_boundaries():
    c = scenes.cassini()
    scheduled, immediate = Simulator(c, 1e-3, "rk4", event_capacity=40), Simulator(c, 1e-3, "rk4")
    for sim in (scheduled, immediate):
        scenes.drive_cassini(sim)
        sim.set_input("scan_az", 2.0)
    for k in range(1, 40):  # a lock or release of scan_az every 5 ms
        scheduled.schedule(5e-3 * k, "lock" if k % 2 else "release", "scan_az")
    for k in range(0, 200):
        if k and k % 5 == 0 and k // 5 < 40:
            (immediate.lock if (k // 5) % 2 else immediate.release)("scan_az")
        immediate.step()
    tr = scheduled.run(0.2)
    np.testing.assert_array_equal(tr.q[-1], immediate.q)
    np.testing.assert_array_equal(tr.v[-1], immediate.v)
    assert scheduled.energy_lost == immediate.energy_lost != 0  # the locks took place (the moving turntable can feed energy)


def test_the_event_queue_capacity_counts_pending_events():
    sim = Simulator(scenes.pendulum_chain(2), 1e-3, event_capacity=3)
    for t in (0.001, 0.002, 0.003):
        sim.schedule(t, "lock", "link_1")
    with pytest.raises(RuntimeError, match="event queue is full: 3 events are pending"):
        sim.schedule(0.004, "release", "link_1")
    with pytest.raises(RuntimeError, match="event queue is full"):
        sim.schedule(0.004, "prescribe", "link_1", MotionSource.constant_velocity(1.0))
    assert sim.pending_events == 3
    sim.run(0.003)  # two have fired (the third is due at the next step's start)
    assert sim.pending_events == 1
    sim.schedule(0.004, "release", "link_1")
    with pytest.raises(ValueError, match="time is not finite"):
        sim.schedule(math.inf, "lock", "link_1")
    assert sim.pending_events == 2 and sim.event_capacity == 3


def test_dopri5_stops_at_its_sub_step_limit_and_leaves_the_state():
    m = scenes.pendulum_chain(5)
    sim = Simulator(m, 0.5, "dopri5")
    sim.rtol, sim.atol = 1e-13, 1e-15
    sim.set_state(np.full(5, 0.4), np.zeros(5))
    sim.max_substeps = 10
    before = snapshot(sim)
    with pytest.raises(DynamicsError, match=r"sub-step limit reached \(dopri5: 10 sub-step attempts"):
        sim.step()
    assert sim.last_substeps == 10
    assert_unchanged(sim, before)
    sim.max_substeps = 100_000
    sim.step()
    assert 10 < sim.last_substeps <= 100_000 and sim.time == 0.5
    for bad in (0, -3):
        with pytest.raises(ValueError, match="max_substeps must be >= 1"):
            sim.max_substeps = bad


def test_tolerances_are_validated():
    sim = Simulator(scenes.pendulum_chain(2), 1e-3, "dopri5")
    for name, value, message in (("rtol", -1.0, "rtol must be >= 0"), ("atol", 0.0, "atol must be > 0"),
                                 ("rtol", math.nan, "rtol is not finite")):
        with pytest.raises(ValueError, match=message):
            setattr(sim, name, value)
    assert (sim.rtol, sim.atol) == (1e-10, 1e-12)
