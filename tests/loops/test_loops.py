"""Closed loops: the planar four-bar in closed form (closure Jacobian of
Saha, Shah & Nandihal 2013, Eq. 52b; reduced equations with
E = [1; -C_d^-1 C_i] of "Joint Coordinate Method, Part 1", Eqs. 1.16-1.24),
prescribed DOFs in loops against Pinocchio's constraint dynamics, the
closure equations of every kind against finite differences, and bad input."""
from __future__ import annotations

import numpy as np
import pytest

import soadyn
from support.closed_loops import closed_loop_case, closed_random_loops, pinocchio_solution
from support.four_bar import closure_jacobian, closure_velocity_product, four_bar, four_bar_state


@pytest.mark.parametrize("theta1", np.linspace(0.1, 2 * np.pi, 7))
def test_four_bar_driven_crank_matches_closed_form(theta1):
    m = four_bar()
    theta, thetad = four_bar_state(theta1, rate=3.0)
    assert np.abs(soadyn.loop_residual(m, theta)).max() < 1e-14
    assert soadyn.loop_rank(m, theta) == 2  # 5 equations of a planar revolute cut, rank 2
    m.set_prescribed(["crank"])
    crank_acc = -1.7
    qdd, tau, wrench = soadyn.constrained_dynamics(m, theta, thetad, np.array([crank_acc, 0.0, 0.0]))
    J = closure_jacobian(theta)
    expected = np.linalg.solve(J[:, 1:], -J[:, 0] * crank_acc - closure_velocity_product(theta, thetad))
    np.testing.assert_allclose(qdd[1:], expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())
    assert qdd[0] == crank_acc
    # Crank torque by virtual work on the independent coordinate (Joint Coordinate Method, Eq. 1.31).
    E = np.r_[1.0, -np.linalg.solve(J[:, 1:], J[:, 0])]
    M, h = soadyn.mass_matrix(m, theta), soadyn.bias_forces(m, theta, thetad)
    torque = E @ (M @ qdd + h)
    assert abs(tau[0] - torque) <= 1e-10 * abs(torque)
    # Planar: no out-of-plane reaction, no reaction torque (the minimum-norm multipliers).
    assert np.abs(wrench[0, [0, 1, 2, 5]]).max() < 1e-12 * np.abs(wrench).max()


@pytest.mark.parametrize("theta1", np.linspace(0.3, 2 * np.pi, 5))
def test_free_four_bar_matches_reduced_equation(theta1):
    m = four_bar()
    theta, thetad = four_bar_state(theta1, rate=-2.0)
    crank_torque = 0.4
    qdd, tau, _ = soadyn.constrained_dynamics(m, theta, thetad, np.array([crank_torque, 0.0, 0.0]))
    J = closure_jacobian(theta)
    E = np.r_[1.0, -np.linalg.solve(J[:, 1:], J[:, 0])]
    gamma = np.r_[0.0, np.linalg.solve(J[:, 1:], -closure_velocity_product(theta, thetad))]
    M, h = soadyn.mass_matrix(m, theta), soadyn.bias_forces(m, theta, thetad)
    crank_acc = (E @ np.array([crank_torque, 0, 0]) - E @ h - E @ M @ gamma) / (E @ M @ E)
    expected = E * crank_acc + gamma
    np.testing.assert_allclose(qdd, expected, rtol=1e-10, atol=1e-10 * np.abs(expected).max())


def test_no_loops_equals_hybrid_dynamics():
    from support.trees import random_state, random_tree
    m, _ = random_tree(3, nbodies=8)
    q, v, rng = random_state(m, 3)
    m.set_prescribed([1, 4, 6])
    u = rng.normal(size=m.nv)
    qdd, tau, wrenches = soadyn.constrained_dynamics(m, q, v, u)
    qdd_h, tau_h = soadyn.hybrid_dynamics(m, q, v, u)
    np.testing.assert_array_equal(qdd, qdd_h)
    np.testing.assert_array_equal(tau, tau_h)
    assert wrenches.shape == (0, 6)


