"""Loop forces in the joint wrenches, redundant actuation, singular and
inconsistent cases, distance loops of the current length, and bad input of
the loop layer.

Oracles: Pinocchio (constraintDynamics for the accelerations and the loop
multipliers, rnea with the loop forces as external forces for the joint
wrenches, data.f), closed forms of the planar four-bar (closure Jacobian of
Saha, Shah & Nandihal 2013, Eq. 52b; E = [1; -C_d^-1 C_i] of "Joint
Coordinate Method, Part 1", Eqs. 1.16-1.24 and the actuator forces of
Eq. 1.31), an independent minimum-norm solve of the constrained equations
written here with numpy, and Newton's law on every body."""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

import soadyn
from support.closed_loops import closed_loop_case, pinocchio_solution
from support.four_bar import (COUPLER, CRANK, GROUND, ROCKER, closure_jacobian, closure_velocity_product, four_bar,
                              four_bar_state)
from support.pinocchio_trees import Mapping, build_pinocchio, build_soadyn, random_specs

RTOL = 1e-9


# ---------------------------------------------------------------------------
# Joint wrenches with loop forces, against Pinocchio
# ---------------------------------------------------------------------------

def _pin_loop_forces(model, constraints, lam):
    """Pinocchio's multipliers as external forces on each constraint's two joints (joint frames):
    lambda acts on joint1 at its contact frame, its opposite on joint2 at its contact frame (the two frames
    coincide in the world: the loops are closed)."""
    forces = [pin.Force.Zero() for _ in range(model.njoints)]
    row = 0
    for c in constraints:
        if c.type == pin.ContactType.CONTACT_3D:
            f = pin.Force(lam[row:row + 3], np.zeros(3))
            row += 3
        else:
            f = pin.Force(lam[row:row + 3], lam[row + 3:row + 6])
            row += 6
        forces[c.joint1_id] += c.joint1_placement.act(f)
        if c.joint2_id > 0:
            forces[c.joint2_id] -= c.joint2_placement.act(f)
    return forces


def _wrench(f: pin.Force) -> np.ndarray:
    """pin.Force (linear, angular) -> soadyn row [torque; force]."""
    return np.r_[f.angular, f.linear]


def _regular_rows_full_rank(C, rng, count):
    """`count` prescribed DOFs leaving C_r of full row rank (the multipliers then unique)."""
    for _ in range(200):
        prescribed = rng.choice(C.shape[1], size=count, replace=False)
        regular = np.setdiff1d(np.arange(C.shape[1]), prescribed)
        if np.linalg.matrix_rank(C[:, regular]) == C.shape[0]:
            return prescribed
    raise AssertionError("no choice of prescribed DOFs leaves C_r of full row rank")


# Random trees and loops of support/closed_loops.py whose loop equations are independent (unique multipliers).
CASES = [(0, True, 1), (0, True, 3), (1, True, 2), (1, False, 1), (1, False, 2), (2, False, 1), (5, False, 3),
         (6, True, 2), (7, False, 2)]


@pytest.mark.parametrize("seed,floating,nloops", CASES,
                         ids=[f"seed{s}-{'floating' if f else 'fixed'}-{n}loops" for s, f, n in CASES])
def test_joint_wrenches_with_loops_match_pinocchio_rnea_with_loop_forces(seed, floating, nloops):
    """Pinocchio: constraintDynamics (every DOF regular, f_ext folded into tau) gives qdd and the
    multipliers; rnea with f_ext plus the multipliers as external forces gives data.f and tau. soadyn, given
    Pinocchio's accelerations on some DOFs as prescribed, must return the same joint wrenches."""
    m, model, mapping, constraints, q, v, rng, _ = closed_loop_case(seed, floating, nloops, ("point", "weld"))
    C = soadyn.loop_jacobian(m, q)
    if np.linalg.matrix_rank(C) < C.shape[0]:
        pytest.fail("the case must have independent loop equations (unique multipliers)")
    tau = rng.normal(size=m.nv)
    f_ext = rng.normal(size=(m.nbodies, 6))
    data = model.createData()
    fext_pin = list(mapping.f_ext(f_ext))
    zero = np.zeros(m.nv)
    generalized_f_ext = (pin.rnea(model, data, mapping.q(q), mapping.v(v), zero)
                         - pin.rnea(model, data, mapping.q(q), mapping.v(v), zero, pin.StdVec_Force(fext_pin)))
    qdd_pin, lam = pinocchio_solution(model, mapping, constraints, q, v, tau + mapping.back(generalized_f_ext))
    loop_forces = _pin_loop_forces(model, constraints, lam)
    total = pin.StdVec_Force([a + b for a, b in zip(fext_pin, loop_forces)])
    tau_pin = mapping.back(pin.rnea(model, data, mapping.q(q), mapping.v(v), mapping.v(qdd_pin), total))
    expected = np.array([_wrench(data.f[jid]) for jid in mapping.joint_ids])

    prescribed = _regular_rows_full_rank(C, rng, 3)
    m.set_prescribed(np.isin(np.arange(m.nv), prescribed))
    u = tau.copy()
    u[prescribed] = qdd_pin[prescribed]
    qdd, tau_out, loop_wrenches, wrenches = soadyn.constrained_dynamics(m, q, v, u, f_ext=f_ext,
                                                                        joint_wrenches=True)
    scale = max(1.0, np.abs(expected).max())
    assert np.abs(qdd - qdd_pin).max() <= RTOL * max(1.0, np.abs(qdd_pin).max())
    assert np.abs(tau_pin - tau).max() <= RTOL * max(1.0, np.abs(tau).max())  # the oracle's own check
    assert np.abs(tau_out - tau).max() <= RTOL * max(1.0, np.abs(tau).max())
    assert np.abs(wrenches - expected).max() <= RTOL * scale
    # The same wrenches from joint_wrenches given the loop wrenches, and without the loop forces they differ.
    again = soadyn.joint_wrenches(m, q, v, qdd, f_ext=f_ext, loop_wrenches=loop_wrenches)
    assert np.abs(again - wrenches).max() <= 1e-12 * scale
    tree_only = soadyn.joint_wrenches(m, q, v, qdd, f_ext=f_ext, loop_wrenches=np.zeros((m.nloops, 6)))
    assert np.abs(tree_only - expected).max() > 1e-3 * scale


