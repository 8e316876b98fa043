"""Conservation laws and closed-form physics: the dynamics must obey them."""
import numpy as np
import pytest

import soadyn
from support.energy import flow_derivative, total_energy
from support.trees import random_state, random_tree


@pytest.mark.parametrize("seed", range(6))
def test_energy_rate_equals_power(seed):
    """d/dt (T + V) = v . tau under forward and hybrid dynamics."""
    m, _ = random_tree(seed, 12)
    q, v, rng = random_state(m, seed)
    tau = rng.normal(size=m.nv)
    qdd = soadyn.forward_dynamics(m, q, v, tau)
    rate = flow_derivative(total_energy, m, q, v, qdd)
    power = v @ tau
    assert abs(rate - power) <= 1e-6 * max(1.0, abs(power), total_energy(m, q, v))
    m.set_prescribed(rng.uniform(size=m.nv) < 0.5)
    qdd_h, tau_h = soadyn.hybrid_dynamics(m, q, v, np.where(m.prescribed, qdd, tau))
    rate_h = flow_derivative(total_energy, m, q, v, qdd_h)
    assert abs(rate_h - v @ tau_h) <= 1e-6 * max(1.0, abs(power), total_energy(m, q, v))


@pytest.mark.parametrize("seed", range(6))
def test_momentum_of_free_floating_tree_is_conserved(seed):
    m, _ = random_tree(seed, 12, floating=True)
    m.gravity = [0.0, 0.0, 0.0]
    q, v, _ = random_state(m, seed)
    qdd = soadyn.forward_dynamics(m, q, v, np.zeros(m.nv))
    h = soadyn.momentum(m, q, v)
    dh = flow_derivative(lambda mm, qq, vv: soadyn.momentum(mm, qq, vv), m, q, v, qdd)
    assert np.max(np.abs(dh)) <= 1e-6 * np.max(np.abs(h))
    # With gravity the linear momentum changes at the rate m g exactly.
    m.gravity = [0.0, 0.0, -9.81]
    qdd = soadyn.forward_dynamics(m, q, v, np.zeros(m.nv))
    dh = flow_derivative(lambda mm, qq, vv: soadyn.momentum(mm, qq, vv), m, q, v, qdd)
    np.testing.assert_allclose(dh[3:], [0, 0, -9.81 * sum(m.masses)], atol=1e-6 * sum(m.masses) * 9.81)


def test_kinetic_energy_is_half_v_M_v():
    m, _ = random_tree(2, 10)
    q, v, _ = random_state(m, 2)
    M = soadyn.mass_matrix(m, q)
    assert soadyn.kinetic_energy(m, q, v) == pytest.approx(0.5 * v @ M @ v, rel=1e-12)


def test_compound_pendulum_closed_form():
    """theta'' = -m g l sin(theta) / (Ic + m l^2) for a rod swinging about x."""
    mass, l, Ic = 1.7, 0.4, 0.02
    m = soadyn.Model()
    m.add_body("rod", None, soadyn.Joint.revolute([1, 0, 0]), mass=mass, com=[0, 0, -l], inertia=[Ic, Ic, 0.001])
    for theta in (0.3, -1.2, 2.5):
        qdd = soadyn.forward_dynamics(m, [theta], [0.7], [0.0])
        expected = -mass * 9.81 * l * np.sin(theta) / (Ic + mass * l * l)
        assert qdd[0] == pytest.approx(expected, rel=1e-13)


def test_helical_screw_closed_form():
    """A body on a vertical screw: (I + m p^2) qdd = -m g p."""
    mass, pitch, Izz = 3.0, 0.05, 0.2
    m = soadyn.Model()
    m.add_body("nut", None, soadyn.Joint.helical([0, 0, 1], pitch), mass=mass, inertia=[0.1, 0.1, Izz])
    qdd = soadyn.forward_dynamics(m, [0.4], [1.0], [0.0])
    assert qdd[0] == pytest.approx(-mass * 9.81 * pitch / (Izz + mass * pitch**2), rel=1e-13)
