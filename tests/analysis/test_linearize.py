"""soadyn.linearize and soadyn.modes.

Discrete linearizations against central differences of one step of soadyn.Simulator
(the map they linearize), with the step's end compared on Pinocchio's manifolds
(pin.difference: SO(3), SE(3), SE(2)), on random trees with every joint type and a
free-floating root; continuous linearizations against central differences of the
tangent-space ODE built from pin.integrate / pin.difference and soadyn.hybrid_dynamics.
Modes against closed-form physics: a pendulum's period, the two modes of a double
pendulum, and natural_frequencies' contract.
"""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import soadyn
from support.beams import euler_bernoulli_frequencies
from support.pinocchio_trees import make_case

EPS = 1e-6


def simulator_step(m, q, v, u, dt, integrator):
    sim = soadyn.Simulator(m, dt, integrator)
    sim.set_state(q, v)
    for k in range(m.nv):
        sim.set_input(k, float(u[k]))
    sim.step()
    return sim.q, sim.v


def planar_joints(m):
    return [(m.q_index[i], m.v_index[i]) for i, kind in enumerate(m.joint_types) if kind == "planar"]


def step_by_differences(c, q, v, u, dt, integrator):
    """(A, B) of one Simulator step by central differences, states compared on Pinocchio's manifolds."""
    m = c.m
    q1, _ = simulator_step(m, q, v, u, dt, integrator)
    q1_pin = c.map.q(q1)

    def state(qs, vs, us):
        qe, ve = simulator_step(m, qs, vs, us, dt, integrator)
        e = c.map.back(pin.difference(c.model, q1_pin, c.map.q(qe)))
        for x, o in planar_joints(m):  # pin's SE(2) log rounds small angles off: first order by hand
            theta = q1[x + 2]
            R = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
            e[o:o + 2] = R.T @ (qe[x:x + 2] - q1[x:x + 2])
            e[o + 2] = qe[x + 2] - theta
        return np.concatenate([e, ve])

    nv = m.nv
    columns = []
    for k in range(3 * nv):
        e = np.zeros(3 * nv)
        e[k] = EPS
        plus = state(soadyn.integrate(m, q, e[:nv], 1.0), v + e[nv:2 * nv], u + e[2 * nv:])
        minus = state(soadyn.integrate(m, q, -e[:nv], 1.0), v - e[nv:2 * nv], u - e[2 * nv:])
        columns.append((plus - minus) / (2 * EPS))
    J = np.stack(columns, axis=1)
    return J[:, :2 * nv], J[:, 2 * nv:]


def relative_error(a, b):
    return np.abs(a - b).max() / max(np.abs(b).max(), 1.0)


@pytest.mark.parametrize("integrator", ["rk4", "euler"])
@pytest.mark.parametrize("seed,floating", [(0, True), (1, True), (2, False)])
def test_discrete_linearization_is_the_simulator_step(seed, floating, integrator):
    c = make_case(seed, floating)
    m = c.m
    m.set_prescribed(np.zeros(m.nv, dtype=bool))
    v, u = c.rng.normal(size=m.nv), c.rng.normal(size=m.nv)
    dt = 2e-3
    A, B = soadyn.linearize(m, c.q, v, u, dt=dt, integrator=integrator)
    A_fd, B_fd = step_by_differences(c, c.q, v, u, dt, integrator)
    assert relative_error(A, A_fd) < 1e-7, relative_error(A, A_fd)
    assert relative_error(B, B_fd) < 1e-7, relative_error(B, B_fd)


