"""Precision of small bodies far from their tree's root.

A body of RMS radius 1e-4 m hanging from a spherical joint at the end of a
lever arm of 1e-4 to 1e4 m: its hinge inertia is about 1e-11 while the
lever arm makes terms of up to 1e5 about the root. Forward and hybrid
dynamics and the mass matrix must agree with Pinocchio and must not change
when the whole tree is rotated (body-frame results of the same motion).
"""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import soadyn
from support.pinocchio_trees import BodySpec, Mapping, build_pinocchio, build_soadyn
from support.trees import random_rotation

LEVER_ARMS = [1e-4, 1e-2, 1.0, 1e2, 1e3, 1e4]
SMALL = 1e-4     # RMS radius of the small body (m)
# Errors relative to each DOF block's largest magnitude. Pinocchio's own
# results carry up to 1.3e-8 of error in the small body's block at 1e4 m
# (against a dense solve of M and h from body-frame Newton-Euler columns,
# where soadyn stays within 1.1e-10): the oracle's precision bounds the
# first comparison. The same tree turned in space must give soadyn's
# body-frame results to 1e-9.
PIN_RTOL = 1e-7
RTOL = 1e-9


def specs(lever: float, root_rotation: np.ndarray) -> list[BodySpec]:
    """A 1 kg hub on a revolute joint, a 2-link arm reaching `lever` metres out,
    and a 1 g, 1e-4 m body on a spherical joint at its tip."""
    z = np.array([0.0, 0.0, 1.0])
    eye = np.eye(3)

    def body(name, parent, kind, axis, rotation, translation, mass, com, inertia):
        return BodySpec(name=name, parent=parent, kind=kind, axis=axis, axis2=axis,
                        pitch=0.0, rotation=rotation, translation=np.asarray(translation, float), mass=mass,
                        com=np.asarray(com, float), inertia=np.asarray(inertia, float))

    half = 0.5 * lever
    rod = 0.5 * half ** 2 / 12 * np.diag([0.01, 1.0, 1.0]) + 1e-9 * np.eye(3)  # 0.5 kg links of length `half`
    return [
        body("hub", -1, "revolute", z, root_rotation, [0, 0, 0], 1.0, [0.1, 0, 0], np.diag([0.01, 0.01, 0.01])),
        body("upper", 0, "revolute", np.array([0.0, 1.0, 0.0]), eye, [0.05, 0, 0], 0.5, [0.5 * half, 0, 0],
             rod),
        body("fore", 1, "revolute", z, eye, [half, 0, 0], 0.5, [0.5 * half, 0, 0],
             rod),
        body("tip", 2, "spherical", z, eye, [half, 0, 0], 1e-3, [0.5 * SMALL, 0, 0],
             1e-3 * SMALL ** 2 * np.diag([0.3, 0.4, 0.5])),
    ]


def state(m: soadyn.Model, seed: int):
    rng = np.random.default_rng(seed)
    q = soadyn.random_configuration(m, seed)
    v = rng.uniform(-1, 1, m.nv)
    u = rng.uniform(-1, 1, m.nv) * np.r_[1.0, 1.0, 1.0, 1e-11, 1e-11, 1e-11]
    return q, v, u


def block_error(a: np.ndarray, b: np.ndarray, blocks) -> float:
    """Largest error relative to the magnitude of its DOF block (joint)."""
    return max(np.abs(a[r] - b[r]).max() / max(np.abs(b[r]).max(), 1e-300) for r in blocks)


def mass_matrix_error(A: np.ndarray, B: np.ndarray) -> float:
    """Entry errors relative to sqrt(B_ii B_jj), the scale of each entry of a mass matrix."""
    d = np.sqrt(np.abs(np.diag(B)))
    return float((np.abs(A - B) / np.outer(d, d)).max())


BLOCKS = [slice(0, 1), slice(1, 2), slice(2, 3), slice(3, 6)]
GRAVITY = np.array([0.0, 0.0, -9.81])


