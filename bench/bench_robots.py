"""Robots: soadyn against Pinocchio (C++ and Python) and DART (Python), same machine, same run.

C++: soadyn's algorithms timed in a C++ loop (timing.time_cpp) with the protocol of
peer_bench (median of 7 repetitions of N calls cycling through 64 random states), on the
same URDFs with the same root joints (ur5 and panda fixed, solo12 and talos free-floating),
both libraries compiled with g++ -O3 and no -march=native; Pinocchio's times come from
peer_bench (bench/peers.py) in the same run. The C++ timings run in rounds, each round timing
Pinocchio (one peer_bench run) and then soadyn on every robot; a ratio is the median over
rounds of the ratio within a round, and the fastest round of each side gives a second
estimate. The mixed masks are timed against all-regular back to back: each mask sample is
divided by the mean of the all-regular samples just before and just after it.

Python: per-call wall time of the Python calls (numpy in, numpy out), the libraries
interleaved repetition by repetition: soadyn.forward_dynamics and soadyn.hybrid_dynamics
against pin.aba, and soadyn.hybrid_dynamics against DART's hybrid dynamics with the same
whole-joint mask (DART: set positions, velocities and commands, computeForwardDynamics, read
accelerations and forces; actuator types set once, outside the timing).

Writes bench/results/robots.json. Usage: python bench/bench_robots.py [--quick]
"""
from __future__ import annotations

import argparse
import sys

import numpy as np

import soadyn
from fixtures import ROBOTS, STATES, dart_oracle, joint_mask, load_robot, pinocchio_robot, random_states, robot
from measure import fastest_ratio, interleaved_per_call_us, median_ratio
from peers import peer_timings
from report import Table, write
from timing import joint_angle_kernel, mass_matrix_kernel, time_cpp

MIXED_FRACTIONS = (0.25, 0.5, 0.75)


def cpp_timings(model, states, calls: int) -> dict[str, float]:
    """soadyn's C++ per-call times (us): ABA, RNEA, CRBA (chosen and baseline kernel), hybrid all-regular and
    all-prescribed."""
    q, v, u = states
    t = {name: time_cpp(model, name, q, v, u, calls) for name in ("aba", "rnea", "crba", "crba_baseline")}
    model.set_prescribed(np.zeros(model.nv, dtype=bool))
    t["hybrid regular"] = time_cpp(model, "hybrid", q, v, u, calls)
    model.set_prescribed(np.ones(model.nv, dtype=bool))
    t["hybrid prescribed"] = time_cpp(model, "hybrid", q, v, u, calls)
    model.set_prescribed(np.zeros(model.nv, dtype=bool))
    return t


def mixed_over_regular(model, states, calls: int, pairs: int) -> list[tuple[float, float]]:
    """(median ratio to all-regular, median time) per random whole-joint mask of MIXED_FRACTIONS (seed 3)."""
    q, v, u = states
    rng = np.random.default_rng(3)
    masks = [joint_mask(model, rng, fraction) for fraction in MIXED_FRACTIONS]

    def timed(mask):
        model.set_prescribed(mask)
        return time_cpp(model, "hybrid", q, v, u, calls, 3)

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


def python_timings(name: str, model, states, calls: int) -> dict[str, float]:
    """Python per-call times (us) of soadyn, pin.aba and DART's hybrid dynamics, and their ratios."""
    import pinocchio as pin

    pmodel = pinocchio_robot(name)
    pdata = pmodel.createData()
    pq = np.array([pin.randomConfiguration(pmodel, -np.ones(pmodel.nq), np.ones(pmodel.nq)) for _ in range(STATES)])
    rng = np.random.default_rng(5)
    pstates = (pq, rng.uniform(-1, 1, (STATES, pmodel.nv)), rng.uniform(-1, 1, (STATES, pmodel.nv)))
    mask = joint_mask(model, 11, 0.5)
    dart = dart_oracle(name, model)
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


