"""soadyn.batch's packet path (lanes=4: four rows per pass, AVX2) against one row per pass (lanes=1).

- On the four robots and on random trees with every joint type (floating and fixed roots), the forward,
  inverse and hybrid dynamics (with a mixed mask) of 23 rows (five packets and three rows past them) equal
  lanes=1, bit for bit. The mass matrix is the baseline kernel's bit for bit (tests/cpp/test_batch.cpp); the
  single call's AVX2 FMA kernel rounds its fused products once, so lanes=1 differs from it in the last bits:
  within 1e-14 of each row's largest entry here.
- The packet path agrees with Pinocchio's ABA, RNEA and CRBA (an oracle) on panda.
- A packet whose rows branch differently (one body beyond its tree-frame reach, where the forward and hybrid
  dynamics and the mass matrix switch to body frames) is computed again row by row: its four rows equal
  lanes=1 bit for bit, the mass matrix included.
- A row whose dynamics overflow raises the same DynamicsError, naming the same row, whatever the lanes.
- Values changed on the model between calls (prescribed flags, gravity) are taken by the next call.
- The rows are grouped by index, so the result does not depend on the number of threads (bit for bit).
- Rollouts of a random tree (every joint type) four runs side by side equal one by one, bit for bit, with RK4,
  Euler and DOPRI5, with no torques, per-run and shared torques, and runs past the last packet; a run that
  fails inside a packet is reported as it is alone (ok, failed step, message, NaN rows) and the others match.
- Rollouts whose runs set their own parameters (a mass, a centre of mass, an inertia, a placement, gravity) four
  runs side by side equal one by one, bit for bit, with RK4 and DOPRI5; a packet whose runs cannot share one
  packet model (a placement turned in one run) or with a refused value goes one by one, reported as alone;
  likewise with two DOFs driven by motion sources (cycloidal, spline) shared by the runs.
- Flexible models (cassini with a prescribed turntable; random trees whose flexible bodies carry bodies on their
  nodes, or are appendages): the forward, inverse and hybrid dynamics and the mass matrix, with and without
  external wrenches, equal lanes=1 bit for bit; cassini's rollouts with RK4 and DOPRI5, shared or per-run bus
  masses, four runs side by side, equal one by one bit for bit.
- lanes other than None, 1 or widest_lanes() is refused by name; with SOADYN_BASELINE_KERNELS set the widest
  is 1 and lanes=4 is refused, naming the reason.
"""
from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

import soadyn
from soadyn import batch
from support.batch_states import batch_states
from support.flexible_trees import random_flexible_tree
from support.robots import robot_with_oracle
from support.trees import random_tree

ROWS = 23  # five packets of four, and three rows on the one-row path
# lanes=4's mass matrix rounds as the baseline kernel, lanes=1's as the AVX2 FMA kernel: they differ by at most
# 8.6e-16 of a row's largest entry over 2,000 random states of each robot (docs/guides/batch.md).
MASS_MATRIX_TOLERANCE = 1e-14


def require_packets():
    """The packet tests need a processor with AVX2 and FMA (every x86-64 machine CI runs on has them)."""
    assert batch.widest_lanes() == 4, "this processor runs no packets (no AVX2 and FMA)"


def states(m, rows=ROWS, seed=0):
    return batch_states(m, rows, seed)


def models():
    out = {}
    for name, floating in (("ur5", False), ("panda", False), ("solo12", True), ("talos", True)):
        out[name] = robot_with_oracle(name, floating)[0]
    for seed, floating in ((3, True), (4, False)):
        out[f"tree-{seed}"] = random_tree(seed, nbodies=14, floating=floating)[0]
    return out


MODELS = models()


def mixed(m):
    """A copy of m with every third DOF prescribed."""
    masked = m.copy()
    masked.set_prescribed(list(m.dof_names[::3]))
    return masked


def calls(m, Q, V, X, lanes, threads=1):
    """Every packet call's results, as a list of (n, ...) arrays."""
    qdd = batch.forward_dynamics(m, Q, V, X, threads=threads, lanes=lanes)
    tau = batch.inverse_dynamics(m, Q, V, X, threads=threads, lanes=lanes)
    hq, ht = batch.hybrid_dynamics(mixed(m), Q, V, X, threads=threads, lanes=lanes)
    M = batch.mass_matrix(m, Q, threads=threads, lanes=lanes)
    return [qdd, tau, hq, ht, M]


