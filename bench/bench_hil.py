"""The real-time loop on the default scene, several runs in a row: `soadyn hil` on cassini at 1 kHz with
RK4, spinning the last 900 us before each deadline (the caches warmed before each), under SCHED_FIFO 80
with memory locked (each granted only with the privilege for it; the report says what was granted).

Per run: the step's wall time (compute), its own CPU time and the spread of it (CPU p99.9 / p50: the
step's work varying by itself), the machine's floors timed interleaved with the steps in their spin
windows (register arithmetic of the first steps' median length, and the dynamics floor: evaluations of the
dynamics at the present state of about the same length), their spreads and the tail ratios (step p99.9 /
floor p99.9), the pre-empted steps and the deadline misses by cause (ours: CPU time over the period; the
machine's). Prints the tables and the last run's timing table.

Writes bench/results/hil_cassini.json (with each run's whole --report) and bench/results/hil_cassini.png
(the last run).
Usage: python bench/bench_hil.py [--duration 10] [--runs 3]
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

from report import RESULTS, Table, write

OPTIONS = ["--scene", "cassini", "--rate", "1000", "--integrator", "rk4", "--no-progress", "--spin-us", "900",
           "--fifo-priority", "80", "--lock-memory"]


def tables_of(reports: list[dict]) -> list[Table]:
    """Per run: wall and CPU time of the step, the floor, the ratios, pre-emptions and misses by cause."""
    times = Table("Cassini at 1 kHz in real time, RK4: each run (us)",
                  ["run", "measure", "p50", "p99", "p99.9", "max"],
                  {c: ".1f" for c in ("p50", "p99", "p99.9", "max")}, key=2, summary=True)
    ratios = Table("Each run: the step's own spread and its tail against the machine's",
                   ["run", "CPU p99.9 / p50", "step p99.9 / floor p99.9", "dynamics floor p99.9 / p50",
                    "step p99.9 / dynamics floor p99.9", "floor periods", "pre-empted steps", "misses",
                    "ours (CPU over the period)", "the machine's"],
                   {c: ".2f" for c in ("CPU p99.9 / p50", "step p99.9 / floor p99.9", "dynamics floor p99.9 / p50",
                                       "step p99.9 / dynamics floor p99.9")},
                   headline=["CPU p99.9 / p50", "step p99.9 / floor p99.9", "dynamics floor p99.9 / p50",
                             "step p99.9 / dynamics floor p99.9"], summary=True)
    for run, report in enumerate(reports, 1):
        for label, key in (("compute (wall)", "compute_us"), ("CPU (the thread's own)", "cpu_us"),
                           ("lateness", "lateness_us"), ("machine floor", "floor_us"), ("dynamics floor", None)):
            values = (report.get(key) if key else (report.get("floor_us") or {}).get("dynamics")) or {}
            times.add(run, label, values.get("p50"), values.get("p99"), values.get("p999"), values.get("max"))
        cpu, floor, misses = report.get("cpu_us") or {}, report.get("floor_us") or {}, report.get("misses") or {}
        dynamics = floor.get("dynamics") or {}
        ratios.add(run, cpu.get("spread"), floor.get("tail_ratio"), dynamics.get("spread"), dynamics.get("tail_ratio"),
                   floor.get("periods"),
                   report.get("preempted_steps"), report.get("deadline_misses"), misses.get("compute"),
                   misses.get("machine"))
    return [times, ratios]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=10.0, help="seconds of real time per run")
    parser.add_argument("--runs", type=int, default=3, help="runs in a row (default 3)")
    args = parser.parse_args()
    RESULTS.mkdir(exist_ok=True)
    reports = []
    with tempfile.TemporaryDirectory() as tmp:
        for run in range(args.runs):
            report_path = Path(tmp) / f"report{run}.json"
            command = ["soadyn", "hil", *OPTIONS, "--duration", f"{args.duration:g}", "--report", str(report_path)]
            if run == args.runs - 1:
                command += ["--plot", str(RESULTS / "hil_cassini.png")]
            out = subprocess.run(command, text=True)
            if out.returncode != 0 or not report_path.is_file():
                return out.returncode or 1
            reports.append(json.loads(report_path.read_text()))
    tables = tables_of(reports)
    for table in tables:
        table.print()
    write("hil_cassini", "Real time: cassini at 1 kHz, RK4, spinning before each deadline, runs in a row", tables,
          {"options": OPTIONS, "duration_s": args.duration, "runs": args.runs,
           "scheduling": reports[-1].get("scheduling")},
          ["The machine floor is register arithmetic of the first steps' median length, timed in the spin window "
           "of the steps' own periods and paced like them: the spread a computation of no data dependence and no "
           "memory traffic shows on this machine in the same phases. The dynamics floor, right after it in the "
           "same periods, is evaluations of the dynamics at the present state of about the same length (after one "
           "untimed, as the step's warm-up): the spread the machine gives memory-touching work whose cost does "
           "not depend on the state. CPU is the loop thread's own CPU time in the step's window."],
          {"reports": reports},
          command_line=f"python bench/bench_hil.py --duration {args.duration:g} --runs {args.runs}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
