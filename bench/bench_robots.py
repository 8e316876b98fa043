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

The machine is shared and its speed drifts by up to 2x within minutes, so nothing is
compared across phases: the C++ timings run in rounds, each round timing Pinocchio (one
peer_bench run) and then soadyn on every robot, and every ratio is the median over rounds
of the ratio measured within a round. The mixed masks are timed against all-regular back to
back, each mask sample between two all-regular samples (mixed_over_regular). The Python
timings interleave the libraries call batch by call batch the same way.

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
from soadyn._soadyn import _joint_angle_kernel, _mass_matrix_kernel, _time_cpp

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
    return parse_peer_output(out.stdout, paths)


def parse_peer_output(stdout: str, paths: dict[str, Path]) -> dict[str, dict[str, float]]:
    """{robot: {timing name: microseconds}} from the `file key=..us ...` lines of a peer program."""
    result = {}
    for line in stdout.splitlines():
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


def interleaved_per_call_us(fns, calls=2000, repetitions=7):
    """Per-call wall time (us) of each named function, the functions timed in turn within each
    repetition. Returns {name: [sample per repetition]}."""
    samples = {name: [] for name in fns}
    for _ in range(repetitions):
        for name, (fn, (q, v, u)) in fns.items():
            n = len(q)
            start = time.perf_counter()
            for i in range(calls):
                fn(q[i % n], v[i % n], u[i % n])
            samples[name].append((time.perf_counter() - start) / calls * 1e6)
    return samples


def median_ratio(a, b):
    """Median over repetitions of the ratio a/b measured within each repetition."""
    return float(np.median(np.asarray(a) / np.asarray(b)))


def fastest_ratio(ours, theirs):
    """The fastest of our times over the fastest of theirs (nan without both): a shared host's noise only
    ever slows a measurement down, so the fastest of many is the least disturbed."""
    return min(ours) / min(theirs) if len(ours) and len(theirs) else float("nan")


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
    t = {name: _time_cpp(model, name, q, v, u, calls) for name in ("aba", "rnea", "crba", "crba_baseline")}
    model.set_prescribed(np.zeros(model.nv, dtype=bool))
    t["hybrid regular"] = _time_cpp(model, "hybrid", q, v, u, calls)
    model.set_prescribed(np.ones(model.nv, dtype=bool))
    t["hybrid prescribed"] = _time_cpp(model, "hybrid", q, v, u, calls)
    model.set_prescribed(np.zeros(model.nv, dtype=bool))
    return t


MIXED_FRACTIONS = (0.25, 0.5, 0.75)


def mixed_over_regular(model, states, calls, pairs):
    """Each mixed mask against all-regular, measured back to back: every mask sample is divided by the mean of
    the all-regular samples just before and just after it, so a change of the machine's speed between samples
    cancels. Returns (median ratio, median time) per mask (random whole-joint masks, MIXED_FRACTIONS)."""
    q, v, u = states
    rng = np.random.default_rng(3)
    masks = [joint_masks(model, rng, fraction) for fraction in MIXED_FRACTIONS]

    def timed(mask):
        model.set_prescribed(mask)
        return _time_cpp(model, "hybrid", q, v, u, calls, 3)

    regular = np.zeros(model.nv, dtype=bool)
    ratios, times = [[] for _ in masks], [[] for _ in masks]
    before = timed(regular)
    for _ in range(pairs):
        for k, mask in enumerate(masks):
            t = timed(mask)
            after = timed(regular)
            ratios[k].append(t / (0.5 * (before + after)))
            times[k].append(t)
            before = after
    model.set_prescribed(regular)
    return [(float(np.median(r)), float(np.median(t))) for r, t in zip(ratios, times)]


