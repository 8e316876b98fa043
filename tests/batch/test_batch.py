"""soadyn.batch: batched dynamics and parallel rollouts on a C++ thread pool.

- Every batched call with one row per pass (lanes=1) equals, bit for bit,
  the single call on each row, with 1, 2 and 3 threads (four rows per pass:
  test_batch_lanes.py), on trees (a URDF robot with external wrenches, a
  prescribed mask), a flexible spacecraft (cassini: the dual-number
  derivatives) and a closed loop (four-bar).
- rollout equals, bit for bit, the same calls on one Simulator per run
  (initial states, shared and per-run torques, per-run parameters, lock
  events, prescribed sources), whatever the number of threads; a run that
  fails (a parameter the model refuses, a step that overflows) is reported
  with its message and never stops the others.
- Bad input is refused before any computation, naming the array, the row and
  the coordinate; a failing row raises DynamicsError naming it.
"""
from __future__ import annotations

import numpy as np
import pytest

import soadyn
from soadyn import batch
from support.batch_states import batch_states
from support.robots import robot_with_oracle

ROWS = 24


def states(m, rows=ROWS, seed=0):
    return batch_states(m, rows, seed)


def models():
    panda, _ = robot_with_oracle("panda", False)
    masked = panda.copy()
    masked.set_prescribed([masked.dof_names[1], masked.dof_names[4]])
    return {"panda": panda, "panda-mixed": masked, "cassini": soadyn.scenes.cassini(),
            "four-bar": soadyn.scenes.four_bar()}


MODELS = models()


@pytest.mark.parametrize("name", sorted(MODELS))
@pytest.mark.parametrize("threads", [1, 2, 3])
def test_batched_calls_equal_single_calls_bit_for_bit(name, threads):
    m = MODELS[name]
    Q, V, X = states(m)
    F = np.random.default_rng(7).uniform(-2, 2, (ROWS, m.nbodies, 6)) if name == "panda" else None
    f = (lambda k: None) if F is None else (lambda k: F[k])
    if not m.nloops:
        qdd = batch.forward_dynamics(m, Q, V, X, F, threads=threads, lanes=1)
        tau = batch.inverse_dynamics(m, Q, V, qdd, F, threads=threads, lanes=1)
        for k in range(ROWS):
            assert np.array_equal(qdd[k], soadyn.forward_dynamics(m, Q[k], V[k], X[k], f(k)))
            assert np.array_equal(tau[k], soadyn.inverse_dynamics(m, Q[k], V[k], qdd[k], f(k)))
    hq, ht = batch.hybrid_dynamics(m, Q, V, X, F, threads=threads, lanes=1)
    M = batch.mass_matrix(m, Q, threads=threads, lanes=1)
    D = batch.dynamics_derivatives(m, Q[:8], V[:8], X[:8], None if F is None else F[:8], threads=threads, lanes=1)
    assert M.shape == (ROWS, m.nv, m.nv) and all(d.shape == (8, m.nv, m.nv) for d in D)
    for k in range(ROWS):
        single_q, single_t = soadyn.hybrid_dynamics(m, Q[k], V[k], X[k], f(k))
        assert np.array_equal(hq[k], single_q) and np.array_equal(ht[k], single_t)
        assert np.array_equal(M[k], soadyn.mass_matrix(m, Q[k]))
    for k in range(8):
        for i, single in enumerate(soadyn.dynamics_derivatives(m, Q[k], V[k], X[k], f(k))):
            assert np.array_equal(D[i][k], single), (k, i)


def test_an_empty_batch_gives_empty_results():
    m = MODELS["panda"]
    Q, V, X = states(m, 0)
    assert batch.forward_dynamics(m, Q, V, X).shape == (0, m.nv)
    assert batch.mass_matrix(m, Q).shape == (0, m.nv, m.nv)