@pytest.mark.parametrize("seed", [0, 3])
def test_continuous_linearization_against_the_tangent_space_ode(seed):
    """f(e, v) = (d/dt of e along q_bar (+) e moving with v, qdd), differentiated by central
    differences; de/dt from Pinocchio's Jacobian of its difference (pin.dDifference)."""
    c = make_case(seed, True)
    m = c.m
    v, u = c.rng.normal(size=m.nv), c.rng.normal(size=m.nv)
    nv = m.nv

    def f(e, vel):
        q = soadyn.integrate(m, c.q, e, 1.0)
        rate = pin.dDifference(c.model, c.q_pin, c.map.q(q), pin.ArgumentPosition.ARG1) @ c.map.v(vel)
        return np.concatenate([c.map.back(rate), soadyn.hybrid_dynamics(m, q, vel, u)[0]])

    step = 1e-5
    columns = []
    for k in range(2 * nv):
        d = np.zeros(2 * nv)
        d[k] = step
        columns.append((f(d[:nv], v + d[nv:]) - f(-d[:nv], v - d[nv:])) / (2 * step))
    A_fd = np.stack(columns, axis=1)
    A, B = soadyn.linearize(m, c.q, v, u)
    assert relative_error(A[:nv], A_fd[:nv]) < 1e-8  # the kinematic block: -1/2 ad_v and I
    assert np.abs(A[:nv, :nv]).max() > 0.1  # the free and spherical joints' bracket terms are present
    # The dynamics rows are dynamics_derivatives (checked against Pinocchio in test_dynamics_derivatives.py).
    dqdd_dq, dqdd_dv, dqdd_du = soadyn.dynamics_derivatives(m, c.q, v, u)[:3]
    assert np.array_equal(A[nv:, :nv], dqdd_dq) and np.array_equal(A[nv:, nv:], dqdd_dv)
    assert np.array_equal(B[nv:], dqdd_du) and not B[:nv].any()


def test_linearize_rejects_bad_arguments():
    c = make_case(0, False)
    z = np.zeros(c.m.nv)
    with pytest.raises(ValueError, match="dopri5"):
        soadyn.linearize(c.m, c.q, z, z, dt=0.01, integrator="dopri5")
    with pytest.raises(ValueError, match="unknown integrator"):
        soadyn.linearize(c.m, c.q, z, z, dt=0.01, integrator="leapfrog")
    with pytest.raises(ValueError, match="dt"):
        soadyn.linearize(c.m, c.q, z, z, dt=-1.0)


# --- modes ---------------------------------------------------------------------------------------

def pendulum_chain(lengths, masses, gravity=9.81):
    """Point masses on massless rods, hinged about y, hanging along -z."""
    m = soadyn.Model()
    m.gravity = np.array([0.0, 0.0, -gravity])
    parent, offset = "world", 0.0
    for k, (length, mass) in enumerate(zip(lengths, masses)):
        name = f"link{k}"
        m.add_body(name, parent, soadyn.Joint.revolute([0, 1, 0]), placement=(np.eye(3), [0, 0, -offset]),
                   mass=mass, com=[0, 0, -length], inertia=np.zeros((3, 3)))
        parent, offset = name, length
    return m


def test_pendulum_mode_is_its_closed_form_frequency():
    m = pendulum_chain([0.7], [1.3])
    md = soadyn.modes(m, np.zeros(1))
    assert md.angular_frequencies[0] == pytest.approx(np.sqrt(9.81 / 0.7), rel=1e-12)
    assert md.frequencies_hz[0] == pytest.approx(np.sqrt(9.81 / 0.7) / (2 * np.pi), rel=1e-12)
    assert md.damping_ratios[0] == pytest.approx(0.0, abs=1e-12)
    assert md.dof_names == ["link0"]


def test_double_pendulum_modes_are_the_closed_form_ones():
    """Equal masses and lengths: w^2 = (2 -+ sqrt 2) g / l; in absolute angles the shapes are
    phi2 / phi1 = +-sqrt 2, so the second hinge's (relative) angle is (+-sqrt 2 - 1) times the first's."""
    g, l = 9.81, 0.5
    m = pendulum_chain([l, l], [1.0, 1.0], g)
    md = soadyn.modes(m, np.zeros(2))
    expected = np.sqrt(np.array([2 - np.sqrt(2), 2 + np.sqrt(2)]) * g / l)
    np.testing.assert_allclose(md.angular_frequencies, expected, rtol=1e-12)
    for shape, sign in zip(md.shapes, (1.0, -1.0)):
        ratio = shape[1] / shape[0]  # relative angle over the first angle
        assert ratio == pytest.approx(sign * np.sqrt(2) - 1, rel=1e-10)
    np.testing.assert_allclose(soadyn.natural_frequencies(m, np.zeros(2)), expected, rtol=1e-12)


