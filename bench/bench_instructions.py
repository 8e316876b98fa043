"""Instructions per call, counted by valgrind's callgrind: soadyn against Pinocchio on the peer
robots, and the cassini RK4 step of this build (and of an earlier one, --before).

The number of instructions executed inside a call does not depend on the host, whose timings
are noisy. It is not a time: it weighs a division like an addition and knows nothing of
caches, of dependency chains or of how many instructions the processor retires per cycle, so a
ratio of counts between two libraries is not a ratio of times (docs/performance.md compares
them). The counts judge a change to one library: compare them with the same library's counts
before the change.

- soadyn: the C++ loop that bench_robots times (timing.time_cpp, one repetition of `calls`
  calls over the peer robots' 64 random states), counted only inside soadyn::forward_dynamics,
  hybrid_dynamics, inverse_dynamics and mass_matrix (and the CRBA's baseline kernel).
- Pinocchio: bench/peer/pin_calls.cpp (peer_bench's models and states), counted only inside
  its never-inlined call_aba, call_rnea and call_crba; built by bench/peer/build.sh.
- cassini: Simulator._run of `steps` RK4 steps at 1 ms as `soadyn hil` runs the scene,
  counted inside Simulator::step, in this build and in the build at --before (a
  `pip install --target` of the commit --before-rev names).

Writes bench/results/instructions.json. Needs valgrind (Debian: apt-get install valgrind).
Usage: python bench/bench_instructions.py [--calls N] [--steps N] [--before DIR --before-rev REV]
"""
from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
from pathlib import Path

# What each of soadyn's timed calls is counted inside, and Pinocchio's call it is compared with.
SOADYN_FUNCTIONS = {
    "aba": "soadyn::Status soadyn::forward_dynamics<double>*",
    "hybrid": "soadyn::Status soadyn::hybrid_dynamics<double>*",
    "rnea": "soadyn::Status soadyn::inverse_dynamics<double>*",
    "crba": "soadyn::Status soadyn::mass_matrix<double>*",
    "crba_baseline": "soadyn::detail::baseline_mass_matrix*",  # crba.cpp's baseline kernel, called directly
}
COMPARISONS = [  # (label, soadyn's call, its prescribed DOFs, Pinocchio's call)
    ("forward dynamics / pin ABA", "aba", "none", "aba"),
    ("hybrid all-regular / pin ABA", "hybrid", "none", "aba"),
    ("hybrid all-prescribed / pin RNEA", "hybrid", "all", "rnea"),
    ("RNEA / pin RNEA", "rnea", "none", "rnea"),
    ("CRBA / pin CRBA", "crba", "none", "crba"),
    ("CRBA's baseline kernel / pin CRBA", "crba_baseline", "none", "crba"),
]
STEP_FUNCTION = "soadyn::SimulatorTpl<double>::step()"


def positive_int(text: str) -> int:
    """argparse type: an integer of at least 1 (counts are divided by it)."""
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def collected(command: list[str], function: str, env: dict | None = None) -> int:
    """Instructions valgrind's callgrind counts inside `function` (a callgrind pattern) while `command` runs."""
    out = subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null",
                          f"--toggle-collect={function}", *command], capture_output=True, text=True, env=env)
    found = re.search(r"Collected : (\d+)", out.stderr)
    if out.returncode != 0 or not found or int(found.group(1)) == 0:
        raise RuntimeError(f"callgrind failed on {command}: {out.stderr[-2000:]}")
    return int(found.group(1))


def soadyn_child(robot_name: str, algorithm: str, prescribed: str, calls: int) -> None:
    """Runs the timed C++ loop once (the process valgrind counts)."""
    import numpy as np
    from fixtures import load_robot, random_states
    from timing import time_cpp

    model = load_robot(robot_name)
    model.set_prescribed(np.full(model.nv, prescribed == "all"))
    time_cpp(model, algorithm, *random_states(model, 1), calls, 1)


