"""Simulator: integrators on the joint manifolds, motion sources, run-time events."""
import numpy as np
import pytest

import soadyn
from soadyn import MotionSource, Simulator, scenes
from support.bodies import tumbling_body
from support.trees import random_state, random_tree


def energy(m, q, v):
    return soadyn.kinetic_energy(m, q, v) + soadyn.potential_energy(m, q)


def test_rk4_energy_drift_of_a_conservative_chain():
    m = scenes.pendulum_chain(5)
    sim = Simulator(m, 1e-3, "rk4")
    q0 = np.full(m.nq, 0.4)
    sim.set_state(q0, np.zeros(m.nv))
    tr = sim.run(10.0)  # 10^4 steps
    assert len(tr.t) == 10_001 and tr.t[-1] == pytest.approx(10.0)
    e = np.array([energy(m, q, v) for q, v in zip(tr.q[::50], tr.v[::50])])
    assert np.max(np.abs(e - e[0])) / abs(e[0]) < 1e-8


@pytest.mark.parametrize("integrator", ["rk4", "euler"])
def test_quaternions_stay_unit_over_1e5_steps(integrator):
    m = tumbling_body()
    sim = Simulator(m, 1e-3, integrator)
    sim.set_state(soadyn.neutral_configuration(m), [1.0, 3.0, -2.0, 0.5, 0.1, 0.0])
    tr = sim.run(100.0)
    assert len(tr.t) == 100_001
    assert np.max(np.abs(np.linalg.norm(tr.q[:, 3:7], axis=1) - 1.0)) < 1e-12


def test_rk4_is_fourth_order_on_the_manifold():
    """Against the adaptive Dormand-Prince reference: halving dt divides the error by ~16."""
    m, _ = random_tree(3, 6)
    m.gravity = [0, 0, -9.81]
    q0, v0, _ = random_state(m, 3)
    v0 *= 0.3

    def final_state(dt, integrator):
        sim = Simulator(m, dt, integrator)
        sim.set_state(q0, v0)
        sim.rtol, sim.atol = 1e-13, 1e-14
        sim.run(0.4)
        return sim.v

    reference = final_state(0.04, "dopri5")
    errors = [np.max(np.abs(final_state(dt, "rk4") - reference)) for dt in (4e-2, 2e-2)]
    assert 12 < errors[0] / errors[1] < 20, errors
    euler = [np.max(np.abs(final_state(dt, "euler") - reference)) for dt in (2e-4, 1e-4)]
    assert 1.6 < euler[0] / euler[1] < 2.4, euler


def test_free_body_momentum_is_conserved_by_rk4():
    m = tumbling_body()
    sim = Simulator(m, 1e-3, "rk4")
    sim.set_state(soadyn.neutral_configuration(m), [1.0, 3.0, -2.0, 0.5, 0.1, 0.0])
    tr = sim.run(5.0)
    h0, h1 = soadyn.momentum(m, tr.q[0], tr.v[0]), soadyn.momentum(m, tr.q[-1], tr.v[-1])
    assert np.max(np.abs(h1 - h0)) < 1e-9 * np.max(np.abs(h0))


def test_prescribed_dof_tracks_its_spline_to_round_off():
    m = scenes.pendulum_chain(3)
    sim = Simulator(m, 1e-3, "rk4")
    times = np.linspace(0.0, 2.0, 9)
    source = MotionSource.spline(times, np.sin(times))
    sim.prescribe("link_2", source)
    tr = sim.run(2.5)
    k = m.dof_index("link_2")
    expected = np.array([source.sample(t) for t in tr.t])
    np.testing.assert_allclose(tr.q[:, k], expected[:, 0], rtol=0, atol=1e-15)
    np.testing.assert_allclose(tr.v[:, k], expected[:, 1], rtol=0, atol=1e-15)
    assert np.all(tr.v[tr.t > 2.0 + 1e-9, k] == 0)  # held after the table


