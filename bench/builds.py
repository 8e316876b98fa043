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

import argparse
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


def add_before_arguments(parser: argparse.ArgumentParser, required: bool, without: str = "") -> None:
    """--before DIR and --before-rev REV (both required when `required`; `without`: what a run without does)."""
    parser.add_argument("--before", type=Path, required=required, default=None,
                        help="a directory holding an earlier build's soadyn package (pip install --target)" + without)
    parser.add_argument("--before-rev", required=required, help="the commit that build was made from")


def before_error(args: argparse.Namespace) -> str | None:
    """Why the parsed --before and --before-rev cannot be used (None: they can, or were not given)."""
    if args.before is None:
        return "--before-rev needs --before" if args.before_rev else None
    if not args.before_rev:
        return "--before needs --before-rev"
    if not has_build(args.before):
        return (f"no soadyn package under {args.before}: install the build of {args.before_rev} there first "
                f"(pip install --no-deps --no-build-isolation --target DIR <sources of {args.before_rev}>)")
    return None