def _random_loops_of_every_kind(seed):
    """A random tree (support/pinocchio_trees.py's specs) with one loop of every kind, closed at the returned q.
    Returns the soadyn model, the Pinocchio model and mapping, q, rng and per loop (body_a, body_b, frame A
    and frame B placements in their bodies, kind)."""
    specs = random_specs(seed, seed % 2 == 0)
    m = build_soadyn(specs)
    model = build_pinocchio(specs, m.gravity)
    mapping = Mapping(m, model, specs)
    rng = np.random.default_rng(500 + seed)
    q = soadyn.random_configuration(m, seed)
    poses = soadyn.forward_kinematics(m, q)[0]
    loops = []
    for kind in ("point", "revolute", "prismatic", "weld", "distance"):
        a, b = sorted(rng.choice(np.arange(-1, m.nbodies), size=2, replace=False), key=lambda x: x < 0)
        A = np.eye(4)
        A[:3, :3] = np.linalg.qr(rng.normal(size=(3, 3)))[0] @ np.diag([1, 1, -1 if kind == "weld" else 1])
        A[:3, :3] *= np.sign(np.linalg.det(A[:3, :3]))
        A[:3, 3] = rng.uniform(-0.3, 0.3, size=3)
        B = np.linalg.solve(np.eye(4) if b < 0 else poses[b], poses[a] @ A)  # frame B = frame A in the world
        if kind == "distance":
            B[:3, 3] += B[:3, :3] @ np.array([0.24, 0.0, 0.32])  # a 0.4 m rod
        if kind == "prismatic":
            B[:3, 3] -= 0.25 * B[:3, 2]  # A's origin on B's z axis
        m.add_loop(kind, m.body_names[a], None if b < 0 else m.body_names[b], kind,
                   placement_a=(A[:3, :3], A[:3, 3]), placement_b=(B[:3, :3], B[:3, 3]),
                   length=0.4 if kind == "distance" else None)
        loops.append((a, b, A, B, kind))
    assert np.abs(soadyn.loop_residual(m, q)).max() < 1e-12
    return m, model, mapping, specs, q, rng, loops


def _about(T_body, point, w):
    """World-axes wrench w = [torque; force] about world `point` -> body frame about the body origin."""
    R, o = T_body[:3, :3], T_body[:3, 3]
    return np.r_[R.T @ (w[:3] + np.cross(point - o, w[3:])), R.T @ w[3:]]


