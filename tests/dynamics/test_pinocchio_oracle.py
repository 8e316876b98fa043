"""soadyn against Pinocchio on seeded random trees built identically in both
(support/pinocchio_trees.py: every joint kind, DOFs matched joint by joint).

Run with `pytest -s` to see the largest relative error per quantity.
"""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import soadyn
from support.error_log import ErrorLog, report_fixture
from support.pinocchio_trees import CASE_IDS, CASES, SEEDS, make_case
from support.trees import JOINT_KINDS

RTOL = 1e-10


# ---------------------------------------------------------------------------
# Comparison with error log
# ---------------------------------------------------------------------------

LOG = ErrorLog("Pinocchio", RTOL)
check = LOG.check


report_errors = report_fixture(LOG)


parametrize_cases = pytest.mark.parametrize("seed,floating", CASES, ids=CASE_IDS)


# ---------------------------------------------------------------------------
# Tests
# ---------------------------------------------------------------------------

@parametrize_cases
def test_tree_covers_every_joint_kind(seed, floating):
    c = make_case(seed, floating)
    assert set(c.m.joint_types) == set(JOINT_KINDS)
    universal_axes = [np.concatenate([s.axis, s.axis2]) for s in c.specs if s.kind == "universal"]
    aligned = [np.count_nonzero(axes) == 2 for axes in universal_axes]
    assert all(aligned) if seed % 2 == 0 else not any(aligned)
    assert 12 <= c.m.nbodies <= 20
    assert (c.m.parents[0] == -1) and (not floating or c.m.parents.count(-1) == 1)


@parametrize_cases
def test_kinematics(seed, floating):
    """Poses and body velocities: validates the joint and q/v conversions on their own."""
    c = make_case(seed, floating)
    v = c.rng.normal(size=c.m.nv)
    poses, vel = soadyn.forward_kinematics(c.m, c.q, v)
    pin.forwardKinematics(c.model, c.data, c.q_pin, c.map.v(v))
    check("body poses", poses, np.array([c.data.oMi[j].homogeneous for j in c.map.joint_ids]))
    check("body velocities", vel,
          np.array([np.r_[c.data.v[j].angular, c.data.v[j].linear] for j in c.map.joint_ids]))


@parametrize_cases
def test_mass_matrix(seed, floating):
    c = make_case(seed, floating)
    M = pin.crba(c.model, c.data, c.q_pin)
    M = np.triu(M) + np.triu(M, 1).T  # Pinocchio fills the upper triangle only
    check("mass_matrix", c.map.matrix(soadyn.mass_matrix(c.m, c.q)), M)


@pytest.mark.parametrize("seed", SEEDS)
def test_mass_matrix_does_not_depend_on_the_free_root_pose(seed):
    """The free joint's velocity is the root body's twist in its own frame, so M
    cannot depend on where the root is or how it is turned: soadyn's M is
    unchanged to the bit when the root moves, and still matches Pinocchio's."""
    c = make_case(seed, True)
    assert c.m.joint_types[0] == "free" and c.m.parents[0] == -1
    moved = c.q.copy()
    moved[0:3] = c.rng.normal(size=3) * 10.0
    quaternion = c.rng.normal(size=4)
    moved[3:7] = quaternion / np.linalg.norm(quaternion)
    M = soadyn.mass_matrix(c.m, moved)
    assert np.array_equal(M, soadyn.mass_matrix(c.m, c.q))
    M_pin = pin.crba(c.model, c.data, c.map.q(moved))
    check("mass_matrix, root moved", c.map.matrix(M), np.triu(M_pin) + np.triu(M_pin, 1).T)


# soadyn call and its Pinocchio counterpart: (model, q, v, x[, f_ext]) -> generalized vector.
DYNAMICS = {"inverse_dynamics": (soadyn.inverse_dynamics, pin.rnea), "forward_dynamics": (soadyn.forward_dynamics, pin.aba)}


@parametrize_cases
@pytest.mark.parametrize("name", sorted(DYNAMICS))
@pytest.mark.parametrize("with_f_ext", [False, True], ids=["no_fext", "fext"])
@pytest.mark.parametrize("at_rest", [False, True], ids=["moving", "at_rest"])
def test_dynamics(seed, floating, name, with_f_ext, at_rest):
    """At rest (v = 0) the sweeps skip every velocity term: the result must not change."""
    c = make_case(seed, floating)
    ours, theirs = DYNAMICS[name]
    v, x = c.rng.normal(size=c.m.nv), c.rng.normal(size=c.m.nv)
    if at_rest:
        v = np.zeros(c.m.nv)
    f = c.rng.normal(size=(c.m.nbodies, 6)) if with_f_ext else None
    pin_f_ext = (c.map.f_ext(f),) if with_f_ext else ()
    result = ours(c.m, c.q, v, x, f_ext=f)
    ref = theirs(c.model, c.data, c.q_pin, c.map.v(v), c.map.v(x), *pin_f_ext)
    check(name + (" f_ext" if with_f_ext else "") + (" at rest" if at_rest else ""), c.map.v(result), ref)


@parametrize_cases
@pytest.mark.parametrize("fraction", [0.0, 0.5, 1.0], ids=["all_regular", "mixed", "all_prescribed"])
def test_hybrid_dynamics_at_rest(seed, floating, fraction):
    """Hybrid dynamics at v = 0 (velocity terms skipped) against Pinocchio's RNEA: the generalized
    forces of the returned accelerations are the returned forces; regular DOFs keep their torques."""
    c = make_case(seed, floating)
    m = c.m.copy()
    mask = c.rng.uniform(size=m.nv) < fraction
    m.set_prescribed(mask)
    u, v = c.rng.normal(size=m.nv), np.zeros(m.nv)
    qdd, tau = soadyn.hybrid_dynamics(m, c.q, v, u)
    np.testing.assert_array_equal(qdd[mask], u[mask])
    np.testing.assert_array_equal(tau[~mask], u[~mask])
    check(f"hybrid at rest ({fraction:.0%} prescribed)", c.map.v(tau),
          pin.rnea(c.model, c.data, c.q_pin, c.map.v(v), c.map.v(qdd)))


@parametrize_cases
def test_bias_forces(seed, floating):
    c = make_case(seed, floating)
    v = c.rng.normal(size=c.m.nv)
    ref = pin.nonLinearEffects(c.model, c.data, c.q_pin, c.map.v(v))
    check("bias_forces", c.map.v(soadyn.bias_forces(c.m, c.q, v)), ref)


@parametrize_cases
def test_energies(seed, floating):
    c = make_case(seed, floating)
    v = c.rng.normal(size=c.m.nv)
    pin.forwardKinematics(c.model, c.data, c.q_pin, c.map.v(v))
    check("kinetic_energy", soadyn.kinetic_energy(c.m, c.q, v),
          pin.computeKineticEnergy(c.model, c.data))
    # Both use -sum m g.c with zero at the world origin, so absolute values compare.
    check("potential_energy", soadyn.potential_energy(c.m, c.q),
          pin.computePotentialEnergy(c.model, c.data))
