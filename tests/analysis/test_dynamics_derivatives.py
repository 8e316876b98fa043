"""Analytic derivatives of inverse and hybrid dynamics (soadyn.inverse_dynamics_derivatives,
soadyn.dynamics_derivatives) against Pinocchio: computeRNEADerivatives and
computeABADerivatives, and central differences of pin.rnea and pin.aba on Pinocchio's own
manifolds (pin.integrate), on the example-robot-data robots and the random trees of
support/pinocchio_trees.py (every joint type, fixed and floating bases, external forces).
Hybrid masks, which Pinocchio has no counterpart for, are checked against central
differences of soadyn.hybrid_dynamics and against the partitioned identities.

Pinocchio's computeRNEADerivatives differs from central differences of its own rnea in the
entries of universal joints (as its computeCoriolisMatrix leaves out the rate of the
universal joint's first axis); those entries are checked against the differences of pin.rnea,
every other entry against computeRNEADerivatives itself.
"""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import soadyn
from support.pinocchio_trees import CASE_IDS, CASES, make_case
from support.robots import ROBOTS, matrix_from_pin, robot_with_oracle

RTOL = 1e-11      # against Pinocchio's analytic derivatives, relative to the largest reference entry
FD_RTOL = 1e-7    # against central differences (eps = 1e-5), relative to the largest reference entry
EPS = 1e-5


def assert_close(actual, expected, rtol, what):
    """max |actual - expected| <= rtol * max |expected|; an all-zero reference must be matched exactly."""
    actual, expected = np.asarray(actual), np.asarray(expected)
    assert actual.shape == expected.shape, what
    scale = np.abs(expected).max(initial=0.0)
    if scale == 0:
        assert not actual.any(), f"{what}: expected zero"
        return
    error = np.abs(actual - expected).max(initial=0.0) / scale
    assert error <= rtol, f"{what}: relative error {error:.2e} > {rtol:.0e}"


def central_differences(f, x0, step, n):
    """Columns (f(step(x0, +eps e_k)) - f(step(x0, -eps e_k))) / (2 eps), k < n."""
    columns = []
    for k in range(n):
        e = np.zeros(n)
        e[k] = EPS
        columns.append((f(step(x0, e)) - f(step(x0, -e))) / (2 * EPS))
    return np.stack(columns, axis=1)


def universal_dofs(m):
    mask = np.zeros(m.nv, dtype=bool)
    for i, kind in enumerate(m.joint_types):
        if kind == "universal":
            mask[m.v_index[i]:m.v_index[i] + 2] = True
    return mask


# --- random trees: every joint type ---------------------------------------------------------------

@pytest.mark.parametrize("seed,floating", CASES, ids=CASE_IDS)
def test_random_tree_inverse_dynamics_derivatives_against_pinocchio(seed, floating):
    c = make_case(seed, floating)
    m = c.m
    v, a = c.rng.normal(size=m.nv), c.rng.normal(size=m.nv)
    f = c.rng.normal(size=(m.nbodies, 6))
    dq, dv, M = soadyn.inverse_dynamics_derivatives(m, c.q, v, a, f)
    vp, ap, fp = c.map.v(v), c.map.v(a), c.map.f_ext(f)
    pin_dq, pin_dv, _ = pin.computeRNEADerivatives(c.model, c.data, c.q_pin, vp, ap, fp)
    pin_dq, pin_dv = c.map.matrix_from_pin(pin_dq), c.map.matrix_from_pin(pin_dv)
    plain = ~universal_dofs(m)
    assert plain.sum() < m.nv  # the trees have universal joints
    assert_close(dq[np.ix_(plain, plain)], pin_dq[np.ix_(plain, plain)], RTOL, "dtau/dq vs computeRNEADerivatives")
    assert_close(dv[np.ix_(plain, plain)], pin_dv[np.ix_(plain, plain)], RTOL, "dtau/dv vs computeRNEADerivatives")
    assert_close(M, soadyn.mass_matrix(m, c.q), 1e-14, "dtau/dqdd = M")
    # Every entry against central differences of Pinocchio's rnea on its own manifold.
    fd_dq = central_differences(lambda qp: pin.rnea(c.model, c.data, qp, vp, ap, fp), c.q_pin,
                                lambda qp, e: pin.integrate(c.model, qp, e), m.nv)
    fd_dv = central_differences(lambda vq: pin.rnea(c.model, c.data, c.q_pin, vq, ap, fp), vp,
                                lambda x, e: x + e, m.nv)
    assert_close(dq, c.map.matrix_from_pin(fd_dq), FD_RTOL, "dtau/dq vs differences of pin.rnea")
    assert_close(dv, c.map.matrix_from_pin(fd_dv), FD_RTOL, "dtau/dv vs differences of pin.rnea")


