"""Closed loops in motion: assembly (Gauss-Newton on the closure equations),
velocity projection, coordinate partitioning ("Joint Coordinate Method,
Part 1", Eqs. 1.6-1.7, 1.16-1.20), and the Simulator stepping loop models
with every integrator, projecting onto the closure after each step, driving
and locking DOFs inside loops. References: the four-bar's closed-form
position and velocity analysis (support/four_bar.py), Pinocchio's mass matrix for
the impulse of a lock, and energy conservation."""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import soadyn
from soadyn import MotionSource, Simulator
from support.closed_loops import closed_random_loops
from support.four_bar import assembled, four_bar, four_bar_state

KINDS = ["point", "revolute", "prismatic", "weld", "distance"]


def energy(m, q, v):
    return soadyn.kinetic_energy(m, q, v) + soadyn.potential_energy(m, q)


# --- assembly ---------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("kind", ["point", "revolute"])
@pytest.mark.parametrize("theta1", [0.3, 1.9, 4.0])
def test_assemble_with_the_crank_held_gives_the_closed_form_four_bar(kind, theta1):
    m = four_bar(kind)
    exact = assembled(theta1)
    start = exact + np.array([0.0, 0.08, -0.06])
    q = soadyn.assemble(m, start, hold="crank")
    assert q[0] == start[0]  # held
    assert np.max(np.abs(q - exact)) <= 1e-10
    assert np.max(np.abs(soadyn.loop_residual(m, q))) <= 1e-12


@pytest.mark.parametrize("seed", range(8))
def test_assemble_closes_random_trees_with_loops_of_every_kind(seed):
    kinds = [KINDS[(seed + k) % len(KINDS)] for k in range(1 + seed % 4)]
    m, q, rng = closed_random_loops(seed, kinds)
    start = soadyn.integrate(m, q, 0.02 * rng.normal(size=m.nv), 1.0)
    assert np.max(np.abs(soadyn.loop_residual(m, start))) > 1e-4
    closed = soadyn.assemble(m, start)
    assert np.max(np.abs(soadyn.loop_residual(m, closed))) <= 1e-12
    # Gauss-Newton with minimum-norm steps stays near the start: the correction is of the start's error's size.
    step = np.max(np.abs(closed - start))
    assert step <= 20 * 0.02 * 3


def test_assemble_names_the_loop_that_cannot_close():
    m = soadyn.Model()
    m.gravity = (0.0, 0.0, 0.0)
    z = soadyn.Joint.revolute((0.0, 0.0, 1.0))
    m.add_body("arm", None, z, mass=1.0, com=(0.5, 0, 0), inertia=(0.0, 0.1, 0.1))
    # The arm's tip (1 m from its pivot) cannot reach a point 3 m away.
    m.add_loop("too_far", "arm", None, "point", placement_a=(None, (1.0, 0, 0)), placement_b=(None, (3.0, 0, 0)))
    # Gauss-Newton reaches the nearest point and stalls there: LoopError at once, not after max_iterations.
    with pytest.raises(soadyn.LoopError, match="loop 'too_far' cannot be closed from here"):
        soadyn.assemble(m, [0.2], max_iterations=10 ** 6)
    with pytest.raises(ValueError, match="nowhere"):
        soadyn.assemble(m, [0.2], hold="nowhere")


def test_assemble_leaves_a_model_without_loops_alone():
    m = soadyn.scenes.pendulum_chain(3)
    q = soadyn.random_configuration(m, 4)
    assert np.array_equal(soadyn.assemble(m, q), q)
    v = np.arange(3.0)
    assert np.array_equal(soadyn.project_velocity(m, q, v), v)
    assert soadyn.independent_coordinates(m, q) == m.dof_names


# --- velocity projection and partitioning -------------------------------------------------------------------

