"""Armature (a rotor inertia on a DOF, Model.set_armature) in every dynamics call.

Oracles: Pinocchio's `model.armature` (its CRBA, ABA, RNEA and ABA
derivatives carry it on the mass matrix's diagonal) on example-robot-data
robots, and MuJoCo's joint `armature` on chains written in MJCF. Hybrid masks
are checked against the partitioned equations assembled from Pinocchio's M
and nonlinear effects, loop models against the KKT system assembled from
Pinocchio's M and soadyn's loop Jacobian.
"""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import soadyn
from soadyn.oracles import PinocchioOracle
from support.mujoco_models import full_mass_matrix
from support.robots import matrix_from_pin, robot
from support.trees import random_state

ROBOTS = [("ur5", False), ("panda", False), ("solo12", True), ("talos", True)]


def _with_armature(name: str, floating: bool, seed: int):
    path, _ = robot(name)
    m = soadyn.load_urdf(path, floating_base=floating)
    oracle = PinocchioOracle(m, path, floating)
    armature = np.random.default_rng(seed).uniform(0.05, 2.0, m.nv)
    for k in range(m.nv):
        m.set_armature(k, armature[k])
    oracle.model.armature[:] = armature[oracle.v_of_pin]
    oracle.data = oracle.model.createData()
    return m, oracle, armature


def _relative(a, b) -> float:
    return float(np.abs(a - b).max() / max(1.0, np.abs(b).max()))


@pytest.fixture(scope="module", params=ROBOTS, ids=[r[0] for r in ROBOTS])
def robot_with_armature(request):
    return _with_armature(*request.param, seed=7)


def test_model_reports_its_armature(robot_with_armature):
    m, _, armature = robot_with_armature
    np.testing.assert_array_equal(m.armature, armature)


def test_mass_matrix_forward_and_inverse_dynamics_match_pinocchio(robot_with_armature):
    m, o, _ = robot_with_armature
    for seed in range(3):
        q, v, _ = random_state(m, seed)
        rng = np.random.default_rng(seed)
        tau, qdd = rng.normal(size=m.nv), rng.normal(size=m.nv)
        M_pin = matrix_from_pin(o, pin.crba(o.model, o.data, o.q(q)))
        M_pin = np.triu(M_pin) + np.triu(M_pin, 1).T
        assert _relative(soadyn.mass_matrix(m, q), M_pin) < 1e-12
        qdd_pin = o.from_pin(pin.aba(o.model, o.data, o.q(q), o.to_pin(v), o.to_pin(tau)))
        assert _relative(soadyn.forward_dynamics(m, q, v, tau), qdd_pin) < 1e-10
        tau_pin = o.from_pin(pin.rnea(o.model, o.data, o.q(q), o.to_pin(v), o.to_pin(qdd)))
        assert _relative(soadyn.inverse_dynamics(m, q, v, qdd), tau_pin) < 1e-10


def test_armature_changes_the_answer(robot_with_armature):
    """The comparison above would fail without armature: it is not negligible."""
    m, o, _ = robot_with_armature
    q, v, _ = random_state(m, 1)
    tau = np.random.default_rng(1).normal(size=m.nv)
    bare = m.copy()
    bare.set_armature(list(range(m.nv)), 0.0)
    assert not bare.armature.any()
    qdd_pin = o.from_pin(pin.aba(o.model, o.data, o.q(q), o.to_pin(v), o.to_pin(tau)))
    assert _relative(soadyn.forward_dynamics(bare, q, v, tau), qdd_pin) > 1e-3


@pytest.mark.parametrize("seed", range(3))
def test_hybrid_masks_solve_the_partitioned_equations_of_pinocchio(robot_with_armature, seed):
    """Jain & Rodriguez 1993, Eq. 12 with Pinocchio's M (armature included) and h."""
    m, o, _ = robot_with_armature
    rng = np.random.default_rng(seed)
    q, v, _ = random_state(m, seed)
    mask = rng.random(m.nv) < 0.5
    u = rng.normal(size=m.nv)
    M = matrix_from_pin(o, pin.crba(o.model, o.data, o.q(q)))
    M = np.triu(M) + np.triu(M, 1).T
    h = o.from_pin(pin.nonLinearEffects(o.model, o.data, o.q(q), o.to_pin(v)))
    p, r = np.flatnonzero(mask), np.flatnonzero(~mask)
    qdd = np.empty(m.nv)
    qdd[p] = u[p]
    qdd[r] = np.linalg.solve(M[np.ix_(r, r)], u[r] - h[r] - M[np.ix_(r, p)] @ u[p])
    tau_p = M[p] @ qdd + h[p]
    m.set_prescribed(mask)
    try:
        qdd_s, tau_s = soadyn.hybrid_dynamics(m, q, v, u)
    finally:
        m.set_prescribed(np.zeros(m.nv, dtype=bool))
    assert _relative(qdd_s, qdd) < 1e-9
    assert _relative(tau_s[p], tau_p) < 1e-9