def test_inverted_pendulum_is_reported_unstable():
    m = pendulum_chain([0.7], [1.3])
    md = soadyn.modes(m, np.array([np.pi]))
    assert md.angular_frequencies[0] == pytest.approx(-np.sqrt(9.81 / 0.7), rel=1e-12)


def test_modes_hold_prescribed_dofs_and_label_the_regular_ones():
    m = pendulum_chain([0.5, 0.5], [1.0, 1.0])
    m.set_prescribed(["link0"])
    md = soadyn.modes(m, np.zeros(2))
    assert md.dof_names == ["link1"]
    # The second link about a held first one: a pendulum of length 0.5 hanging from a fixed point.
    assert md.angular_frequencies[0] == pytest.approx(np.sqrt(9.81 / 0.5), rel=1e-12)
    assert "link1" in md.table()


def test_stiffness_matrix_is_the_gradient_of_gravity():
    """K = dg/dq against central differences of gravity_forces on a random floating tree."""
    c = make_case(2, True)
    m = c.m
    K = soadyn.stiffness_matrix(m, c.q)
    K_fd = np.stack([(soadyn.gravity_forces(m, soadyn.integrate(m, c.q, e, 1e-6))
                      - soadyn.gravity_forces(m, soadyn.integrate(m, c.q, e, -1e-6))) / 2e-6
                     for e in np.eye(m.nv)], axis=1)
    assert relative_error(K, K_fd) < 1e-7


def test_hostile_inputs_are_named():
    c = make_case(1, True)
    m, z = c.m, np.zeros(c.m.nv)
    bad = z.copy()
    bad[2] = np.nan
    with pytest.raises(ValueError, match=m.dof_names[2]):
        soadyn.linearize(m, c.q, bad, z)
    with pytest.raises(ValueError, match=m.dof_names[2]):
        soadyn.linearize(m, c.q, z, bad, dt=1e-3)
    with pytest.raises(ValueError):
        soadyn.linearize(m, c.q, z[:-1], z)
    with pytest.raises(ValueError, match="dt"):
        soadyn.linearize(m, c.q, z, z, dt=float("nan"))
    q_bad = c.q.copy()
    q_bad[0] = np.inf
    with pytest.raises(ValueError, match=m.coordinate_names[0]):
        soadyn.modes(m, q_bad)
    with pytest.raises(ValueError):
        soadyn.modes(m, c.q[:-1])


def test_derivatives_from_many_threads_agree():
    """Calls from several threads on one model give the single-threaded results (each call runs on
    the model's own Data under its lock)."""
    from concurrent.futures import ThreadPoolExecutor
    c = make_case(2, True)
    m = c.m
    states = [(soadyn.random_configuration(m, k), c.rng.normal(size=m.nv), c.rng.normal(size=m.nv))
              for k in range(6)]
    expected = [soadyn.dynamics_derivatives(m, *s) for s in states]
    with ThreadPoolExecutor(max_workers=4) as pool:
        results = list(pool.map(lambda s: soadyn.dynamics_derivatives(m, *s), states * 4))
    for k, result in enumerate(results):
        for a, b in zip(result, expected[k % len(states)]):
            assert np.array_equal(a, b)


def test_cantilever_modes_are_euler_bernoulli():
    """A clamped flexible beam (modal coordinates only): modes gives the clamped-free bending
    frequencies of Euler-Bernoulli theory (to the lumped model's discretisation error), in pairs
    labelled by the beam's modal DOFs, and matches the beam's own clamped frequencies to rounding."""
    length, EI, mu = 2.0, 3.0e3, 1.5
    m = soadyn.scenes.cantilever_beam(length, EI, mu, n_modes=3, n_nodes=120)
    md = soadyn.modes(m, soadyn.neutral_configuration(m))
    assert md.dof_names == m.dof_names
    beam = m.flexible_body("beam")
    np.testing.assert_allclose(md.angular_frequencies, np.sort(beam.natural_frequencies_clamped()), rtol=1e-10)
    beta_l = np.array([1.8751040687, 4.6940911330, 7.8547574382])
    np.testing.assert_allclose(md.angular_frequencies[::2], euler_bernoulli_frequencies(beta_l, length, EI, mu),
                               rtol=2e-3)
    np.testing.assert_allclose(md.damping_ratios, 0.0, atol=1e-12)