@pytest.mark.parametrize("seed", range(6))
def test_project_velocity_is_the_minimum_norm_correction(seed):
    m, q, rng = closed_random_loops(50 + seed, [KINDS[seed % 5], KINDS[(seed + 2) % 5]])
    v = rng.normal(size=m.nv)
    held = [m.dof_names[0]]
    out = soadyn.project_velocity(m, q, v, hold=held)
    C = soadyn.loop_jacobian(m, q)
    Cf = C.copy()
    Cf[:, 0] = 0.0
    # Reference: v - Cf^+ (C v), numpy's SVD pseudo-inverse.
    reference = v - np.linalg.pinv(Cf, rcond=1e-12) @ (C @ v)
    assert out[0] == v[0]
    assert np.max(np.abs(out - reference)) <= 1e-10 * max(1.0, np.max(np.abs(v)))
    if np.linalg.matrix_rank(Cf, 1e-10) == np.linalg.matrix_rank(C, 1e-10):  # consistent: closure met
        assert np.max(np.abs(C @ out)) <= 1e-11 * max(1.0, np.max(np.abs(v)))


def test_independent_coordinates_partition_the_four_bar():
    m = four_bar("revolute")  # 5 equations of rank 2: one independent DOF
    for theta1 in np.linspace(0.2, 6.0, 9):
        q, _ = four_bar_state(theta1, 0.0)
        independent = soadyn.independent_coordinates(m, q)
        assert len(independent) == m.nv - soadyn.loop_rank(m, q) == 1
        # The dependent block C_d is invertible on the loop's range (Eqs. 1.16-1.20).
        C = soadyn.loop_jacobian(m, q)
        dependent = [k for k, n in enumerate(m.dof_names) if n not in independent]
        assert np.linalg.matrix_rank(C[:, dependent], 1e-9) == 2


@pytest.mark.parametrize("seed", range(6))
def test_independent_coordinates_leave_a_nonsingular_dependent_block(seed):
    m, q, _ = closed_random_loops(20 + seed, (KINDS[seed % 5:] + KINDS[:seed % 5])[:1 + seed % 4])
    independent = soadyn.independent_coordinates(m, q)
    C = soadyn.loop_jacobian(m, q)
    rank = soadyn.loop_rank(m, q)
    assert len(independent) == m.nv - rank
    dependent = [k for k, n in enumerate(m.dof_names) if n not in independent]
    assert np.linalg.matrix_rank(C[:, dependent], 1e-9 * np.abs(C).max()) == rank


# --- the Simulator with loops ----------------------------------------------------------------------------------

def test_free_four_bar_conserves_energy_and_closure_over_ten_seconds_of_rk4():
    m = four_bar("point")
    q, _ = four_bar_state(0.7, 0.0)
    errors = []
    for dt in (2e-3, 1e-3):
        sim = Simulator(m, dt, "rk4")
        sim.set_state(q, np.zeros(3))
        e0 = energy(m, sim.q, sim.v)
        worst_closure = 0.0
        for _ in range(int(round(10.0 / dt))):
            sim.step()
            psi, cv = soadyn.loop_residual(m, sim.q, sim.v)
            worst_closure = max(worst_closure, np.max(np.abs(psi)), np.max(np.abs(cv)))
        assert worst_closure <= 1e-12  # after the projection of every step
        assert 0 < sim.max_loop_drift[0] <= 1e-8 and 0 < sim.max_loop_drift[1] <= 1e-6  # what RK4 left
        errors.append(abs(energy(m, sim.q, sim.v) - e0))
    assert errors[1] <= 1e-6 * e0  # 10 s at 1 kHz
    assert errors[0] / errors[1] >= 16  # fourth order or better: the projection adds no low-order error


@pytest.mark.parametrize("integrator", ["euler", "rk4", "dopri5"])
def test_every_integrator_keeps_a_random_loop_model_closed(integrator):
    m, q, rng = closed_random_loops(3, ["weld", "point", "distance"])
    v = soadyn.project_velocity(m, q, rng.normal(size=m.nv))
    e0 = energy(m, q, v)
    drifts = []
    for dt in (1e-3, 5e-4):
        sim = Simulator(m, dt, integrator)
        sim.set_state(q, v)
        sim.run(0.3)
        psi, cv = soadyn.loop_residual(m, sim.q, sim.v)
        assert np.max(np.abs(psi)) <= 1e-12 and np.max(np.abs(cv)) <= 1e-11
        drifts.append(abs(energy(m, sim.q, sim.v) - e0))
    if integrator == "euler":  # first order: the energy error halves with the step
        assert 1.5 <= drifts[0] / drifts[1] <= 3.0
    else:
        assert drifts[0] <= 1e-7 * e0