@pytest.mark.parametrize("seed", range(4))
def test_newton_law_on_every_body_with_loop_forces(seed):
    """Sum of the wrenches on each body (its hinge, its children's hinges, f_ext, gravity and the loop
    forces) equals its rate of momentum I a + v x* I v, with a and v from Pinocchio's forward kinematics of
    the same tree. A loop of every kind, random prescribed DOFs."""
    m, model, mapping, specs, q, rng, loops = _random_loops_of_every_kind(seed)
    C = soadyn.loop_jacobian(m, q)
    v = rng.normal(size=m.nv)
    v -= np.linalg.pinv(C) @ (C @ v)
    f_ext = rng.normal(size=(m.nbodies, 6))
    u = rng.normal(size=m.nv)
    motion = soadyn.constrained_dynamics(m, q, v, u, f_ext=f_ext)[0]
    prescribed = rng.uniform(size=m.nv) < 0.2  # driven along that motion, possibly redundantly
    m.set_prescribed(prescribed)
    qdd, tau, loop_wrenches, wrenches = soadyn.constrained_dynamics(m, q, v, np.where(prescribed, motion, u),
                                                                    f_ext=f_ext, joint_wrenches=True)
    assert np.abs(qdd - motion).max() <= RTOL * np.abs(motion).max()
    data = model.createData()
    pin.forwardKinematics(model, data, mapping.q(q), mapping.v(v), mapping.v(qdd))
    poses = soadyn.forward_kinematics(m, q)[0]
    g = np.asarray(m.gravity)
    total = wrenches + f_ext
    momentum_rate = np.zeros_like(total)
    for i, s in enumerate(specs):
        inertia = model.inertias[mapping.joint_ids[i]]
        vel, acc = data.v[mapping.joint_ids[i]], data.a[mapping.joint_ids[i]]
        momentum_rate[i] = _wrench(inertia * acc + vel.cross(inertia * vel))
        weight = s.mass * poses[i][:3, :3].T @ g
        total[i] += np.r_[np.cross(s.com, weight), weight]
        if s.parent >= 0:  # body i's hinge wrench reacts on its parent
            X = np.linalg.solve(poses[s.parent], poses[i])
            total[s.parent] -= np.r_[X[:3, :3] @ wrenches[i, :3] + np.cross(X[:3, 3], X[:3, :3] @ wrenches[i, 3:]),
                                     X[:3, :3] @ wrenches[i, 3:]]
    for k, (a, b, A, B, kind) in enumerate(loops):
        pa = (poses[a] @ A)[:3, 3]
        total[a] += _about(poses[a], pa, loop_wrenches[k])
        if b >= 0:  # B's side takes the opposite, its force at frame B's origin (A's for a prismatic loop)
            total[b] -= _about(poses[b], pa if kind == "prismatic" else (poses[b] @ B)[:3, 3], loop_wrenches[k])
    scale = np.abs(momentum_rate).max() + np.abs(wrenches).max()
    assert np.abs(total - momentum_rate).max() <= RTOL * scale
    # Each hinge wrench projected on its joint's motion subspace (Pinocchio's LOCAL Jacobian columns of the
    # joint's own DOFs) is the generalized force soadyn returns: tau_p on prescribed DOFs, u on regular ones.
    pin.computeJointJacobians(model, data, mapping.q(q))
    projected = np.zeros(m.nv)
    for i, jid in enumerate(mapping.joint_ids):
        J = pin.getJointJacobian(model, data, jid, pin.ReferenceFrame.LOCAL)
        joint = model.joints[jid]
        for k in range(joint.idx_v, joint.idx_v + joint.nv):
            projected[mapping.perm[k]] = J[:, k] @ np.r_[wrenches[i, 3:], wrenches[i, :3]]
    assert np.abs(projected - tau).max() <= RTOL * max(1.0, np.abs(tau).max())


# ---------------------------------------------------------------------------
# Actuator forces: Eq. 1.31 and redundant actuation (minimum-norm tau_p)
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("theta1", np.linspace(0.2, 2 * np.pi, 6))
def test_four_bar_with_crank_and_rocker_driven_gives_minimum_norm_torques(theta1):
    """Two actuators on a one-DOF mechanism. Every (t_crank, t_rocker) with E'(tau - M qdd - h) = 0 drives
    the motion (E: the basis [1; -C_d^-1 C_i] of the closure's null space); the smallest is
    (E_crank, E_rocker) Q / (E_crank^2 + E_rocker^2), Q = E'(M qdd + h) - E_coupler u_coupler."""
    m = four_bar()
    theta, thetad = four_bar_state(theta1, rate=2.5)
    J = closure_jacobian(theta)
    E = np.r_[1.0, -np.linalg.solve(J[:, 1:], J[:, 0])]
    gamma = np.r_[0.0, np.linalg.solve(J[:, 1:], -closure_velocity_product(theta, thetad))]
    crank_acc, coupler_torque = 1.3, 0.07
    expected_qdd = E * crank_acc + gamma
    m.set_prescribed(["crank", "rocker"])
    qdd, tau, _ = soadyn.constrained_dynamics(m, theta, thetad,
                                              np.array([crank_acc, coupler_torque, expected_qdd[2]]))
    np.testing.assert_allclose(qdd, expected_qdd, rtol=1e-11, atol=1e-11 * np.abs(expected_qdd).max())
    M, h = soadyn.mass_matrix(m, theta), soadyn.bias_forces(m, theta, thetad)
    Q = E @ (M @ expected_qdd + h) - E[1] * coupler_torque
    expected_tau = Q * E[[0, 2]] / (E[0] ** 2 + E[2] ** 2)
    assert tau[1] == coupler_torque
    assert np.abs(tau[[0, 2]] - expected_tau).max() <= 1e-10 * np.abs(expected_tau).max()


def _least_norm_actuation(M, h, C, kappa, prescribed, u):
    """The constrained equations M qdd + h = tau + C' lambda, C qdd = kappa, with qdd_p and tau_r given, as
    one linear system in y = (qdd_r, tau_p, lambda), solved for the smallest ||tau_p|| over all its
    solutions (numpy: SVD null space of the system, then least squares on that space)."""
    nv, mrows = M.shape[0], C.shape[0]
    p = np.flatnonzero(prescribed)
    r = np.flatnonzero(~prescribed)
    qdd_p, tau_r = u[p], u[r]
    select_p = np.eye(nv)[:, p]
    A = np.block([[M[:, r], -select_p, -C.T], [C[:, r], np.zeros((mrows, len(p))), np.zeros((mrows, mrows))]])
    b = np.r_[np.eye(nv)[:, r] @ tau_r - h - M[:, p] @ qdd_p, kappa - C[:, p] @ qdd_p]
    y0 = np.linalg.lstsq(A, b, rcond=None)[0]
    assert np.abs(A @ y0 - b).max() <= 1e-9 * np.abs(b).max(), "the motion is consistent"
    _, s, Vt = np.linalg.svd(A)
    null = Vt[np.sum(s > 1e-10 * s[0]):].T
    tau_rows = slice(len(r), len(r) + len(p))
    w = np.linalg.lstsq(null[tau_rows], -y0[tau_rows], rcond=None)[0]
    y = y0 + null @ w
    qdd = np.empty(nv)
    qdd[p], qdd[r] = qdd_p, y[:len(r)]
    return qdd, y[tau_rows]


