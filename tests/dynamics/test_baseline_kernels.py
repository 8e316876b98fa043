"""SOADYN_BASELINE_KERNELS: a process that sets it chooses every kernel as a processor without
AVX2 and FMA would (processor_features.hpp), so runs on different x86-64 processors agree bit
for bit. A child process with the variable set forms the mass matrix and the hybrid dynamics
of panda (six quarter-turn placements) and solo12 (free root) at random states, and of the
cassini scene (two flexible booms of four modes: the appendage kernels); its kernels must be
the baseline ones, and its results must match Pinocchio's (robots) or the inverse dynamics'
(cassini, whose booms' terms the inverse dynamics forms without the appendage step) and, to
rounding, this process's."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import soadyn
from soadyn import scenes
from soadyn._soadyn import _appendage_kernel, _joint_angle_kernel, _mass_matrix_kernel
from support.robots import robot, robot_with_oracle

STATES = 12
CHILD = r"""
import json, sys
import numpy as np
import soadyn
from soadyn import scenes
from soadyn._soadyn import _appendage_kernel, _joint_angle_kernel, _mass_matrix_kernel

path, floating, states = sys.argv[1], sys.argv[2] == "1", json.loads(sys.stdin.read())
m = scenes.cassini() if path == "cassini" else soadyn.load_urdf(path, floating_base=floating)
out = {"kernels": [_joint_angle_kernel(), _mass_matrix_kernel(), _appendage_kernel()], "M": [], "qdd": []}
for q, v, u in states:
    out["M"].append(soadyn.mass_matrix(m, np.array(q)).tolist())
    out["qdd"].append(soadyn.forward_dynamics(m, np.array(q), np.array(v), np.array(u)).tolist())
print(json.dumps(out))
"""


def child_results(path, floating, states, value):
    env = {**os.environ, "SOADYN_BASELINE_KERNELS": value}
    done = subprocess.run([sys.executable, "-c", CHILD, str(path), "1" if floating else "0"], env=env,
                          input=json.dumps([[x.tolist() for x in s] for s in states]), capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


@pytest.mark.parametrize("name, floating", [("panda", False), ("solo12", True)])
def test_baseline_kernels_on_request(name, floating):
    path, _ = robot(name)
    m, oracle = robot_with_oracle(name, floating)
    rng = np.random.default_rng(17)
    states = [(soadyn.random_configuration(m, seed=int(rng.integers(1 << 30))), rng.uniform(-1, 1, m.nv),
               rng.uniform(-1, 1, m.nv)) for _ in range(STATES)]
    baseline = child_results(path, floating, states, "1")
    assert baseline["kernels"][1:] == ["baseline", "baseline"]
    assert baseline["kernels"][0] in ("libmvec SSE2", "std")
    unset = child_results(path, floating, states, "0")  # "0" requests nothing: the processor's own choice
    assert unset["kernels"] == [_joint_angle_kernel(), _mass_matrix_kernel(), _appendage_kernel()]
    differs_somewhere = False
    for k, (q, v, u) in enumerate(states):
        M_child, M_here = np.array(baseline["M"][k]), soadyn.mass_matrix(m, q)
        scale = np.max(np.abs(M_here))
        np.testing.assert_array_equal(np.array(unset["M"][k]), M_here)
        assert np.max(np.abs(M_child - M_here)) <= 1e-14 * scale, (name, k)
        assert np.max(np.abs(M_child - oracle.mass_matrix(q))) <= 1e-10 * scale, (name, k)
        qdd_child, qdd_here = np.array(baseline["qdd"][k]), soadyn.forward_dynamics(m, q, v, u)
        np.testing.assert_allclose(qdd_child, qdd_here, rtol=1e-12, atol=1e-12 * np.max(np.abs(qdd_here)))
        differs_somewhere |= not np.array_equal(M_child, M_here) or not np.array_equal(qdd_child, qdd_here)
    # Where this process runs AVX2 kernels, the child's baseline ones round differently somewhere:
    # proof that the variable took effect.
    assert differs_somewhere == (_mass_matrix_kernel() != "baseline" or _joint_angle_kernel() not in
                                 ("libmvec SSE2", "std"))


def test_baseline_appendage_kernel_on_request():
    """The cassini scene's booms through the baseline appendage kernel in a child process: the
    child's forward and hybrid dynamics agree with this process's to rounding, and both satisfy
    the inverse dynamics (M qdd + h = tau, formed without the appendage step)."""
    m = scenes.cassini()
    rng = np.random.default_rng(23)
    states = [(soadyn.random_configuration(m, seed=int(rng.integers(1 << 30))), rng.uniform(-1, 1, m.nv),
               rng.uniform(-1, 1, m.nv)) for _ in range(STATES)]
    baseline = child_results("cassini", False, states, "1")
    assert baseline["kernels"][1:] == ["baseline", "baseline"]
    unset = child_results("cassini", False, states, "0")
    assert unset["kernels"] == [_joint_angle_kernel(), _mass_matrix_kernel(), _appendage_kernel()]
    differs_somewhere = False
    for k, (q, v, u) in enumerate(states):
        qdd_child, qdd_here = np.array(baseline["qdd"][k]), soadyn.forward_dynamics(m, q, v, u)
        np.testing.assert_array_equal(np.array(unset["qdd"][k]), qdd_here)
        np.testing.assert_allclose(qdd_child, qdd_here, rtol=1e-12, atol=1e-12 * np.max(np.abs(qdd_here)))
        for qdd in (qdd_child, qdd_here):
            np.testing.assert_allclose(soadyn.inverse_dynamics(m, q, v, qdd), u, rtol=0, atol=1e-10)
        differs_somewhere |= not np.array_equal(qdd_child, qdd_here)
    assert differs_somewhere == (_appendage_kernel() != "baseline" or _joint_angle_kernel() not in
                                 ("libmvec SSE2", "std"))


HOSTILE = r"""
import json, sys
import numpy as np
import soadyn
from soadyn import scenes