def test_driven_crank_follows_the_closed_form_four_bar_and_reports_its_torque():
    """Crank prescribed at 2 rad/s: the coupler and rocker follow the position analysis;
    the drive torque equals inverse dynamics with loops (constrained_dynamics) at each state."""
    m = four_bar("revolute")
    rate = 2.0
    q, v = four_bar_state(0.4, rate)
    sim = Simulator(m, 1e-3, "rk4")
    sim.set_state(q, v)
    sim.prescribe("crank", MotionSource.constant_velocity(rate))
    crank = m.dof_index("crank")
    driven = m.copy()
    driven.set_prescribed("crank")
    for _ in range(40):
        q0, v0 = sim.q, sim.v
        sim.run(0.05)
        theta1 = sim.q[0]
        assert theta1 == pytest.approx(0.4 + rate * sim.time, abs=1e-12)
        assert np.max(np.abs(sim.q - assembled(theta1))) <= 1e-9
        exact_q, exact_v = four_bar_state(theta1, rate)
        assert np.max(np.abs(sim.v - exact_v)) <= 1e-8
    # forces: the crank torque at the start of the last step, from the state at that start.
    u = np.zeros(3)
    sim2 = Simulator(m, 1e-3, "rk4")
    sim2.set_state(q0, v0)
    sim2.prescribe("crank", MotionSource.constant_velocity(rate))
    sim2.step()
    _, tau, _ = soadyn.constrained_dynamics(driven, q0, v0, u)
    assert sim2.forces[crank] == pytest.approx(tau[crank], rel=1e-12, abs=1e-12)


def kkt_velocity_after_lock(model, q, v, C, locked):
    """The plastic impact that stops DOF `locked` inside the loops: v+ minimises the kinetic
    energy distance (v+ - v)' M (v+ - v) subject to C v+ = 0 and v+_locked = 0; M from Pinocchio."""
    A = np.vstack([C, np.eye(len(v))[locked]])
    M = pin.crba(*model)
    Minv_At = np.linalg.solve(M, A.T)
    return v - Minv_At @ np.linalg.lstsq(A @ Minv_At, A @ v, rcond=1e-12)[0]


def test_lock_inside_a_loop_is_a_plastic_impact_with_the_cut_impulses():
    """A five-bar (two DOF): locking one leg stops it and keeps the loop closed; the velocity jump is the
    constrained plastic impact computed from Pinocchio's mass matrix."""
    m = soadyn.Model()
    m.gravity = (0.0, -9.81, 0.0)
    z = soadyn.Joint.revolute((0.0, 0.0, 1.0))
    rod = lambda length, mass: dict(mass=mass, com=(length / 2, 0, 0), inertia=(0.0, mass * length**2 / 12,
                                                                                   mass * length**2 / 12))
    m.add_body("left", None, z, **rod(0.3, 1.0))
    m.add_body("left_upper", "left", z, placement=(0.3, 0, 0), **rod(0.5, 0.8))
    m.add_body("right", None, z, placement=(0.4, 0, 0), **rod(0.3, 1.2))
    m.add_body("right_upper", "right", z, placement=(0.3, 0, 0), **rod(0.5, 0.7))
    m.add_loop("apex", "left_upper", "right_upper", "point", placement_a=(None, (0.5, 0, 0)),
               placement_b=(None, (0.5, 0, 0)))
    q = soadyn.assemble(m, np.array([1.8, -1.2, 1.3, 1.1]), hold=["left", "right"])
    v = soadyn.project_velocity(m, q, np.array([1.5, 0.0, -0.7, 0.0]), hold=["left", "right"])
    sim = Simulator(m, 1e-3, "rk4")
    sim.set_state(q, v)
    sim.run(0.1)
    q, v = sim.q, sim.v
    pm = pin.Model()
    # Pinocchio mirror of the same tree for M (revolute z joints, same inertias).
    def add(parent, name, offset, length, mass):
        jid = pm.addJoint(parent, pin.JointModelRZ(), pin.SE3(np.eye(3), np.array([offset, 0, 0])), name)
        pm.appendBodyToJoint(jid, pin.Inertia(mass, np.array([length / 2, 0, 0]),
                                              np.diag([0.0, mass * length**2 / 12, mass * length**2 / 12])),
                             pin.SE3.Identity())
        return jid
    left = add(0, "left", 0.0, 0.3, 1.0)
    add(left, "left_upper", 0.3, 0.5, 0.8)
    right = add(0, "right", 0.4, 0.3, 1.2)
    add(right, "right_upper", 0.3, 0.5, 0.7)
    C = soadyn.loop_jacobian(m, q)
    e0 = soadyn.kinetic_energy(m, q, v)
    sim.lock("left")
    expected = kkt_velocity_after_lock((pm, pm.createData(), q), q, v, C, 0)
    assert np.max(np.abs(sim.v - expected)) <= 1e-12 * max(1.0, np.max(np.abs(v)))
    assert sim.v[0] == 0.0
    assert np.max(np.abs(C @ sim.v)) <= 1e-12
    e1 = soadyn.kinetic_energy(m, sim.q, sim.v)
    assert sim.energy_lost == pytest.approx(e0 - e1, rel=1e-12) and e1 < e0
    # The remaining DOF keeps moving under gravity, the locked leg holds, the loop stays closed.
    held = sim.q[0]
    tr = sim.run(0.5)
    assert np.all(tr.q[:, 0] == held) and np.ptp(tr.q[:, 2]) > 1e-3
    assert np.max(np.abs(soadyn.loop_residual(m, sim.q))) <= 1e-12
    # Locking the second leg locks the mechanism (mobility 0): everything stops.
    sim.lock("right")
    assert np.max(np.abs(sim.v)) <= 1e-12
    sim.release("left")
    sim.release("right")
    sim.run(0.2)
    assert np.max(np.abs(sim.v)) > 1e-3  # falls again


