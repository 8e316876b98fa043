"""Pinocchio's C++ timings on this machine, the peer of the C++ comparisons.

peer_bench (../shared/tools/peer_bench beside the repository, or the folder
PEER_BENCH_TOOL names) builds Pinocchio's PyPI release into a C++ program that
times ABA, RNEA and CRBA: median of 7 repetitions of 20000 calls cycling
through 64 random states, free-flyer root unless the path names ur5 or panda,
g++ -O3 without -march=native. bench/peer/ adds programs built against the
same Pinocchio (bench/peer/build.sh): pin_derivatives (the analytic
derivatives, same protocol) and pin_calls (never-inlined calls for
instruction counts). Builds go to PEER_BENCH_DIR (default: peer_bench in the
user's cache folder) and are made on first use.
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
PEER_BENCH = Path(os.environ.get("PEER_BENCH_TOOL", HERE.parent.parent / "shared" / "tools" / "peer_bench"))
PEER_DIR = Path(os.environ.get("PEER_BENCH_DIR", Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache"))
                               / "peer_bench"))


def peer_timings(paths: dict[str, Path]) -> dict[str, dict[str, float]]:
    """Pinocchio's C++ ABA/RNEA/CRBA per robot ({robot: {"aba": us, ...}}) from one peer_bench run, built on
    first use; {} without peer_bench."""
    run, build = PEER_BENCH / "run.sh", PEER_BENCH / "build.sh"
    if not run.is_file():
        print(f"peer_bench not found (set PEER_BENCH_TOOL): {PEER_BENCH.name}", file=sys.stderr)
        return {}
    out = subprocess.run(["bash", str(run), *map(str, paths.values())], capture_output=True, text=True)
    if out.returncode == 2 and build.is_file():  # not built yet
        subprocess.run(["bash", str(build)], check=False)
        out = subprocess.run(["bash", str(run), *map(str, paths.values())], capture_output=True, text=True)
    return parse_peer_output(out.stdout, paths)


def parse_peer_output(stdout: str, paths: dict[str, Path]) -> dict[str, dict[str, float]]:
    """{robot: {timing name: microseconds}} from the `file key=..us ...` lines of a peer program."""
    result = {}
    for line in stdout.splitlines():
        fields = line.split()
        name = next((r for r, p in paths.items() if p.name == fields[0]), None) if fields else None
        if name:
            result[name] = {k: float(v.rstrip("us")) for k, v in (f.split("=") for f in fields[1:]) if k != "nv"}
    return result


def peer_program(name: str) -> Path | None:
    """A program of bench/peer/ (pin_derivatives, pin_calls), built on first use after peer_bench's own build."""
    program = PEER_DIR / name
    if program.is_file():
        return program
    if not (PEER_DIR / "prefix").is_file() and (PEER_BENCH / "build.sh").is_file():
        subprocess.run(["bash", str(PEER_BENCH / "build.sh")], check=False)
    if (PEER_DIR / "prefix").is_file():
        subprocess.run(["bash", str(HERE / "peer" / "build.sh")], check=False)
    return program if program.is_file() else None