def row_difference(a, b):
    """The largest difference of each row, over that row's largest magnitude."""
    a, b = a.reshape(len(a), -1), b.reshape(len(b), -1)
    return np.max(np.abs(a - b), axis=1) / np.max(np.abs(a), axis=1)


def assert_lanes_agree(one, four):
    """The dynamics bit for bit; the mass matrix (last) within MASS_MATRIX_TOLERANCE of each row's largest."""
    for a, b in zip(one[:-1], four[:-1]):
        assert np.array_equal(a, b)
    assert np.all(row_difference(one[-1], four[-1]) <= MASS_MATRIX_TOLERANCE)


@pytest.mark.parametrize("name", sorted(MODELS))
def test_four_lanes_equal_one_row_per_pass(name):
    require_packets()
    m = MODELS[name]
    Q, V, X = states(m)
    assert_lanes_agree(calls(m, Q, V, X, 1), calls(m, Q, V, X, 4))


@pytest.mark.parametrize("name", sorted(MODELS))
def test_one_row_per_pass_mass_matrix_is_the_single_calls_bit_for_bit(name):
    """A row's M is copied out as M's column-major storage, which is its row-major one only because M is exactly
    symmetric: the single call's M equals its transpose, and the batched rows equal it, on the robots (free roots
    included) and the random trees."""
    m = MODELS[name]
    Q = states(m, rows=9, seed=5)[0]
    M = batch.mass_matrix(m, Q, threads=1, lanes=1)
    for k in range(len(Q)):
        single = soadyn.mass_matrix(m, Q[k])
        assert np.array_equal(single, single.T)
        assert np.array_equal(M[k], single)


def test_packet_path_matches_pinocchio():
    require_packets()
    m, oracle = robot_with_oracle("panda", False)
    Q, V, X = states(m, rows=16, seed=5)
    qdd = batch.forward_dynamics(m, Q, V, X, lanes=4)
    tau = batch.inverse_dynamics(m, Q, V, X, lanes=4)
    M = batch.mass_matrix(m, Q, lanes=4)
    for k in range(16):
        scale = 1 + np.max(np.abs(qdd[k]))
        assert np.max(np.abs(qdd[k] - oracle.forward_dynamics(Q[k], V[k], X[k]))) <= 1e-9 * scale
        assert np.max(np.abs(tau[k] - oracle.inverse_dynamics(Q[k], V[k], X[k]))) <= 1e-9 * (1 + np.max(np.abs(tau[k])))
        assert np.max(np.abs(M[k] - oracle.mass_matrix(Q[k]))) <= 1e-12 * (1 + np.max(np.abs(M[k])))


def far_prismatic_model():
    """A revolute root and a chain below it whose third joint slides: a slide of 1e5 m puts the bodies below it
    beyond their tree-frame reach (1000 radii of gyration), where the dynamics switch to body frames."""
    m = soadyn.Model()
    rng = np.random.default_rng(11)
    joints = [soadyn.Joint.revolute([0, 0, 1]), soadyn.Joint.revolute([0, 1, 0]),
              soadyn.Joint.prismatic([1, 0, 0]), soadyn.Joint.revolute([1, 0, 0]), soadyn.Joint.revolute([0, 1, 0])]
    for i, joint in enumerate(joints):
        m.add_body(f"b{i}", i - 1, joint, placement=(np.eye(3), rng.uniform(-0.3, 0.3, 3)), mass=1.0 + i,
                   com=rng.uniform(-0.1, 0.1, 3), inertia=np.diag(rng.uniform(0.1, 0.15, 3)))
    return m


def test_rows_that_branch_apart_are_computed_row_by_row():
    require_packets()
    m = far_prismatic_model()
    Q, V, X = states(m, rows=16, seed=2)
    Q[5, 2] = 1e5  # the slide's coordinate; row 5: beyond the reach; rows 4, 6, 7 within
    one, four = calls(m, Q, V, X, 1), calls(m, Q, V, X, 4)
    assert_lanes_agree(one, four)
    assert np.array_equal(one[-1][4:8], four[-1][4:8])  # the split packet's mass matrices: the single call's


