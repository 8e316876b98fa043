"""A Model used from several Python threads at once: structural changes, flag
and gravity changes race against GIL-released dynamics calls. Each race runs
in a subprocess for a few seconds (a crash there fails the test instead of
killing the suite); every call either returns the right numbers or raises
the documented error, and the process exits cleanly."""
from __future__ import annotations

import subprocess
import sys
import textwrap

RACE_SECONDS = 2.5

PRELUDE = """
import threading, time
import numpy as np
import soadyn
from soadyn import scenes

RACE_SECONDS = {seconds}
stop = threading.Event()
failures = []
counts = {{"ok": 0, "refused": 0}}

def worker(body):
    try:
        while not stop.is_set():
            body()
    except BaseException as e:  # reported by the main thread
        failures.append(repr(e))
        stop.set()

def race(bodies, mutate):
    threads = [threading.Thread(target=worker, args=(b,)) for b in bodies]
    for t in threads:
        t.start()
    end = time.monotonic() + RACE_SECONDS
    try:
        while time.monotonic() < end and not stop.is_set():
            mutate()
    finally:
        stop.set()
        for t in threads:
            t.join()
    assert not failures, failures
"""


def run_race(body: str) -> str:
    code = PRELUDE.format(seconds=RACE_SECONDS) + textwrap.dedent(body)
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, f"exit {result.returncode}\n{result.stdout[-3000:]}\n{result.stderr[-3000:]}"
    return result.stdout


def test_add_body_while_another_thread_runs_dynamics_on_the_model():
    # The chain's 30 DOFs release the GIL; bodies are added as separate trees,
    # so the chain's accelerations do not depend on them: every call that
    # computes must give the reference numbers for the chain's DOFs.
    out = run_race("""
    m = scenes.pendulum_chain(30)
    rng = np.random.default_rng(1)
    q30, v30, tau30 = rng.uniform(-1, 1, 30), rng.uniform(-1, 1, 30), rng.uniform(-1, 1, 30)
    reference = soadyn.forward_dynamics(m.copy(), q30, v30, tau30)

    def call():
        nq, nv = m.nq, m.nv
        q, v, tau = np.zeros(nq), np.zeros(nv), np.zeros(nv)
        q[:30], v[:30], tau[:30] = q30, v30, tau30
        try:
            qdd = soadyn.forward_dynamics(m, q, v, tau)
        except ValueError as e:   # sized for the model before a body was added
            assert "expected" in str(e), e
            counts["refused"] += 1
            return
        except RuntimeError as e:  # checked, then the model changed before it computed
            assert "changed structurally by another thread" in str(e), e
            counts["refused"] += 1
            return
        np.testing.assert_allclose(qdd[:30], reference, rtol=1e-12, atol=1e-12)
        assert np.all(np.isfinite(qdd))
        counts["ok"] += 1

    added = [0]
    def add():
        if added[0] < 3000:
            m.add_body(f"extra{added[0]}", None, soadyn.Joint.revolute([1, 0, 0]), mass=1.0,
                       com=[0, 0, -0.1], inertia=[0.01, 0.01, 0.01])
            added[0] += 1
        else:
            time.sleep(0.001)

    race([call, call], add)
    assert m.nbodies == 30 + added[0]
    print(counts["ok"], counts["refused"], added[0])
    """)
    ok, refused, added = map(int, out.split())
    assert ok > 0 and added > 0


def test_flags_and_gravity_change_while_other_threads_run_hybrid_dynamics():
    # Every result must be the hybrid solution for one of the two masks and
    # one of the two gravities: never a mixture or garbage.
    run_race("""
    m = scenes.pendulum_chain(40)
    rng = np.random.default_rng(2)
    q, v, u = rng.uniform(-1, 1, 40), rng.uniform(-1, 1, 40), rng.uniform(-1, 1, 40)
    mask = np.zeros(40, dtype=bool); mask[::3] = True
    answers = []
    for g in ([0, 0, -9.81], [0, 0, -1.62]):
        for prescribed in (mask, ~mask):
            ref = m.copy(); ref.gravity = g; ref.set_prescribed(prescribed)
            answers.append(soadyn.hybrid_dynamics(ref, q, v, u))
    m.set_prescribed(mask)

    def call():
        qdd, tau = soadyn.hybrid_dynamics(m, q, v, u)
        assert any(np.array_equal(qdd, a) and np.array_equal(tau, b) for a, b in answers), "mixed result"

    flip = [0]
    def mutate():
        flip[0] += 1
        m.set_prescribed(mask if flip[0] % 2 else ~mask)
        m.gravity = [0, 0, -9.81] if flip[0] % 3 else [0, 0, -1.62]

    race([call, call], mutate)
    """)


def test_gravity_changes_while_other_threads_run_constrained_dynamics():
    # The loop call's fast entry (f(model, q, v, u) with float64 arrays) under the same race: every result
    # is the four-bar's answer for one of the two gravities, bit for bit.
    run_race("""
    m = scenes.four_bar()
    q, v = scenes.four_bar_state(0.7, 2.0)
    u = np.array([0.5, 0.0, 0.0])
    answers = []
    for g in ([0, -9.81, 0], [0, -1.62, 0]):
        ref = m.copy(); ref.gravity = g
        answers.append(soadyn.constrained_dynamics(ref, q, v, u))
    assert not np.array_equal(answers[0][0], answers[1][0])

    def call():
        qdd, tau, wrenches = soadyn.constrained_dynamics(m, q, v, u)
        assert any(np.array_equal(qdd, a) and np.array_equal(tau, b) and np.array_equal(wrenches, c)
                   for a, b, c in answers), "mixed result"

    flip = [0]
    def mutate():
        flip[0] += 1
        m.gravity = [0, -9.81, 0] if flip[0] % 2 else [0, -1.62, 0]

    race([call, call], mutate)
    """)


def test_copy_and_scene_reload_while_other_threads_compute():
    run_race("""
    m = scenes.pendulum_chain(30)
    q, v, tau = np.full(30, 0.2), np.full(30, -0.1), np.zeros(30)
    reference = soadyn.forward_dynamics(m.copy(), q, v, tau)
    other = scenes.pendulum_chain(30)

    def call():
        try:
            np.testing.assert_array_equal(soadyn.forward_dynamics(m, q, v, tau), reference)
            np.testing.assert_array_equal(soadyn.mass_matrix(m, q), soadyn.mass_matrix(other, q))
            counts["ok"] += 1
        except RuntimeError as e:  # replacing the model is a structural change
            assert "changed structurally by another thread" in str(e), e
            counts["refused"] += 1

    def mutate():
        c = m.copy()
        assert c.nv == 30
        m._copy_from(other)  # same structure and numbers: results unchanged

    race([call, call], mutate)
    assert counts["ok"] > 0
    """)
