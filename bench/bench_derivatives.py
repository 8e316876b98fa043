"""Analytic derivatives: soadyn.dynamics_derivatives against Pinocchio's computeABADerivatives, and
soadyn.inverse_dynamics_derivatives against computeRNEADerivatives, C++, same machine, same run.

soadyn: C++ loops in the extension (_time_cpp, the protocol of ../shared/tools/peer_bench: median of
7 repetitions of N calls cycling through 64 random states), all DOFs regular, and with half of the
DOFs prescribed (hybrid). Pinocchio: bench/peer/pin_derivatives.cpp, the same protocol, built by
bench/peer/build.sh against the Pinocchio of peer_bench (its build.sh runs first if needed), the
same compiler, -O3, no -march=native on either side. The machine's speed drifts, so the timings run
in rounds (Pinocchio, then soadyn, per round) and each ratio is the median over rounds of the ratio
within a round.

Writes bench/results/derivatives.md. Usage: python bench/bench_derivatives.py [--quick]
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

import soadyn
from soadyn._soadyn import _time_cpp

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests"))
from bench_robots import PEER, ROBOTS, parse_peer_output, random_states, write_report  # noqa: E402
from robots import robot  # noqa: E402

PEER_DIR = Path(os.environ.get("PEER_BENCH_DIR", Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache"))
                               / "peer_bench"))


def peer_program(name: str = "pin_derivatives") -> Path | None:
    """A program of bench/peer/ (built by its build.sh, after peer_bench's own build if needed)."""
    program = PEER_DIR / name
    if program.is_file():
        return program
    if not (PEER_DIR / "prefix").is_file():
        subprocess.run(["bash", str(PEER / "build.sh")], check=False)
    subprocess.run(["bash", str(HERE / "peer" / "build.sh")], check=False)
    return program if program.is_file() else None


def pinocchio_timings(program: Path, paths: dict, calls: int) -> dict:
    out = subprocess.run([str(program), *map(str, paths.values())], capture_output=True, text=True,
                         env={**os.environ, "PEER_CALLS": str(calls)})
    return parse_peer_output(out.stdout, paths)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer calls and rounds (smoke test)")
    args = parser.parse_args()
    calls, rounds = (500, 1) if args.quick else (5000, 5)
    program = peer_program()
    if program is None:
        print("Pinocchio's derivative timing program could not be built", file=sys.stderr)
        return 1
    paths = {name: robot(name)[0] for name in ROBOTS}
    models, states = {}, {}
    rng = np.random.default_rng(0)
    for name in ROBOTS:
        m = soadyn.load_urdf(paths[name], floating_base=robot(name)[1])
        models[name], states[name] = m, random_states(m, rng)
    samples = {name: {k: [] for k in ("aba_d", "rnea_d", "fd", "id", "hybrid", "ratio_fd", "ratio_id")}
               for name in ROBOTS}
    for _ in range(rounds):
        peer = pinocchio_timings(program, paths, calls)
        for name in ROBOTS:
            m, (q, v, u) = models[name], states[name]
            m.set_prescribed(np.zeros(m.nv, dtype=bool))
            fd = _time_cpp(m, "dynamics_derivatives", q, v, u, calls)
            id_ = _time_cpp(m, "inverse_dynamics_derivatives", q, v, u, calls)
            m.set_prescribed(np.arange(m.nv) % 2 == 0)
            hybrid = _time_cpp(m, "dynamics_derivatives", q, v, u, calls)
            m.set_prescribed(np.zeros(m.nv, dtype=bool))
            s = samples[name]
            s["aba_d"].append(peer[name]["aba_derivatives"])
            s["rnea_d"].append(peer[name]["rnea_derivatives"])
            s["fd"].append(fd)
            s["id"].append(id_)
            s["hybrid"].append(hybrid)
            s["ratio_fd"].append(fd / peer[name]["aba_derivatives"])
            s["ratio_id"].append(id_ / peer[name]["rnea_derivatives"])
    med = {name: {k: float(np.median(x)) for k, x in s.items()} for name, s in samples.items()}
    lines = ["# Analytic derivatives: soadyn against Pinocchio (C++)", "",
             f"Command: `python bench/bench_derivatives.py{' --quick' if args.quick else ''}` "
             f"({rounds} rounds of {calls} calls per timing; medians over rounds).", "",
             "| robot | nv | soadyn dynamics_derivatives (us) | pin computeABADerivatives (us) | ratio | "
             "soadyn, half the DOFs prescribed (us) | soadyn inverse_dynamics_derivatives (us) | "
             "pin computeRNEADerivatives (us) | ratio |",
             "|---|---|---|---|---|---|---|---|---|"]
    for name in ROBOTS:
        r = med[name]
        lines.append(f"| {name} | {models[name].nv} | {r['fd']:.2f} | {r['aba_d']:.2f} | {r['ratio_fd']:.2f} | "
                     f"{r['hybrid']:.2f} | {r['id']:.2f} | {r['rnea_d']:.2f} | {r['ratio_id']:.2f} |")
    lines += ["", "Ratios are soadyn over Pinocchio (below 1: soadyn faster). dynamics_derivatives returns all six "
              "matrices (dqdd/dq, dqdd/dv, dqdd/du = M^-1, and the prescribed DOFs' force derivatives) and the "
              "hybrid dynamics itself; computeABADerivatives returns dqdd/dq, dqdd/dv and M^-1."]
    write_report("derivatives.md", lines)
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
