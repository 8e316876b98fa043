"""The hybrid (prescribed/regular) dynamics against the dense equations of
motion: Jain & Rodriguez 1993, Eq. 10 (M qdd + h = tau) and its partitioned solve, Eq. 12."""
import numpy as np
import pytest

import soadyn
from support.trees import JOINT_KINDS, random_state, random_tree

SEEDS = range(8)
RTOL = 1e-10


def assert_close(actual, expected, rtol=RTOL):
    scale = max(1.0, float(np.max(np.abs(expected))))
    err = float(np.max(np.abs(np.asarray(actual) - np.asarray(expected))))
    assert err <= rtol * scale, f"max error {err:.3e} > {rtol:.0e} * {scale:.3e}"


def dense_state(seed, floating=True, nbodies=14):
    m, _ = random_tree(seed, nbodies, floating=floating)
    q, v, rng = random_state(m, seed)
    M = soadyn.mass_matrix(m, q)
    h = soadyn.bias_forces(m, q, v)
    return m, q, v, rng, M, h


def partitioned_solve(M, h, mask, u):
    """Jain & Rodriguez 1993, Eq. 12: known tau_r and qdd_p; unknown qdd_r and tau_p."""
    r, p = ~mask, mask
    qdd = np.empty(len(u))
    tau = np.empty(len(u))
    qdd[p] = u[p]
    tau[r] = u[r]
    qdd[r] = np.linalg.solve(M[np.ix_(r, r)], u[r] - h[r] - M[np.ix_(r, p)] @ u[p])
    tau[p] = M[np.ix_(p, r)] @ qdd[r] + M[np.ix_(p, p)] @ u[p] + h[p]
    return qdd, tau


def check_mask(m, q, v, M, h, mask, u):
    """Hybrid dynamics under `mask` equals the dense partitioned solve."""
    m.set_prescribed(mask)
    np.testing.assert_array_equal(m.prescribed, mask)
    qdd, tau = soadyn.hybrid_dynamics(m, q, v, u)
    qdd_ref, tau_ref = partitioned_solve(M, h, mask, u)
    assert_close(qdd, qdd_ref)
    assert_close(tau, tau_ref)


@pytest.mark.parametrize("floating", [True, False])
@pytest.mark.parametrize("seed", SEEDS)
def test_all_regular_is_mass_matrix_solve(seed, floating):
    m, q, v, rng, M, h = dense_state(seed, floating)
    tau = rng.normal(size=m.nv)
    expected = np.linalg.solve(M, tau - h)
    qdd, tau_out = soadyn.hybrid_dynamics(m, q, v, tau)
    assert_close(qdd, expected)
    np.testing.assert_array_equal(tau_out, tau)
    assert_close(soadyn.forward_dynamics(m, q, v, tau), expected)
    # Asking for joint wrenches takes the general three-sweep path.
    qdd, tau_out, wrenches = soadyn.hybrid_dynamics(m, q, v, tau, joint_wrenches=True)
    assert_close(qdd, expected)
    np.testing.assert_array_equal(tau_out, tau)
    assert_close(wrenches, soadyn.joint_wrenches(m, q, v, qdd))


@pytest.mark.parametrize("floating", [True, False])
@pytest.mark.parametrize("seed", SEEDS)
def test_all_prescribed_is_inverse_dynamics(seed, floating):
    m, q, v, rng, M, h = dense_state(seed, floating)
    qdd = rng.normal(size=m.nv)
    m.set_prescribed(np.ones(m.nv, dtype=bool))
    qdd_out, tau = soadyn.hybrid_dynamics(m, q, v, qdd)
    np.testing.assert_array_equal(qdd_out, qdd)
    assert_close(tau, soadyn.inverse_dynamics(m, q, v, qdd))
    assert_close(tau, M @ qdd + h)


@pytest.mark.parametrize("seed", SEEDS)
def test_random_masks_match_partitioned_solve(seed):
    m, q, v, rng, M, h = dense_state(seed)
    for _ in range(6):
        mask = rng.uniform(size=m.nv) < rng.uniform(0.2, 0.8)
        check_mask(m, q, v, M, h, mask, rng.normal(size=m.nv))