@pytest.mark.parametrize("seed,floating", CASES, ids=CASE_IDS)
def test_random_tree_forward_dynamics_derivatives_against_pinocchio(seed, floating):
    """All DOFs regular: dqdd/dq, dqdd/dv against central differences of pin.aba, dqdd/du = M^-1."""
    c = make_case(seed, floating)
    m = c.m
    m.set_prescribed(np.zeros(m.nv, dtype=bool))
    v, tau = c.rng.normal(size=m.nv), c.rng.normal(size=m.nv)
    f = c.rng.normal(size=(m.nbodies, 6))
    dqdd_dq, dqdd_dv, dqdd_du, dtau_dq, dtau_dv, dtau_du = soadyn.dynamics_derivatives(m, c.q, v, tau, f)
    vp, tp, fp = c.map.v(v), c.map.v(tau), c.map.f_ext(f)
    fd_dq = central_differences(lambda qp: pin.aba(c.model, c.data, qp, vp, tp, fp), c.q_pin,
                                lambda qp, e: pin.integrate(c.model, qp, e), m.nv)
    fd_dv = central_differences(lambda vq: pin.aba(c.model, c.data, c.q_pin, vq, tp, fp), vp,
                                lambda x, e: x + e, m.nv)
    assert_close(dqdd_dq, c.map.matrix_from_pin(fd_dq), 10 * FD_RTOL, "dqdd/dq vs differences of pin.aba")
    assert_close(dqdd_dv, c.map.matrix_from_pin(fd_dv), 10 * FD_RTOL, "dqdd/dv vs differences of pin.aba")
    pin.computeMinverse(c.model, c.data, c.q_pin)
    Minv = np.triu(c.data.Minv) + np.triu(c.data.Minv, 1).T
    assert_close(dqdd_du, c.map.matrix_from_pin(Minv), 1e-10, "dqdd/du = M^-1 (pin.computeMinverse)")
    assert not dtau_dq.any() and not dtau_dv.any(), "no prescribed DOF: tau = u"
    assert np.array_equal(dtau_du, np.eye(m.nv))


# --- robots -----------------------------------------------------------------------------------

