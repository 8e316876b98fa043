"""Instructions per call, counted by valgrind's callgrind: soadyn against Pinocchio on the
bench_robots robots, and the cassini RK4 step against the round's starting build.

A shared host's timings swing by up to 2x within seconds (bench/results/history.md); the
number of instructions executed inside a call does not depend on the host at all. It is not a
time: it weighs a division like an addition and knows nothing of caches, of dependency chains
or of how many instructions the processor retires per cycle. Both libraries here are scalar
double-precision code built by g++ -O3 without -march=native, yet their ratios of counts and
of times differ by algorithm: on 2026-11-28 the counts gave CRBA ratios of 0.67-0.76 where the
quietest timings gave 0.65-0.75, but hybrid / pin ABA 0.58-0.62 where the timings gave
0.31-0.33 (soadyn's sweeps retire more instructions per cycle). So the counts are the
deterministic companion of bench_robots.py and bench_round2.py for judging a change to one
library, and not a measure of speed against the other.

- soadyn: the C++ loop that bench_robots times (soadyn._soadyn._time_cpp, one repetition of
  `calls` calls over bench_robots' 64 random states), counted only inside
  soadyn::forward_dynamics, hybrid_dynamics, inverse_dynamics and mass_matrix.
- Pinocchio: bench/peer/pin_calls.cpp (peer_bench's models and states), counted only inside
  its never-inlined call_aba, call_rnea and call_crba; built by bench/peer/build.sh.
- cassini: Simulator._run of `steps` RK4 steps at 1 ms as `soadyn hil` runs the scene
  (soadyn.hil.scene_simulator), counted inside Simulator::step, in this build and in the build
  at --before (a `pip install --target` of the commit the round started from).

Writes bench/results/instructions.md. Needs valgrind (Debian: apt-get install valgrind).
Usage: python bench/bench_instructions.py [--calls N] [--before DIR --before-rev REV]
"""
from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))

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
    import soadyn
    from soadyn._soadyn import _time_cpp
    from bench_robots import random_states
    from robots import robot

    path, floating = robot(robot_name)
    model = soadyn.load_urdf(path, floating_base=floating)
    model.set_prescribed(np.full(model.nv, prescribed == "all"))
    q, v, u = random_states(model, np.random.default_rng(1))
    _time_cpp(model, algorithm, q, v, u, calls, 1)


def cassini_child(steps: int) -> None:
    from soadyn.hil import scene_simulator
    scene_simulator("cassini", 1000.0)._run(steps)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=positive_int, default=500, help="calls counted per algorithm and robot")
    parser.add_argument("--steps", type=positive_int, default=200, help="cassini steps counted per build")
    parser.add_argument("--before", type=Path, default=None,
                        help="a directory holding the earlier build's soadyn package (pip install --target); "
                             "without it the cassini step is counted for this build only")
    parser.add_argument("--before-rev", default="26f4505", help="the commit that build was made from")
    args = parser.parse_args()
    if shutil.which("valgrind") is None:
        print("valgrind not found (Debian: apt-get install valgrind)", file=sys.stderr)
        return 2
    from bench_derivatives import peer_program
    from soadyn._soadyn import _joint_angle_kernel, _mass_matrix_kernel
    from bench_robots import ROBOTS, source_revision, write_report
    from build_comparison import has_build
    from robots import robot

    program = peer_program("pin_calls")
    if program is None:
        print("bench/peer/pin_calls could not be built (peer_bench's Pinocchio missing?)", file=sys.stderr)
        return 2
    me = [sys.executable, str(Path(__file__).resolve())]
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    rows = []
    for name in ROBOTS:
        path = str(robot(name)[0])
        peer = {alg: collected([str(program), path, alg, str(args.calls)], f"call_{alg}*") / args.calls
                for alg in ("aba", "rnea", "crba")}
        cells = []
        for label, ours, prescribed, theirs in COMPARISONS:
            count = collected([*me, "--child", name, ours, prescribed, str(args.calls)], SOADYN_FUNCTIONS[ours],
                              env) / args.calls
            cells.append(f"{count:,.0f} / {peer[theirs]:,.0f} = **{count / peer[theirs]:.2f}**")
        rows.append(f"| {name} | " + " | ".join(cells) + " |")
        print(rows[-1], flush=True)
    step_rows = []
    builds = [("this build", env)]
    if has_build(args.before):
        builds.append((f"commit {args.before_rev}", {**env, "PYTHONPATH": str(args.before)}))
    steps = {label: collected([*me, "--cassini-child", str(args.steps)], STEP_FUNCTION, e) / args.steps
             for label, e in builds}
    for label, count in steps.items():
        step_rows.append(f"| {label} | {count:,.0f} |")
    if len(steps) == 2:
        after, before = steps.values()
        step_rows.append(f"| **this build / commit {args.before_rev}** (goal <= 0.6 in time) | **{after / before:.3f}** |")
    source = source_revision()
    lines = [
        "# Instructions per call (valgrind callgrind): soadyn against Pinocchio, and the cassini step", "",
        f"- Date: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; source: {source}; command: "
        f"`python bench/bench_instructions.py` ({args.calls} calls per algorithm and robot, {args.steps} cassini steps)",
        "- Counted only inside the calls: soadyn's C++ loop of bench_robots (`_time_cpp`) and Pinocchio's "
        "never-inlined calls of bench/peer/pin_calls.cpp, on the same URDFs, roots and kind of random states. "
        "A count is not a time, but it does not depend on the host: compare a change's counts with the same "
        "library's counts before it. Ratios of counts between the libraries are not ratios of times (see the "
        "script's docstring: hybrid / pin ABA counts about 0.6 where timings give about 0.3).",
        f"- soadyn's kernels on this processor (chosen at run time): joint angles `{_joint_angle_kernel()}`, mass "
        f"matrix `{_mass_matrix_kernel()}`; the CRBA's `baseline` kernel (x86-64 SSE2) is counted too.", "",
        "## soadyn / Pinocchio, instructions per call", "",
        "| robot | " + " | ".join(label for label, *_ in COMPARISONS) + " |",
        "|---|" + "---:|" * len(COMPARISONS),
        *rows, "",
        "## The cassini RK4 step (15 bodies, nv 28), instructions per step", "",
        "| build | instructions per step |",
        "|---|---:|",
        *step_rows,
    ]
    write_report("instructions.md", lines, timings=False)
    return 0


if __name__ == "__main__" and len(sys.argv) > 1 and sys.argv[1] == "--child":
    soadyn_child(sys.argv[2], sys.argv[3], sys.argv[4], int(sys.argv[5]))
elif __name__ == "__main__" and len(sys.argv) > 1 and sys.argv[1] == "--cassini-child":
    cassini_child(int(sys.argv[2]))
elif __name__ == "__main__":
    sys.exit(main())
