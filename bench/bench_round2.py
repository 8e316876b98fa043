"""Performance round 2: this build against the build the round started from, and CRBA against Pinocchio.

Each round times, in child processes, the build at --before DIR (required: a
`pip install --target DIR` of commit 26f4505, the code when the round's goals were set) and
this build, alternating which goes first (build_comparison.alternate_builds), then runs
Pinocchio's peer_bench once (../shared/tools/peer_bench). Per child:
- C++ per call (`_time_cpp`, median of 7 repetitions of `calls` calls over 64 random
  states): mass_matrix (CRBA), hybrid_dynamics (all regular) and inverse_dynamics on the
  bench_robots robots, and hybrid_dynamics and mass_matrix of the cassini model;
- the cassini RK4 step at 1 ms as the HIL scene runs it (turntable and gimbal driven,
  soadyn.hil.scene_simulator): Simulator._run of `steps` steps, per-step time, median of 7;
- where cassini's hybrid_dynamics time goes: the same call on the scene with parts removed
  (the saved model's bodies filtered, cassini_without).
Ratios are medians over rounds of the ratio within a round. Then paired phases, since a shared
host's speed drifts over the seconds a round takes: the cassini step and hybrid_dynamics of
both builds, and each robot's CRBA beside one peer_bench run on that robot, each timed in
short children back to back, alternating the order; their ratios are the medians of the
within-pair ratios, with interquartile ranges, and the fastest measurement of one side over
the fastest of the other (noise only slows a measurement down).

Writes bench/results/round2.md. Usage: python bench/bench_round2.py [--quick] [--before DIR --before-rev REV]
"""
from __future__ import annotations

import argparse
import functools
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))
sys.path.insert(0, str(HERE))
ROBOTS = ["ur5", "panda", "solo12", "talos"]
BOOMS = ("magnetometer_boom", "plasma_wave_antenna")
WHEELS = ("wheel_1", "wheel_2", "wheel_3", "wheel_4")
SLOSH = ("oxidizer_slosh", "fuel_slosh")
CASSINI_PARTS = {"all 15 bodies": (), "without the two flexible booms": BOOMS, "without the four wheels": WHEELS,
                 "without the two slosh pendulums": SLOSH,
                 "the bus and its six other bodies (none of the above)": BOOMS + WHEELS + SLOSH}


def random_states(soadyn, m, count=64):
    """q, v, u: `count` random states of model m (the same in every child)."""
    rng = np.random.default_rng(1)
    q = np.array([soadyn.random_configuration(m, int(rng.integers(1 << 31))) for _ in range(count)])
    return q, rng.uniform(-1, 1, (count, m.nv)), rng.uniform(-1, 1, (count, m.nv))


def cassini_step_us(steps: int) -> float:
    """The cassini RK4 step at 1 ms as `soadyn hil` runs it: median of 7 runs of `steps` steps (us)."""
    from soadyn.hil import scene_simulator
    sim = scene_simulator("cassini", 1000.0)
    sim._run(500)
    per_step = []
    for _ in range(7):
        start = time.perf_counter()
        sim._run(steps)
        per_step.append((time.perf_counter() - start) / steps * 1e6)
    return float(np.median(per_step))


def cassini_without(soadyn, names):
    """The cassini model without the bodies `names`: its saved file with those bodies left out."""
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "cassini.json"
        soadyn.save_model(soadyn.scenes.cassini(), path)
        spec = json.loads(path.read_text())
        spec["bodies"] = [body for body in spec["bodies"] if body["name"] not in names]
        path.write_text(json.dumps(spec))
        return soadyn.load_model(path)
ALGORITHMS = {"crba": "mass_matrix (CRBA)", "hybrid": "hybrid_dynamics", "rnea": "inverse_dynamics"}


def child(calls: int, steps: int) -> None:
    """Child process: timings with whichever soadyn is first on the path."""
    import soadyn
    from soadyn._soadyn import _time_cpp
    from robots import robot

    states = functools.partial(random_states, soadyn)

    out = {}
    for name in ROBOTS:
        path, floating = robot(name)
        m = soadyn.load_urdf(path, floating_base=floating)
        s = states(m)
        out[name] = {alg: _time_cpp(m, alg, *s, calls) for alg in ALGORITHMS}
    cassini = soadyn.scenes.cassini()
    s = states(cassini)
    out["cassini"] = {alg: _time_cpp(cassini, alg, *s, calls) for alg in ("hybrid", "crba")}
    out["cassini"]["step"] = cassini_step_us(steps)
    out["cassini_parts"] = {}
    parts = CASSINI_PARTS if hasattr(soadyn, "load_model") else {}  # the round's starting build has no model files
    for label, names in parts.items():
        part = cassini_without(soadyn, names)
        out["cassini_parts"][label] = {"nv": part.nv, "hybrid": _time_cpp(part, "hybrid", *states(part), calls)}
    print(json.dumps(out))