def tables() -> tuple[Table, Table, Table, Table]:
    us, ratio = ".2f", ".2f"
    cpp = Table("C++ per call (us)", [
        "robot", "nv", "soadyn ABA", "soadyn hybrid all-regular", "Pinocchio ABA", "hybrid all-regular / pin ABA",
        "soadyn hybrid all-prescribed", "soadyn RNEA", "Pinocchio RNEA", "all-prescribed / pin RNEA",
        "worst mixed mask", "mixed / all-regular", "soadyn CRBA", "Pinocchio CRBA", "CRBA / pin CRBA"],
        headline=["hybrid all-regular / pin ABA", "all-prescribed / pin RNEA", "mixed / all-regular",
                  "CRBA / pin CRBA"])
    cpp.formats = {c: us for c in cpp.columns[2:]}
    fastest = Table("C++ ratios from the fastest round of each side", [
        "robot", "hybrid all-regular / pin ABA", "all-prescribed / pin RNEA", "CRBA / pin CRBA",
        "CRBA baseline kernel / pin CRBA"])
    fastest.formats = {c: ratio for c in fastest.columns[1:]}
    mixed = Table("Mixed masks over all-regular (C++), per share of joints prescribed",
                  ["robot", "25 %", "50 %", "75 %"], {c: ratio for c in ("25 %", "50 %", "75 %")})
    python = Table("Python per call (us, numpy in and out)", [
        "robot", "soadyn.forward_dynamics", "soadyn.hybrid_dynamics (all regular)", "pin.aba",
        "hybrid / pin.aba", "soadyn.hybrid_dynamics (half the joints prescribed)", "DART hybrid (same mask)",
        "DART / soadyn"], headline=["hybrid / pin.aba", "DART / soadyn"])
    python.formats = {c: us for c in python.columns[1:]}
    python.formats["DART / soadyn"] = ".1f"
    return cpp, fastest, mixed, python


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer calls (a smoke run, noisier)")
    args = parser.parse_args()
    cpp_calls, py_calls, rounds = (2000, 300, 2) if args.quick else (20000, 2000, 5)
    paths = {name: robot(name)[0] for name in ROBOTS}
    models = {name: load_robot(name) for name in ROBOTS}
    states = {name: random_states(models[name], 1) for name in ROBOTS}
    peer_rounds, ours_rounds = [], []
    for r in range(rounds):  # Pinocchio and soadyn back to back, so both see the same machine
        peer_rounds.append(peer_timings(paths))
        ours_rounds.append({name: cpp_timings(models[name], states[name], cpp_calls) for name in ROBOTS})
        print(f"round {r + 1}/{rounds} done", flush=True)
    mixed = {name: mixed_over_regular(models[name], states[name], cpp_calls // 10, 4 * rounds) for name in ROBOTS}
    cpp, fastest, mixed_table, python = tables()
    for name in ROBOTS:
        model = models[name]
        c = {k: float(np.median([o[name][k] for o in ours_rounds])) for k in ours_rounds[0][name]}
        have_peer = all(name in p for p in peer_rounds)
        p = {k: float(np.median([pr[name][k] for pr in peer_rounds])) for k in peer_rounds[0][name]} if have_peer else {}

        def ratio(ours, theirs):
            return (float(np.median([o[name][ours] / pr[name][theirs] for o, pr in zip(ours_rounds, peer_rounds)]))
                    if have_peer else None)

        def fastest_of(ours, theirs):
            return (fastest_ratio([o[name][ours] for o in ours_rounds], [pr[name][theirs] for pr in peer_rounds])
                    if have_peer else None)

        worst_ratio, worst_time = max(mixed[name])
        cpp.add(name, model.nv, c["aba"], c["hybrid regular"], p.get("aba"), ratio("hybrid regular", "aba"),
                c["hybrid prescribed"], c["rnea"], p.get("rnea"), ratio("hybrid prescribed", "rnea"), worst_time,
                worst_ratio, c["crba"], p.get("crba"), ratio("crba", "crba"))
        fastest.add(name, fastest_of("hybrid regular", "aba"), fastest_of("hybrid prescribed", "rnea"),
                    fastest_of("crba", "crba"), fastest_of("crba_baseline", "crba"))
        mixed_table.add(name, *(r for r, _ in mixed[name]))
        t = python_timings(name, model, states[name], py_calls)
        python.add(name, t["forward_dynamics"], t["hybrid regular"], t["pin.aba"], t["hybrid / pin.aba"],
                   t["hybrid mixed"], t["dart hybrid mixed"], t["dart / hybrid"])
        print(f"{name} done", flush=True)
    all_tables = [cpp, fastest, mixed_table, python]
    for table in all_tables:
        table.print()
    settings = {
        "rounds": rounds, "cpp_calls": cpp_calls, "repetitions": 7, "states": STATES, "python_calls": py_calls,
        "python_repetitions": 7, "mixed_mask_pairs": 4 * rounds, "mixed_mask_calls": cpp_calls // 10,
        "mixed_mask_repetitions": 3, "peer": "Pinocchio C++ (peer_bench), g++ -O3, no -march=native",
        "kernels": {"joint angles": joint_angle_kernel(), "mass matrix": mass_matrix_kernel()},
    }
    notes = ["C++ times: medians over rounds; ratios: medians over rounds of the ratio within a round.",
             "CRBA baseline kernel: the x86-64 SSE2 kernel a processor without AVX2 and FMA runs.",
             "Mixed masks: random whole-joint masks (seed 3), each timed between two all-regular timings; "
             "the C++ table shows the worst mask."]
    write("robots", "Robots: soadyn against Pinocchio and DART", all_tables, settings, notes)
    return 0


if __name__ == "__main__":
    sys.exit(main())