def test_bad_batches_are_refused_naming_the_row_and_the_item():
    m = MODELS["cassini"]
    Q, V, X = states(m, 6)
    with pytest.raises(ValueError, match=r"V must have shape \(6, 28\)"):
        batch.forward_dynamics(m, Q, V[:5], X)
    with pytest.raises(ValueError, match="leading batch dimension"):
        batch.mass_matrix(m, Q[0])
    bad = V.copy()
    bad[3, m.dof_names.index("scan_az")] = np.nan
    with pytest.raises(ValueError, match="V row 3: 'scan_az' is NaN"):
        batch.hybrid_dynamics(m, Q, bad, X)
    q = Q.copy()
    q[4, :4] *= 1.1  # the bus quaternion
    with pytest.raises(ValueError, match="Q row 4: the quaternion of joint 'bus'"):
        batch.dynamics_derivatives(m, q, V, X)
    with pytest.raises(ValueError, match=r"f_ext must have shape \(6, 15, 6\)"):
        batch.forward_dynamics(m, Q, V, X, np.zeros((6, 6)))
    with pytest.raises(ValueError, match="threads"):
        batch.mass_matrix(m, Q, threads=0)
    huge = X.copy()
    huge[2] = 1e308
    huge[5] = 1e308
    with pytest.raises(soadyn.DynamicsError, match=r"row 2, the first of 2 failed rows"):
        batch.forward_dynamics(m, Q, V, huge)


def chain_runs(runs=5, steps=120, seed=3):
    m = soadyn.scenes.pendulum_chain(4)
    rng = np.random.default_rng(seed)
    x0 = np.hstack([rng.uniform(-0.6, 0.6, (runs, m.nq)), rng.uniform(-0.2, 0.2, (runs, m.nv))])
    return m, x0, rng.uniform(-0.3, 0.3, (runs, steps, m.nv)), rng.uniform(0.5, 2.0, runs)


def simulate_alone(m, x0, controls, mass=None, lock_at=None, sources=None, record_every=1):
    """The same run on one Simulator, call by call."""
    model = m.copy()
    if mass is not None:
        model.set_parameter("link_2.mass", mass)
    sim = soadyn.Simulator(model, 1e-3, "rk4")
    for dof, source in (sources or {}).items():
        sim.prescribe(dof, source)
    sim.set_state(x0[:m.nq], x0[m.nq:])
    if lock_at is not None:
        sim.schedule(lock_at, "lock", "link_3")
    q, v = [sim.q.copy()], [sim.v.copy()]
    for k in range(len(controls)):
        for dof in range(m.nv):
            if not sim.prescribed[dof]:
                sim.set_input(dof, controls[k, dof])
        sim.step()
        if (k + 1) % record_every == 0:
            q.append(sim.q.copy())
            v.append(sim.v.copy())
    return np.array(q), np.array(v)


@pytest.mark.parametrize("threads", [1, 2])
def test_rollout_equals_one_simulator_per_run(threads):
    m, x0, controls, masses = chain_runs()
    lock_times = np.linspace(0.02, 0.1, len(x0))
    result = batch.rollout(m, x0, controls, dt=1e-3, steps=120, parameters={"link_2.mass": masses},
                           events=[("lock", "link_3", lock_times)], record_every=3, threads=threads)
    assert result.ok.all() and (result.failed_step == -1).all() and result.messages == [""] * len(x0)
    assert result.q.shape == (len(x0), 41, m.nq) and np.allclose(result.t, np.arange(41) * 3e-3)
    for r in range(len(x0)):
        q, v = simulate_alone(m, x0[r], controls[r], masses[r], lock_times[r], record_every=3)
        assert np.array_equal(result.q[r], q) and np.array_equal(result.v[r], v)
    shared = batch.rollout(m, x0, controls[0], steps=120, threads=threads)
    for r in range(len(x0)):
        q, _ = simulate_alone(m, x0[r], controls[0])
        assert np.array_equal(shared.q[r], q)


