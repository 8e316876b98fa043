"""Timing this build against an earlier one in the same run.

The earlier build is a soadyn package installed with `pip install --target DIR` from an
earlier commit. Each measurement runs a child process of the calling script with either
build first on PYTHONPATH; the builds alternate round by round (before/after, then
after/before), so a drift of the shared machine's speed hits both alike. The child prints
one JSON object on its last line of output.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path


def alternate_builds(script: Path, child_args: list[str], before: Path, rounds: int, label: str = "") -> dict:
    """{"before": [child output per round], "after": [...]} from `python script *child_args`."""
    env_after = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env_before = {**env_after, "PYTHONPATH": str(before)}
    builds = (("before", env_before), ("after", env_after))
    runs = {"before": [], "after": []}
    for r in range(rounds):
        for name, env in builds if r % 2 == 0 else builds[::-1]:
            out = subprocess.run([sys.executable, str(Path(script).resolve()), *child_args], env=env,
                                 capture_output=True, text=True, check=True, cwd="/")
            runs[name].append(json.loads(out.stdout.strip().splitlines()[-1]))
        print(f"{label or 'builds'}: round {r + 1}/{rounds} done", flush=True)
    return runs


def has_build(directory: Path | None) -> bool:
    """Whether `directory` (None: no earlier build given) holds an installed soadyn package."""
    return directory is not None and (Path(directory) / "soadyn" / "__init__.py").is_file()