def cassini_child(steps: int) -> None:
    from fixtures import cassini_simulator

    cassini_simulator(1000.0)._run(steps)


def main() -> int:
    from builds import add_before_arguments, before_error, build_env, has_build

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=positive_int, default=500, help="calls counted per algorithm and robot")
    parser.add_argument("--steps", type=positive_int, default=200, help="cassini steps counted per build")
    add_before_arguments(parser, required=False, without="; without it the cassini step is counted for this "
                         "build only")
    args = parser.parse_args()
    if shutil.which("valgrind") is None:
        print("valgrind not found (Debian: apt-get install valgrind)", file=sys.stderr)
        return 2
    from fixtures import ROBOTS, robot
    from peers import peer_program
    from report import Table, write
    from timing import joint_angle_kernel, mass_matrix_kernel

    if before_error(args):
        print(before_error(args), file=sys.stderr)
        return 2
    program = peer_program("pin_calls")
    if program is None:
        print("bench/peer/pin_calls could not be built (peer_bench's Pinocchio missing?)", file=sys.stderr)
        return 2
    me = [sys.executable, str(Path(__file__).resolve())]
    env = build_env()
    calls = Table("soadyn / Pinocchio, instructions per call", [
        "robot", "comparison", "soadyn", "Pinocchio", "soadyn / Pinocchio"],
        {"soadyn": ",.0f", "Pinocchio": ",.0f", "soadyn / Pinocchio": ".2f"}, headline=["soadyn / Pinocchio"], key=2)
    for name in ROBOTS:
        path = str(robot(name)[0])
        peer = {alg: collected([str(program), path, alg, str(args.calls)], f"call_{alg}*") / args.calls
                for alg in ("aba", "rnea", "crba")}
        for label, ours, prescribed, theirs in COMPARISONS:
            count = collected([*me, "--child", name, ours, prescribed, str(args.calls)], SOADYN_FUNCTIONS[ours],
                              env) / args.calls
            print(calls.add(name, label, count, peer[theirs], count / peer[theirs]), flush=True)
    builds = [("this build", env)]
    if has_build(args.before):
        builds.append((f"commit {args.before_rev}", build_env(args.before)))
    steps = {label: collected([*me, "--cassini-child", str(args.steps)], STEP_FUNCTION, e) / args.steps
             for label, e in builds}
    step = Table("The cassini RK4 step (15 bodies, nv 28), instructions per step",
                 ["build", "instructions per step", "this build / that build"],
                 {"instructions per step": ",.0f", "this build / that build": ".3f"},
                 headline=["instructions per step", "this build / that build"])
    for label, count in steps.items():
        step.add(label, count, steps["this build"] / count if label != "this build" else None)
    for table in (calls, step):
        table.print()
    settings = {"calls": args.calls, "steps": args.steps, "before": {"commit": args.before_rev} if len(steps) > 1 else None,
                "kernels": {"joint angles": joint_angle_kernel(), "mass matrix": mass_matrix_kernel()}}
    notes = ["Counted only inside the calls: soadyn's C++ timing loop and Pinocchio's never-inlined calls of "
             "bench/peer/pin_calls.cpp, on the same URDFs, roots and kind of random states.",
             "A count is not a time, but it does not depend on the host: compare a change's counts with the same "
             "library's counts before it."]
    write("instructions", "Instructions per call (valgrind callgrind): soadyn against Pinocchio, and the cassini "
          "step", [calls, step], settings, notes)
    return 0


if __name__ == "__main__" and len(sys.argv) > 1 and sys.argv[1] == "--child":
    soadyn_child(sys.argv[2], sys.argv[3], sys.argv[4], int(sys.argv[5]))
elif __name__ == "__main__" and len(sys.argv) > 1 and sys.argv[1] == "--cassini-child":
    cassini_child(int(sys.argv[2]))
elif __name__ == "__main__":
    sys.exit(main())
