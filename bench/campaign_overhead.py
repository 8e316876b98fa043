"""Campaign overhead and scaling: the same runs of the built-in cassini example as a plain loop in
this process (soadyn.campaign.run_one, rows kept in a list) and as soadyn.campaign.run on a local
Dask cluster of 1 and of 2 workers (results written to Parquet, as the command line does).

For each worker count two times are kept: the run phase (from the first task submitted to the last
part written: campaign.run's `run_seconds`) and the whole call (spec check, cluster start and
stop, results.parquet). Overhead = time / plain loop - 1 with 1 worker; speedup = plain loop /
time with N workers. The three are timed in turns, `--rounds` times, and the medians reported
(the machine's speed drifts; nothing is compared across rounds). Writes
bench/results/campaign_overhead.json with the command that produced it.

    python bench/campaign_overhead.py [--runs 1000] [--duration 1.0] [--workers 1 2] [--rounds 3]
"""
from __future__ import annotations

import argparse
import json
import platform
import shlex
import statistics
import sys
import tempfile
import time
from datetime import datetime, timezone
from pathlib import Path

HERE = Path(__file__).resolve().parent


def example_spec(runs: int, duration: float):
    from soadyn.campaign import load_spec
    from soadyn.campaign.spec import EXAMPLES, parse_toml

    path = EXAMPLES["cassini-example"]
    raw = parse_toml(path.read_text(), str(path))
    raw["runs"] = runs
    raw["simulation"]["duration"] = duration
    return load_spec(raw)


def plain_loop(spec) -> float:
    from soadyn.campaign import run_one

    start = time.perf_counter()
    rows = [run_one(spec, i).row for i in range(spec.runs)]
    seconds = time.perf_counter() - start
    assert len(rows) == spec.runs
    return seconds


def campaign(spec, workers: int, chunk: int | None) -> tuple[float, float, int]:
    from soadyn.campaign import run

    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        result = run(spec, out=Path(tmp) / "out", workers=workers, chunk_size=chunk, progress=False,
                     verbose=False, dashboard=False)
        total = time.perf_counter() - start
    assert result.table.num_rows == spec.runs
    return result.run_seconds, total, result.failed


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=1000)
    parser.add_argument("--duration", type=float, default=1.0, help="simulated seconds per run (default 1)")
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--chunk", type=int, default=None, help="runs per task (default: campaign.run's choice)")
    parser.add_argument("--json", default=str(HERE / "results" / "campaign_overhead.json"))
    args = parser.parse_args(argv)

    import dask
    import distributed

    import soadyn

    spec = example_spec(args.runs, args.duration)
    plain_loop(example_spec(min(20, args.runs), args.duration))  # warm: imports, the model read once
    samples = {"loop": [], **{f"{n}w_run": [] for n in args.workers}, **{f"{n}w_total": [] for n in args.workers}}
    failed = None
    for k in range(args.rounds):
        samples["loop"].append(plain_loop(spec))
        for n in args.workers:
            run_seconds, total, failed = campaign(spec, n, args.chunk)
            samples[f"{n}w_run"].append(run_seconds)
            samples[f"{n}w_total"].append(total)
        print(f"round {k + 1}/{args.rounds}: " + ", ".join(f"{key} {v[-1]:.2f} s" for key, v in samples.items()),
              flush=True)

    median = {key: statistics.median(v) for key, v in samples.items()}
    loop = median["loop"]
    print(f"\n{args.runs} runs of cassini-example, {args.duration:g} s simulated each (RK4, 1 ms), "
          f"{failed} failed; medians of {args.rounds} rounds")
    print(f"{'':<22}{'seconds':>10}{'runs/s':>10}{'vs loop':>10}")
    print(f"{'plain loop':<22}{loop:>10.2f}{args.runs / loop:>10.1f}{1.0:>10.3f}")
    summary = {}
    for n in args.workers:
        for phase, label in (("run", "run phase"), ("total", "whole call")):
            t = median[f"{n}w_{phase}"]
            print(f"{f'{n} worker(s), {label}':<22}{t:>10.2f}{args.runs / t:>10.1f}{t / loop:>10.3f}")
        summary[f"{n}_workers"] = {
            "run_seconds": median[f"{n}w_run"], "total_seconds": median[f"{n}w_total"],
            "runs_per_second": args.runs / median[f"{n}w_run"],
            "overhead_run_phase": median[f"{n}w_run"] / loop - 1 if n == 1 else None,
            "overhead_total": median[f"{n}w_total"] / loop - 1 if n == 1 else None,
            "speedup_run_phase": loop / median[f"{n}w_run"], "speedup_total": loop / median[f"{n}w_total"]}
    if 1 in args.workers:
        one = summary["1_workers"]
        print(f"\noverhead with 1 worker: {100 * one['overhead_run_phase']:.1f} % (run phase), "
              f"{100 * one['overhead_total']:.1f} % (whole call, cluster start included)")
    for n in args.workers:
        if n > 1:
            s = summary[f"{n}_workers"]
            print(f"speedup with {n} workers: {s['speedup_run_phase']:.2f}x (run phase), "
                  f"{s['speedup_total']:.2f}x (whole call)")

    command = "python bench/campaign_overhead.py " + " ".join(shlex.quote(a) for a in (argv or sys.argv[1:]))
    report = {"command": command.strip(), "date": datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
              "runs": args.runs, "duration_s": args.duration, "rounds": args.rounds, "chunk": args.chunk,
              "failed_runs": failed, "plain_loop_seconds": loop, "plain_loop_runs_per_second": args.runs / loop,
              "workers": summary, "samples": samples,
              "software": {"soadyn": soadyn.__version__, "dask": dask.__version__,
                           "distributed": distributed.__version__, "python": platform.python_version()},
              "machine": {"cores": _cores(), "platform": platform.platform()}}
    path = Path(args.json)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(report, indent=2) + "\n")
    print(f"wrote {path}")
    return 0


def _cores() -> int:
    import os

    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


if __name__ == "__main__":
    sys.exit(main())
