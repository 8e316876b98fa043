"""Campaign overhead and scaling: the same runs of the built-in cassini example as a plain loop in
this process (soadyn.campaign.run_one, rows kept in a list) and as soadyn.campaign.run on a local
Dask cluster of 1 and of 2 workers (results written to Parquet, as the command line does).

For each worker count two times are kept: the run phase (from the first task submitted to the last
part written: campaign.run's `run_seconds`) and the whole call (spec check, cluster start and
stop, results.parquet). Overhead = time / plain loop - 1 with 1 worker; speedup = plain loop /
time with N workers. The three are timed in turns, `--rounds` times, and the medians reported
(the machine's speed drifts; nothing is compared across rounds). Writes
bench/results/campaign_overhead.json.

    python bench/campaign_overhead.py [--runs 1000] [--duration 1.0] [--workers 1 2] [--rounds 3]
"""
from __future__ import annotations

import argparse
import platform
import statistics
import sys
import tempfile
import time
from pathlib import Path

from report import Table, command, write


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
    table = Table(f"{args.runs} runs of cassini-example, {args.duration:g} s simulated each (RK4, 1 ms); medians of "
                  f"{args.rounds} rounds", ["setting", "seconds", "runs per second", "time / plain loop"],
                  {"seconds": ".2f", "runs per second": ".1f", "time / plain loop": ".3f"},
                  headline=["time / plain loop"])
    table.add("plain loop", loop, args.runs / loop, 1.0)
    for n in args.workers:
        for phase, label in (("run", "run phase"), ("total", "whole call")):
            t = median[f"{n}w_{phase}"]
            table.add(f"{n} worker{'s' if n > 1 else ''}, {label}", t, args.runs / t, t / loop)
    table.print()
    print(f"\nfailed runs: {failed}")
    settings = {"runs": args.runs, "duration_s": args.duration, "rounds": args.rounds, "chunk": args.chunk,
                "workers": args.workers, "cores_available": _cores()}
    notes = ["Run phase: from the first task submitted to the last part written (campaign.run's run_seconds); "
             "whole call: spec check, cluster start and stop, results.parquet included.",
             "Overhead = time / plain loop - 1 with 1 worker; speedup = plain loop / time with N workers."]
    extra = {"failed_runs": failed, "samples_seconds": samples,
             "software": {"soadyn": soadyn.__version__, "dask": dask.__version__,
                          "distributed": distributed.__version__, "python": platform.python_version()}}
    write("campaign_overhead", "Campaign overhead and scaling on local Dask workers", [table], settings, notes, extra,
          command_line=command([sys.argv[0], *(argv if argv is not None else sys.argv[1:])]))
    return 0


def _cores() -> int:
    import os

    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


if __name__ == "__main__":
    sys.exit(main())