def test_forward_dynamics_derivatives_match_pinocchio(robot_with_armature):
    m, o, _ = robot_with_armature
    q, v, _ = random_state(m, 2)
    tau = np.random.default_rng(2).normal(size=m.nv)
    dq, dv, du, *_ = soadyn.dynamics_derivatives(m, q, v, tau)
    pin.computeABADerivatives(o.model, o.data, o.q(q), o.to_pin(v), o.to_pin(tau))
    Minv = o.data.Minv.copy()
    Minv = np.triu(Minv) + np.triu(Minv, 1).T
    assert _relative(dq, matrix_from_pin(o, o.data.ddq_dq)) < 1e-9
    assert _relative(dv, matrix_from_pin(o, o.data.ddq_dv)) < 1e-9
    assert _relative(du, matrix_from_pin(o, Minv)) < 1e-9


def test_kinetic_energy_is_half_v_M_v(robot_with_armature):
    m, o, _ = robot_with_armature
    q, v, _ = random_state(m, 4)
    M = matrix_from_pin(o, pin.crba(o.model, o.data, o.q(q)))
    M = np.triu(M) + np.triu(M, 1).T
    assert abs(soadyn.kinetic_energy(m, q, v) - 0.5 * v @ M @ v) < 1e-11 * max(1.0, 0.5 * v @ M @ v)


def _mjcf_chain(axes, armature, damping=0.0) -> str:
    """A chain of hinges and slides (axes: ('hinge'|'slide', axis)) in MJCF, every body a capsule-free point mass
    with an explicit full inertia."""
    body = ""
    close = ""
    for k, (kind, axis) in enumerate(axes):
        body += (f'<body name="b{k}" pos="0.1 0.2 0.3" quat="0.9 0.1 0.3 0.2">'
                 f'<joint name="j{k}" type="{kind}" axis="{axis[0]} {axis[1]} {axis[2]}" '
                 f'armature="{armature[k]}" damping="{damping}"/>'
                 f'<inertial pos="0.05 -0.02 0.1" mass="{1.0 + k}" fullinertia="0.3 0.4 0.5 0.01 0.02 0.03"/>')
        close += "</body>"
    return (f'<mujoco><option gravity="0 0 -9.81"/><compiler angle="radian"/>'
            f'<worldbody>{body}{close}</worldbody></mujoco>')


def _soadyn_chain(axes, armature) -> soadyn.Model:
    """The same chain built with soadyn's own API."""
    from scipy.spatial.transform import Rotation

    m = soadyn.Model()
    R = Rotation.from_quat([0.1, 0.3, 0.2, 0.9]).as_matrix()  # MuJoCo's quat is (w, x, y, z), normalised
    inertia = np.array([[0.3, 0.01, 0.02], [0.01, 0.4, 0.03], [0.02, 0.03, 0.5]])
    parent = None
    for k, (kind, axis) in enumerate(axes):
        joint = soadyn.Joint.revolute(axis) if kind == "hinge" else soadyn.Joint.prismatic(axis)
        m.add_body(f"b{k}", parent, joint, placement=(R, np.array([0.1, 0.2, 0.3])), mass=1.0 + k,
                   com=[0.05, -0.02, 0.1], inertia=inertia)
        parent = f"b{k}"
    for k in range(len(axes)):
        m.set_armature(k, armature[k])
    return m


def test_chains_match_mujoco():
    import mujoco

    rng = np.random.default_rng(11)
    kinds = ["hinge", "slide", "hinge", "hinge", "slide", "hinge"]
    axes = [(kind, rng.normal(size=3).round(3)) for kind in kinds]
    armature = rng.uniform(0.1, 1.5, len(axes)).round(4)
    mj = mujoco.MjModel.from_xml_string(_mjcf_chain(axes, armature))
    data = mujoco.MjData(mj)
    m = _soadyn_chain(axes, armature)
    for seed in range(3):
        r = np.random.default_rng(seed)
        q, v, tau = r.normal(size=m.nv), r.normal(size=m.nv), r.normal(size=m.nv)
        data.qpos[:], data.qvel[:], data.qfrc_applied[:] = q, v, tau
        mujoco.mj_forward(mj, data)
        M = full_mass_matrix(mj, data)
        assert _relative(soadyn.mass_matrix(m, q), M) < 1e-12
        assert _relative(soadyn.inverse_dynamics(m, q, v, np.zeros(m.nv)), data.qfrc_bias) < 1e-12
        assert _relative(soadyn.forward_dynamics(m, q, v, tau), data.qacc) < 1e-9