def test_sources_match_their_closed_forms():
    c = MotionSource.cycloidal(0.5, 1.5, 1.0, 2.0)
    for t in (0.5, 1.0, 1.7, 2.9, 3.5):
        s = np.clip((t - 1.0) / 2.0, 0, 1)
        q = 0.5 + 1.0 * (s - np.sin(2 * np.pi * s) / (2 * np.pi))
        v = (1.0 / 2.0) * (1 - np.cos(2 * np.pi * s)) if 0 < s < 1 else 0.0
        assert c.sample(t)[:2] == pytest.approx((q, v), abs=1e-15)
    p = MotionSource.polynomial([1.0, -2.0, 0.5, 0.25], t0=1.0)
    t, s = 2.5, 1.5
    assert p.sample(t) == pytest.approx((1 - 2 * s + 0.5 * s**2 + 0.25 * s**3, -2 + s + 0.75 * s**2, 1 + 1.5 * s))
    assert MotionSource.constant_acceleration(2.0, v0=1.0, q0=3.0).sample(2.0) == pytest.approx((9.0, 5.0, 2.0))
    spline = MotionSource.spline([0, 1, 2, 3], [0, 1, 0, 1])
    eps = 1e-6
    for t in (0.3, 1.5, 2.2):  # velocity and acceleration are the derivatives of position
        (qa, va, _), (qb, vb, _), (_, v, a) = spline.sample(t + eps), spline.sample(t - eps), spline.sample(t)
        assert (qa - qb) / (2 * eps) == pytest.approx(v, rel=1e-7)
        assert (va - vb) / (2 * eps) == pytest.approx(a, rel=1e-6)


def test_lock_conserves_momentum_and_never_gains_energy():
    """With every other driven DOF at rest (the turntable and gimbal held), a lock is a plastic impact."""
    c = scenes.cassini()
    sim = Simulator(c, 1e-3, "rk4")
    for name, torque in (("scan_az", 2.0), ("scan_el", -1.0), ("wheel_2", 0.5), ("probe_relay_antenna", 0.3)):
        sim.set_input(name, torque)
    sim.run(1.0)
    for name in ("scan_az", "wheel_2", "probe_relay_antenna", "oxidizer_slosh"):
        q, v = sim.q, sim.v
        h0, e0, lost0 = soadyn.momentum(c, q, v), soadyn.kinetic_energy(c, q, v), sim.energy_lost
        sim.lock(name)
        h1, e1 = soadyn.momentum(c, sim.q, sim.v), soadyn.kinetic_energy(c, sim.q, sim.v)
        assert np.max(np.abs(h1 - h0)) <= 1e-12 * max(1.0, np.max(np.abs(h0)))
        assert e1 <= e0
        assert sim.energy_lost - lost0 == pytest.approx(e0 - e1, rel=1e-12, abs=1e-15)
        for k in c._dof_indices(name):
            assert sim.v[k] == 0.0
        sim.run(0.2)
    assert sim.energy_lost > 0


def test_release_keeps_state_continuous_and_locked_dof_holds():
    c = scenes.cassini()
    sim = Simulator(c, 1e-3, "rk4")
    sim.set_input("scan_az", 2.0)
    sim.schedule(0.5, "lock", "scan_az")
    sim.schedule(0.8, "release", "scan_az")
    k = c.dof_index("scan_az")
    tr = sim.run(1.0)
    locked = (tr.t > 0.5 + 1e-9) & (tr.t < 0.8 - 1e-9)
    assert np.all(tr.v[locked, k] == 0) and np.ptp(tr.q[locked, c.coordinate_names.index("scan_az")]) == 0
    assert tr.v[-1, k] > 0  # torqued again after the release
    assert np.max(np.abs(np.diff(tr.v[tr.t > 0.6], axis=0))) < 0.01  # no jump at the release


def test_scheduled_prescribe_and_python_callable_source():
    m = scenes.pendulum_chain(2)
    sim = Simulator(m, 1e-3, "rk4")
    sim.schedule(0.25, "prescribe", "link_1", MotionSource.function(lambda t: (np.sin(t), np.cos(t), -np.sin(t))))
    tr = sim.run(0.5)
    k = m.dof_index("link_1")
    after = tr.t >= 0.25 + 1e-9
    np.testing.assert_allclose(tr.v[after, k], np.cos(tr.t[after]), atol=1e-15)
    assert sim.prescribed[k]


