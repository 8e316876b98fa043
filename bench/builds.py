"""This build against an earlier one, in the same run.

The earlier build is a soadyn package installed with
`pip install --no-deps --target DIR` from an earlier commit and given on the
command line (--before DIR); its commit is given with --before-rev. A
measurement runs a child process of the calling script with either build
first on the path (PYTHONPATH=DIR for the earlier one); the builds alternate
round by round (before then after, then after then before), so a drift of
the shared machine's speed hits both alike. The child prints one JSON object
on its last line of output.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path


def build_env(before: Path | None = None) -> dict:
    """The environment of a child: this build (before None) or the one installed in `before`."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    return env if before is None else {**env, "PYTHONPATH": str(before)}


def run_child(script: Path, child_args: list[str], before: Path | None = None) -> dict:
    """The JSON object the child `python script *child_args` prints last, with this build or `before`'s."""
    out = subprocess.run([sys.executable, str(Path(script).resolve()), *child_args], env=build_env(before),
                         capture_output=True, text=True, check=True, cwd="/")
    return json.loads(out.stdout.strip().splitlines()[-1])


def alternate_builds(script: Path, child_args: list[str], before: Path, rounds: int, label: str = "") -> dict:
    """{"before": [child output per round], "after": [...]}, the builds' order alternating round by round."""
    builds = (("before", before), ("after", None))
    runs = {"before": [], "after": []}
    for r in range(rounds):
        for name, directory in builds if r % 2 == 0 else builds[::-1]:
            runs[name].append(run_child(script, child_args, directory))
        print(f"{label or 'builds'}: round {r + 1}/{rounds} done", flush=True)
    return runs


def has_build(directory: Path | None) -> bool:
    """Whether `directory` (None: no earlier build given) holds an installed soadyn package."""
    return directory is not None and (Path(directory) / "soadyn" / "__init__.py").is_file()


def missing_build_message(directory: Path, rev: str) -> str:
    return (f"no soadyn package under {directory}: install the build of {rev} there first "
            f"(pip install --no-deps --no-build-isolation --target DIR <checkout of {rev}>)")