@pytest.mark.parametrize("call", ["forward_dynamics", "inverse_dynamics", "hybrid_dynamics"])
def test_a_failing_row_is_reported_as_the_single_call_reports_it(call):
    require_packets()
    m = MODELS["panda"]
    Q, V, X = states(m, rows=16, seed=3)
    V[6] = 1e200  # the velocity products overflow in row 6 only
    messages = []
    for lanes in (1, 4):
        with pytest.raises(soadyn.DynamicsError) as info:
            getattr(batch, call)(m, Q, V, X, lanes=lanes)
        messages.append(str(info.value))
    assert "row 6" in messages[0]
    assert messages[0] == messages[1]


def test_values_changed_between_calls_are_taken():
    require_packets()
    m = MODELS["ur5"].copy()
    Q, V, X = states(m, rows=16, seed=4)
    before = batch.hybrid_dynamics(m, Q, V, X, lanes=4)
    m.set_prescribed([m.dof_names[0], m.dof_names[2]])
    m.gravity = np.array([0.0, 3.0, -5.0])
    after = batch.hybrid_dynamics(m, Q, V, X, lanes=4)
    reference = batch.hybrid_dynamics(m, Q, V, X, lanes=1)
    assert not np.allclose(before[0], after[0])
    for one, four in zip(reference, after):
        assert np.array_equal(one, four)


def test_calls_of_fewer_rows_than_a_packet_run_one_row_per_pass_and_one_packet_runs_in_packets():
    """Below packet_minimum_rows() rows (one packet), lanes=4 runs one row per pass: every result is the single
    call's, bit for bit, the mass matrix too. From that many rows on the packets run: their mass matrix is the
    baseline kernel's, which differs from the single call's AVX2 FMA kernel in the last bits of about half its
    entries, while their dynamics stay the single call's bit for bit."""
    require_packets()
    m = MODELS["panda"]
    fewest = batch.packet_minimum_rows()
    assert fewest == batch.widest_lanes()
    for rows in range(1, fewest):
        Q, V, X = states(m, rows=rows, seed=rows)
        for one, four in zip(calls(m, Q, V, X, 1), calls(m, Q, V, X, 4)):
            assert np.array_equal(one, four)
    Q, V, X = states(m, rows=fewest, seed=fewest)
    one, four = calls(m, Q, V, X, 1), calls(m, Q, V, X, 4)
    assert_lanes_agree(one, four)
    assert not np.array_equal(one[-1], four[-1])


def test_threads_do_not_change_the_packets():
    require_packets()
    m = MODELS["talos"]
    Q, V, X = states(m, rows=37, seed=6)
    for one, two in zip(calls(m, Q, V, X, 4, threads=1), calls(m, Q, V, X, 4, threads=2)):
        assert np.array_equal(one, two)


@pytest.mark.parametrize("lanes", [0, 2, 3, 8, -4, True, 4.0, "4"])
def test_bad_lanes_are_refused_by_name(lanes):
    m = MODELS["ur5"]
    Q, V, X = states(m, rows=4)
    for call in (lambda: batch.forward_dynamics(m, Q, V, X, lanes=lanes),
                 lambda: batch.mass_matrix(m, Q, lanes=lanes),
                 lambda: batch.dynamics_derivatives(m, Q, V, X, lanes=lanes),
                 lambda: batch.rollout(m, np.zeros((2, m.nq + m.nv)), steps=2, lanes=lanes)):
        with pytest.raises(ValueError, match="lanes must be"):
            call()