@pytest.mark.parametrize("name", sorted(ROBOTS))
@pytest.mark.parametrize("floating", [False, True], ids=["fixed", "floating"])
def test_robot_derivatives_against_pinocchio(name, floating):
    m, o = robot_with_oracle(name, floating)
    m.set_prescribed(np.zeros(m.nv, dtype=bool))
    rng = np.random.default_rng(5)
    for state in range(2):
        q = soadyn.random_configuration(m, state)
        v, a, tau = rng.normal(size=m.nv), rng.normal(size=m.nv), rng.normal(size=m.nv)
        qp, vp = o.q(q), o.to_pin(v)
        dq, dv, M = soadyn.inverse_dynamics_derivatives(m, q, v, a)
        pin_dq, pin_dv, _ = pin.computeRNEADerivatives(o.model, o.data, qp, vp, o.to_pin(a))
        assert_close(dq, matrix_from_pin(o, pin_dq), RTOL, f"{name} dtau/dq")
        assert_close(dv, matrix_from_pin(o, pin_dv), RTOL, f"{name} dtau/dv")
        dqdd_dq, dqdd_dv, dqdd_du = soadyn.dynamics_derivatives(m, q, v, tau)[:3]
        pin_ddq_dq, pin_ddq_dv, pin_minv = pin.computeABADerivatives(o.model, o.data, qp, vp, o.to_pin(tau))
        pin_minv = np.triu(pin_minv) + np.triu(pin_minv, 1).T
        assert_close(dqdd_dq, matrix_from_pin(o, pin_ddq_dq), RTOL, f"{name} dqdd/dq vs computeABADerivatives")
        assert_close(dqdd_dv, matrix_from_pin(o, pin_ddq_dv), RTOL, f"{name} dqdd/dv vs computeABADerivatives")
        assert_close(dqdd_du, matrix_from_pin(o, pin_minv), RTOL, f"{name} dqdd/du vs computeABADerivatives' M^-1")


# --- hybrid masks ------------------------------------------------------------------------------

def hybrid_by_differences(m, q, v, u, f=None):
    """The six derivatives of soadyn.hybrid_dynamics by central differences."""
    def out(k):
        return lambda args: soadyn.hybrid_dynamics(m, *args, f)[k]

    columns = []
    for k in (0, 1):
        columns.append([
            central_differences(lambda x: out(k)((x, v, u)), q, lambda x, e: soadyn.integrate(m, x, e, 1.0), m.nv),
            central_differences(lambda x: out(k)((q, x, u)), v, lambda x, e: x + e, m.nv),
            central_differences(lambda x: out(k)((q, v, x)), u, lambda x, e: x + e, m.nv)])
    return columns[0] + columns[1]


NAMES = ("dqdd_dq", "dqdd_dv", "dqdd_du", "dtau_dq", "dtau_dv", "dtau_du")


def check_hybrid(m, q, v, u, f=None, rtol=FD_RTOL):
    analytic = soadyn.dynamics_derivatives(m, q, v, u, f)
    reference = hybrid_by_differences(m, q, v, u, f)
    for name, a, r in zip(NAMES, analytic, reference):
        scale = max(np.abs(r).max(initial=0.0), 1.0)
        error = np.abs(a - r).max(initial=0.0) / scale
        assert error <= rtol, f"{name}: relative error {error:.2e} > {rtol:.0e}"
    return analytic


def check_partition_identities(m, q, v, u, analytic):
    """The hybrid derivatives from the dense partition of M and inverse-dynamics derivatives."""
    dqdd_dq, dqdd_dv, dqdd_du, dtau_dq, dtau_dv, dtau_du = analytic
    P = np.asarray(m.prescribed, dtype=bool)
    R = ~P
    qdd, _ = soadyn.hybrid_dynamics(m, q, v, u)
    id_dq, id_dv, M = soadyn.inverse_dynamics_derivatives(m, q, v, qdd)
    M_RR = M[np.ix_(R, R)]
    for name, d_qdd, d_tau, partial in (("q", dqdd_dq, dtau_dq, id_dq), ("v", dqdd_dv, dtau_dv, id_dv)):
        expected = np.zeros((m.nv, m.nv))
        expected[R] = -np.linalg.solve(M_RR, partial[R])
        assert_close(d_qdd, expected, 1e-10, f"dqdd/d{name} = -M_RR^-1 dID_R/d{name}")
        tau_expected = np.zeros((m.nv, m.nv))
        tau_expected[P] = partial[P] + M[P] @ expected
        assert_close(d_tau, tau_expected, 1e-10, f"dtau/d{name}")
    B = np.eye(m.nv)
    B[np.ix_(R, P)] = -M[np.ix_(R, P)]
    expected = np.zeros((m.nv, m.nv))
    expected[R] = np.linalg.solve(M_RR, B[R])
    expected[P] = B[P]
    assert_close(dqdd_du, expected, 1e-10, "dqdd/du")
    tau_expected = np.zeros((m.nv, m.nv))
    tau_expected[np.ix_(R, R)] = np.eye(R.sum())
    tau_expected[P] = M[P] @ expected
    assert_close(dtau_du, tau_expected, 1e-10, "dtau/du")


