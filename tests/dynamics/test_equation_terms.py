"""The equations of motion term by term: g(q), J' f_ext, C(q, v), dM/dt and the
Christoffel symbols, against Pinocchio (computeGeneralizedGravity,
computeCoriolisMatrix, rnea with and without f_ext) on the example-robot-data
robots and the random trees of support/pinocchio_trees.py, and against central
differences of soadyn.mass_matrix and soadyn.potential_energy.

Derivatives with respect to q are taken in the tangent space: d/dq_k f(q) is
(f(q (+) eps e_k) - f(q (+) -eps e_k)) / (2 eps) with (+) = soadyn.integrate,
so for spherical, planar and free joints (body-frame velocities) they are
derivatives along moving-frame directions e_k whose Lie brackets are those of
the joint's group; the Christoffel symbols then carry the bracket terms
(Koszul's formula, in `christoffel_by_differences`).
"""
from __future__ import annotations

import functools

import numpy as np
import pinocchio as pin
import pytest

import soadyn
from support.flexible_trees import random_flexible_state, random_flexible_tree
from support.four_bar import assembled, four_bar
from support.pinocchio_trees import CASE_IDS, CASES, make_case
from support.robots import ROBOTS, matrix_from_pin, robot_with_oracle

RTOL = 1e-12       # against Pinocchio and exact identities, relative to the largest reference entry
FD_RTOL = 1e-8     # against central differences (eps = 1e-5: truncation ~1e-10, rounding ~1e-11)
EPS = 1e-5


def assert_close(actual, expected, rtol, what, scale=None):
    """max |actual - expected| <= rtol * scale, scale the largest |expected| unless given."""
    actual, expected = np.asarray(actual), np.asarray(expected)
    assert actual.shape == expected.shape, what
    scale = np.abs(expected).max(initial=0.0) if scale is None else scale
    assert scale > 0, what
    error = np.abs(actual - expected).max(initial=0.0) / scale
    assert error <= rtol, f"{what}: relative error {error:.2e} > {rtol:.0e}"


def tangent_derivative(f, m, q, k, eps=EPS):
    e = np.zeros(m.nv)
    e[k] = 1.0
    return (f(soadyn.integrate(m, q, e, eps)) - f(soadyn.integrate(m, q, e, -eps))) / (2 * eps)


def mass_matrix_rate_by_differences(m, q, v, eps=EPS):
    """dM/dt along the motion q(t) = q (+) t v."""
    return (soadyn.mass_matrix(m, soadyn.integrate(m, q, v, eps))
            - soadyn.mass_matrix(m, soadyn.integrate(m, q, v, -eps))) / (2 * eps)


def _levi_civita_3():
    eps3 = np.zeros((3, 3, 3))
    for a, b, c in [(0, 1, 2), (1, 2, 0), (2, 0, 1)]:
        eps3[a, b, c], eps3[b, a, c] = 1.0, -1.0
    return eps3


def frame_brackets(m):
    """c[a, b, l] with [e_a, e_b] = sum_l c[a, b, l] e_l for the DOF directions of
    soadyn.integrate: zero for joints whose coordinates integrate their velocities;
    so(3) for spherical joints (w x w'), se(3) for free joints (v = (w, v_origin),
    [(w, u), (w', u')] = (w x w', w x u' - w' x u)), se(2) for planar joints
    (v = (vx, vy, wz): [e_wz, e_vx] = e_vy, [e_wz, e_vy] = -e_vx)."""
    nv, eps3 = m.nv, _levi_civita_3()
    c = np.zeros((nv, nv, nv))
    for i, kind in enumerate(m.joint_types):
        o = m.v_index[i]
        w, u = slice(o, o + 3), slice(o + 3, o + 6)
        if kind in ("spherical", "free"):
            c[w, w, w] = eps3
        if kind == "free":
            c[w, u, u] = eps3
            c[u, w, u] = -eps3.transpose(1, 0, 2)
        if kind == "planar":
            vx, vy, wz = o, o + 1, o + 2
            c[wz, vx, vy], c[vx, wz, vy] = 1.0, -1.0
            c[wz, vy, vx], c[vy, wz, vx] = -1.0, 1.0
    return c


