"""Constrained dynamics of random trees closed by 1-3 loops against
Pinocchio's constraint dynamics (pin.RigidConstraintModel +
pin.initConstraintDynamics + pin.constraintDynamics, proximal settings tight).

Each loop joins a frame on one body (frame_a, Pinocchio's joint1 placement)
to a frame on another body or the world (frame_b, joint2), placed so that
the loop is closed at the drawn configuration; the velocity is projected onto
the loop's tangent space. "point" is Pinocchio's CONTACT_3D, "weld" its
CONTACT_6D. Pinocchio's multipliers are, in the LOCAL frame of joint1's
placement, the force (CONTACT_3D) or the spatial force (linear, angular;
CONTACT_6D) the constraint applies to joint1's side, which soadyn reports in
world axes as loop_wrenches [torque; force]."""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import soadyn
from support.closed_loops import closed_loop_case, pinocchio_solution

RTOL = 1e-9
CASES = [(seed, floating, nloops) for seed in range(4) for floating in (True, False) for nloops in (1, 2, 3)]
IDS = [f"seed{s}-{'floating' if f else 'fixed'}-{n}loops" for s, f, n in CASES]


@pytest.mark.parametrize("seed,floating,nloops", CASES, ids=IDS)
@pytest.mark.parametrize("kinds", [("point",), ("weld",), ("point", "weld")], ids=["point", "weld", "mixed"])
def test_constrained_dynamics_matches_pinocchio(seed, floating, nloops, kinds):
    m, model, mapping, constraints, q, v, rng, _ = closed_loop_case(seed, floating, nloops, kinds)
    assert np.abs(soadyn.loop_residual(m, q)).max() < 1e-12
    tau = rng.normal(size=m.nv)
    qdd, tau_out, wrenches = soadyn.constrained_dynamics(m, q, v, tau)
    qdd_pin, lam_pin = pinocchio_solution(model, mapping, constraints, q, v, tau)
    scale = max(1.0, np.abs(qdd_pin).max())
    assert np.abs(qdd - qdd_pin).max() <= RTOL * scale
    np.testing.assert_array_equal(tau_out, tau)
    C = soadyn.loop_jacobian(m, q)
    if np.linalg.matrix_rank(C) < C.shape[0]:
        # Redundant loop equations: the multipliers are not unique (soadyn gives the minimum-norm ones),
        # the generalized loop force C' lambda = M qdd + h - tau is, and qdd above already pins it.
        return
    # Pinocchio's multipliers in soadyn's convention, loop by loop.
    poses = soadyn.forward_kinematics(m, q)[0]
    row = 0
    expected = np.zeros((m.nloops, 6))
    for k, c in enumerate(constraints):
        RA = (poses[c.joint1_id - 1] @ c.joint1_placement.homogeneous)[:3, :3]
        size = 3 if c.type == pin.ContactType.CONTACT_3D else 6
        if size == 3:
            expected[k, 3:] = RA @ lam_pin[row:row + 3]
        else:
            expected[k, :3] = RA @ lam_pin[row + 3:row + 6]
            expected[k, 3:] = RA @ lam_pin[row:row + 3]
        row += size
    assert np.abs(wrenches - expected).max() <= RTOL * max(1.0, np.abs(expected).max())


@pytest.mark.parametrize("seed,floating,nloops", CASES, ids=IDS)
def test_models_with_flexible_bodies_take_the_mass_matrix_path(seed, floating, nloops):
    """A model with a flexible body is off the rigid tree-frame path (model.hpp, DynamicsPath), so
    constrained_dynamics forms M (CRBA) and factors it with the tree's sparsity instead of running the
    articulated-body response of the rigid models. A cantilever beam as a tree of its own, hinged to the
    world, does not interact with the loop model: the loop model's accelerations must still be Pinocchio's,
    and its actuator forces and loop wrenches those of the same model without the beam."""
    m, model, mapping, constraints, q, v, rng, _ = closed_loop_case(seed, floating, nloops, ("point", "weld"))
    tau = rng.normal(size=m.nv)
    qdd_rigid, tau_rigid, wrenches_rigid = soadyn.constrained_dynamics(m, q, v, tau)
    nq, nv = m.nq, m.nv
    m.add_flexible_body("beam", None, soadyn.FlexibleBody.cantilever_beam(1.0, 10.0, 1.0, 2),
                        soadyn.Joint.revolute((0, 1, 0)))
    extra_q, extra_v = m.nq - nq, m.nv - nv
    beam_v = rng.normal(size=extra_v)
    qdd, tau_out, wrenches = soadyn.constrained_dynamics(m, np.concatenate([q, 0.1 * rng.normal(size=extra_q)]),
                                                        np.concatenate([v, beam_v]),
                                                        np.concatenate([tau, rng.normal(size=extra_v)]))
    qdd_pin, _ = pinocchio_solution(model, mapping, constraints, q, v, tau)
    assert np.abs(qdd[:nv] - qdd_pin).max() <= RTOL * max(1.0, np.abs(qdd_pin).max())
    assert np.abs(qdd[:nv] - qdd_rigid).max() <= RTOL * max(1.0, np.abs(qdd_rigid).max())
    np.testing.assert_array_equal(tau_out[:nv], tau_rigid)
    assert np.abs(wrenches - wrenches_rigid).max() <= RTOL * max(1.0, np.abs(wrenches_rigid).max())