@pytest.mark.parametrize("seed,floating,nloops", [(0, True, 1), (1, False, 2), (2, True, 2), (4, False, 1)])
@pytest.mark.parametrize("extra", [1, 3], ids=["one-more", "three-more"])
def test_redundant_actuation_gives_minimum_norm_actuator_forces(seed, floating, nloops, extra):
    """More prescribed DOFs than the mechanism's mobility: tau_p against the independent least-norm solve,
    the accelerations against Pinocchio (its constraintDynamics, fed soadyn's actuator forces as torques,
    moves exactly as prescribed)."""
    m, model, mapping, constraints, q, v, rng, _ = closed_loop_case(seed, floating, nloops, ("point", "weld"))
    C = soadyn.loop_jacobian(m, q)
    mobility = m.nv - np.linalg.matrix_rank(C)
    tau0 = rng.normal(size=m.nv)
    qdd_motion, _ = pinocchio_solution(model, mapping, constraints, q, v, tau0)  # a motion the loops allow
    prescribed = np.isin(np.arange(m.nv), rng.choice(m.nv, size=mobility + extra, replace=False))
    m.set_prescribed(prescribed)
    u = np.where(prescribed, qdd_motion, tau0)
    qdd, tau, _ = soadyn.constrained_dynamics(m, q, v, u)
    M, h = soadyn.mass_matrix(m, q), soadyn.bias_forces(m, q, v)
    expected_qdd, expected_tau_p = _least_norm_actuation(M, h, C, C @ qdd_motion, prescribed, u)
    assert np.abs(qdd - qdd_motion).max() <= RTOL * max(1.0, np.abs(qdd_motion).max())
    assert np.abs(qdd - expected_qdd).max() <= RTOL * max(1.0, np.abs(qdd_motion).max())
    assert np.abs(tau[prescribed] - expected_tau_p).max() <= RTOL * max(1.0, np.abs(expected_tau_p).max())
    assert np.linalg.norm(tau[prescribed]) <= np.linalg.norm(tau0[prescribed]) * (1 + 1e-12)
    np.testing.assert_array_equal(tau[~prescribed], u[~prescribed])
    qdd_pin, _ = pinocchio_solution(model, mapping, constraints, q, v, tau)
    assert np.abs(qdd_pin - qdd).max() <= RTOL * max(1.0, np.abs(qdd).max())


@pytest.mark.parametrize("seed,floating,nloops", [(0, True, 1), (1, False, 2), (5, False, 3)])
def test_independent_prescribed_dofs_give_the_eq_1_31_actuator_forces(seed, floating, nloops):
    """Prescribed DOFs that are independent coordinates (C_r square and invertible): the actuator forces are
    unique, E'(M qdd + h) - E_r' tau_r with E = [I; -C_r^-1 C_p] ("Joint Coordinate Method", Eq. 1.31)."""
    m, model, mapping, constraints, q, v, rng, _ = closed_loop_case(seed, floating, nloops, ("point", "weld"))
    C = soadyn.loop_jacobian(m, q)
    regular = []  # dependent coordinates: columns of C raising its rank, in random order
    for k in rng.permutation(m.nv):
        if np.linalg.matrix_rank(C[:, regular + [k]]) > len(regular):
            regular.append(k)
    assert len(regular) == C.shape[0]
    prescribed = ~np.isin(np.arange(m.nv), regular)
    m.set_prescribed(prescribed)
    u = rng.normal(size=m.nv)
    qdd, tau, _ = soadyn.constrained_dynamics(m, q, v, u)
    E = np.zeros((m.nv, prescribed.sum()))
    E[prescribed] = np.eye(prescribed.sum())
    E[~prescribed] = -np.linalg.solve(C[:, ~prescribed], C[:, prescribed])
    M, h = soadyn.mass_matrix(m, q), soadyn.bias_forces(m, q, v)
    expected = E.T @ (M @ qdd + h) - E[~prescribed].T @ u[~prescribed]
    assert np.abs(tau[prescribed] - expected).max() <= RTOL * max(1.0, np.abs(expected).max())


# ---------------------------------------------------------------------------
# Singular and inconsistent cases: a named DynamicsError or the exact answer, never NaN
# ---------------------------------------------------------------------------

def _dead_centre_state(rate):
    """The four-bar with crank and coupler in line (the crank's dead centre when the rocker drives):
    configuration and a velocity on the loop (rocker at rest, coupler turning with the crank)."""
    reach = CRANK + COUPLER
    t1 = np.arccos((reach**2 + GROUND**2 - ROCKER**2) / (2 * reach * GROUND))
    tip = reach * np.array([np.cos(t1), np.sin(t1)])
    t3 = np.arctan2(tip[1], tip[0] - GROUND)
    return np.array([t1, 0.0, t3]), np.array([rate, -reach / COUPLER * rate, 0.0])


