"""Analytic derivatives: soadyn.dynamics_derivatives against Pinocchio's computeABADerivatives, and
soadyn.inverse_dynamics_derivatives against computeRNEADerivatives, C++, same machine, same run.

soadyn: C++ loops (timing.time_cpp, peer_bench's protocol: median of 7 repetitions of N calls
cycling through 64 random states), all DOFs regular, and with every other DOF prescribed
(hybrid), and the hybrid call over the all-regular one (the papers' promise: prescribed hinges
cost no more than regular ones). Pinocchio: bench/peer/pin_derivatives.cpp, the same protocol, built by
bench/peer/build.sh against peer_bench's Pinocchio (bench/peers.py), the same compiler, -O3,
no -march=native on either side. The timings run in rounds (Pinocchio, then soadyn, per
round) and each ratio is the median over rounds of the ratio within a round.

Writes bench/results/derivatives.json. Usage: python bench/bench_derivatives.py [--quick]
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from fixtures import ROBOTS, load_robot, random_states, robot
from peers import parse_peer_output, peer_program
from report import Table, write
from timing import time_cpp


def pinocchio_timings(program: Path, paths: dict, calls: int) -> dict:
    out = subprocess.run([str(program), *map(str, paths.values())], capture_output=True, text=True,
                         env={**os.environ, "PEER_CALLS": str(calls)})
    return parse_peer_output(out.stdout, paths)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer calls and rounds (smoke test)")
    args = parser.parse_args()
    calls, rounds = (500, 1) if args.quick else (5000, 5)
    program = peer_program("pin_derivatives")
    if program is None:
        print("Pinocchio's derivative timing program could not be built", file=sys.stderr)
        return 1
    paths = {name: robot(name)[0] for name in ROBOTS}
    models, states = {}, {}
    rng = np.random.default_rng(0)  # one stream, drawn robot after robot
    for name in ROBOTS:
        models[name] = load_robot(name)
        states[name] = random_states(models[name], rng)
    samples = {name: {k: [] for k in ("aba_d", "rnea_d", "fd", "id", "hybrid", "ratio_fd", "ratio_id",
                                      "ratio_hybrid")}
               for name in ROBOTS}
    for _ in range(rounds):
        peer = pinocchio_timings(program, paths, calls)
        for name in ROBOTS:
            m, (q, v, u) = models[name], states[name]
            m.set_prescribed(np.zeros(m.nv, dtype=bool))
            fd = time_cpp(m, "dynamics_derivatives", q, v, u, calls)
            id_ = time_cpp(m, "inverse_dynamics_derivatives", q, v, u, calls)
            m.set_prescribed(np.arange(m.nv) % 2 == 0)
            hybrid = time_cpp(m, "dynamics_derivatives", q, v, u, calls)
            m.set_prescribed(np.zeros(m.nv, dtype=bool))
            s = samples[name]
            s["aba_d"].append(peer[name]["aba_derivatives"])
            s["rnea_d"].append(peer[name]["rnea_derivatives"])
            s["fd"].append(fd)
            s["id"].append(id_)
            s["hybrid"].append(hybrid)
            s["ratio_fd"].append(fd / peer[name]["aba_derivatives"])
            s["ratio_id"].append(id_ / peer[name]["rnea_derivatives"])
            s["ratio_hybrid"].append(hybrid / fd)
    med = {name: {k: float(np.median(x)) for k, x in s.items()} for name, s in samples.items()}
    table = Table("C++ per call (us)", [
        "robot", "nv", "soadyn dynamics_derivatives", "pin computeABADerivatives", "dynamics_derivatives / pin",
        "soadyn, half the DOFs prescribed", "half prescribed / all regular", "soadyn inverse_dynamics_derivatives",
        "pin computeRNEADerivatives", "inverse_dynamics_derivatives / pin"],
        headline=["dynamics_derivatives / pin", "half prescribed / all regular", "inverse_dynamics_derivatives / pin"])
    table.formats = {c: ".2f" for c in table.columns[2:]}
    for name in ROBOTS:
        r = med[name]
        table.add(name, models[name].nv, r["fd"], r["aba_d"], r["ratio_fd"], r["hybrid"], r["ratio_hybrid"], r["id"],
                  r["rnea_d"], r["ratio_id"])
    table.print()
    notes = ["Times: medians over rounds; ratios: soadyn over Pinocchio (below 1: soadyn faster), medians over "
             "rounds of the ratio within a round; half prescribed / all regular likewise, soadyn against itself.",
             "dynamics_derivatives returns all six matrices (dqdd/dq, dqdd/dv, dqdd/du = M^-1, and the prescribed "
             "DOFs' force derivatives) and the hybrid dynamics itself; computeABADerivatives returns dqdd/dq, "
             "dqdd/dv and M^-1."]
    write("derivatives", "Analytic derivatives: soadyn against Pinocchio (C++)", [table],
          {"rounds": rounds, "calls": calls, "repetitions": 7, "states": 64,
           "peer": "Pinocchio C++ (bench/peer/pin_derivatives.cpp), g++ -O3, no -march=native"}, notes)
    return 0


if __name__ == "__main__":
    sys.exit(main())