def christoffel_by_differences(m, q):
    """Gamma[i, j, k] = <nabla_{e_k} e_j, e_i> by Koszul's formula with <a, b> = a' M b:
    1/2 (dM_ij/dq_k + dM_ik/dq_j - dM_jk/dq_i) + 1/2 (<[e_k, e_j], e_i> - <[e_k, e_i], e_j> - <[e_j, e_i], e_k>)."""
    dM = np.stack([tangent_derivative(functools.partial(soadyn.mass_matrix, m), m, q, k) for k in range(m.nv)],
                  axis=2)  # dM[i, j, k] = dM_ij / dq_k
    bracket = np.einsum("abl,lc->abc", frame_brackets(m), soadyn.mass_matrix(m, q))  # <[e_a, e_b], e_c>
    return 0.5 * (dM + np.einsum("ikj->ijk", dM) - np.einsum("jki->ijk", dM)
                  + np.einsum("kji->ijk", bracket) - np.einsum("kij->ijk", bracket) - np.einsum("jik->ijk", bracket))


def check_identities(m, q, v):
    """The identities every model must meet, Pinocchio or not."""
    C = soadyn.coriolis_matrix(m, q, v)
    g = soadyn.gravity_forces(m, q)
    h = soadyn.bias_forces(m, q, v)
    assert_close(C @ v + g, h, RTOL, "C v + g = bias_forces")
    assert_close(g, soadyn.bias_forces(m, q, np.zeros(m.nv)), RTOL, "g = h(q, 0)")
    Mdot = soadyn.mass_matrix_derivative(m, q, v)
    assert_close(Mdot, C + C.T, RTOL, "dM/dt = C + C'")
    N = Mdot - 2 * C
    assert_close(N + N.T, np.zeros_like(N), RTOL, "dM/dt - 2C skew-symmetric", scale=np.abs(Mdot).max())
    assert_close(Mdot, mass_matrix_rate_by_differences(m, q, v), FD_RTOL, "dM/dt by central differences")
    gamma = soadyn.christoffel_symbols(m, q)
    assert gamma.shape == (m.nv,) * 3
    assert_close(np.einsum("ijk,k->ij", gamma, v), C, RTOL, "sum_k Gamma[:, :, k] v_k = C")
    # Symmetry in (j, k) up to the frame's brackets: Gamma[i,j,k] - Gamma[i,k,j] = <[e_k, e_j], e_i>.
    bracket = np.einsum("abl,lc->abc", frame_brackets(m), soadyn.mass_matrix(m, q))
    assert_close(gamma - gamma.transpose(0, 2, 1), np.einsum("kji->ijk", bracket), RTOL,
                 "torsion-free: Gamma[i,j,k] - Gamma[i,k,j] = <[e_k, e_j], e_i>", scale=np.abs(gamma).max())
    assert_close(gamma, christoffel_by_differences(m, q), FD_RTOL, "Christoffel symbols by differences of M")
    return C, g


# --- random trees: every joint kind, fixed and floating ------------------------------------------

@pytest.mark.parametrize("seed,floating", CASES, ids=CASE_IDS)
def test_random_tree_identities(seed, floating):
    c = make_case(seed, floating)
    check_identities(c.m, c.q, c.rng.normal(size=c.m.nv))


@pytest.mark.parametrize("seed,floating", CASES, ids=CASE_IDS)
def test_random_tree_against_pinocchio(seed, floating):
    c = make_case(seed, floating)
    v = c.rng.normal(size=c.m.nv)
    assert_close(c.map.v(soadyn.gravity_forces(c.m, c.q)),
                 pin.computeGeneralizedGravity(c.model, c.data, c.q_pin), RTOL, "gravity_forces")
    C = soadyn.coriolis_matrix(c.m, c.q, v)
    C_pin = c.map.matrix_from_pin(pin.computeCoriolisMatrix(c.model, c.data, c.q_pin, c.map.v(v)))
    # Pinocchio's computeCoriolisMatrix leaves out the rate of the universal joint's first axis in
    # its body frame (its C v then differs from nonLinearEffects - g); every other column is the same
    # matrix. The universal columns are checked by the identities (dM/dt by differences) and by
    # C v + g = nonLinearEffects below.
    universal = np.zeros(c.m.nv, dtype=bool)
    for i, kind in enumerate(c.m.joint_types):
        if kind == "universal":
            universal[c.m.v_index[i]:c.m.v_index[i] + 2] = True
    assert universal.any()
    assert_close(C[:, ~universal], C_pin[:, ~universal], RTOL, "coriolis_matrix (non-universal columns)")
    assert_close(c.map.v(C @ v + soadyn.gravity_forces(c.m, c.q)),
                 pin.nonLinearEffects(c.model, c.data, c.q_pin, c.map.v(v)), RTOL, "C v + g = nonLinearEffects")