def test_loop_model_matches_the_kkt_system():
    m = soadyn.scenes.four_bar()
    for k in range(m.nv):
        m.set_armature(k, 0.1 * (k + 1))
    q, v = soadyn.scenes.four_bar_state(0.7, 1.3)
    u = np.linspace(0.5, -0.5, m.nv)
    qdd, _, _ = soadyn.constrained_dynamics(m, q, v, u)
    M = soadyn.mass_matrix(m, q)
    bare = m.copy()
    bare.set_armature(list(range(m.nv)), 0.0)
    assert np.allclose(M - soadyn.mass_matrix(bare, q), np.diag(0.1 * np.arange(1, m.nv + 1)), atol=1e-14)
    h = soadyn.inverse_dynamics(m, q, v, np.zeros(m.nv))
    C = soadyn.loop_jacobian(m, q)
    # C qdd = -Cdot v: the velocity product from C's directional derivative along v (central differences of C).
    eps = 1e-6
    Cdot = (soadyn.loop_jacobian(m, soadyn.integrate(m, q, v, eps)) -
            soadyn.loop_jacobian(m, soadyn.integrate(m, q, v, -eps))) / (2 * eps)
    residual_dynamics = M @ qdd + h - u
    # M qdd + h - u lies in the row space of C (the loop forces), and C qdd + Cdot v = 0.
    lam, *_ = np.linalg.lstsq(C.T, residual_dynamics, rcond=None)
    assert np.abs(C.T @ lam - residual_dynamics).max() < 1e-9
    assert np.abs(C @ qdd + Cdot @ v).max() < 1e-6


@pytest.mark.parametrize("value, message", [(-1.0, "non-negative"), (float("nan"), "finite"),
                                            (float("inf"), "finite")])
def test_bad_armature_is_refused_by_name(value, message):
    m = soadyn.Model()
    m.add_body("a", None, soadyn.Joint.revolute([0, 0, 1]), mass=1.0, com=[0, 0, 0], inertia=np.eye(3))
    with pytest.raises(ValueError, match=f"DOF 'a.*{message}"):
        m.set_armature("a", value)
    assert not m.armature.any()


def test_unknown_dof_and_modal_dof_are_refused():
    m = soadyn.scenes.cassini()
    with pytest.raises(ValueError, match="unknown DOF or joint 'nope'"):
        m.set_armature("nope", 1.0)
    modal = int(np.flatnonzero(m.modal)[0])
    with pytest.raises(ValueError, match=f"DOF '{m.dof_names[modal]}' is a modal coordinate"):
        m.set_armature(modal, 1.0)
    with pytest.raises(TypeError, match="armature must be a real number"):
        m.set_armature(0, "1.0")


def test_flexible_model_with_armature_solves_its_own_mass_matrix():
    """Cassini (flexible appendages, body-frame and tree-frame sweeps): forward dynamics with
    armatures equals M^-1 (tau - h) with M from the Newton-Euler columns, and M grows by exactly
    the armature on the diagonal."""
    m = soadyn.scenes.cassini()
    hinge = np.flatnonzero(~m.modal)
    armature = np.linspace(0.5, 3.0, hinge.size)
    bare = m.copy()
    for k, a in zip(hinge, armature):
        m.set_armature(int(k), float(a))
    rng = np.random.default_rng(5)
    q = soadyn.integrate(m, soadyn.neutral_configuration(m), rng.normal(size=m.nv) * 0.1, 1.0)
    v, tau = rng.normal(size=m.nv) * 0.1, rng.normal(size=m.nv)
    M = soadyn.mass_matrix(m, q)
    added = np.zeros(m.nv)
    added[hinge] = armature
    np.testing.assert_allclose(M - soadyn.mass_matrix(bare, q), np.diag(added), atol=1e-9 * np.abs(M).max())
    h = soadyn.inverse_dynamics(m, q, v, np.zeros(m.nv))
    assert _relative(soadyn.forward_dynamics(m, q, v, tau), np.linalg.solve(M, tau - h)) < 1e-9
