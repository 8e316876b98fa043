"""Runs one of the C++ benchmark programs (built in build/bench by run_core.sh or run_all.sh),
prints its output, and writes its tables as data to bench/results/NAME.json.

Usage: python bench/run_cpp_bench.py NAME PROGRAM [ARGUMENTS ...]
  NAME: core, skips, step_spread or events (bench_core, bench_skips, bench_step_spread,
  bench_events); the program's exit status is passed on, and nothing is written when it
  fails (bench_core and bench_skips fail when two ways of solving a problem disagree).
"""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from report import repo_path, tables_from_markdown, write

BENCHMARKS = {  # name: (title, table titles, key columns per table)
    "core": ("Core benchmark: the hybrid algorithm against ABA, RNEA and CRBA",
             ["C++ per call (us) on a 7-DOF arm, chains, a random tree and a chain of flexible beams"], [1]),
    "skips": ("What each skip of the sweeps saves",
              ["C++ per call (us) with and without each skip, on the same problem"], [2]),
    "step_spread": ("Step-time spread at 1 kHz: how much of a real-time step's tail is the machine's",
                    ["Paced workloads at 1 kHz, per-period time (us)",
                     "Interruptions per second of a thread that only reads the clock"], [1, 1]),
    "events": ("What scheduled events cost a cassini RK4 step",
               ["Cassini RK4 step at 1 ms (us)"], [1]),
}


def main() -> int:
    if len(sys.argv) < 3 or sys.argv[1] not in BENCHMARKS:
        print(__doc__, file=sys.stderr)
        return 2
    name, program, arguments = sys.argv[1], sys.argv[2], sys.argv[3:]
    out = subprocess.run([program, *arguments], capture_output=True, text=True)
    print(out.stdout, end="")
    print(out.stderr, end="", file=sys.stderr)
    if out.returncode != 0:
        return out.returncode
    title, titles, keys = BENCHMARKS[name]
    tables, notes = tables_from_markdown(out.stdout, titles, keys)
    for table in tables:
        table.summary = True
    command = " ".join([str(repo_path(program)), *arguments])
    write(name, title, tables, {"program": Path(program).name, "arguments": arguments,
                                "build": "Release (-O3 -DNDEBUG), no -march=native"}, notes, command_line=command)
    return 0


if __name__ == "__main__":
    sys.exit(main())