def test_a_step_whose_projection_fails_names_the_loop_and_changes_nothing():
    m = four_bar("point")
    q, v = four_bar_state(0.7, 3.0)
    sim = Simulator(m, 1e-3, "rk4")
    sim.set_state(q + np.array([0.0, 0.3, 0.0]), v)  # far from closure: set_state keeps what it is given
    sim.loop_max_iterations = 1
    before = (sim.q, sim.v, sim.time, sim.steps_taken)
    with pytest.raises(soadyn.DynamicsError, match="loop 'pin'"):
        sim.step()
    after = (sim.q, sim.v, sim.time, sim.steps_taken)
    assert all(np.array_equal(a, b) for a, b in zip(before, after))
    sim.loop_max_iterations = 20
    sim.step()
    assert np.max(np.abs(soadyn.loop_residual(m, sim.q))) <= 1e-12
    with pytest.raises(ValueError):
        sim.loop_tolerance = float("nan")
    with pytest.raises(ValueError):
        sim.loop_max_iterations = 0


def test_a_model_without_loops_steps_exactly_as_before():
    """The loop projection is skipped: identical trajectories to hybrid_dynamics-driven RK4 by hand."""
    m = soadyn.scenes.pendulum_chain(4)
    q, v = soadyn.random_configuration(m, 2), np.linspace(-1, 1, 4)
    sim = Simulator(m, 1e-3, "rk4")
    sim.set_state(q, v)
    sim.step()
    f = lambda x, y: soadyn.forward_dynamics(m, x, y, np.zeros(4))
    h = 1e-3
    k1v = f(q, v)
    k2v = f(q + h / 2 * v, v + h / 2 * k1v)
    k3v = f(q + h / 2 * (v + h / 2 * k1v), v + h / 2 * k2v)
    k4v = f(q + h * (v + h / 2 * k2v), v + h * k3v)
    v1 = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v)
    assert np.max(np.abs(sim.v - v1)) <= 1e-14
    assert sim.loop_drift == (0.0, 0.0)


# --- the HIL runner with loops -----------------------------------------------------------------------------------