m = scenes.cassini()
q, u = soadyn.random_configuration(m, seed=1), np.zeros(m.nv)
mode = m.dof_names.index("magnetometer_boom:mode1")
cases = {"q NaN": ("q", mode + 1, float("nan")), "v infinite": ("v", mode, float("inf")),
         "bus rate 1e160": ("v", 0, 1e160), "modal rate 1e200": ("v", mode, 1e200)}
out = {}
for label, (which, index, value) in cases.items():
    x = {"q": q.copy(), "v": np.zeros(m.nv)}
    x[which][index] = value
    try:
        qdd, _ = soadyn.hybrid_dynamics(m, x["q"], x["v"], u)
        out[label] = "finite" if np.all(np.isfinite(qdd)) else "NOT FINITE"
    except (ValueError, ArithmeticError) as e:
        out[label] = f"{type(e).__name__}: {e}"
print(json.dumps(out))
"""


@pytest.mark.parametrize("value", ["0", "1"])
def test_hostile_inputs_through_either_appendage_kernel(value):
    """NaN and infinite modal inputs are refused by name before any kernel runs; a bus rate whose
    square overflows gives a DynamicsError naming the DOF, never a silent non-finite result; a
    huge modal rate (linear in the appendage's terms without a body rate) stays finite. The same
    with the processor's kernels ("0") and the baseline ones ("1")."""
    env = {**os.environ, "SOADYN_BASELINE_KERNELS": value}
    done = subprocess.run([sys.executable, "-c", HOSTILE], env=env, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    out = json.loads(done.stdout)
    assert out["q NaN"] == "ValueError: q[7] ('magnetometer_boom:mode1') is NaN"
    assert out["v infinite"] == "ValueError: v[6] ('magnetometer_boom:mode1') is infinite"
    assert out["bus rate 1e160"].startswith("DynamicsError: hybrid_dynamics: the result for DOF 'bus:wx' is not "
                                            "finite"), out["bus rate 1e160"]
    assert out["modal rate 1e200"] == "finite"


LATE_REQUEST = r"""
import json, os
import numpy as np
import soadyn
from soadyn import scenes
from soadyn._soadyn import _appendage_kernel, _joint_angle_kernel, _mass_matrix_kernel

def names():
    return [_joint_angle_kernel(), _mass_matrix_kernel(), _appendage_kernel()]

m = scenes.cassini()
q = soadyn.random_configuration(m, seed=5)
first = names()  # chooses every kernel, before any dynamics call
os.environ["SOADYN_BASELINE_KERNELS"] = "1"  # too late: the choices are made
qdd = soadyn.forward_dynamics(m, q, np.ones(m.nv), np.ones(m.nv))
print(json.dumps({"first": first, "after": names(), "qdd": qdd.tolist()}))
"""


def test_kernel_names_are_the_kernels_that_run():
    """A kernel's name is that of the kernel the process runs, fixed by the first call or the first
    question: a request for the baseline kernels made after it changes neither the names nor the
    numbers (the dynamics equal this process's bit for bit)."""
    done = subprocess.run([sys.executable, "-c", LATE_REQUEST], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    out = json.loads(done.stdout)
    here = [_joint_angle_kernel(), _mass_matrix_kernel(), _appendage_kernel()]
    assert out["first"] == out["after"] == here
    m = scenes.cassini()
    q = soadyn.random_configuration(m, seed=5)
    np.testing.assert_array_equal(np.array(out["qdd"]), soadyn.forward_dynamics(m, q, np.ones(m.nv), np.ones(m.nv)))


def test_timing_the_baseline_kernel_refuses_a_flexible_model_by_name():
    """`time_cpp(..., "crba_baseline")` (soadyn._timing) times the rigid-model kernel alone: a model with flexible
    bodies (whose mass matrix is formed in body frames) is refused with the algorithm named."""
    from soadyn import scenes
    from soadyn._timing import time_cpp

    m = scenes.cassini()
    q = soadyn.random_configuration(m, seed=3)[None, :]
    zeros = np.zeros((1, m.nv))
    with pytest.raises(ValueError, match="crba_baseline takes rigid models only"):
        time_cpp(m, "crba_baseline", q, zeros, zeros, 10, 1)
    with pytest.raises(ValueError, match="unknown algorithm 'crba_fma'.*crba_baseline"):
        time_cpp(m, "crba_fma", q, zeros, zeros, 10, 1)
    rigid, _ = robot_with_oracle("panda", False)
    qr = soadyn.random_configuration(rigid, seed=3)[None, :]
    assert time_cpp(rigid, "crba_baseline", qr, np.zeros((1, rigid.nv)), np.zeros((1, rigid.nv)), 10, 1) > 0