def _consistent_rocker_acceleration(theta, thetad):
    """At the dead centre C_r = [crank, coupler columns] has rank 1 (both along e_perp(t1)); the rocker
    acceleration must make kappa - C_p qdd_p orthogonal to e(t1)."""
    J = closure_jacobian(theta)
    kappa = -closure_velocity_product(theta, thetad)
    y = np.array([np.cos(theta[0]), np.sin(theta[0])])
    return (y @ kappa) / (y @ J[:, 2])


def test_rocker_driven_four_bar_at_the_crank_dead_centre():
    m = four_bar()
    theta, thetad = _dead_centre_state(rate=1.5)
    assert np.abs(soadyn.loop_residual(m, theta, thetad)[0]).max() < 1e-14
    J = closure_jacobian(theta)
    assert np.linalg.matrix_rank(J[:, :2]) == 1
    m.set_prescribed(["rocker"])
    consistent = _consistent_rocker_acceleration(theta, thetad)
    # Any other rocker acceleration cannot be met: the error names the loop.
    with pytest.raises(soadyn.DynamicsError, match=r"^constrained_dynamics: the closure equations of loop 'pin' "
                                                   r"cannot be met"):
        soadyn.constrained_dynamics(m, theta, thetad, np.array([0.0, 0.0, consistent + 0.5]))
    # The consistent one gives a finite motion that closes the loop.
    qdd, tau, wrench = soadyn.constrained_dynamics(m, theta, thetad, np.array([0.0, 0.0, consistent]))
    assert np.isfinite(qdd).all() and np.isfinite(tau).all() and np.isfinite(wrench).all()
    closure = J @ qdd + closure_velocity_product(theta, thetad)
    assert np.abs(closure).max() <= 1e-9 * np.abs(closure_velocity_product(theta, thetad)).max()


def test_free_four_bar_through_the_dead_centre_is_an_ordinary_case():
    """With no DOF prescribed the Delassus matrix keeps full in-plane rank at the dead centre: the motion is
    the reduced equation's (E of the rocker as independent coordinate cannot be formed there, so the check
    is the closure and d'Alembert's principle on the null space of C)."""
    m = four_bar()
    theta, thetad = _dead_centre_state(rate=-2.0)
    u = np.array([0.3, 0.0, -0.1])
    qdd, tau, _ = soadyn.constrained_dynamics(m, theta, thetad, u)
    J = closure_jacobian(theta)
    assert np.abs(J @ qdd + closure_velocity_product(theta, thetad)).max() <= 1e-12
    null = np.linalg.svd(J)[2][-1]  # the one free direction
    M, h = soadyn.mass_matrix(m, theta), soadyn.bias_forces(m, theta, thetad)
    assert abs(null @ (M @ qdd + h - u)) <= 1e-12 * np.abs(M @ qdd).max()


def _locked_arm():
    """Two links in a vertical plane whose tip is pinned to the world: mobility zero (a locked mechanism)."""
    m = soadyn.Model()
    m.gravity = (0.0, -9.81, 0.0)
    z = soadyn.Joint.revolute((0, 0, 1))
    m.add_body("upper", None, z, mass=2.0, com=(0.5, 0, 0), inertia=(0.01, 0.2, 0.2))
    m.add_body("lower", "upper", z, placement=(1.0, 0, 0), mass=1.0, com=(0.4, 0, 0), inertia=(0.01, 0.1, 0.1))
    q = np.array([0.4, -1.1])
    tip = soadyn.forward_kinematics(m, q)[0][1] @ np.array([0.8, 0, 0, 1])
    m.add_loop("tip", "lower", None, "point", placement_a=(None, (0.8, 0, 0)), placement_b=(None, tip[:3]))
    return m, q


def test_locked_mechanism_carries_its_load_and_refuses_motion():
    m, q = _locked_arm()
    v = np.zeros(2)
    C = soadyn.loop_jacobian(m, q)
    assert np.linalg.matrix_rank(C) == 2 == m.nv
    h = soadyn.bias_forces(m, q, v)
    # Every DOF regular: it does not move, and the pin takes the weight: C' lambda = h.
    qdd, _, wrench = soadyn.constrained_dynamics(m, q, v, np.zeros(2))
    assert np.abs(qdd).max() <= 1e-12
    assert np.abs(C.T @ wrench[0, 3:] - h).max() <= 1e-12 * np.abs(h).max()
    # The shoulder prescribed at rest: the structure can carry the whole load, so the minimum-norm
    # actuator torque is zero.
    m.set_prescribed(["upper"])
    qdd, tau, _ = soadyn.constrained_dynamics(m, q, v, np.array([0.0, 0.0]))
    assert np.abs(qdd).max() <= 1e-12 and abs(tau[0]) <= 1e-12 * np.abs(h).max()
    # Driving it is inconsistent with the pin.
    with pytest.raises(soadyn.DynamicsError, match=r"the closure equations of loop 'tip' cannot be met"):
        soadyn.constrained_dynamics(m, q, v, np.array([1.0, 0.0]))
    # Held at rest without load, with a velocity drift the pin does not allow: the closure acceleration it
    # leaves is drift (below the absolute floor), not an inconsistency.
    m.gravity = (0.0, 0.0, 0.0)
    drift = np.array([1e-9, -2e-9])
    qdd, tau, _ = soadyn.constrained_dynamics(m, q, drift, np.zeros(2))
    assert np.isfinite(qdd).all() and np.abs(qdd).max() < 1e-12 and abs(tau[0]) < 1e-12