@pytest.mark.parametrize("seed,floating", CASES[:6], ids=CASE_IDS[:6])
def test_random_tree_hybrid_masks(seed, floating):
    c = make_case(seed, floating)
    m = c.m
    for fraction in (0.3, 0.7, 1.0):
        mask = c.rng.random(m.nv) < fraction
        m.set_prescribed(mask)
        v, u = c.rng.normal(size=m.nv), c.rng.normal(size=m.nv)
        f = c.rng.normal(size=(m.nbodies, 6))
        check_hybrid(m, c.q, v, u, f, rtol=10 * FD_RTOL)
        check_partition_identities(m, c.q, v, u, soadyn.dynamics_derivatives(m, c.q, v, u))
    m.set_prescribed(np.zeros(m.nv, dtype=bool))


@pytest.mark.parametrize("name", sorted(ROBOTS))
def test_robot_hybrid_masks(name):
    m, _ = robot_with_oracle(name, True)
    rng = np.random.default_rng(3)
    try:
        for fraction in (0.5, 1.0):
            m.set_prescribed(rng.random(m.nv) < fraction)
            q, v, u = soadyn.random_configuration(m, 2), rng.normal(size=m.nv), rng.normal(size=m.nv)
            analytic = check_hybrid(m, q, v, u)
            check_partition_identities(m, q, v, u, analytic)
    finally:
        m.set_prescribed(np.zeros(m.nv, dtype=bool))


def test_all_prescribed_is_inverse_dynamics():
    c = make_case(0, True)
    m = c.m
    m.set_prescribed(np.ones(m.nv, dtype=bool))
    try:
        v, qdd = c.rng.normal(size=m.nv), c.rng.normal(size=m.nv)
        dqdd_dq, dqdd_dv, dqdd_du, dtau_dq, dtau_dv, dtau_du = soadyn.dynamics_derivatives(m, c.q, v, qdd)
        id_dq, id_dv, M = soadyn.inverse_dynamics_derivatives(m, c.q, v, qdd)
        assert not dqdd_dq.any() and not dqdd_dv.any()
        assert np.array_equal(dqdd_du, np.eye(m.nv))
        assert_close(dtau_dq, id_dq, 1e-14, "dtau/dq")
        assert_close(dtau_dv, id_dv, 1e-14, "dtau/dv")
        assert_close(dtau_du, M, 1e-14, "dtau/du = M")
    finally:
        m.set_prescribed(np.zeros(m.nv, dtype=bool))


# --- bad input ---------------------------------------------------------------------------------

def test_bad_input_is_named():
    c = make_case(1, False)
    m = c.m
    q, v = c.q.copy(), np.zeros(m.nv)
    bad = v.copy()
    bad[3] = np.nan
    with pytest.raises(ValueError, match=m.dof_names[3]):
        soadyn.dynamics_derivatives(m, q, v, bad)
    with pytest.raises(ValueError, match="f_ext"):
        soadyn.inverse_dynamics_derivatives(m, q, v, v, np.zeros((m.nbodies, 5)))
    with pytest.raises(ValueError):
        soadyn.dynamics_derivatives(m, q[:-1], v, v)


# --- force elements ------------------------------------------------------------------------------

def mass_on_spring(mass=2.0, stiffness=50.0, damping=0.7, rest=0.1):
    m = soadyn.Model()
    m.gravity = np.zeros(3)
    m.add_body("cart", "world", soadyn.Joint.prismatic([1, 0, 0]), mass=mass, com=[0, 0, 0],
               inertia=np.eye(3) * 0.01)
    m.add_joint_spring("spring", "cart", stiffness, damping=damping, rest=rest)
    return m