def test_rollout_with_prescribed_sources_on_cassini():
    m = MODELS["cassini"]
    runs = 3
    x0 = np.tile(np.concatenate([soadyn.neutral_configuration(m), np.zeros(m.nv)]), (runs, 1))
    x0[:, m.nq + m.dof_names.index("bus:wz")] = [0.0, 0.01, -0.02]
    sources = {"turntable": soadyn.MotionSource.constant_velocity(0.3),
               "scan_az": soadyn.MotionSource.cycloidal(0.0, 0.5, 0.01, 0.05)}
    result = batch.rollout(m, x0, sources, dt=1e-3, steps=80, threads=2)
    assert result.ok.all()
    for r in range(runs):
        sim = soadyn.Simulator(m, 1e-3, "rk4")
        for dof, source in sources.items():
            sim.prescribe(dof, source)
        sim.set_state(x0[r, :m.nq], x0[r, m.nq:])
        trajectory = sim.run(0.08)
        assert np.array_equal(result.q[r], trajectory.q) and np.array_equal(result.v[r], trajectory.v)
    assert not np.array_equal(result.q[1], result.q[2])


def test_failed_runs_are_reported_and_the_others_complete():
    m, x0, controls, masses = chain_runs(runs=4)
    masses[1] = -1.0  # refused by the model
    controls[2, 50:] = 1e308  # overflows from step 50
    result = batch.rollout(m, x0, controls, steps=120, parameters={"link_2.mass": masses}, threads=2)
    assert list(result.ok) == [True, False, False, True]
    assert "link_2.mass" in result.messages[1] and result.failed_step[1] == -1 and np.isnan(result.q[1]).all()
    assert result.failed_step[2] == 50 and result.messages[2]
    assert np.isfinite(result.q[2, :51]).all() and np.isnan(result.q[2, 51:]).all()
    for r in (0, 3):
        q, _ = simulate_alone(m, x0[r], controls[r], masses[r])
        assert np.array_equal(result.q[r], q)


def test_every_entry_position_is_checked_and_quaternion_norms_agree_with_the_single_call():
    # The batch checks scan the rows in blocks of eight entries and a tail:
    # one bad entry at each position of 3 rows of panda (21 entries: two
    # blocks and a tail of five) is named by row and DOF.
    m = MODELS["panda"]
    Q, V, X = states(m, 3)
    for k in range(V.size):
        row, dof = divmod(k, m.nv)
        for value, word in ((np.inf, "infinite"), (-np.inf, "infinite"), (np.nan, "NaN")):
            bad = V.copy()
            bad[row, dof] = value
            with pytest.raises(ValueError, match=f"V row {row}: '{m.dof_names[dof]}' is {word}"):
                batch.forward_dynamics(m, Q, bad, X, lanes=1)
    # Quaternions at the edge of the tolerance: the batch accepts and refuses
    # exactly the rows the single call does (soadyn.QUATERNION_TOLERANCE).
    c = MODELS["cassini"]
    Q, V, X = states(c, 8)
    scales = [1 + soadyn.QUATERNION_TOLERANCE * f for f in (-1.5, -1.0, -0.999, 0.0, 0.5, 0.999, 1.0, 1.5)]
    quaternion = slice(c.coordinate_names.index("bus:qx"), c.coordinate_names.index("bus:qw") + 1)
    for k, scale in enumerate(scales):
        Q[k, quaternion] *= scale / np.linalg.norm(Q[k, quaternion])
    accepted = []
    for k in range(8):
        one = Q[[k]]
        try:
            soadyn.forward_dynamics(c, Q[k], V[k], X[k])
            accepted.append(True)
        except ValueError as error:
            assert "quaternion" in str(error)
            accepted.append(False)
        if accepted[-1]:
            assert batch.forward_dynamics(c, one, V[[k]], X[[k]]).shape == (1, c.nv)
        else:
            with pytest.raises(ValueError, match="Q row 0: the quaternion of joint 'bus'"):
                batch.forward_dynamics(c, one, V[[k]], X[[k]])
    assert not accepted[0] and accepted[2:6] == [True] * 4 and not accepted[7]  # both branches seen