def test_baseline_kernels_leave_one_lane():
    script = (
        "import numpy as np, soadyn\n"
        "from soadyn import batch\n"
        "m = soadyn.scenes.pendulum_chain(3)\n"
        "assert batch.widest_lanes() == 1, batch.widest_lanes()\n"
        "Q = np.zeros((4, m.nq))\n"
        "batch.mass_matrix(m, Q)\n"
        "batch.mass_matrix(m, Q, lanes=1)\n"
        "try:\n"
        "    batch.mass_matrix(m, Q, lanes=4)\n"
        "except ValueError as e:\n"
        "    assert 'AVX2' in str(e), e\n"
        "else:\n"
        "    raise SystemExit('lanes=4 accepted without packets')\n")
    env = dict(os.environ, SOADYN_BASELINE_KERNELS="1")
    done = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr


def rollout_states(m, runs, seed):
    Q, V, _ = states(m, rows=runs, seed=seed)
    return np.hstack([Q, 0.3 * V])


@pytest.mark.parametrize("integrator", ["rk4", "euler", "dopri5"])
def test_rollouts_four_runs_side_by_side_equal_one_by_one(integrator):
    require_packets()
    m = random_tree(5, nbodies=10, floating=True)[0]
    runs, steps = 10, 40  # two packets of four runs and two runs alone
    x0 = rollout_states(m, runs, 8)
    controls = np.random.default_rng(9).uniform(-1, 1, (runs, steps, m.nv))
    for u in (None, controls, controls[0]):  # no torques, one series per run, one series for all
        one = batch.rollout(m, x0, u, dt=2e-3, steps=steps, integrator=integrator, record_every=2, lanes=1)
        four = batch.rollout(m, x0, u, dt=2e-3, steps=steps, integrator=integrator, record_every=2, lanes=4)
        assert one.ok.all() and four.ok.all()
        assert np.array_equal(one.q, four.q) and np.array_equal(one.v, four.v)
        assert (one.side_by_side, four.side_by_side) == (0, 8)


@pytest.mark.parametrize("integrator", ["rk4", "dopri5"])
def test_a_failing_run_in_a_packet_is_reported_as_alone(integrator):
    require_packets()
    m = soadyn.scenes.pendulum_chain(4)
    x0 = rollout_states(m, 8, 10)
    x0[2, m.nq:] = 1e155  # run 2's velocities square to infinity in its first step
    one = batch.rollout(m, x0, None, dt=1e-3, steps=20, integrator=integrator, lanes=1)
    four = batch.rollout(m, x0, None, dt=1e-3, steps=20, integrator=integrator, lanes=4)
    assert not one.ok[2] and one.ok.sum() == 7 and one.messages[2]
    assert_rollouts_equal(one, four)


def run_parameters(m, runs, seed):
    """Per-run values of a mass, a centre of mass, an inertia, a placement's translation and gravity."""
    rng = np.random.default_rng(seed)
    a, b, c = m.body_names[2], m.body_names[4], m.body_names[6]
    placement = np.asarray(m.get_parameter(f"{c}.placement"))
    placements = np.repeat(placement[None], runs, axis=0)
    placements[:, :3, 3] *= rng.uniform(0.8, 1.2, (runs, 1))
    inertia = np.asarray(m.get_parameter(f"{b}.inertia"))
    return {f"{a}.mass": m.get_parameter(f"{a}.mass") * rng.uniform(0.5, 2.0, runs),
            f"{a}.com": np.asarray(m.get_parameter(f"{a}.com")) + rng.uniform(-0.02, 0.02, (runs, 3)),
            f"{b}.inertia": inertia[None] * rng.uniform(0.8, 1.2, (runs, 1, 1)),
            f"{c}.placement": placements,
            "gravity": np.asarray(m.get_parameter("gravity")) * rng.uniform(0.5, 1.5, (runs, 1))}


def assert_rollouts_equal(one, four):
    assert list(one.ok) == list(four.ok) and one.messages == four.messages
    assert np.array_equal(one.failed_step, four.failed_step)
    assert np.array_equal(np.isnan(one.q), np.isnan(four.q)) and np.array_equal(np.isnan(one.v), np.isnan(four.v))
    assert np.array_equal(np.nan_to_num(one.q), np.nan_to_num(four.q))
    assert np.array_equal(np.nan_to_num(one.v), np.nan_to_num(four.v))