@pytest.mark.parametrize("seed", SEEDS)
def test_inverse_dynamics_reproduces_hybrid_outputs(seed):
    """RNEA fed the hybrid accelerations gives back every torque and every joint wrench."""
    m, q, v, rng, _, _ = dense_state(seed)
    f_ext = rng.normal(size=(m.nbodies, 6))
    for _ in range(4):
        m.set_prescribed(rng.uniform(size=m.nv) < 0.5)
        u = rng.normal(size=m.nv)
        qdd, tau, wrenches = soadyn.hybrid_dynamics(m, q, v, u, f_ext=f_ext, joint_wrenches=True)
        assert_close(soadyn.inverse_dynamics(m, q, v, qdd, f_ext=f_ext), tau)
        assert_close(soadyn.joint_wrenches(m, q, v, qdd, f_ext=f_ext), wrenches)


def test_multi_dof_hinges_mix_modes():
    """Jain & Rodriguez 1993, conclusion 5: one DOF of a spherical/free/planar/universal hinge prescribed, the others regular."""
    m, q, v, rng, M, h = dense_state(3, nbodies=20)
    multi = [n for n in m.dof_names if ":" in n]
    assert len({n.split(":")[0] for n in multi}) >= 5
    mask = np.zeros(m.nv, dtype=bool)
    for joint in sorted({n.split(":")[0] for n in multi}):
        dofs = [i for i, n in enumerate(m.dof_names) if n.startswith(joint + ":")]
        mask[dofs[:: 2]] = True  # every other DOF of the hinge
    check_mask(m, q, v, M, h, mask, rng.normal(size=m.nv))


def test_prescribed_hinge_below_regular_and_regular_below_prescribed():
    """Both region kinds of a tree: all-prescribed subtrees under regular hinges and vice versa."""
    m, q, v, rng, M, h = dense_state(5, floating=False, nbodies=16)
    n = m.nv
    for mask in (np.arange(n) < n // 2, np.arange(n) >= n // 2, np.arange(n) % 3 == 0):
        check_mask(m, q, v, M, h, mask, rng.normal(size=n))


@pytest.mark.parametrize("kind", JOINT_KINDS)
def test_every_joint_kind_alone(kind):
    """A two-body chain per joint kind, all masks."""
    m, _ = random_tree(11, 3, kinds=(kind,), floating=False)
    q, v, rng = random_state(m, 11)
    M = soadyn.mass_matrix(m, q)
    h = soadyn.bias_forces(m, q, v)
    for bits in range(2 ** min(m.nv, 6)):
        mask = np.array([(bits >> (k % 6)) & 1 for k in range(m.nv)], dtype=bool)
        check_mask(m, q, v, M, h, mask, rng.normal(size=m.nv))


def test_gravity_and_external_wrench_enter_as_forces():
    """A free body under gravity and a pure external force: qdd is the closed-form rigid-body answer."""
    m = soadyn.Model()
    m.add_body("box", None, soadyn.Joint.free(), mass=2.0, inertia=[0.1, 0.2, 0.3])
    q = soadyn.neutral_configuration(m)
    v = np.zeros(6)
    f = np.array([[0.0, 0.0, 0.0, 4.0, 0.0, 0.0]])  # 4 N along body x
    qdd = soadyn.forward_dynamics(m, q, v, np.zeros(6), f_ext=f)
    np.testing.assert_allclose(qdd, [0, 0, 0, 2.0, 0, -9.81], atol=1e-14)
    m.gravity = [0.0, 0.0, 0.0]
    np.testing.assert_allclose(soadyn.forward_dynamics(m, q, v, np.zeros(6)), np.zeros(6), atol=0)


@pytest.mark.parametrize("seed", SEEDS[:3])
def test_far_from_the_world_origin(seed):
    """Translating a free-floating tree by 1e6 m changes nothing: the sweeps refer spatial vectors to the
    root body's origin (tree frames), so no lever arm of 1e6 m eats the digits of the result."""
    m, q, v, rng, _, _ = dense_state(seed)
    u = rng.normal(size=m.nv)
    far = q.copy()
    far[:3] += np.array([1e6, -2e6, 3e6])  # the free root's position comes first
    m.set_prescribed(rng.uniform(size=m.nv) < 0.5)
    near_out, far_out = soadyn.hybrid_dynamics(m, q, v, u), soadyn.hybrid_dynamics(m, far, v, u)
    for a, b in zip(near_out, far_out):
        np.testing.assert_allclose(b, a, rtol=1e-12, atol=1e-12 * np.abs(a).max())
    m.set_prescribed(np.zeros(m.nv, dtype=bool))
    a, b = soadyn.forward_dynamics(m, q, v, u), soadyn.forward_dynamics(m, far, v, u)
    np.testing.assert_allclose(b, a, rtol=1e-12, atol=1e-12 * np.abs(a).max())