def paired_child(steps: int, calls: int, robot_name: str) -> None:
    """Child process of the paired phases: the cassini step and hybrid_dynamics only (robot_name
    "-"), or one robot's CRBA with peer_bench's protocol (7 repetitions of `calls` calls)."""
    import soadyn
    from soadyn._soadyn import _time_cpp
    from robots import robot

    states = functools.partial(random_states, soadyn)

    if robot_name != "-":
        path, floating = robot(robot_name)
        m = soadyn.load_urdf(path, floating_base=floating)
        print(json.dumps({"crba": _time_cpp(m, "crba", *states(m), calls)}))
        return
    cassini = soadyn.scenes.cassini()
    print(json.dumps({"step": cassini_step_us(steps), "hybrid": _time_cpp(cassini, "hybrid", *states(cassini), calls)}))


if __name__ == "__main__" and len(sys.argv) > 1 and sys.argv[1] == "--child":
    child(int(sys.argv[2]), int(sys.argv[3]))
    sys.exit(0)
if __name__ == "__main__" and len(sys.argv) > 1 and sys.argv[1] == "--paired-child":
    paired_child(int(sys.argv[2]), int(sys.argv[3]), sys.argv[4])
    sys.exit(0)

from bench_robots import fastest_ratio, median_ratio, peer_timings, source_revision  # noqa: E402
from build_comparison import alternate_builds, has_build  # noqa: E402
from robots import robot  # noqa: E402


