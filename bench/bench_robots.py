"""Robots: soadyn against Pinocchio (C++ and Python) and DART (Python), same machine, same run.

C++: soadyn's algorithms are timed in a C++ loop (soadyn._soadyn._time_cpp) with the
protocol of ../shared/tools/peer_bench (median of 7 repetitions of 20000 calls cycling
through 64 random states), on the same URDFs, with the same root joints (ur5 and panda
fixed, solo12 and talos free-floating), compiled with the same compiler and -O3 and no
-march=native on both sides. Pinocchio's numbers come from peer_bench in the same run.

Python: per-call wall time of the Python calls (numpy in, numpy out), median over
repetitions of many calls: soadyn.forward_dynamics and soadyn.hybrid_dynamics against
pin.aba, and soadyn.hybrid_dynamics against DART's hybrid dynamics with the same masks
(DART: set positions, velocities and commands, computeForwardDynamics, read
accelerations and forces; actuator types set once per mask, outside the timing).

Writes bench/results/robots.md. Usage: python bench/bench_robots.py [--quick]
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

import soadyn
from soadyn._soadyn import _time_cpp

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))
from robots import robot  # noqa: E402  (tests/robots.py: example-robot-data paths)

ROBOTS = ["ur5", "panda", "solo12", "talos"]
STATES = 64
PEER = HERE.parent.parent / "shared" / "tools" / "peer_bench"


def peer_timings(paths: dict[str, Path]) -> dict[str, dict[str, float]]:
    """Pinocchio's C++ ABA/RNEA/CRBA per robot from peer_bench, built on first use."""
    run, build = PEER / "run.sh", PEER / "build.sh"
    if not run.is_file():
        print(f"peer_bench not found at {PEER}", file=sys.stderr)
        return {}
    out = subprocess.run(["bash", str(run), *map(str, paths.values())], capture_output=True, text=True)
    if out.returncode == 2 and build.is_file():  # not built yet
        subprocess.run(["bash", str(build)], check=False)
        out = subprocess.run(["bash", str(run), *map(str, paths.values())], capture_output=True, text=True)
    result = {}
    for line in out.stdout.splitlines():
        fields = line.split()
        name = next((r for r, p in paths.items() if p.name == fields[0]), None) if fields else None
        if name:
            result[name] = {k: float(v.rstrip("us")) for k, v in (f.split("=") for f in fields[1:]) if k != "nv"}
    return result


def random_states(model, rng, count=STATES):
    q = np.array([soadyn.random_configuration(model, int(rng.integers(1 << 31))) for _ in range(count)])
    v = rng.uniform(-1, 1, size=(count, model.nv))
    u = rng.uniform(-1, 1, size=(count, model.nv))
    return q, v, u


def python_per_call_us(fn, states, calls=2000, repetitions=7):
    q, v, u = states
    n = len(q)
    samples = []
    for _ in range(repetitions):
        start = time.perf_counter()
        for i in range(calls):
            fn(q[i % n], v[i % n], u[i % n])
        samples.append((time.perf_counter() - start) / calls * 1e6)
    return float(np.median(samples))


def joint_masks(model, rng, fraction):
    """A random mask of whole joints (DART cannot mix modes within a joint)."""
    mask = np.zeros(model.nv, dtype=bool)
    for joint in model.joint_names:
        dofs = model._dof_indices(joint)
        if rng.uniform() < fraction:
            mask[dofs] = True
    return mask


def cpp_timings(model, states, calls):
    q, v, u = states
    t = {name: _time_cpp(model, name, q, v, u, calls) for name in ("aba", "rnea", "crba")}
    model.set_prescribed(np.zeros(model.nv, dtype=bool))
    t["hybrid regular"] = _time_cpp(model, "hybrid", q, v, u, calls)
    model.set_prescribed(np.ones(model.nv, dtype=bool))
    t["hybrid prescribed"] = _time_cpp(model, "hybrid", q, v, u, calls)
    rng = np.random.default_rng(3)
    mixed = []
    for fraction in (0.25, 0.5, 0.75):
        model.set_prescribed(joint_masks(model, rng, fraction))
        mixed.append(_time_cpp(model, "hybrid", q, v, u, calls))
    t["hybrid mixed worst"] = max(mixed)
    model.set_prescribed(np.zeros(model.nv, dtype=bool))
    return t