def test_joint_spring_derivatives_are_the_oscillators():
    """m x'' + c x' + k (x - rest) = u: dqdd/dq = -k/m, dqdd/dv = -c/m, dqdd/du = 1/m; and the
    sensitivity to the stiffness is -(x - rest)/m."""
    m = mass_on_spring()
    q, v, u = np.array([0.4]), np.array([-1.2]), np.array([3.0])
    dqdd_dq, dqdd_dv, dqdd_du = soadyn.dynamics_derivatives(m, q, v, u)[:3]
    assert dqdd_dq[0, 0] == pytest.approx(-50.0 / 2.0, rel=1e-14)
    assert dqdd_dv[0, 0] == pytest.approx(-0.7 / 2.0, rel=1e-14)
    assert dqdd_du[0, 0] == pytest.approx(1 / 2.0, rel=1e-14)
    dtau_dq, dtau_dv, M = soadyn.inverse_dynamics_derivatives(m, q, v, np.zeros(1))
    assert dtau_dq[0, 0] == pytest.approx(50.0, rel=1e-14) and dtau_dv[0, 0] == pytest.approx(0.7, rel=1e-14)
    dqdd_dk = soadyn.parameter_sensitivity(m, q, v, u, ["spring.stiffness"])["spring.stiffness"][0]
    assert dqdd_dk[0] == pytest.approx(-(0.4 - 0.1) / 2.0, rel=1e-14)
    assert soadyn.modes(m, np.zeros(1)).angular_frequencies[0] == pytest.approx(5.0, rel=1e-14)
    assert soadyn.modes(m, np.zeros(1)).damping_ratios[0] == pytest.approx(0.7 / (2 * np.sqrt(50.0 * 2.0)), rel=1e-12)


@pytest.mark.parametrize("seed", [0, 1])
def test_joint_springs_on_random_trees_against_differences(seed):
    c = make_case(seed, True)
    m = c.m.copy()
    scalar = [i for i, kind in enumerate(m.joint_types) if kind in ("revolute", "prismatic", "helical", "universal")]
    for k, i in enumerate(scalar[:4]):
        m.add_joint_spring(f"spring{k}", m.dof_names[m.v_index[i]], 10.0 + k, damping=0.5 * k, rest=0.1 * k)
    m.set_prescribed(c.rng.random(m.nv) < 0.3)
    v, u = c.rng.normal(size=m.nv), c.rng.normal(size=m.nv)
    check_hybrid(m, c.q, v, u, rtol=10 * FD_RTOL)