def test_hil_run_of_a_loop_model_matches_plain_stepping_and_reports_the_drift():
    from soadyn.hil import format_table, run_hil
    m = four_bar("point")
    q, _ = four_bar_state(0.7, 0.0)
    sims = []
    for _ in range(2):
        sim = Simulator(m, 1e-3, "rk4")
        sim.set_state(q, np.zeros(3))
        sims.append(sim)
    report = run_hil(sims[0], 1000.0, 1.0, progress=False, realtime=False)
    sims[1].run(1.0)
    assert report.ok and report.steps == 1000
    np.testing.assert_array_equal(sims[0].q, sims[1].q)
    np.testing.assert_array_equal(sims[0].v, sims[1].v)
    assert report.loop_drift == {"max_position": sims[1].max_loop_drift[0], "max_velocity": sims[1].max_loop_drift[1]}
    assert 0 < report.loop_drift["max_position"] <= 1e-8
    assert "loop drift" in format_table(report) and report.to_dict()["loop_drift"] == report.loop_drift


def test_hil_run_names_the_loop_whose_closure_fails():
    from soadyn.hil import format_table, run_hil
    m = four_bar("point")
    q, v = four_bar_state(0.7, 3.0)
    sim = Simulator(m, 1e-3, "rk4")
    sim.set_state(q + np.array([0.0, 0.3, 0.0]), v)
    sim.loop_max_iterations = 1
    report = run_hil(sim, 1000.0, 0.1, progress=False, realtime=False)
    assert not report.ok and report.steps == 0
    assert report.status == "loop closure not reached"
    assert report.failed_loop == "pin" and report.failed_dof is None
    assert "(loop 'pin')" in format_table(report)


@pytest.mark.parametrize("scene", ["four-bar", "slider-crank", "delta-robot"])
def test_soadyn_hil_runs_the_loop_scenes_from_a_closed_start(scene):
    from soadyn import cli
    from soadyn.hil import run_hil, scene_simulator
    sim = scene_simulator(scene, 1000.0)
    q0, v0 = sim.q, sim.v
    m = soadyn.scenes.SCENES[scene]()
    assert np.max(np.abs(soadyn.loop_residual(m, q0))) <= 1e-12 and not v0.any()
    report = run_hil(sim, 1000.0, 0.3, progress=False, realtime=False)
    assert report.ok and report.loop_drift["max_position"] <= 1e-8
    assert np.max(np.abs(soadyn.loop_residual(m, sim.q, sim.v)[0])) <= 1e-12
    e0 = energy(m, q0, v0)
    assert abs(energy(m, sim.q, sim.v) - e0) <= 1e-6 * max(1.0, abs(e0))  # they fall, conserving energy
    assert np.max(np.abs(sim.v)) > 1e-2
    assert cli.main(["hil", "--scene", scene, "--duration", "0.05", "--as-fast-as-possible", "--no-progress"]) == 0


def test_assembly_and_projection_refuse_bad_input_by_name():
    m = four_bar("point")
    q, v = four_bar_state(0.7, 1.0)
    for bad_q, match in ((np.array([np.nan, 0.9, 1.9]), "crank"), (np.zeros(2), "q"), ("abc", "q")):
        with pytest.raises((ValueError, TypeError), match=match):
            soadyn.assemble(m, bad_q)
        with pytest.raises((ValueError, TypeError), match=match):
            soadyn.independent_coordinates(m, bad_q)
    with pytest.raises(ValueError, match="v"):
        soadyn.project_velocity(m, q, np.array([1.0, np.inf, 0.0]))
    with pytest.raises(ValueError, match="v"):
        soadyn.project_velocity(m, q, np.zeros(4))
    for tolerance in (float("nan"), 0.0, -1.0, float("inf")):
        with pytest.raises(ValueError, match="tolerance"):
            soadyn.assemble(m, q, tolerance=tolerance)
    with pytest.raises(ValueError, match="max_iterations"):
        soadyn.assemble(m, q, max_iterations=0)
    with pytest.raises(ValueError, match="unknown DOF or joint 'rod'"):
        soadyn.project_velocity(m, q, v, hold=["crank", "rod"])
    # Far from anything reachable, with a huge but finite start: a named failure, never NaN.
    with pytest.raises(soadyn.LoopError, match="loop 'pin' cannot be closed from here"):
        soadyn.assemble(m, np.array([0.0, 1e300, -1e300]), hold="crank", max_iterations=5)