def test_inconsistent_prescribed_accelerations_name_the_loop():
    """Crank and rocker of the four-bar both driven, with accelerations the loop cannot follow; a second,
    consistent loop in the same model is not the one named."""
    m = four_bar()
    z = soadyn.Joint.revolute((0, 0, 1))
    m.add_body("arm", None, z, placement=(0, 0.5, 0), mass=1.0, com=(0.2, 0, 0), inertia=(0.01, 0.02, 0.02))
    m.add_loop("arm tip", "arm", None, "distance", placement_a=(None, (0.4, 0, 0)),
               placement_b=(None, (0.1, 0.8, 0.3)))  # a rod of the arm's length at rest: the arm is locked
    theta, thetad = four_bar_state(1.0, rate=2.0)
    q, v = np.r_[theta, 0.0], np.r_[thetad, 0.0]
    assert abs(soadyn.loop_residual(m, q)[-1]) < 1e-15 and abs(soadyn.loop_jacobian(m, q)[-1, 3]) > 0.1
    J = closure_jacobian(theta)
    E = np.r_[1.0, -np.linalg.solve(J[:, 1:], J[:, 0])]
    gamma = np.r_[0.0, np.linalg.solve(J[:, 1:], -closure_velocity_product(theta, thetad))]
    rocker = (E * 0.7 + gamma)[2]
    m.set_prescribed(["crank", "rocker"])
    qdd, _, _ = soadyn.constrained_dynamics(m, q, v, np.array([0.7, 0.0, rocker, 0.0]))
    assert np.abs(qdd[:3] - (E * 0.7 + gamma)).max() <= 1e-10 * np.abs(qdd).max()
    with pytest.raises(soadyn.DynamicsError, match=r"the closure equations of loop 'pin' cannot be met"):
        soadyn.constrained_dynamics(m, q, v, np.array([0.7, 0.0, rocker + 1e-3, 0.0]))
    m.set_prescribed(["arm"], True)
    with pytest.raises(soadyn.DynamicsError, match=r"the closure equations of loop 'arm tip' cannot be met"):
        soadyn.constrained_dynamics(m, q, v, np.array([0.7, 0.0, rocker, 2.0]))


# ---------------------------------------------------------------------------
# Distance loops of the current length
# ---------------------------------------------------------------------------

def _arm():
    m = soadyn.Model()
    z = soadyn.Joint.revolute((0, 0, 1))
    m.add_body("a", None, z, mass=1.0, com=(0.5, 0, 0), inertia=(0.1, 0.1, 0.1))
    m.add_body("b", "a", soadyn.Joint.revolute((0, 1, 0)), placement=(1.0, 0, 0), mass=1.0, com=(0.5, 0, 0),
               inertia=(0.1, 0.1, 0.1))
    return m


def test_distance_loop_without_length_takes_the_neutral_or_given_configuration():
    m = _arm()
    target = np.array([0.5, 1.2, 0.3])
    m.add_loop("rod", "b", None, "distance", placement_a=(None, (1.0, 0, 0)), placement_b=(None, target))
    neutral = soadyn.neutral_configuration(m)
    tip = soadyn.forward_kinematics(m, neutral)[0][1] @ np.array([1.0, 0, 0, 1])
    assert np.allclose(tip[:3], (2.0, 0, 0))
    assert abs(soadyn.loop_residual(m, neutral)[0]) <= 1e-15
    q = np.array([0.7, -0.4])
    assert abs(soadyn.loop_residual(m, q)[0]) > 1e-3
    m.add_loop("rod at q", "b", None, "distance", placement_a=(None, (1.0, 0, 0)), placement_b=(None, target), q=q)
    assert abs(soadyn.loop_residual(m, q)[1]) <= 1e-15
    tip = soadyn.forward_kinematics(m, q)[0][1] @ np.array([1.0, 0, 0, 1])
    expected = np.linalg.norm(np.array([2.0, 0, 0]) - target) - np.linalg.norm(tip[:3] - target)
    assert abs(soadyn.loop_residual(m, neutral)[1] - expected) <= 1e-14


@pytest.mark.parametrize("kwargs,error,message", [
    (dict(q=np.zeros(2), length=1.0), soadyn.LoopError,
     r"^loop 'l': q= gives the length of a distance loop without length=$"),
    (dict(q=np.zeros(3)), ValueError, r"q has shape \(3,\), expected \(2,\)"),
    (dict(q=np.array([0.0, np.nan])), ValueError, r"q"),
    (dict(placement_b=(None, (2.0, 0, 0))), soadyn.LoopError,
     r"^loop 'l': frame_a and frame_b coincide at the neutral configuration: give the rod's length=$"),
    (dict(length=0.0), soadyn.LoopError, r"^loop 'l': a distance loop needs a finite, positive length$"),
    (dict(length=np.inf), soadyn.LoopError, r"^loop 'l': a distance loop needs a finite, positive length$"),
    (dict(length=np.nan), soadyn.LoopError, r"^loop 'l': a distance loop needs a finite, positive length$"),
    (dict(length=-0.5), soadyn.LoopError, r"^loop 'l': a distance loop needs a finite, positive length$"),
], ids=["q-and-length", "q-shape", "q-nan", "coincident", "zero", "inf", "nan", "negative"])
def test_bad_distance_loops_are_refused_by_name(kwargs, error, message):
    m = _arm()
    args = dict(placement_a=(None, (1.0, 0, 0)))
    args.update(kwargs)
    with pytest.raises(error, match=message):
        m.add_loop("l", "b", None, "distance", **args)
    assert m.nloops == 0