def test_point_spring_derivatives_are_the_oscillators():
    """A cart pulled by a spring to an anchor at (d, 0, 0), rest length L0: m x'' = k (d - x - L0) + u,
    so dqdd/dq = -k/m (by the dual-number sweeps, which carry point springs)."""
    m = soadyn.Model()
    m.gravity = np.zeros(3)
    m.add_body("cart", "world", soadyn.Joint.prismatic([1, 0, 0]), mass=2.0, com=[0, 0, 0],
               inertia=np.eye(3) * 0.01)
    m.add_point_spring("strut", "cart", None, 30.0, damping=0.4, rest_length=0.5,
                       placement_b=(np.eye(3), [2.0, 0, 0]))
    q, v, u = np.array([0.3]), np.array([0.7]), np.array([1.0])
    dqdd_dq, dqdd_dv, dqdd_du = soadyn.dynamics_derivatives(m, q, v, u)[:3]
    assert dqdd_dq[0, 0] == pytest.approx(-15.0, rel=1e-12)
    assert dqdd_dv[0, 0] == pytest.approx(-0.2, rel=1e-12)
    assert dqdd_du[0, 0] == pytest.approx(0.5, rel=1e-12)
    dtau_dq, dtau_dv, M = soadyn.inverse_dynamics_derivatives(m, q, v, np.zeros(1))
    assert dtau_dq[0, 0] == pytest.approx(30.0, rel=1e-12) and M[0, 0] == pytest.approx(2.0, rel=1e-12)
    A, B = soadyn.linearize(m, q, v, u)  # through the dual-number sweeps too
    np.testing.assert_allclose(A, [[0.0, 1.0], [-15.0, -0.2]], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(B, [[0.0], [0.5]], rtol=1e-12, atol=1e-15)
    md = soadyn.modes(m, q)  # m x'' + c x' + k x = 0: w = sqrt(k/m), zeta = c / (2 sqrt(k m))
    assert md.angular_frequencies[0] == pytest.approx(np.sqrt(15.0), rel=1e-12)
    assert md.damping_ratios[0] == pytest.approx(0.4 / (2 * np.sqrt(60.0)), rel=1e-12)
    eq = soadyn.static_equilibrium(m, q)  # the spring at its rest length: x = d - L0, stiffness k
    assert eq.q[0] == pytest.approx(1.5, rel=1e-12)
    np.testing.assert_allclose(eq.stiffness_eigenvalues, [30.0], rtol=1e-12)


@pytest.mark.parametrize("seed", [0, 1])
def test_point_springs_on_random_trees_against_differences(seed):
    c = make_case(seed, True)
    m = c.m.copy()
    for k in range(3):
        m.add_point_spring(f"strut{k}", m.body_names[2 * k + 1], m.body_names[2 * k + 4], 20.0 + k,
                           damping=0.3, rest_length=0.2 + 0.1 * k)
    m.set_prescribed(c.rng.random(m.nv) < 0.3)
    v, u = c.rng.normal(size=m.nv), c.rng.normal(size=m.nv)
    check_hybrid(m, c.q, v, u, rtol=10 * FD_RTOL)
    m.set_prescribed(np.zeros(m.nv, dtype=bool))
    qdd = c.rng.normal(size=m.nv)
    dq, dv, M = soadyn.inverse_dynamics_derivatives(m, c.q, v, qdd)
    fd_dq = central_differences(lambda x: soadyn.inverse_dynamics(m, x, v, qdd), c.q,
                                lambda x, e: soadyn.integrate(m, x, e, 1.0), m.nv)
    assert_close(dq, fd_dq, FD_RTOL, "dtau/dq with point springs")
    assert_close(M, soadyn.mass_matrix(m, c.q), 1e-13, "M")


# --- loop models and flexible bodies ---------------------------------------------------------------

def constrained_by_differences(m, q, v, u, directions):
    """Derivatives of constrained_dynamics' (qdd, tau) by central differences: along q in the given
    tangent directions (columns), kept on the closure by soadyn.assemble (its correction is second
    order), and along every v and u."""
    def out(k):
        return lambda args: soadyn.constrained_dynamics(m, *args)[k]

    def along_q(k):
        columns = []
        for d in directions.T:
            plus = soadyn.assemble(m, soadyn.integrate(m, q, d, EPS))
            minus = soadyn.assemble(m, soadyn.integrate(m, q, d, -EPS))
            columns.append((out(k)((plus, v, u)) - out(k)((minus, v, u))) / (2 * EPS))
        return np.stack(columns, axis=1)

    result = []
    for k in (0, 1):
        result.append([
            along_q(k),
            central_differences(lambda x: out(k)((q, x, u)), v, lambda x, e: x + e, m.nv),
            central_differences(lambda x: out(k)((q, v, x)), u, lambda x, e: x + e, m.nv)])
    return result[0] + result[1]


LOOP_CASES = {
    "four-bar": (soadyn.scenes.four_bar, lambda: soadyn.scenes.four_bar_state(0.7, 1.3), ["crank"]),
    "four-bar-point": (lambda: soadyn.scenes.four_bar("point"), lambda: soadyn.scenes.four_bar_state(-0.4, 0.8),
                       ["crank"]),
    "slider-crank": (soadyn.scenes.slider_crank, lambda: soadyn.scenes.slider_crank_state(0.5, -2.0), ["crank"]),
    "delta-robot": (soadyn.scenes.delta_robot,
                    lambda: soadyn.scenes.delta_robot_state((0.05, -0.02, -0.6), (0.1, 0.2, -0.1)),
                    ["arm_1", "arm_2", "arm_3"]),
}


@pytest.mark.parametrize("name", sorted(LOOP_CASES))
@pytest.mark.parametrize("driven", [False, True], ids=["free", "driven"])
def test_loop_model_derivatives_against_differences(name, driven):
    build, state, drives = LOOP_CASES[name]
    m = build()
    q, v = state()
    if driven:
        m.set_prescribed(drives)
    u = np.random.default_rng(8).normal(size=m.nv)
    # Tangent directions that keep the loops closed: the null space of the loop Jacobian. (Off
    # the closure a redundant cut's equations can change rank, so the dynamics are not smooth
    # there: their derivative is taken along the closure.)
    C = soadyn.loop_jacobian(m, q)
    _, sv, vt = np.linalg.svd(C)
    rank = int((sv > 1e-9 * sv.max()).sum())
    directions = vt[rank:].T
    assert directions.shape[1] >= 1
    analytic = list(soadyn.dynamics_derivatives(m, q, v, u))
    analytic[0], analytic[3] = analytic[0] @ directions, analytic[3] @ directions
    reference = constrained_by_differences(m, q, v, u, directions)
    for label, a, r in zip(NAMES, analytic, reference):
        scale = max(np.abs(r).max(initial=0.0), 1.0)
        error = np.abs(a - r).max(initial=0.0) / scale
        assert error <= 10 * FD_RTOL, f"{name} {label}: relative error {error:.2e}"


FLEXIBLE_CASES = {  # random flexible trees: bodies on nodes (body-frame sweeps) and appendages (tree frames)
    "on-nodes": dict(), "appendages-floating-damped": dict(appendages=True, floating=True, damping=True),
    "on-nodes-floating": dict(floating=True),
}


@pytest.mark.parametrize("name", sorted(FLEXIBLE_CASES))
@pytest.mark.parametrize("masked", [False, True], ids=["regular", "mixed"])
def test_flexible_model_derivatives_against_differences(name, masked):
    """Flexible bodies (modal coordinates among the DOFs) by the dual-number sweeps, against central
    differences of hybrid_dynamics; and inverse_dynamics_derivatives against those of inverse_dynamics."""
    from support.flexible_trees import random_flexible_tree
    seed = sorted(FLEXIBLE_CASES).index(name)
    m = random_flexible_tree(seed, **FLEXIBLE_CASES[name])[0]
    assert any(m.n_modes)
    rng = np.random.default_rng(seed)
    q = soadyn.integrate(m, soadyn.neutral_configuration(m), 0.3 * rng.normal(size=m.nv), 1.0)
    v, u = rng.normal(size=m.nv), rng.normal(size=m.nv)
    if masked:
        m.set_prescribed((rng.random(m.nv) < 0.4) & ~m.modal)
    for label, a, r in zip(NAMES, soadyn.dynamics_derivatives(m, q, v, u), hybrid_by_differences(m, q, v, u)):
        assert_close(a, r, FD_RTOL, f"{name} {label}")
    qdd = rng.normal(size=m.nv)
    dq, dv, M = soadyn.inverse_dynamics_derivatives(m, q, v, qdd)
    assert_close(dq, central_differences(lambda x: soadyn.inverse_dynamics(m, x, v, qdd), q,
                                         lambda x, e: soadyn.integrate(m, x, e, 1.0), m.nv), FD_RTOL, "dtau/dq")
    assert_close(dv, central_differences(lambda x: soadyn.inverse_dynamics(m, q, x, qdd), v,
                                         lambda x, e: x + e, m.nv), FD_RTOL, "dtau/dv")
    assert_close(M, soadyn.mass_matrix(m, q), 1e-12, "M")