def python_timings(name, path, floating, model, states, calls):
    import pinocchio as pin
    from soadyn.oracles import DartOracle

    pmodel = (pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer()) if floating
              else pin.buildModelFromUrdf(str(path)))
    pdata = pmodel.createData()
    pq = np.array([pin.randomConfiguration(pmodel, -np.ones(pmodel.nq), np.ones(pmodel.nq)) for _ in range(STATES)])
    rng = np.random.default_rng(5)
    pstates = (pq, rng.uniform(-1, 1, (STATES, pmodel.nv)), rng.uniform(-1, 1, (STATES, pmodel.nv)))
    mask = joint_masks(model, np.random.default_rng(11), 0.5)
    dart = DartOracle(model, str(path), floating)
    sk = dart.skeleton
    dart._set_actuators(mask, np.zeros(model.nv))
    for tree in range(sk.getNumTrees()):
        sk.dirtyArticulatedInertia(tree)
    q, v, u = states
    dstates = (np.array([dart._positions(x) for x in q]), v[:, dart.v_of_dart], u[:, dart.v_of_dart])

    def dart_call(q, v, u):
        sk.setPositions(q)
        sk.setVelocities(v)
        sk.setCommands(u)
        sk.computeForwardDynamics()
        return sk.getAccelerations(), sk.getForces()

    model.set_prescribed(np.zeros(model.nv, dtype=bool))
    regular = interleaved_per_call_us({
        "pin.aba": (lambda q, v, u: pin.aba(pmodel, pdata, q, v, u), pstates),
        "forward_dynamics": (lambda q, v, u: soadyn.forward_dynamics(model, q, v, u), states),
        "hybrid regular": (lambda q, v, u: soadyn.hybrid_dynamics(model, q, v, u), states),
    }, calls)
    model.set_prescribed(mask)
    mixed = interleaved_per_call_us({
        "hybrid mixed": (lambda q, v, u: soadyn.hybrid_dynamics(model, q, v, u), states),
        "dart hybrid mixed": (dart_call, dstates),
    }, calls)
    model.set_prescribed(np.zeros(model.nv, dtype=bool))
    t = {k: float(np.median(x)) for k, x in {**regular, **mixed}.items()}
    t["hybrid / pin.aba"] = median_ratio(regular["hybrid regular"], regular["pin.aba"])
    t["dart / hybrid"] = median_ratio(mixed["dart hybrid mixed"], mixed["hybrid mixed"])
    return t


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer calls (a smoke run, noisier)")
    args = parser.parse_args()
    cpp_calls, py_calls, rounds = (2000, 300, 2) if args.quick else (20000, 2000, 5)
    paths = {name: robot(name)[0] for name in ROBOTS}
    models, states = {}, {}
    for name in ROBOTS:
        path, floating = robot(name)
        models[name] = soadyn.load_urdf(path, floating_base=floating)
        states[name] = random_states(models[name], np.random.default_rng(1))
    peer_rounds, ours_rounds = [], []
    for r in range(rounds):  # Pinocchio and soadyn back to back, so both see the same machine
        peer_rounds.append(peer_timings(paths))
        ours_rounds.append({name: cpp_timings(models[name], states[name], cpp_calls) for name in ROBOTS})
        print(f"round {r + 1}/{rounds} done", flush=True)
    mixed = {name: mixed_over_regular(models[name], states[name], cpp_calls // 10, 4 * rounds) for name in ROBOTS}
    rows_cpp, rows_py, rows_fastest = [], [], []
    for name in ROBOTS:
        model = models[name]
        c = {k: float(np.median([o[name][k] for o in ours_rounds])) for k in ours_rounds[0][name]}
        have_peer = all(name in p for p in peer_rounds)
        p = {k: float(np.median([pr[name][k] for pr in peer_rounds])) for k in peer_rounds[0][name]} if have_peer else {}

        def ratio(ours, theirs):
            if not have_peer:
                return "n/a"
            return f"{np.median([o[name][ours] / pr[name][theirs] for o, pr in zip(ours_rounds, peer_rounds)]):.2f}"

        def fastest(ours, theirs):
            if not have_peer:
                return "n/a"
            return f"{fastest_ratio([o[name][ours] for o in ours_rounds], [pr[name][theirs] for pr in peer_rounds]):.2f}"

        rows_fastest.append(f"| {name} | **{fastest('hybrid regular', 'aba')}** | "
                            f"**{fastest('hybrid prescribed', 'rnea')}** | **{fastest('crba', 'crba')}** | "
                            f"{fastest('crba_baseline', 'crba')} |")
        worst_ratio, worst_time = max(mixed[name])
        rows_cpp.append(
            f"| {name} | {model.nv} | {c['aba']:.2f} | {c['hybrid regular']:.2f} | {p.get('aba', float('nan')):.2f} | "
            f"**{ratio('hybrid regular', 'aba')}** | {c['hybrid prescribed']:.2f} | {c['rnea']:.2f} | "
            f"{p.get('rnea', float('nan')):.2f} | **{ratio('hybrid prescribed', 'rnea')}** | "
            f"{worst_time:.2f} | **{worst_ratio:.2f}** | "
            f"{c['crba']:.2f} | {p.get('crba', float('nan')):.2f} | **{ratio('crba', 'crba')}** |")
        path, floating = robot(name)
        t = python_timings(name, path, floating, model, states[name], py_calls)
        rows_py.append(
            f"| {name} | {t['forward_dynamics']:.2f} | {t['hybrid regular']:.2f} | {t['pin.aba']:.2f} | "
            f"**{t['hybrid / pin.aba']:.2f}** | {t['hybrid mixed']:.2f} | {t['dart hybrid mixed']:.2f} | "
            f"**{t['dart / hybrid']:.1f}** |")
        print(rows_cpp[-1], rows_py[-1], sep="\n", flush=True)
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "unknown")
    source = source_revision()
    lines = [
        "# Robots: soadyn against Pinocchio and DART", "",
        f"- Date: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; machine: {cpu}, {os.cpu_count()} logical cores",
        f"- Source: {source}; command: `python bench/bench_robots.py{' --quick' if args.quick else ''}`",
        f"- C++: {rounds} rounds, each timing Pinocchio (peer_bench) then soadyn on every robot; per library and "
        f"round the median of 7 repetitions of {cpp_calls} calls over {STATES} random states; both libraries built "
        "with g++ -O3, no -march=native. Times: medians over rounds. Ratios: medians over rounds of the ratio "
        "within a round.",
        f"- soadyn's kernels on this processor (chosen at run time): joint angles `{_joint_angle_kernel()}`, mass "
        f"matrix `{_mass_matrix_kernel()}`; the CRBA's `baseline` kernel (x86-64 SSE2, what a processor without "
        "AVX2 and FMA runs) is timed too.",
        "", "## C++ per call (us)", "",
        "| robot | nv | soadyn ABA | soadyn hybrid all-regular | Pinocchio ABA | **hybrid / pin ABA** (target <= 0.7) "
        "| soadyn hybrid all-prescribed | soadyn RNEA | Pinocchio RNEA | **all-prescribed / pin RNEA** (target <= 1) "
        "| worst mixed mask | **mixed / all-regular** (target <= 1) | soadyn CRBA | Pinocchio CRBA | **CRBA ratio** |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
        *rows_cpp, "",
        "The same three ratios against Pinocchio from the fastest of the rounds' times on each side (a shared "
        "host's noise only ever slows a measurement down, so the fastest of several is the least disturbed):", "",
        "| robot | hybrid all-regular / pin ABA | all-prescribed / pin RNEA | CRBA / pin CRBA "
        "| CRBA's baseline kernel / pin CRBA |",
        "|---|---:|---:|---:|---:|",
        *rows_fastest, "",
        "Mixed masks: random whole-joint masks with 25, 50 and 75 % of the joints prescribed, each timed "
        f"{4 * rounds} times between two all-regular timings ({cpp_calls // 10} calls x 3 repetitions each); a "
        "mask's ratio is the median of its time over the mean of the two all-regular times around it. Per mask "
        "(25 / 50 / 75 %): "
        + "; ".join(f"{name} {' / '.join(f'{r:.2f}' for r, _ in mixed[name])}" for name in ROBOTS) + ". The worst "
        "mask is shown in the table.",
        "", "## Python per call (us, numpy in and out)", "",
        "| robot | soadyn.forward_dynamics | soadyn.hybrid_dynamics (regular) | pin.aba | **hybrid / pin.aba** "
        "(target <= 1) | soadyn.hybrid_dynamics (50 % joints prescribed) | DART hybrid (same mask) "
        "| **DART / soadyn** (target >= 5) |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
        *rows_py,
    ]
    write_report("robots.md", lines)
    return 0


def source_revision() -> str:
    """The checkout's commit, as `git describe --always --dirty` gives it."""
    return subprocess.run(["git", "-C", str(HERE.parent), "describe", "--always", "--dirty"], capture_output=True,
                          text=True).stdout.strip()


def write_report(name: str, lines: list, timings: bool = True) -> None:
    """bench/results/<name>: the report's lines and, for timings, the note every timing report ends with."""
    out = HERE / "results" / name
    out.parent.mkdir(exist_ok=True)
    note = ["", "Times on a shared, possibly noisy machine: compare the ratios, measured in the same run."] if timings else []
    out.write_text("\n".join(list(lines) + note) + "\n")
    print(f"wrote {out}")


if __name__ == "__main__":
    sys.exit(main())