def test_q_is_only_for_distance_loops():
    m = _arm()
    with pytest.raises(soadyn.LoopError, match=r"^loop 'l': q= gives the length of a distance loop"):
        m.add_loop("l", "b", None, "point", q=np.zeros(2))


# ---------------------------------------------------------------------------
# Bad input of the loop layer: named errors
# ---------------------------------------------------------------------------

def _reflection():
    return np.diag([1.0, 1.0, -1.0])


@pytest.mark.parametrize("args,kwargs,message", [
    (("l", "a", "a", "weld"), {}, r"^loop 'l': frame_a 'a' and frame_b 'a' are on the same body 'a'$"),
    (("l", "a", "nope", "point"), {}, r"^loop 'l': frame_b 'nope' is neither a body nor a frame$"),
    (("l", "nope", None, "point"), {}, r"^loop 'l': frame_a 'nope' is neither a body nor a frame$"),
    (("l", "a", "b", "point"), dict(placement_a=(None, (np.inf, 0, 0))), r"^loop 'l': placement_a is not finite$"),
    (("l", "a", "b", "point"), dict(placement_b=(np.full((3, 3), np.nan), None)),
     r"^loop 'l': placement_b is not finite$"),
    (("l", "a", "b", "revolute"), dict(placement_a=(_reflection(), None)),
     r"^loop 'l': placement_a rotation is not a rotation matrix \(orthonormal, determinant 1\)$"),
    (("l", "a", None, "prismatic"), dict(placement_b=(np.array([[1, 0.1, 0], [0, 1, 0], [0, 0, 1]]), None)),
     r"^loop 'l': placement_b rotation is not a rotation matrix \(orthonormal, determinant 1\)$"),
    (("l", "a", "b", "distance"), dict(length=-1.0), r"^loop 'l': a distance loop needs a finite, positive length$"),
], ids=["same-body", "unknown-b", "unknown-a", "inf-placement", "nan-rotation", "reflection", "skewed",
        "negative-length"])
def test_bad_loops_are_refused_with_named_errors(args, kwargs, message):
    m = _arm()
    with pytest.raises(soadyn.LoopError, match=message):
        m.add_loop(*args, **kwargs)
    assert m.nloops == 0 and m.nloop_equations == 0


def test_duplicate_loop_name_is_refused_and_the_model_kept():
    m = _arm()
    m.add_loop("l", "b", None, "point")
    with pytest.raises(soadyn.LoopError, match=r"^loop 'l': duplicate loop name$"):
        m.add_loop("l", "a", None, "weld")
    assert m.loop_names == ["l"] and m.nloop_equations == 3


def test_loops_touching_a_flexible_body_name_it():
    m = soadyn.Model()
    beam = soadyn.FlexibleBody.cantilever_beam(1.0, 10.0, 1.0, 2)
    m.add_flexible_body("beam", None, beam, soadyn.Joint.revolute((0, 0, 1)))
    m.add_body("rigid", None, soadyn.Joint.revolute((0, 0, 1)), mass=1.0, com=(0.1, 0, 0), inertia=(0.1, 0.1, 0.1))
    node = next(f for f in m.frame_names if f.startswith("beam:"))
    with pytest.raises(soadyn.LoopError, match=rf"^loop 'l': frame_b '{node}' is a node of flexible body 'beam'; "
                                               r"loops on flexible bodies are not supported$"):
        m.add_loop("l", "rigid", node, "point")
    with pytest.raises(soadyn.LoopError, match=r"^loop 'l': frame_a 'beam' is on flexible body 'beam' or carried "
                                               r"by it; loops on flexible bodies are not supported$"):
        m.add_loop("l", "beam", "rigid", "point")
    assert m.nloops == 0


@pytest.fixture
def loop_model():
    m = four_bar()
    theta, thetad = four_bar_state(0.8, rate=1.0)
    return m, theta, thetad


LOOP_CALLS = {
    "loop_residual": lambda m, q, v, u, f: soadyn.loop_residual(m, q, v),
    "loop_jacobian": lambda m, q, v, u, f: soadyn.loop_jacobian(m, q),
    "loop_rank": lambda m, q, v, u, f: soadyn.loop_rank(m, q),
    "constrained_dynamics": lambda m, q, v, u, f: soadyn.constrained_dynamics(m, q, v, u, f_ext=f,
                                                                              joint_wrenches=True),
    "joint_wrenches": lambda m, q, v, u, f: soadyn.joint_wrenches(m, q, v, u, f_ext=f,
                                                                  loop_wrenches=np.zeros((1, 6))),
}