@pytest.mark.parametrize("seed", (0, 1, 2, 4))  # cases whose loop equations are independent (not seed 3)
@pytest.mark.parametrize("kinds", [("point",), ("weld",), ("point", "weld")], ids=["point", "weld", "mixed"])
def test_prescribed_dofs_in_loops_match_pinocchio(seed, kinds):
    """Pinocchio solves with every DOF regular; soadyn, given Pinocchio's accelerations on some DOFs as
    prescribed, must return Pinocchio's accelerations on the others and the torques on those DOFs."""
    m, model, mapping, constraints, q, v, rng, _ = closed_loop_case(seed, seed % 2 == 0, 1 + seed % 2, kinds)
    tau = rng.normal(size=m.nv)
    qdd_pin, _ = pinocchio_solution(model, mapping, constraints, q, v, tau)
    C = soadyn.loop_jacobian(m, q)
    assert np.linalg.matrix_rank(C) == C.shape[0]
    for _ in range(100):  # four prescribed DOFs that leave the multipliers determined (C_r of full row rank)
        prescribed = rng.choice(m.nv, size=4, replace=False)
        regular = np.setdiff1d(np.arange(m.nv), prescribed)
        if np.linalg.matrix_rank(C[:, regular]) == C.shape[0]:
            break
    else:
        raise AssertionError("no choice of prescribed DOFs leaves C_r of full row rank")
    m.set_prescribed(np.isin(np.arange(m.nv), prescribed))
    u = tau.copy()
    u[prescribed] = qdd_pin[prescribed]
    qdd, tau_out, _ = soadyn.constrained_dynamics(m, q, v, u)
    assert np.abs(qdd - qdd_pin).max() <= 1e-9 * max(1.0, np.abs(qdd_pin).max())
    assert np.abs(tau_out - tau).max() <= 1e-9 * max(1.0, np.abs(tau).max())


ALL_KINDS = ("point", "revolute", "prismatic", "weld", "distance")


@pytest.mark.parametrize("seed", range(3))
def test_closure_jacobian_and_kappa_match_finite_differences(seed):
    m, q, rng = closed_random_loops(seed, ALL_KINDS)
    assert m.nloop_equations == 3 + 5 + 5 + 6 + 1
    assert np.abs(soadyn.loop_residual(m, q)).max() < 1e-12
    C = soadyn.loop_jacobian(m, q)
    v = rng.normal(size=m.nv)
    h = 1e-6
    dpsi = (soadyn.loop_residual(m, soadyn.integrate(m, q, v, h))
            - soadyn.loop_residual(m, soadyn.integrate(m, q, v, -h))) / (2 * h)
    assert np.abs(dpsi - C @ v).max() <= 1e-7 * np.abs(C @ v).max()
    # kappa: along the constrained motion d/dt (C v) = 0, i.e. C qdd = kappa.
    v -= np.linalg.pinv(C) @ (C @ v)
    qdd, _, _ = soadyn.constrained_dynamics(m, q, v, rng.normal(size=m.nv))
    h = 1e-5
    plus = soadyn.loop_residual(m, soadyn.integrate(m, q, h * v + 0.5 * h * h * qdd, 1.0), v + h * qdd)[1]
    minus = soadyn.loop_residual(m, soadyn.integrate(m, q, -h * v + 0.5 * h * h * qdd, 1.0), v - h * qdd)[1]
    scale = np.abs(C).max() * (np.abs(qdd).max() + np.abs(v).max() ** 2)
    assert np.abs((plus - minus) / (2 * h)).max() <= 1e-6 * scale


def test_loop_names_and_counts():
    m = four_bar()
    assert m.loop_names == ["pin"] and m.nloops == 1 and m.nloop_equations == 5


def _two_links():
    m = soadyn.Model()
    z = soadyn.Joint.revolute((0, 0, 1))
    m.add_body("a", None, z, mass=1.0, com=(0.5, 0, 0), inertia=(0.1, 0.1, 0.1))
    m.add_body("b", "a", z, placement=(1.0, 0, 0), mass=1.0, com=(0.5, 0, 0), inertia=(0.1, 0.1, 0.1))
    return m


@pytest.mark.parametrize("args,message", [
    (("l", "a", "a", "point"), "loop 'l': frame_a 'a' and frame_b 'a' are on the same body 'a'"),
    (("l", "nope", "b", "point"), "loop 'l': frame_a 'nope' is neither a body nor a frame"),
    (("l", "a", "nope", "weld"), "loop 'l': frame_b 'nope' is neither a body nor a frame"),
    (("l", "a", "b", "hinge"), "loop 'l': unknown kind 'hinge' (expected point, revolute, prismatic, weld or distance)"),
    (("l", "a", None, "distance"),  # no length=: measured at the neutral configuration, where they coincide
     "loop 'l': frame_a and frame_b coincide at the neutral configuration: give the rod's length="),
    (("l", None, "b", "point"), "loop 'l': frame_a '' is on the world; frame_a must be on a body"),
])
def test_bad_loops_are_refused_by_name(args, message):
    m = _two_links()
    with pytest.raises(soadyn.LoopError) as info:
        m.add_loop(*args)
    assert str(info.value) == message
    assert m.nloops == 0


def test_nan_placement_duplicate_name_and_bad_length_are_refused():
    m = _two_links()
    with pytest.raises(soadyn.LoopError, match=r"^loop 'l': placement_a is not finite$"):
        m.add_loop("l", "a", "b", "point", placement_a=(None, (np.nan, 0, 0)))
    with pytest.raises(soadyn.LoopError, match=r"^loop 'l': placement_b rotation is not a rotation matrix"):
        m.add_loop("l", "a", "b", "point", placement_b=(2 * np.eye(3), None))
    with pytest.raises(soadyn.LoopError, match=r"^loop 'l': a distance loop needs a finite, positive length$"):
        m.add_loop("l", "a", "b", "distance", length=-1.0)
    m.add_loop("l", "a", "b", "point")
    with pytest.raises(soadyn.LoopError, match=r"^loop 'l': duplicate loop name$"):
        m.add_loop("l", "a", None, "point")
    assert m.nloops == 1