@pytest.mark.parametrize("integrator", ["rk4", "dopri5"])
def test_rollouts_with_their_own_parameters_four_side_by_side_equal_one_by_one(integrator):
    require_packets()
    m = random_tree(6, nbodies=10, floating=True)[0]
    runs, steps = 10, 40
    x0 = rollout_states(m, runs, 13)
    params = run_parameters(m, runs, 14)
    one = batch.rollout(m, x0, None, dt=2e-3, steps=steps, integrator=integrator, parameters=params, lanes=1)
    four = batch.rollout(m, x0, None, dt=2e-3, steps=steps, integrator=integrator, parameters=params, lanes=4)
    assert one.ok.all()
    assert_rollouts_equal(one, four)
    assert four.side_by_side == 8


def test_runs_whose_parameters_cannot_share_packets_go_one_by_one():
    """A placement turned in one run of a packet (its rotation no longer the identity) and a refused mass."""
    require_packets()
    m = soadyn.scenes.pendulum_chain(4)
    runs = 8
    x0 = rollout_states(m, runs, 15)
    body = m.body_names[2]
    placements = np.repeat(np.asarray(m.get_parameter(f"{body}.placement"))[None], runs, axis=0)
    turn = 0.2
    placements[1, :3, :3] = placements[1, :3, :3] @ np.array([[np.cos(turn), -np.sin(turn), 0.0],
                                                              [np.sin(turn), np.cos(turn), 0.0], [0.0, 0.0, 1.0]])
    masses = m.get_parameter(f"{body}.mass") * np.linspace(0.5, 2.0, runs)
    masses[6] = -1.0  # refused: run 6 fails with the parameter's message, every row NaN
    params = {f"{body}.placement": placements, f"{body}.mass": masses}
    one = batch.rollout(m, x0, None, dt=1e-3, steps=30, parameters=params, lanes=1)
    four = batch.rollout(m, x0, None, dt=1e-3, steps=30, parameters=params, lanes=4)
    assert not one.ok[6] and f"{body}.mass" in one.messages[6] and one.ok.sum() == 7
    assert_rollouts_equal(one, four)
    assert four.side_by_side == 0  # run 1's turn refuses the first four, run 6's mass the second


def test_rollouts_with_shared_sources_four_side_by_side_equal_one_by_one():
    """Two DOFs driven by sources shared by the runs; the runs' own masses too."""
    require_packets()
    m = random_tree(7, nbodies=10, floating=True)[0]
    one_coordinate = [name for name in m.dof_names if ":" not in name]
    runs = 10
    x0 = rollout_states(m, runs, 16)
    sources = {one_coordinate[0]: soadyn.MotionSource.cycloidal(0.0, 0.4, 0.01, 0.05),
               one_coordinate[-1]: soadyn.MotionSource.spline([0.0, 0.03, 0.06], [0.1, -0.2, 0.0])}
    body = m.body_names[3]
    masses = {f"{body}.mass": m.get_parameter(f"{body}.mass") * np.linspace(0.5, 2.0, runs)}
    for parameters in (None, masses):
        one = batch.rollout(m, x0, sources, dt=2e-3, steps=40, parameters=parameters, lanes=1)
        four = batch.rollout(m, x0, sources, dt=2e-3, steps=40, parameters=parameters, lanes=4)
        assert one.ok.all()
        assert_rollouts_equal(one, four)
        assert four.side_by_side == 8