def test_bad_rollouts_are_refused_by_name():
    m, x0, controls, masses = chain_runs(runs=2)
    with pytest.raises(ValueError, match="unknown parameter 'link_9.mass'"):
        batch.rollout(m, x0, None, steps=10, parameters={"link_9.mass": masses})
    with pytest.raises(ValueError, match=r"controls must have shape \(10, 4\)"):
        batch.rollout(m, x0, controls, steps=10)
    with pytest.raises(ValueError, match="record_every"):
        batch.rollout(m, x0, None, steps=10, record_every=3)
    with pytest.raises(ValueError, match="callback sources"):
        batch.rollout(m, x0, {"link_1": soadyn.MotionSource.function(lambda t: (0.0, 0.0, 0.0))}, steps=10)
    with pytest.raises(ValueError, match="unknown integrator"):
        batch.rollout(m, x0, None, steps=10, integrator="leapfrog")
    bad = x0.copy()
    bad[1, m.nq] = np.inf
    with pytest.raises(ValueError, match="x0s row 1: 'link_1' is infinite"):
        batch.rollout(m, bad, None, steps=10)


def test_batches_from_several_threads_and_a_model_changed_under_them():
    """Threads share one model: concurrent batched and single calls give the single calls' results; a body added
    while another thread runs batches gives either a result for the old model or a named refusal, never a crash."""
    import threading

    m = soadyn.scenes.cassini()
    Q, V, X = states(m, 40)
    expected = np.stack([soadyn.forward_dynamics(m, Q[k], V[k], X[k]) for k in range(40)])
    errors, results = [], []

    def batches():
        try:
            for _ in range(15):
                results.append(batch.forward_dynamics(m, Q, V, X, threads=2))
        except Exception as error:  # noqa: BLE001 - reported below
            errors.append(error)

    def singles():
        try:
            for k in range(200):
                assert np.array_equal(soadyn.forward_dynamics(m, Q[k % 40], V[k % 40], X[k % 40]), expected[k % 40])
        except Exception as error:  # noqa: BLE001
            errors.append(error)

    threads = [threading.Thread(target=batches), threading.Thread(target=batches), threading.Thread(target=singles)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == [] and len(results) == 30
    assert all(np.array_equal(r, expected) for r in results)

    refused, done = [], []

    def batches_during_change():
        for _ in range(30):
            try:
                done.append(batch.forward_dynamics(m, Q, V, X))
            except (ValueError, RuntimeError) as error:
                refused.append(str(error))

    worker = threading.Thread(target=batches_during_change)
    worker.start()
    m.add_body("probe", "bus", soadyn.Joint.revolute([0, 0, 1]), mass=1.0, inertia=[0.1, 0.1, 0.1])
    worker.join()
    assert all(np.array_equal(r, expected) for r in done)  # computed before the change, on the old model
    assert all("shape" in text or "changed structurally" in text for text in refused)
    assert len(done) + len(refused) == 30
    Qg, Vg, Xg = states(m, 3)  # the per-thread Data follows the new structure
    grown = batch.forward_dynamics(m, Qg, Vg, Xg)
    assert all(np.array_equal(grown[k], soadyn.forward_dynamics(m, Qg[k], Vg[k], Xg[k])) for k in range(3))


def test_a_forked_child_runs_batches_with_threads_of_its_own():
    import multiprocessing

    m = MODELS["cassini"]
    Q, V, X = states(m, 16)
    expected = batch.forward_dynamics(m, Q, V, X, threads=2)  # the parent's pool exists before the fork
    context = multiprocessing.get_context("fork")
    child = context.Process(target=_child_batch, args=(m, Q, V, X, expected))
    child.start()
    child.join(60)
    hung = child.is_alive()
    if hung:
        child.kill()
    assert not hung and child.exitcode == 0


def test_thread_counts_in_turn_keep_their_results_and_follow_a_structural_change():
    """A model keeps a pool per thread count, up to four, the least recently used going first: calls that
    alternate five thread counts give the one-row results throughout, and after a structural change each
    count's pool follows the new structure."""
    m = MODELS["panda"].copy()
    Q, V, X = states(m, 37)
    expected = batch.forward_dynamics(m, Q, V, X, threads=1, lanes=1)
    for threads in (1, 2, 3, 2, 1, 4, 5, 3, 2, 1, 5):
        assert np.array_equal(batch.forward_dynamics(m, Q, V, X, threads=threads), expected)
    m.add_body("probe", m.body_names[2], soadyn.Joint.revolute([0, 0, 1]), mass=1.0, inertia=[0.1, 0.1, 0.1])
    Qg, Vg, Xg = states(m, 9)
    for threads in (1, 2, 3):
        grown = batch.forward_dynamics(m, Qg, Vg, Xg, threads=threads)
        assert all(np.array_equal(grown[k], soadyn.forward_dynamics(m, Qg[k], Vg[k], Xg[k])) for k in range(9))


def _child_batch(m, Q, V, X, expected):
    import os
    os._exit(0 if np.array_equal(batch.forward_dynamics(m, Q, V, X, threads=2), expected) else 1)


def test_bad_rollout_events_and_empty_parameter_batches_are_named():
    m, x0, controls, masses = chain_runs(runs=2)
    with pytest.raises(ValueError, match="expected \\(kind, DOF, times\\)"):
        batch.rollout(m, x0, None, steps=10, events=[("lock", "link_3")])
    for dof in (9, -1, True, "link_9"):
        with pytest.raises(ValueError, match=f"event lock {dof!r}: not a DOF name or an index below nv = 4"):
            batch.rollout(m, x0, None, steps=10, events=[("lock", dof, 0.1)])
    with pytest.raises(ValueError, match="one time for all runs or 2 times"):
        batch.rollout(m, x0, None, steps=10, events=[("lock", "link_3", [0.1, 0.2, 0.3])])
    empty = batch.rollout(m, x0[:0], None, steps=10, parameters={"link_2.com": np.zeros((0, 3))})
    assert empty.q.shape == (0, 11, m.nq) and empty.messages == []


NOT_REAL = {"complex128": lambda a: a + 1j, "<U32": lambda a: a.astype(str), "bool": lambda a: a != 0,
            "object": lambda a: a.astype(object), "|S32": lambda a: a.astype(bytes)}


def batch_calls(m, Q, V, X):
    """Every batched call, as (name, [argument names], call taking the arguments in that order)."""
    return [("forward_dynamics", ["Q", "V", "TAU"], lambda q, v, x: batch.forward_dynamics(m, q, v, x)),
            ("inverse_dynamics", ["Q", "V", "QDD"], lambda q, v, x: batch.inverse_dynamics(m, q, v, x)),
            ("hybrid_dynamics", ["Q", "V", "U"], lambda q, v, x: batch.hybrid_dynamics(m, q, v, x)),
            ("dynamics_derivatives", ["Q", "V", "U"], lambda q, v, x: batch.dynamics_derivatives(m, q, v, x)),
            ("mass_matrix", ["Q"], lambda q, v, x: batch.mass_matrix(m, q))]


@pytest.mark.parametrize("dtype", sorted(NOT_REAL))
def test_batched_calls_refuse_arrays_that_are_not_real_as_the_single_calls_do(dtype):
    """A complex, string, bytes, boolean or object array is refused with a TypeError naming the argument and the
    dtype (as soadyn.forward_dynamics refuses q), never cast (the imaginary part dropped, '0.5' read as 0.5)."""
    m = soadyn.scenes.pendulum_chain(3)
    Q, V, X = states(m, 4)
    with pytest.raises(TypeError, match=f"q must be an array of real numbers, got dtype {dtype}"):
        soadyn.forward_dynamics(m, NOT_REAL[dtype](Q[0]), V[0], X[0])
    for name, arguments, call in batch_calls(m, Q, V, X):
        for k, argument in enumerate(arguments):
            spoiled = [Q, V, X]
            spoiled[k] = NOT_REAL[dtype](spoiled[k])
            with pytest.raises(TypeError, match=f"^{argument} must be an array of real numbers, got dtype {dtype}$"):
                call(*spoiled)
    F = np.zeros((4, m.nbodies, 6))
    with pytest.raises(TypeError, match=f"^f_ext must be an array of real numbers, got dtype {dtype}$"):
        batch.forward_dynamics(m, Q, V, X, NOT_REAL[dtype](F))


def test_batched_calls_take_integer_float32_and_nested_list_rows():
    m = soadyn.scenes.pendulum_chain(3)
    Q, V, X = states(m, 4)
    expected = batch.forward_dynamics(m, Q.astype(np.float32).astype(float), np.zeros_like(V), np.round(X))
    assert np.array_equal(batch.forward_dynamics(m, Q.astype(np.float32), [[0] * 3] * 4, np.round(X).astype(int)),
                          expected)
    with pytest.raises(TypeError, match="^V must be an array of real numbers: .*inhomogeneous"):
        batch.forward_dynamics(m, Q, [[0.0] * 3, [0.0]] * 2, X)


def test_batch_shape_errors_name_the_argument_the_expected_shape_and_the_shape_given():
    m = soadyn.scenes.pendulum_chain(3)
    Q, V, X = states(m, 4)
    with pytest.raises(ValueError, match=r"^QDD must have shape \(4, 3\) \(a leading batch dimension\), got \(4, 2\)$"):
        batch.inverse_dynamics(m, Q, V, X[:, :2])
    with pytest.raises(ValueError, match=r"^Q must have shape \(n, 3\) \(a leading batch dimension\), got \(3,\)$"):
        batch.mass_matrix(m, Q[0])
    with pytest.raises(ValueError, match=r"^f_ext must have shape \(4, 3, 6\), got \(4, 18\)$"):
        batch.hybrid_dynamics(m, Q, V, X, np.zeros((4, 18)))


def test_rollout_refuses_arguments_that_are_not_real_naming_them():
    m, x0, controls, masses = chain_runs(runs=2, steps=10)
    refusals = [
        (dict(x0s=x0 + 0j), r"^x0s must be an array of real numbers, got dtype complex128$"),
        (dict(x0s=x0.astype(str)), r"^x0s must be an array of real numbers, got dtype <U32$"),
        (dict(controls_or_sources=controls.astype(complex)), r"^controls must be an array of real numbers, got dtype "
                                                            r"complex128$"),
        (dict(controls_or_sources=controls[0].astype(str)), r"^controls must be an array of real numbers"),
        (dict(parameters={"link_2.mass": masses.astype(str)}),
         r"^values of parameter 'link_2.mass' must be an array of real numbers, got dtype <U32$"),
        (dict(events=[("lock", "link_3", np.array([0.01, 0.02]) + 1j)]),
         r"^times of event lock 'link_3' must be an array of real numbers, got dtype complex128$"),
        (dict(dt="0.001"), r"^dt must be an array of real numbers, got dtype <U5$"),
        (dict(dt=1e-3 + 0j), r"^dt must be an array of real numbers, got dtype complex128$"),
        (dict(integrator=4), r"^integrator must be a str"),
    ]
    for changes, message in refusals:
        arguments = dict(x0s=x0, controls_or_sources=None, steps=10) | changes
        with pytest.raises(TypeError, match=message):
            batch.rollout(m, **arguments)


def test_rollout_shape_and_count_errors_name_the_argument():
    m, x0, controls, masses = chain_runs(runs=2, steps=10)
    refusals = [
        (dict(controls_or_sources=controls[:, :4]),
         r"^controls must have shape \(10, 4\) or \(2, 10, 4\) \(shared by every run or one per run\), "
         r"got \(2, 4, 4\)$"),
        (dict(parameters={"link_2.mass": masses[:1]}),
         r"^values of parameter 'link_2.mass' must have shape \(2,\), got \(1,\)$"),
        (dict(x0s=x0[0]), r"^x0s must have shape \(n, 8\) \(a leading batch dimension\), got \(8,\)$"),
        (dict(dt=[1e-3, 1e-3]), r"^dt must have shape \(\), got \(2,\)$"),
        (dict(events=[("lock", "link_3", [0.1, 0.2, 0.3])]),
         r"^times of event lock 'link_3' must have shape \(\) or \(2,\) \(one time for all runs or 2 times\), "
         r"got \(3,\)$"),
        (dict(steps=np.nan), r"^steps must be a whole number >= 0, got nan$"),
        (dict(steps=None), r"^steps must be a whole number >= 0, got None$"),
        (dict(record_every=0), r"^record_every must be a whole number >= 1, got 0$"),
        (dict(threads=10 ** 12), r"^threads must be an integer from 1 to 1024"),
    ]
    for changes, message in refusals:
        arguments = dict(x0s=x0, controls_or_sources=None, steps=10) | changes
        with pytest.raises(ValueError, match=message):
            batch.rollout(m, **arguments)