def test_loops_on_flexible_bodies_are_refused():
    m = soadyn.Model()
    beam = soadyn.FlexibleBody.cantilever_beam(1.0, 10.0, 1.0, 2)
    m.add_flexible_body("beam", None, beam, soadyn.Joint.revolute((0, 0, 1)))
    m.add_body("tip", "beam", soadyn.Joint.revolute((0, 0, 1)), placement=(1.0, 0, 0), mass=1.0,
               com=(0.1, 0, 0), inertia=(0.1, 0.1, 0.1))
    with pytest.raises(soadyn.LoopError, match=r"^loop 'l': frame_a 'tip' is on flexible body 'beam' or carried "
                                               r"by it; loops on flexible bodies are not supported$"):
        m.add_loop("l", "tip", None, "point")


def _spinner_on_a_locked_turntable(seed: int, with_loop: bool):
    """A turntable (prescribed) carrying a spinner (regular) whose axis passes through a point pinned
    to the world: the loop locks the turntable, and the spinner turns freely about an axis through
    the pin, so the pin exerts no torque on it. The spinner's column of C is zero, but formed as
    axis x lever arm along the axis it is rounding noise for most axes."""
    rng = np.random.default_rng(seed)
    m = soadyn.Model()
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    m.add_body("turntable", None, soadyn.Joint.revolute((0.0, 0.0, 1.0)), mass=2.0, com=(0.1, 0.0, 0.0),
               inertia=(0.1, 0.2, 0.3))
    m.add_body("spinner", "turntable", soadyn.Joint.revolute(tuple(axis)), placement=tuple(rng.uniform(0.1, 0.5, 3)),
               mass=1.0, com=tuple(rng.uniform(-0.1, 0.1, 3)), inertia=(0.05, 0.06, 0.07))
    q = rng.uniform(-np.pi, np.pi, 2)
    if with_loop:
        point = rng.uniform(0.2, 0.9) * axis
        pose = soadyn.frame_pose(m, q, "spinner")
        m.add_loop("pin", "spinner", None, "point", placement_a=(None, tuple(point)),
                   placement_b=(None, tuple(pose[:3, :3] @ point + pose[:3, 3])))
    m.set_prescribed([True, False])
    return m, q, rng


@pytest.mark.parametrize("seed", range(12))
def test_a_regular_dof_whose_jacobian_column_is_rounding_noise_feels_no_loop_force(seed):
    m, q, rng = _spinner_on_a_locked_turntable(seed, with_loop=True)
    free, _, _ = _spinner_on_a_locked_turntable(seed, with_loop=False)
    v = np.array([0.0, rng.normal()])
    u = np.array([0.0, rng.normal()])  # the turntable held (the pin allows no other motion), a torque on the spinner
    qdd, tau, wrenches = soadyn.constrained_dynamics(m, q, v, u)
    qdd_free, _ = soadyn.hybrid_dynamics(free, q, v, u)
    assert abs(qdd[1] - qdd_free[1]) <= 1e-9 * max(1.0, abs(qdd_free[1]))
    assert qdd[0] == 0.0


def _model_with_solver(solver):
    """The four-bar (its loops solved through the mass matrix) or a random 12-20 body tree closed by a
    point loop (the articulated-body response): each loop solver of constrained_dynamics."""
    if solver == "mass matrix":
        m = four_bar("point")
        q, v = four_bar_state(0.7, 1.3)
    else:
        m, _, _, _, q, v, _, _ = closed_loop_case(0, True, 1, ("point",))
    assert m.loop_solver == solver
    return m, q, v


@pytest.mark.parametrize("solver", ["mass matrix", "articulated"])
def test_overflow_is_a_named_error_in_either_loop_solver(solver):
    """Finite inputs whose dynamics overflow raise DynamicsError naming the call, never return inf or NaN;
    the model then computes normally again."""
    m, q, v = _model_with_solver(solver)
    u = np.zeros(m.nv)
    expected = soadyn.constrained_dynamics(m, q, v, u)
    for q_, v_, u_ in ((q, np.full(m.nv, 1e200), u), (q, v, np.full(m.nv, 1e308))):
        with pytest.raises(soadyn.DynamicsError, match="constrained_dynamics"):
            soadyn.constrained_dynamics(m, q_, v_, u_)
    for a, b in zip(soadyn.constrained_dynamics(m, q, v, u), expected):
        np.testing.assert_array_equal(a, b)