BAD_ARRAYS = [
    ("q", np.zeros(2), r"q has shape \(2,\), expected \(3,\)"),
    ("q", np.zeros((3, 1)), r"q has shape \(3, 1\), expected \(3,\)"),
    ("q", np.array([0.1, np.nan, 0.0]), r"q"),
    ("v", np.zeros(4), r"v has shape \(4,\), expected \(3,\)"),
    ("v", np.array([0.0, np.inf, 0.0]), r"v"),
    ("u", np.zeros(2), r"(u|qdd) has shape \(2,\), expected \(3,\)"),
    ("u", np.array([np.nan, 0.0, 0.0]), r"(u|qdd)"),
    ("f", np.zeros((3, 5)), r"f_ext must have shape \(3, 6\)"),
    ("f", np.full((3, 6), np.nan), r"f_ext"),
]
CALL_ARGS = {"loop_residual": "qv", "loop_jacobian": "q", "loop_rank": "q", "constrained_dynamics": "qvuf",
             "joint_wrenches": "qvuf"}
BAD_CALLS = [(call, arg, bad, message) for call in LOOP_CALLS for arg, bad, message in BAD_ARRAYS
             if arg in CALL_ARGS[call]]


@pytest.mark.parametrize("call,arg,bad,message", BAD_CALLS,
                         ids=[f"{c}-{a}-{i}" for i, (c, a, _, _) in enumerate(BAD_CALLS)])
def test_loop_functions_refuse_bad_arrays_by_name(loop_model, call, arg, bad, message):
    m, q, v = loop_model
    args = dict(q=q, v=v, u=np.zeros(3), f=None)
    args[arg] = bad
    with pytest.raises(ValueError, match=message):
        LOOP_CALLS[call](m, args["q"], args["v"], args["u"], args["f"])


def test_joint_wrenches_on_a_loop_model_need_the_loop_wrenches(loop_model):
    m, q, v = loop_model
    with pytest.raises(ValueError, match=r"^joint_wrenches: the model has closed loops: pass loop_wrenches="):
        soadyn.joint_wrenches(m, q, v, np.zeros(3))
    with pytest.raises(ValueError, match=r"loop_wrenches must have shape \(1, 6\)"):
        soadyn.joint_wrenches(m, q, v, np.zeros(3), loop_wrenches=np.zeros((2, 6)))
    with pytest.raises(ValueError, match=r"loop_wrenches"):
        soadyn.joint_wrenches(m, q, v, np.zeros(3), loop_wrenches=np.full((1, 6), np.nan))


# ---------------------------------------------------------------------------
# Fuzz: finite results or a named error, never NaN, never a crash
# ---------------------------------------------------------------------------

KINDS = ("point", "revolute", "prismatic", "weld", "distance")


@st.composite
def loop_models(draw):
    from support.trees import random_tree
    seed = draw(st.integers(0, 10_000))
    nbodies = draw(st.integers(2, 7))
    m, _ = random_tree(seed, nbodies=nbodies, floating=draw(st.booleans()))
    rng = np.random.default_rng(seed)
    for k in range(draw(st.integers(1, 3))):
        a = int(rng.integers(m.nbodies))
        b = int(rng.integers(-1, m.nbodies - 1))
        b = b + 1 if b >= a else b  # never a itself
        kind = draw(st.sampled_from(KINDS))
        R = np.linalg.qr(rng.normal(size=(3, 3)))[0]
        R *= np.sign(np.linalg.det(R))
        m.add_loop(f"loop{k}", m.body_names[a], None if b < 0 else m.body_names[b], kind,
                   placement_a=(R, rng.uniform(-1, 1, 3)), placement_b=(np.eye(3), rng.uniform(-1, 1, 3)),
                   length=float(rng.uniform(0.1, 2.0)) if kind == "distance" else None)
    m.set_prescribed(rng.uniform(size=m.nv) < draw(st.sampled_from([0.0, 0.3, 0.7, 1.0])))
    magnitude = draw(st.sampled_from([1.0, 1e3, 1e150, 1e300]))
    q = soadyn.random_configuration(m, seed)
    v = rng.normal(size=m.nv) * magnitude
    u = rng.normal(size=m.nv) * draw(st.sampled_from([1.0, 1e200]))
    f_ext = rng.normal(size=(m.nbodies, 6)) if draw(st.booleans()) else None
    return m, q, v, u, f_ext


@settings(max_examples=300, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(loop_models())
def test_constrained_dynamics_fuzz_is_finite_or_a_named_error(case):
    m, q, v, u, f_ext = case
    try:
        qdd, tau, loop_wrenches, wrenches = soadyn.constrained_dynamics(m, q, v, u, f_ext=f_ext,
                                                                        joint_wrenches=True)
    except soadyn.DynamicsError as error:
        text = str(error)
        assert text.startswith("constrained_dynamics: ")
        assert any(f"'{name}'" in text for name in m.loop_names + m.dof_names + m.body_names), text
        return
    for out in (qdd, tau, loop_wrenches, wrenches):
        assert np.isfinite(out).all()
    assert loop_wrenches.shape == (m.nloops, 6) and wrenches.shape == (m.nbodies, 6)
    again = soadyn.joint_wrenches(m, q, v, qdd, f_ext=f_ext, loop_wrenches=loop_wrenches)
    assert np.isfinite(again).all()