def soadyn_model(lever: float, rotation: np.ndarray) -> soadyn.Model:
    m = build_soadyn(specs(lever, rotation))
    m.gravity = rotation @ GRAVITY  # the world turned with the tree: the same motion
    return m


def partitioned_solve(M, h, u, prescribed):
    """Hybrid dynamics from the dense equations (Jain & Rodriguez's Eq. 12): the
    regular accelerations solve M_rr qdd_r = u_r - h_r - M_rp qdd_p, then the
    prescribed forces are M_p. qdd + h_p."""
    r, p = ~prescribed, prescribed
    qdd = u.copy()
    qdd[r] = np.linalg.solve(M[np.ix_(r, r)], u[r] - h[r] - M[np.ix_(r, p)] @ u[p])
    tau = u.copy()
    tau[p] = M[p] @ qdd + h[p]
    return qdd, tau


def driven_arm(m: soadyn.Model, tau: np.ndarray):
    """The arm's two joints prescribed (accelerations 0.3, -0.2); hub and small body free."""
    prescribed = np.isin(np.arange(m.nv), [1, 2])
    u = tau.copy()
    u[[1, 2]] = [0.3, -0.2]
    return prescribed, u


@pytest.mark.parametrize("lever", LEVER_ARMS)
def test_small_body_far_out_agrees_with_pinocchio(lever):
    tree = specs(lever, np.eye(3))
    m = build_soadyn(tree)
    model = build_pinocchio(tree, GRAVITY)
    data = model.createData()
    mapping = Mapping(m, model, tree)
    perm = mapping.perm
    assert list(perm) == list(range(m.nv))  # one chain: both libraries order the DOFs alike
    for seed in range(3):
        q, v, tau = state(m, seed)
        qp = mapping.q(q)
        assert block_error(soadyn.forward_dynamics(m, q, v, tau), pin.aba(model, data, qp, v, tau), BLOCKS) < PIN_RTOL
        M = pin.crba(model, data, qp)
        M = np.triu(M) + np.triu(M, 1).T
        assert mass_matrix_error(soadyn.mass_matrix(m, q), M) < PIN_RTOL
        prescribed, u = driven_arm(m, tau)
        m.set_prescribed(prescribed)
        qdd, forces = soadyn.hybrid_dynamics(m, q, v, u)
        m.set_prescribed(np.zeros(m.nv, dtype=bool))
        expected_qdd, expected_tau = partitioned_solve(M, pin.nle(model, data, qp, v), u, prescribed)
        assert block_error(qdd, expected_qdd, BLOCKS) < PIN_RTOL
        assert block_error(forces, expected_tau, BLOCKS) < PIN_RTOL


@pytest.mark.parametrize("lever", LEVER_ARMS)
def test_small_body_far_out_does_not_depend_on_the_tree_orientation(lever):
    rng = np.random.default_rng(7)
    upright = soadyn_model(lever, np.eye(3))
    turned = [soadyn_model(lever, random_rotation(rng)) for _ in range(3)]
    for seed in range(3):
        q, v, tau = state(upright, seed)
        expected = soadyn.forward_dynamics(upright, q, v, tau)
        expected_M = soadyn.mass_matrix(upright, q)
        prescribed, u = driven_arm(upright, tau)
        upright.set_prescribed(prescribed)
        expected_hybrid = soadyn.hybrid_dynamics(upright, q, v, u)
        for m in turned:
            assert block_error(soadyn.forward_dynamics(m, q, v, tau), expected, BLOCKS) < RTOL
            assert mass_matrix_error(soadyn.mass_matrix(m, q), expected_M) < RTOL
            m.set_prescribed(prescribed)
            qdd, forces = soadyn.hybrid_dynamics(m, q, v, u)
            m.set_prescribed(np.zeros(m.nv, dtype=bool))
            assert block_error(qdd, expected_hybrid[0], BLOCKS) < RTOL
            assert block_error(forces, expected_hybrid[1], BLOCKS) < RTOL
        upright.set_prescribed(np.zeros(upright.nv, dtype=bool))