def test_a_source_is_called_once_per_time_and_again_after_a_failure():
    """RK4 samples a source at t + h/2 in two stages and at t + h in its last stage and
    for the step's end positions (then the next step's first stage): each time once. A
    raising source is asked again on the next attempt, and raises again."""
    m = scenes.pendulum_chain(2)
    sim = Simulator(m, 0.01, "rk4")
    times = []

    def source(t):
        times.append(t)
        if t > 0.1:
            raise RuntimeError("encoder lost")
        return np.sin(t), np.cos(t), -np.sin(t)

    sim.prescribe("link_1", MotionSource.function(source))
    times.clear()
    sim.run(0.1)
    assert len(times) == len(set(times)) == 20
    np.testing.assert_allclose(sorted(times), 0.005 * np.arange(1, 21), atol=1e-15)
    k = m.dof_index("link_1")
    assert sim.q[k] == pytest.approx(np.sin(0.1), abs=1e-15) and sim.v[k] == pytest.approx(np.cos(0.1), abs=1e-15)
    for attempt in range(2):
        with pytest.raises(soadyn.DynamicsError) as info:
            sim.step()
        assert isinstance(info.value.__cause__, RuntimeError), attempt
    assert sim.time == pytest.approx(0.1, abs=1e-15)


def test_simulator_bad_input():
    m = scenes.pendulum_chain(2)
    with pytest.raises(ValueError, match="unknown integrator 'rk5'"):
        Simulator(m, 1e-3, "rk5")
    with pytest.raises(ValueError, match="dt must be positive"):
        Simulator(m, 0.0)
    sim = Simulator(m, 1e-3)
    with pytest.raises(ValueError, match="unknown DOF or joint 'elbow'"):
        sim.lock("elbow")
    with pytest.raises(ValueError, match="strictly"):
        MotionSource.spline([0, 1, 1], [0, 1, 2])
    with pytest.raises(ValueError, match="unknown event 'explode'"):
        sim.schedule(1.0, "explode", "link_1")
    with pytest.raises(ValueError, match="q has shape"):
        sim.set_state(np.zeros(5), np.zeros(2))
    free = Simulator(tumbling_body(), 1e-3)
    with pytest.raises(ValueError, match="body:wx' has no scalar coordinate"):
        free.prescribe("body:wx", MotionSource.constant_velocity(1.0))
    free.lock("body:wx")  # locking any DOF is fine


def test_failure_stops_the_run_cleanly():
    m = soadyn.Model()
    m.add_body("arm", None, soadyn.Joint.revolute([0, 0, 1]), mass=1.0, com=[0.5, 0, 0])
    m.add_body("ghost", "arm", soadyn.Joint.revolute([1, 0, 0]), placement=[1, 0, 0])  # massless, regular
    sim = Simulator(m, 1e-3)
    with pytest.raises(soadyn.DynamicsError, match="singular articulated inertia \\(DOF 'ghost'\\)") as info:
        sim.run(0.1)
    assert len(info.value.trajectory.t) == 1


def test_cassini_drive_turntable_rate_and_gimbal_velocity_commands():
    c = scenes.cassini()
    sim = Simulator(c, 1e-3, "rk4")
    scenes.drive_cassini(sim)
    tr = sim.run(3.0)
    amplitude, omega = np.radians(0.5), 2 * np.pi / 20
    np.testing.assert_allclose(tr.v[1:, c.dof_index("turntable")], scenes.TURNTABLE_RATE, rtol=0, atol=1e-15)
    np.testing.assert_allclose(tr.v[:, c.dof_index("gimbal_pitch")], amplitude * np.sin(omega * tr.t), atol=1e-15)
    np.testing.assert_allclose(tr.v[:, c.dof_index("gimbal_yaw")], amplitude * np.cos(omega * tr.t), atol=1e-15)
    h = [soadyn.momentum(c, q, v) for q, v in zip(tr.q[::500], tr.v[::500])]
    assert np.max(np.abs(np.array(h) - h[0])) < 1e-9  # internal drives: momentum stays (RK4 error only)