def test_rollouts_with_events_step_side_by_side_when_due_in_the_same_steps():
    """A lock and a release at each run's own times: runs whose events fall due in the same steps step four
    side by side, whatever their order (the lock an impact in every run); the others one by one. Each run
    equals its run alone."""
    require_packets()
    m = random_tree(8, nbodies=10, floating=True)[0]
    dof = [name for name in m.dof_names if ":" not in name][1]
    runs, dt = 11, 2e-3
    x0 = rollout_states(m, runs, 17)
    controls = np.random.default_rng(18).uniform(-1, 1, (runs, 40, m.nv))
    rng = np.random.default_rng(19)
    due = rng.permutation(np.repeat([11, 21, 31], [5, 4, 2]))  # the step each run locks in: 5, 4 and 2 runs
    lock = (due - 1 + rng.uniform(0.05, 0.95, runs)) * dt  # inside the step before: due at the start of `due`
    events = [("lock", dof, lock), ("release", dof, lock + 10 * dt)]
    one = batch.rollout(m, x0, controls, dt=dt, steps=40, events=events, lanes=1)
    assert one.ok.all() and one.side_by_side == 0
    for threads in (1, 2):
        four = batch.rollout(m, x0, controls, dt=dt, steps=40, events=events, threads=threads, lanes=4)
        assert_rollouts_equal(one, four)
        assert four.side_by_side == 8  # four of the first five, the four of the second; the rest alone
    shared = [("lock", dof, 0.0301), ("release", dof, 0.0501)]  # one time for all runs: two packets, three alone
    one = batch.rollout(m, x0, controls, dt=dt, steps=40, events=shared, lanes=1)
    four = batch.rollout(m, x0, controls, dt=dt, steps=40, events=shared, lanes=4)
    assert_rollouts_equal(one, four)
    assert four.side_by_side == 8
    v_at_lock = one.v[:, 15, m.dof_names.index(dof)]  # t = 30 ms, just before the lock: an impact in every run
    assert np.all(np.abs(v_at_lock) > 1e-3)


def flexible_models():
    """cassini (two booms of four modes: appendages, whose update runs lane by lane) with a prescribed turntable,
    and random trees whose flexible bodies carry bodies on their nodes or are appendages."""
    cassini = soadyn.scenes.cassini()
    cassini.set_prescribed(["turntable"])
    return {"cassini": cassini,
            "nodes": random_flexible_tree(31, n_bodies=8, floating=True, damping=True)[0],
            "appendages": random_flexible_tree(32, n_bodies=8, floating=False, appendages=True)[0]}


@pytest.mark.parametrize("name", ["cassini", "nodes", "appendages"])
def test_flexible_models_run_in_packets_equal_to_one_row_per_pass(name):
    """The forward, inverse and hybrid dynamics and the mass matrix of flexible models, four rows per pass,
    equal one row per pass bit for bit (the appendages' update runs the single call's double kernel in each
    lane), external wrenches included."""
    require_packets()
    m = flexible_models()[name]
    Q, V, X = states(m, seed=3)
    F = np.random.default_rng(4).uniform(-1, 1, (ROWS, m.nbodies, 6))
    for f_ext in (None, F):
        one = [batch.forward_dynamics(m, Q, V, X, f_ext, lanes=1), *batch.hybrid_dynamics(m, Q, V, X, f_ext, lanes=1)]
        four = [batch.forward_dynamics(m, Q, V, X, f_ext, lanes=4), *batch.hybrid_dynamics(m, Q, V, X, f_ext, lanes=4)]
        one.append(batch.inverse_dynamics(m, Q, V, one[0], f_ext, lanes=1))
        four.append(batch.inverse_dynamics(m, Q, V, one[0], f_ext, lanes=4))
        for a, b in zip(one, four):
            assert np.array_equal(a, b)
    assert np.array_equal(batch.mass_matrix(m, Q, lanes=1), batch.mass_matrix(m, Q, lanes=4))


@pytest.mark.parametrize("integrator", ["rk4", "dopri5"])
def test_flexible_rollouts_four_side_by_side_equal_one_by_one(integrator):
    """Cassini's rollouts, with shared and with per-run bus masses (each lane's own model in the lane-by-lane
    appendage update), four runs side by side equal one by one, bit for bit."""
    require_packets()
    m = soadyn.scenes.cassini()
    runs, steps = 9, 30  # two packets of four runs and one run alone
    x0 = rollout_states(m, runs, 21)
    masses = {"bus.mass": m.get_parameter("bus.mass") * np.random.default_rng(22).uniform(0.8, 1.2, runs)}
    for parameters in (None, masses):
        one = batch.rollout(m, x0, None, dt=1e-3, steps=steps, integrator=integrator, parameters=parameters, lanes=1)
        four = batch.rollout(m, x0, None, dt=1e-3, steps=steps, integrator=integrator, parameters=parameters,
                             lanes=4)
        assert one.ok.all()
        assert_rollouts_equal(one, four)
        assert four.side_by_side == 8