def kernel_names() -> str:
    """The kernels this build chose on this processor (the round's starting build had none)."""
    from soadyn._soadyn import _appendage_kernel, _joint_angle_kernel, _mass_matrix_kernel

    return (f"joint angles `{_joint_angle_kernel()}`, mass matrix `{_mass_matrix_kernel()}`, "
            f"flexible appendages `{_appendage_kernel()}`")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer rounds and calls (a smoke run, noisier)")
    parser.add_argument("--before", type=Path, required=True,
                        help="a directory holding the earlier build's soadyn package (pip install --target)")
    parser.add_argument("--before-rev", default="26f4505", help="the commit that build was made from")
    args = parser.parse_args()
    if not has_build(args.before):
        print(f"no soadyn package under {args.before}: build commit {args.before_rev} there first "
              f"(pip install --no-deps --no-build-isolation --target {args.before} <source of {args.before_rev}>)",
              file=sys.stderr)
        return 2
    rounds, calls, steps = (2, 2000, 500) if args.quick else (6, 20000, 4000)
    paths = {name: robot(name)[0] for name in ROBOTS}
    load_start = os.getloadavg()[0]
    runs = {"before": [], "after": []}
    peers = []
    for r in range(rounds):
        one = alternate_builds(Path(__file__), ["--child", str(calls), str(steps)], args.before, 1, f"round {r + 1}")
        runs["before"] += one["before"]
        runs["after"] += one["after"]
        peers.append(peer_timings(paths))

    # Paired phases: the machine's speed drifts over seconds (a shared host), so each ratio is also
    # taken between two short measurements made back to back, many times, alternating the order.
    pairs = 6 if args.quick else 20
    short = alternate_builds(Path(__file__), ["--paired-child", str(steps // 4), str(calls // 4), "-"], args.before,
                             pairs, "paired cassini")
    paired_cassini = {alg: [a[alg] / b[alg] for a, b in zip(short["after"], short["before"])]
                      for alg in ("step", "hybrid")}
    fastest_cassini = {alg: fastest_ratio([a[alg] for a in short["after"]], [b[alg] for b in short["before"]])
                       for alg in ("step", "hybrid")}
    env_after = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    paired_pin = {name: [] for name in ROBOTS}
    paired_times = {name: ([], []) for name in ROBOTS}  # (ours, Pinocchio's) per pair
    for r in range(pairs // 2):
        for name in ROBOTS:
            ours = peer = None
            for which in (("ours", "peer") if (r + ROBOTS.index(name)) % 2 == 0 else ("peer", "ours")):
                if which == "peer":
                    peer = peer_timings({name: paths[name]}).get(name, {}).get("crba")
                else:
                    out = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--paired-child", "0",
                                          str(calls), name], env=env_after, capture_output=True, text=True,
                                         check=True, cwd="/")
                    ours = json.loads(out.stdout.strip().splitlines()[-1])["crba"]
            if peer:
                paired_pin[name].append(ours / peer)
                paired_times[name][0].append(ours)
                paired_times[name][1].append(peer)
        print(f"paired CRBA: round {r + 1}/{pairs // 2} done", flush=True)

    def spread(values):
        q1, q2, q3 = np.percentile(values, [25, 50, 75]) if values else (float("nan"),) * 3
        return f"**{q2:.2f}** ({q1:.2f}-{q3:.2f})"

    def med(build, model, alg):
        return float(np.median([run[model][alg] for run in runs[build]]))

    def ratio(model, alg):
        return median_ratio([run[model][alg] for run in runs["after"]], [run[model][alg] for run in runs["before"]])

    def pin_ratio(model):
        pairs = [(a[model]["crba"], p[model]["crba"]) for a, p in zip(runs["after"], peers) if model in p]
        return median_ratio(*zip(*pairs)) if pairs else float("nan")

    def pin_median(model):
        values = [p[model]["crba"] for p in peers if model in p]
        return float(np.median(values)) if values else float("nan")

    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "unknown")
    source = source_revision()
    lines = [
        "# Performance round 2: this build against the round's starting build, same run", "",
        f"- Date: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; machine: {cpu}, {os.cpu_count()} logical cores "
        f"(load average {load_start:.1f} at the start, {os.getloadavg()[0]:.1f} at the end)",
        f"- Source: {source}; before: commit {args.before_rev} (PYTHONPATH={args.before}); "
        f"command: `python bench/bench_round2.py{' --quick' if args.quick else ''}`",
        f"- {rounds} rounds; each round runs both builds in child processes (alternating which goes first) and "
        f"Pinocchio's peer_bench once. C++ per call: `_time_cpp`, median of 7 repetitions of {calls} calls over 64 "
        f"random states. Times: medians over rounds; ratios: medians over rounds of the ratio within a round.",
        f"- This build's kernels on this processor (chosen at run time): {kernel_names()}", "",
        "## C++ per call on the bench_robots robots (us)", "",
        "| robot | CRBA before | CRBA after | **after / before** | Pinocchio CRBA | **after / Pinocchio** (goal <= 0.7) "
        "| hybrid after / before | RNEA after / before |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name in ROBOTS:
        lines.append(f"| {name} | {med('before', name, 'crba'):.2f} | {med('after', name, 'crba'):.2f} | "
                     f"**{ratio(name, 'crba'):.2f}** | {pin_median(name):.2f} | **{pin_ratio(name):.2f}** | "
                     f"{ratio(name, 'hybrid'):.2f} | {ratio(name, 'rnea'):.2f} |")
    lines += [
        "", "## The cassini scene (15 bodies, two flexible booms with 4 modes each, nv 28)", "",
        "| measure | before (us) | after (us) | **after / before** |",
        "|---|---:|---:|---:|",
        f"| RK4 step at 1 ms, driven as in `soadyn hil` (goal <= 0.6) | {med('before', 'cassini', 'step'):.2f} | "
        f"{med('after', 'cassini', 'step'):.2f} | **{ratio('cassini', 'step'):.2f}** |",
        f"| hybrid_dynamics, C++ | {med('before', 'cassini', 'hybrid'):.2f} | {med('after', 'cassini', 'hybrid'):.2f} | "
        f"**{ratio('cassini', 'hybrid'):.2f}** |",
        f"| mass_matrix (composite bodies with augmented flexible bodies), C++ | {med('before', 'cassini', 'crba'):.2f} | "
        f"{med('after', 'cassini', 'crba'):.2f} | **{ratio('cassini', 'crba'):.2f}** |",
        "", "## Paired measurements", "",
        f"The ratios again, each from two short measurements made back to back (alternating which goes first), "
        f"{pairs} pairs per build comparison and {pairs // 2} per robot against Pinocchio: the median of the "
        f"within-pair ratios, with their interquartile range. Cassini: 7 x {steps // 4} steps and `_time_cpp` with "
        f"{calls // 4} calls per child; CRBA: one robot per peer_bench run, beside a child timing the same robot with "
        f"peer_bench's protocol (median of 7 repetitions of {calls} calls). The last column divides the fastest "
        f"of those measurements of one side by the fastest of the other's: a shared host's noise only ever slows a "
        f"measurement down, so the fastest of many is the least disturbed (the estimator Python's timeit "
        f"recommends).", "",
        "| ratio | median of the pairs (interquartile range) | fastest / fastest |",
        "|---|---|---:|",
        f"| cassini RK4 step, after / before (goal <= 0.6) | {spread(paired_cassini['step'])} | "
        f"**{fastest_cassini['step']:.2f}** |",
        f"| cassini hybrid_dynamics, after / before | {spread(paired_cassini['hybrid'])} | "
        f"**{fastest_cassini['hybrid']:.2f}** |",
    ]
    for name in ROBOTS:
        lines.append(f"| CRBA / Pinocchio, {name} (goal <= 0.7) | {spread(paired_pin[name])} | "
                     f"**{fastest_ratio(*paired_times[name]):.2f}** |")
    lines += [
        "", "## Where cassini's hybrid_dynamics time goes (this build)", "",
        "The same C++ call on the scene with parts removed (`cassini_without`: the saved model's bodies "
        "filtered); medians over rounds.", "",
        "| scene | nv | hybrid_dynamics (us) | share of the whole scene's time |",
        "|---|---:|---:|---:|",
    ]
    whole = float(np.median([run["cassini_parts"]["all 15 bodies"]["hybrid"] for run in runs["after"]]))
    for label in CASSINI_PARTS:
        t = float(np.median([run["cassini_parts"][label]["hybrid"] for run in runs["after"]]))
        lines.append(f"| {label} | {runs['after'][0]['cassini_parts'][label]['nv']} | {t:.2f} | {t / whole:.2f} |")
    lines += ["", "Times on a shared, possibly noisy machine: compare the ratios, measured in the same run."]
    out = HERE / "results" / "round2.md"
    out.write_text("\n".join(lines) + "\n")
    print(out.read_text())
    return 0


if __name__ == "__main__":
    sys.exit(main())