@pytest.mark.parametrize("seed,floating", CASES, ids=CASE_IDS)
def test_random_tree_external_forces_against_pinocchio(seed, floating):
    """J' f_ext = rnea(q, v, a) - rnea(q, v, a, f_ext)."""
    c = make_case(seed, floating)
    v, a = c.rng.normal(size=c.m.nv), c.rng.normal(size=c.m.nv)
    f = c.rng.normal(size=(c.m.nbodies, 6))
    ref = (pin.rnea(c.model, c.data, c.q_pin, c.map.v(v), c.map.v(a))
           - pin.rnea(c.model, c.data, c.q_pin, c.map.v(v), c.map.v(a), c.map.f_ext(f)))
    assert_close(c.map.v(soadyn.external_forces_to_generalized(c.m, c.q, f)), ref, RTOL,
                 "external_forces_to_generalized")


# --- example-robot-data robots ----------------------------------------------------------------

@pytest.mark.parametrize("name", sorted(ROBOTS))
@pytest.mark.parametrize("floating", [False, True], ids=["fixed", "floating"])
def test_robot_against_pinocchio(name, floating):
    m, o = robot_with_oracle(name, floating)
    rng = np.random.default_rng(11)
    for state in range(2):
        q, v = soadyn.random_configuration(m, state), rng.normal(size=m.nv)
        C, g = check_identities(m, q, v) if state == 0 else (soadyn.coriolis_matrix(m, q, v),
                                                             soadyn.gravity_forces(m, q))
        q_pin = o.q(q)
        assert_close(g, o.from_pin(pin.computeGeneralizedGravity(o.model, o.data, q_pin)), RTOL,
                     f"{name} gravity_forces")
        C_pin = matrix_from_pin(o, pin.computeCoriolisMatrix(o.model, o.data, q_pin, o.to_pin(v)))
        assert_close(C, C_pin, RTOL, f"{name} coriolis_matrix")


# --- flexible bodies, loops, bad input -------------------------------------------------------------

def test_gravity_is_the_gradient_of_the_potential_energy():
    """g_k = dV/dq_k on a rigid tree; on a tree with deformed flexible bodies (modal DOFs
    included) potential_energy also holds the strain energy 1/2 eta' K eta, whose gradient
    K eta is not gravity: dV/dq = g + K eta."""
    rigid = make_case(3, True)
    flexible, parts = random_flexible_tree(4, floating=True)
    q_flexible = random_flexible_state(flexible, 4)[0]
    for m, q in [(rigid.m, rigid.q), (flexible, q_flexible)]:
        strain_gradient = np.zeros(m.nv)
        for part in parts if m is flexible else []:
            if part.flexible is None:
                continue
            modal = [k for k, n in enumerate(m.coordinate_names) if n.startswith(part.name + ":mode")]
            modal_v = [k for k, n in enumerate(m.dof_names) if n.startswith(part.name + ":mode")]
            assert len(modal) == len(modal_v) == part.flexible.n_modes
            strain_gradient[modal_v] = part.flexible.stiffness @ q[modal]
        assert (m is rigid.m) == (not strain_gradient.any())
        grad = np.array([tangent_derivative(lambda x: np.array(soadyn.potential_energy(m, x)), m, q, k)
                         for k in range(m.nv)])
        assert_close(soadyn.gravity_forces(m, q) + strain_gradient, grad, FD_RTOL, "gravity_forces = dV/dq")


def test_flexible_models_are_refused_by_name():
    m, parts = random_flexible_tree(4)
    flexible = [p.name for p in parts if p.flexible is not None]
    q, v, _ = random_flexible_state(m, 4)
    for call in (lambda: soadyn.coriolis_matrix(m, q, v), lambda: soadyn.mass_matrix_derivative(m, q, v),
                 lambda: soadyn.christoffel_symbols(m, q)):
        with pytest.raises(ValueError, match=f"body '{flexible[0]}' is flexible"):
            call()


def test_loop_model_terms_are_the_spanning_trees():
    m = four_bar()
    q = assembled(0.7)
    v = np.array([1.3, -0.4, 0.9])
    check_identities(m, q, v)


def test_external_forces_are_checked_by_name():
    c = make_case(0, False)
    with pytest.raises(ValueError, match="f_ext"):
        soadyn.external_forces_to_generalized(c.m, c.q, np.zeros((c.m.nbodies - 1, 6)))
    f = np.zeros((c.m.nbodies, 6))
    f[2, 4] = np.nan
    with pytest.raises(ValueError, match=c.m.body_names[2]):
        soadyn.external_forces_to_generalized(c.m, c.q, f)
    with pytest.raises(ValueError, match="v"):
        soadyn.coriolis_matrix(c.m, c.q, np.zeros(c.m.nv + 1))
