"""Semi-implicit Euler's energy drift is the method's, not a defect: the same update
(v += dt qdd(q, v); q += dt v) on Pinocchio's ABA gives the same states and energy, and
with a constant mass matrix (one link) the method is symplectic and its energy error stays bounded."""
import numpy as np
import pinocchio as pin
import pytest

import soadyn
from soadyn import Simulator, scenes


def pinocchio_chain(n, length=0.5, mass=1.0):
    """scenes.pendulum_chain(n) built in Pinocchio: x-axis hinges, rods along -z."""
    model = pin.Model()
    parent = 0
    for i in range(n):
        joint = model.addJoint(parent, pin.JointModelRX(),
                               pin.SE3(np.eye(3), np.array([0.0, 0.0, -length if i else 0.0])), f"link_{i + 1}")
        inertia = np.diag([mass * length**2 / 12] * 2 + [1e-3 * mass])
        model.appendBodyToJoint(joint, pin.Inertia(mass, np.array([0.0, 0.0, -length / 2]), inertia),
                                pin.SE3.Identity())
        parent = joint
    model.gravity.linear = np.array([0.0, 0.0, -9.81])
    return model


def energy(m, q, v):
    return soadyn.kinetic_energy(m, q, v) + soadyn.potential_energy(m, q)


def test_euler_drift_equals_the_same_method_on_pinocchio():
    n, dt, steps = 10, 1e-3, 2000
    m = scenes.pendulum_chain(n)
    q0 = np.full(n, 0.3)
    sim = Simulator(m, dt, "euler")
    sim.set_state(q0, np.zeros(n))
    tr = sim.run(steps * dt)
    model = pinocchio_chain(n)
    data = model.createData()
    q, v = q0.copy(), np.zeros(n)

    def pin_energy(q, v):
        return pin.computeKineticEnergy(model, data, q, v) + pin.computePotentialEnergy(model, data, q)

    e0 = pin_energy(q, v)
    for _ in range(steps):
        v = v + dt * pin.aba(model, data, q, v, np.zeros(n))
        q = q + dt * v
    np.testing.assert_allclose(tr.q[-1], q, rtol=0, atol=1e-10)
    np.testing.assert_allclose(tr.v[-1], v, rtol=0, atol=1e-9)
    pin_drift = pin_energy(q, v) - e0
    drift = energy(m, tr.q[-1], tr.v[-1]) - energy(m, tr.q[0], tr.v[0])
    assert abs(pin_drift) > 1.0  # a real drift (J), not rounding
    assert drift == pytest.approx(pin_drift, rel=1e-9)


def test_euler_energy_error_is_bounded_when_the_mass_matrix_is_constant():
    """One link: M does not depend on q, the method is symplectic Euler, no secular drift over 100 s."""
    m = scenes.pendulum_chain(1)
    sim = Simulator(m, 1e-3, "euler")
    sim.set_state([1.0], [0.0])
    tr = sim.run(100.0)
    e = np.array([energy(m, q, v) for q, v in zip(tr.q[::10], tr.v[::10])])
    error = np.abs(e - e[0])
    first, last = error[:1000].max(), error[-1000:].max()  # the first and the last 10 s
    assert 0 < last < 1.05 * first


def test_euler_energy_error_is_first_order_in_the_step():
    m = scenes.pendulum_chain(10)

    def worst_energy_error(dt):
        sim = Simulator(m, dt, "euler")
        sim.set_state(np.full(10, 0.05), np.zeros(10))
        tr = sim.run(5.0)
        stride = round(0.01 / dt)
        e = np.array([energy(m, q, v) for q, v in zip(tr.q[::stride], tr.v[::stride])])
        return np.max(np.abs(e - e[0]))

    ratio = worst_energy_error(1e-3) / worst_energy_error(5e-4)
    assert 1.8 < ratio < 2.2, ratio