def test_flexible_stiffness_is_the_gradient_of_the_bias_at_rest():
    """cassini (flexible appendages, gravity-free but with elastic modes): the exact K and D at rest
    against central differences of bias_forces, and modes labelled by DOF name."""
    m = soadyn.scenes.cassini()
    rng = np.random.default_rng(4)
    q = soadyn.integrate(m, soadyn.neutral_configuration(m), 0.2 * rng.normal(size=m.nv), 1.0)
    K = soadyn.stiffness_matrix(m, q)
    zero = np.zeros(m.nv)
    K_fd = np.stack([(soadyn.bias_forces(m, soadyn.integrate(m, q, e, 1e-6), zero)
                      - soadyn.bias_forces(m, soadyn.integrate(m, q, e, -1e-6), zero)) / 2e-6
                     for e in np.eye(m.nv)], axis=1)
    assert relative_error(K, K_fd) < 1e-7
    D = soadyn.inverse_dynamics_derivatives(m, q, zero, zero)[1]
    D_fd = np.stack([(soadyn.bias_forces(m, q, 1e-6 * e) - soadyn.bias_forces(m, q, -1e-6 * e)) / 2e-6
                     for e in np.eye(m.nv)], axis=1)
    assert relative_error(D, D_fd) < 1e-7
    md = soadyn.modes(m, q)
    assert md.dof_names == [n for n, held in zip(m.dof_names, m.prescribed) if not held]
    elastic = np.abs(md.angular_frequencies) > 0
    assert elastic.sum() == int(m.modal.sum())  # one elastic mode per modal coordinate, the rest rigid
    assert np.all((md.damping_ratios[elastic] > 0) & (md.damping_ratios[elastic] < 0.05))


@pytest.mark.parametrize("integrator", ["rk4", "euler", None])
@pytest.mark.parametrize("kind", ["on-nodes", "appendages-damped"])
def test_flexible_linearization_against_differences(kind, integrator):
    """Fixed-base flexible trees (revolute, prismatic and modal coordinates: vector spaces, so states
    difference coordinate by coordinate): the discrete map against central differences of one
    Simulator step, the continuous one (with a hybrid mask) against central differences of
    hybrid_dynamics."""
    from support.flexible_trees import random_flexible_tree
    options = {"on-nodes": {}, "appendages-damped": {"appendages": True, "damping": True}}[kind]
    m = random_flexible_tree(5, **options)[0]
    assert m.nq == m.nv and any(m.n_modes)
    rng = np.random.default_rng(6)
    q, v, u = 0.3 * rng.normal(size=m.nv), rng.normal(size=m.nv), rng.normal(size=m.nv)
    mask = (rng.random(m.nv) < 0.3) & ~m.modal
    if integrator is None:  # (a Simulator starts prescribed DOFs locked: the steps are taken all-regular)
        m.set_prescribed(mask)
    nv, dt = m.nv, 2e-3
    if integrator is None:
        def f(x):
            return np.concatenate([x[nv:2 * nv], soadyn.hybrid_dynamics(m, x[:nv], x[nv:2 * nv], x[2 * nv:])[0]])
    else:
        def f(x):
            return np.concatenate(simulator_step(m, x[:nv], x[nv:2 * nv], x[2 * nv:], dt, integrator))
    x0 = np.concatenate([q, v, u])
    J = np.stack([(f(x0 + EPS * e) - f(x0 - EPS * e)) / (2 * EPS) for e in np.eye(3 * nv)], axis=1)
    A, B = soadyn.linearize(m, q, v, u) if integrator is None else \
        soadyn.linearize(m, q, v, u, dt=dt, integrator=integrator)
    assert relative_error(A, J[:, :2 * nv]) < 1e-7
    assert relative_error(B, J[:, 2 * nv:]) < 1e-7
