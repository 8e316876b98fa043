"""Long fuzz campaign: each case in its own process, counting crashes, hangs,
silent non-finite results and unexpected exceptions per surface.

    python bench/fuzz_campaign.py [--surface api urdf packet] [--cases 100000] [--timeout 10]

The parent imports soadyn once and forks one child per case (a fork costs
about a millisecond, far less than starting Python), so a crash or a hang
of one case is seen and counted without ending the campaign. A case is a
seed: the same seed rebuilds the same case (tests/fuzz/*_cases.py), so any
failure printed here is reproduced with `run_case(seed)`. Results go to
bench/results/fuzz_campaign.json.
"""
from __future__ import annotations

import argparse
import collections
import importlib
import os
import signal
import sys
import time
from pathlib import Path

from report import Table, write

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))

# Child exit codes.
OK, EXPECTED_ERROR, NON_FINITE, UNEXPECTED = 0, 1, 3, 4
SURFACES = {"api": "fuzz.api_cases", "urdf": "fuzz.urdf_cases", "packet": "fuzz.packet_cases",
            "loops": "fuzz.loop_cases", "analysis": "fuzz.analysis_cases", "batch": "fuzz.batch_cases",
            "model_file": "fuzz.model_file_cases", "mjcf": "fuzz.mjcf_cases", "spec": "fuzz.spec_cases"}


def child(run_case, seed: int) -> None:
    """Runs one case in the forked child and leaves through os._exit."""
    code = UNEXPECTED
    try:
        code = OK if run_case(seed) == "ok" else EXPECTED_ERROR
    except AssertionError as e:
        print(f"seed {seed}: {type(e).__name__}: {e}", file=sys.stderr)
        code = NON_FINITE
    except BaseException as e:  # noqa: BLE001 - counting is the point
        print(f"seed {seed}: unexpected {type(e).__name__}: {e}", file=sys.stderr)
    finally:
        sys.stderr.flush()
        os._exit(code)


def run_one(run_case, seed: int, timeout: float) -> str:
    pid = os.fork()
    if pid == 0:
        child(run_case, seed)
    deadline = time.monotonic() + timeout
    while True:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            break
        if time.monotonic() > deadline:
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            return "hang"
        time.sleep(0.0005)
    if os.WIFSIGNALED(status):
        return f"crash ({signal.Signals(os.WTERMSIG(status)).name})"
    return {OK: "ok", EXPECTED_ERROR: "expected error", NON_FINITE: "silent non-finite or broken property",
            UNEXPECTED: "unexpected exception"}.get(os.WEXITSTATUS(status), f"exit {os.WEXITSTATUS(status)}")


def campaign(surface: str, cases: int, timeout: float, first_seed: int) -> tuple[collections.Counter, list, float]:
    run_case = importlib.import_module(SURFACES[surface]).run_case
    counts: collections.Counter = collections.Counter()
    failures = []
    start = time.monotonic()
    from tqdm import tqdm
    for seed in tqdm(range(first_seed, first_seed + cases), desc=surface, unit="case", mininterval=2.0):
        outcome = run_one(run_case, seed, timeout)
        counts[outcome] += 1
        if outcome not in ("ok", "expected error"):
            failures.append((seed, outcome))
    return counts, failures, time.monotonic() - start


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--surface", nargs="+", choices=sorted(SURFACES), default=sorted(SURFACES))
    parser.add_argument("--cases", type=int, default=100_000)
    parser.add_argument("--timeout", type=float, default=10.0, help="seconds before a case counts as a hang")
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--results", default="fuzz_campaign",
                        help="the results file, bench/results/RESULTS.json (campaigns run side by side need one each)")
    args = parser.parse_args()
    table = Table(f"Cases from seed {args.first_seed}, each in its own forked process (hang timeout "
                  f"{args.timeout:g} s)", ["surface", "cases", "ok", "expected errors", "crashes", "hangs",
                                          "silent non-finite / broken", "unexpected exceptions", "seconds"],
                  {"seconds": ".0f"}, summary=True)
    failed = {}
    bad = 0
    for surface in args.surface:
        counts, failures, seconds = campaign(surface, args.cases, args.timeout, args.first_seed)
        crashes = sum(n for k, n in counts.items() if k.startswith("crash"))
        bad += len(failures)
        table.add(surface, args.cases, counts["ok"], counts["expected error"], crashes, counts["hang"],
                  counts["silent non-finite or broken property"], counts["unexpected exception"], seconds)
        failed[surface] = [{"seed": seed, "outcome": outcome} for seed, outcome in failures[:20]]
    table.print()
    write(args.results, "Fuzz campaign", [table],
          {"cases": args.cases, "first_seed": args.first_seed, "timeout_s": args.timeout, "surfaces": args.surface},
          ["Each failure's seed rebuilds its case: run_case(seed) of tests/fuzz/<surface>_cases.py."],
          {"failures": failed})
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
