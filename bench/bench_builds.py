"""This build against an earlier build, and the CRBA against Pinocchio, in the same run.

Each round times, in child processes, the build at --before DIR (required: a
`pip install --target DIR` of the commit named by --before-rev) and this build,
alternating which goes first (builds.alternate_builds), then runs Pinocchio's peer_bench
once. Per child:
- C++ per call (timing.time_cpp, median of 7 repetitions of `calls` calls over 64 random
  states): mass_matrix (CRBA), hybrid_dynamics (all regular) and inverse_dynamics on the
  peer robots, and hybrid_dynamics and mass_matrix of the cassini model;
- the cassini RK4 step at 1 ms as `soadyn hil` runs the scene (turntable and gimbal driven):
  Simulator._run of `steps` steps, per-step time, median of 7;
- where cassini's hybrid_dynamics time goes: the same call on the scene with parts removed
  (fixtures.cassini_without; builds without model files skip it).
Ratios are medians over rounds of the ratio within a round. Then paired measurements: the
cassini step and hybrid_dynamics of both builds, and each robot's CRBA beside one peer_bench
run on that robot, each timed in short children back to back, alternating the order; their
ratios are the medians of the within-pair ratios with interquartile ranges, and the fastest
measurement of one side over the fastest of the other.

Writes bench/results/builds.json.
Usage: python bench/bench_builds.py --before DIR --before-rev REV [--quick]
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

import fixtures
from fixtures import CASSINI_PARTS, ROBOTS, load_robot, random_states, robot

ALGORITHMS = ("crba", "hybrid", "rnea")


def cassini_step_us(steps: int) -> float:
    """The cassini RK4 step at 1 ms as `soadyn hil` runs it: median of 7 runs of `steps` steps (us)."""
    sim = fixtures.cassini_simulator(1000.0)
    sim._run(500)
    per_step = []
    for _ in range(7):
        start = time.perf_counter()
        sim._run(steps)
        per_step.append((time.perf_counter() - start) / steps * 1e6)
    return float(np.median(per_step))


def child(calls: int, steps: int) -> None:
    """Child process: timings with whichever soadyn is first on the path."""
    import soadyn
    from timing import time_cpp

    out = {}
    for name in ROBOTS:
        m = load_robot(name)
        s = random_states(m, 1)
        out[name] = {alg: time_cpp(m, alg, *s, calls) for alg in ALGORITHMS}
    cassini = fixtures.cassini()
    s = random_states(cassini, 1)
    out["cassini"] = {alg: time_cpp(cassini, alg, *s, calls) for alg in ("hybrid", "crba")}
    out["cassini"]["step"] = cassini_step_us(steps)
    out["cassini_parts"] = {}
    for label, names in (CASSINI_PARTS if hasattr(soadyn, "load_model") else {}).items():
        part = fixtures.cassini_without(names)
        out["cassini_parts"][label] = {"nv": part.nv, "hybrid": time_cpp(part, "hybrid", *random_states(part, 1), calls)}
    print(json.dumps(out))


def paired_child(steps: int, calls: int, robot_name: str) -> None:
    """Child process of the paired measurements: the cassini step and hybrid_dynamics (robot_name "-"), or one
    robot's CRBA with peer_bench's protocol (7 repetitions of `calls` calls)."""
    from timing import time_cpp

    if robot_name != "-":
        m = load_robot(robot_name)
        print(json.dumps({"crba": time_cpp(m, "crba", *random_states(m, 1), calls)}))
        return
    cassini = fixtures.cassini()
    print(json.dumps({"step": cassini_step_us(steps),
                      "hybrid": time_cpp(cassini, "hybrid", *random_states(cassini, 1), calls)}))


def kernel_names() -> dict:
    """The kernels this build chose on this processor."""
    import soadyn
    from timing import joint_angle_kernel, mass_matrix_kernel

    return {"joint angles": joint_angle_kernel(), "mass matrix": mass_matrix_kernel(),
            "flexible appendages": soadyn._soadyn._appendage_kernel()}


def main() -> int:
    from builds import add_before_arguments, alternate_builds, before_error, run_child
    from measure import fastest_ratio, median_ratio, quartiles
    from peers import peer_timings
    from report import Table, write

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer rounds and calls (a smoke run, noisier)")
    add_before_arguments(parser, required=True)
    args = parser.parse_args()
    if before_error(args):
        print(before_error(args), file=sys.stderr)
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

    # Paired measurements: two short children back to back, many times, alternating the order.
    pairs = 6 if args.quick else 20
    short = alternate_builds(Path(__file__), ["--paired-child", str(steps // 4), str(calls // 4), "-"], args.before,
                             pairs, "paired cassini")
    paired_cassini = {alg: [a[alg] / b[alg] for a, b in zip(short["after"], short["before"])] for alg in ("step", "hybrid")}
    fastest_cassini = {alg: fastest_ratio([a[alg] for a in short["after"]], [b[alg] for b in short["before"]])
                       for alg in ("step", "hybrid")}
    paired_pin = {name: [] for name in ROBOTS}
    paired_times = {name: ([], []) for name in ROBOTS}  # (ours, Pinocchio's) per pair
    for r in range(pairs // 2):
        for name in ROBOTS:
            ours = peer = None
            for which in (("ours", "peer") if (r + ROBOTS.index(name)) % 2 == 0 else ("peer", "ours")):
                if which == "peer":
                    peer = peer_timings({name: paths[name]}).get(name, {}).get("crba")
                else:
                    ours = run_child(Path(__file__), ["--paired-child", "0", str(calls), name])["crba"]
            if peer:
                paired_pin[name].append(ours / peer)
                paired_times[name][0].append(ours)
                paired_times[name][1].append(peer)
        print(f"paired CRBA: round {r + 1}/{pairs // 2} done", flush=True)

    def med(build, model, alg):
        return float(np.median([run[model][alg] for run in runs[build]]))

    def ratio(model, alg):
        return median_ratio([run[model][alg] for run in runs["after"]], [run[model][alg] for run in runs["before"]])

    def pin_ratio(model):
        pairs_ = [(a[model]["crba"], p[model]["crba"]) for a, p in zip(runs["after"], peers) if model in p]
        return median_ratio(*zip(*pairs_)) if pairs_ else None

    def pin_median(model):
        values = [p[model]["crba"] for p in peers if model in p]
        return float(np.median(values)) if values else None

    robots = Table("C++ per call on the peer robots (us)", [
        "robot", "CRBA before", "CRBA after", "CRBA after / before", "Pinocchio CRBA", "CRBA after / Pinocchio",
        "hybrid after / before", "RNEA after / before"], headline=["CRBA after / before", "CRBA after / Pinocchio"])
    robots.formats = {c: ".2f" for c in robots.columns[1:]}
    for name in ROBOTS:
        robots.add(name, med("before", name, "crba"), med("after", name, "crba"), ratio(name, "crba"),
                   pin_median(name), pin_ratio(name), ratio(name, "hybrid"), ratio(name, "rnea"))
    cassini = Table("The cassini scene (15 bodies, two flexible booms with 4 modes each, nv 28)",
                    ["measure", "before (us)", "after (us)", "after / before"],
                    {c: ".2f" for c in ("before (us)", "after (us)", "after / before")}, headline=["after / before"])
    for label, alg in (("RK4 step at 1 ms, driven as in `soadyn hil`", "step"), ("hybrid_dynamics, C++", "hybrid"),
                       ("mass_matrix (composite bodies with augmented flexible bodies), C++", "crba")):
        cassini.add(label, med("before", "cassini", alg), med("after", "cassini", alg), ratio("cassini", alg))
    paired = Table("Paired measurements", ["ratio", "median of the pairs", "first quartile", "third quartile",
                                           "fastest / fastest"], {}, headline=["median of the pairs"])
    paired.formats = {c: ".2f" for c in paired.columns[1:]}
    for label, alg in (("cassini RK4 step, after / before", "step"), ("cassini hybrid_dynamics, after / before", "hybrid")):
        q1, q2, q3 = quartiles(paired_cassini[alg])
        paired.add(label, q2, q1, q3, fastest_cassini[alg])
    for name in ROBOTS:
        q1, q2, q3 = quartiles(paired_pin[name])
        paired.add(f"CRBA / Pinocchio, {name}", q2, q1, q3, fastest_ratio(*paired_times[name]))
    parts = Table("Where cassini's hybrid_dynamics time goes (this build)",
                  ["scene", "nv", "hybrid_dynamics (us)", "share of the whole scene's time"],
                  {"hybrid_dynamics (us)": ".2f", "share of the whole scene's time": ".2f"}, summary=False)
    if runs["after"][0]["cassini_parts"]:
        whole = float(np.median([run["cassini_parts"]["all 15 bodies"]["hybrid"] for run in runs["after"]]))
        for label in CASSINI_PARTS:
            t = float(np.median([run["cassini_parts"][label]["hybrid"] for run in runs["after"]]))
            parts.add(label, runs["after"][0]["cassini_parts"][label]["nv"], t, t / whole)
    tables = [robots, cassini, paired, parts]
    for table in tables:
        table.print()
    settings = {
        "before": {"commit": args.before_rev}, "rounds": rounds, "calls": calls, "repetitions": 7, "states": 64,
        "cassini_steps": steps, "pairs": pairs, "robot_pairs": pairs // 2, "paired_steps": steps // 4,
        "paired_calls": calls // 4, "load_average": [round(load_start, 1), round(os.getloadavg()[0], 1)],
        "kernels": kernel_names(),
    }
    notes = ["Times: medians over rounds; ratios: medians over rounds of the ratio within a round.",
             "Paired: the median of the within-pair ratios of two short measurements made back to back "
             "(alternating which goes first), with its quartiles; fastest / fastest divides the fastest "
             "measurement of one side by the fastest of the other.",
             "Where the time goes: the same C++ call on the scene with parts removed, medians over rounds."]
    write("builds", f"This build against the build of {args.before_rev}, and the CRBA against Pinocchio", tables,
          settings, notes)
    return 0


if __name__ == "__main__" and len(sys.argv) > 1 and sys.argv[1] == "--child":
    child(int(sys.argv[2]), int(sys.argv[3]))
elif __name__ == "__main__" and len(sys.argv) > 1 and sys.argv[1] == "--paired-child":
    paired_child(int(sys.argv[2]), int(sys.argv[3]), sys.argv[4])
elif __name__ == "__main__":
    sys.exit(main())
