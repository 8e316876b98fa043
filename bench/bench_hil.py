"""The real-time loop on the default scene: `soadyn hil` on cassini at 1 kHz for 10 s with RK4,
spinning the last 900 us before each deadline, under SCHED_FIFO 80 with memory locked (each
granted only with the privilege for it; the report says what was granted). Prints the run's
timing table, and writes the percentiles of the step's compute time, of its lateness and of
the machine's floor (register arithmetic of the steps' median length, paced like the steps)
with the whole `--report` of the run.

Writes bench/results/hil_cassini.json and bench/results/hil_cassini.png.
Usage: python bench/bench_hil.py [--duration 10]
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


def tables_of(report: dict) -> list[Table]:
    """The step's compute time, its lateness and the machine's floor (us), and the deadline misses."""
    times = Table("Cassini at 1 kHz in real time, RK4 (us)", ["measure", "p50", "p99", "p99.9", "max"],
                  {c: ".1f" for c in ("p50", "p99", "p99.9", "max")}, summary=True)
    for label, key in (("compute", "compute_us"), ("lateness", "lateness_us"), ("machine floor", "floor_us")):
        values = report.get(key) or {}
        times.add(label, values.get("p50"), values.get("p99"), values.get("p999"), values.get("max"))
    misses = report.get("misses") or {}
    runs = Table("Deadlines", ["steps", "deadline misses", "compute overran the period", "woken or run late"],
                 summary=True)
    runs.add(report.get("steps"), report.get("deadline_misses"), misses.get("compute"), misses.get("machine"))
    return [times, runs]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=10.0, help="seconds of real time")
    args = parser.parse_args()
    RESULTS.mkdir(exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        report_path = Path(tmp) / "report.json"
        command = ["soadyn", "hil", *OPTIONS, "--duration", f"{args.duration:g}", "--report", str(report_path),
                   "--plot", str(RESULTS / "hil_cassini.png")]
        out = subprocess.run(command, text=True)
        if out.returncode != 0 or not report_path.is_file():
            return out.returncode or 1
        report = json.loads(report_path.read_text())
    tables = tables_of(report)
    for table in tables:
        table.print()
    write("hil_cassini", "Real time: cassini at 1 kHz, RK4, spinning before each deadline", tables,
          {"options": OPTIONS, "duration_s": args.duration, "scheduling": report.get("scheduling")},
          ["The machine floor is register arithmetic of the steps' median length, paced like the steps after the "
           "run: the spread a step of no data dependence shows on this machine."],
          {"report": report},
          command_line=f"python bench/bench_hil.py --duration {args.duration:g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