def python_timings(name, path, floating, model, states, calls):
    import pinocchio as pin
    from soadyn.oracles import DartOracle

    pmodel = (pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer()) if floating
              else pin.buildModelFromUrdf(str(path)))
    pdata = pmodel.createData()
    pq = np.array([pin.randomConfiguration(pmodel, -np.ones(pmodel.nq), np.ones(pmodel.nq)) for _ in range(STATES)])
    rng = np.random.default_rng(5)
    pstates = (pq, rng.uniform(-1, 1, (STATES, pmodel.nv)), rng.uniform(-1, 1, (STATES, pmodel.nv)))
    t = {"pin.aba": python_per_call_us(lambda q, v, u: pin.aba(pmodel, pdata, q, v, u), pstates, calls)}
    t["forward_dynamics"] = python_per_call_us(lambda q, v, u: soadyn.forward_dynamics(model, q, v, u), states, calls)
    t["hybrid regular"] = python_per_call_us(lambda q, v, u: soadyn.hybrid_dynamics(model, q, v, u), states, calls)
    mask = joint_masks(model, np.random.default_rng(11), 0.5)
    model.set_prescribed(mask)
    t["hybrid mixed"] = python_per_call_us(lambda q, v, u: soadyn.hybrid_dynamics(model, q, v, u), states, calls)
    model.set_prescribed(np.zeros(model.nv, dtype=bool))
    dart = DartOracle(model, str(path), floating)
    sk = dart.skeleton
    dart._set_actuators(mask, np.zeros(model.nv))
    for tree in range(sk.getNumTrees()):
        sk.dirtyArticulatedInertia(tree)
    q, v, u = states
    dq = np.array([dart._positions(x) for x in q])
    dv, du = v[:, dart.v_of_dart], u[:, dart.v_of_dart]

    def dart_call(i):
        sk.setPositions(dq[i])
        sk.setVelocities(dv[i])
        sk.setCommands(du[i])
        sk.computeForwardDynamics()
        return sk.getAccelerations(), sk.getForces()

    samples = []
    for _ in range(7):
        start = time.perf_counter()
        for i in range(calls):
            dart_call(i % STATES)
        samples.append((time.perf_counter() - start) / calls * 1e6)
    t["dart hybrid mixed"] = float(np.median(samples))
    return t


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer calls (a smoke run, noisier)")
    args = parser.parse_args()
    cpp_calls, py_calls = (2000, 300) if args.quick else (20000, 2000)
    paths = {name: robot(name)[0] for name in ROBOTS}
    peer = peer_timings(paths)
    rows_cpp, rows_py = [], []
    for name in ROBOTS:
        path, floating = robot(name)
        model = soadyn.load_urdf(path, floating_base=floating)
        states = random_states(model, np.random.default_rng(1))
        c = cpp_timings(model, states, cpp_calls)
        p = peer.get(name, {})
        ratio = lambda a, b: f"{a / b:.2f}" if b else "n/a"  # noqa: E731
        rows_cpp.append(
            f"| {name} | {model.nv} | {c['aba']:.2f} | {c['hybrid regular']:.2f} | {p.get('aba', float('nan')):.2f} | "
            f"**{ratio(c['hybrid regular'], p.get('aba'))}** | {c['hybrid prescribed']:.2f} | {c['rnea']:.2f} | "
            f"{p.get('rnea', float('nan')):.2f} | **{ratio(c['hybrid prescribed'], p.get('rnea'))}** | "
            f"{c['hybrid mixed worst']:.2f} | **{c['hybrid mixed worst'] / c['hybrid regular']:.2f}** | "
            f"{c['crba']:.2f} | {p.get('crba', float('nan')):.2f} |")
        t = python_timings(name, path, floating, model, states, py_calls)
        rows_py.append(
            f"| {name} | {t['forward_dynamics']:.2f} | {t['hybrid regular']:.2f} | {t['pin.aba']:.2f} | "
            f"**{t['hybrid regular'] / t['pin.aba']:.2f}** | {t['hybrid mixed']:.2f} | {t['dart hybrid mixed']:.2f} | "
            f"**{t['dart hybrid mixed'] / t['hybrid mixed']:.1f}** |")
        print(rows_cpp[-1], rows_py[-1], sep="\n", flush=True)
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "unknown")
    source = subprocess.run(["git", "-C", str(HERE.parent), "describe", "--always", "--dirty"], capture_output=True,
                            text=True).stdout.strip()
    lines = [
        "# Robots: soadyn against Pinocchio and DART", "",
        f"- Date: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; machine: {cpu}, {os.cpu_count()} logical cores",
        f"- Source: {source}; command: `python bench/bench_robots.py{' --quick' if args.quick else ''}`",
        "- C++: median of 7 repetitions of "
        f"{cpp_calls} calls over {STATES} random states, both libraries built with g++ -O3, no -march=native.",
        "", "## C++ per call (us)", "",
        "| robot | nv | soadyn ABA | soadyn hybrid all-regular | Pinocchio ABA | **hybrid / pin ABA** (target <= 0.7) "
        "| soadyn hybrid all-prescribed | soadyn RNEA | Pinocchio RNEA | **all-prescribed / pin RNEA** (target <= 1) "
        "| worst mixed mask | **mixed / all-regular** (target <= 1) | soadyn CRBA | Pinocchio CRBA |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
        *rows_cpp, "",
        "Mixed masks: random whole-joint masks with 25, 50 and 75 % of the joints prescribed; the worst is shown.",
        "", "## Python per call (us, numpy in and out)", "",
        "| robot | soadyn.forward_dynamics | soadyn.hybrid_dynamics (regular) | pin.aba | **hybrid / pin.aba** "
        "(target <= 1) | soadyn.hybrid_dynamics (50 % joints prescribed) | DART hybrid (same mask) "
        "| **DART / soadyn** (target >= 5) |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
        *rows_py, "",
        "Times on a shared, possibly noisy machine: compare the ratios, measured in the same run.",
    ]
    out = HERE / "results" / "robots.md"
    out.parent.mkdir(exist_ok=True)
    out.write_text("\n".join(lines) + "\n")
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
