"""Where the robots of the PyPI package example-robot-data live on this machine.

The package has no Python module: its files are installed under the cmeel
prefix of site-packages (``cmeel.prefix/share/example-robot-data/robots``).
`soadyn robots` prints them, and the tests and benchmarks load them from here.
"""
from __future__ import annotations

import sys
from importlib import metadata
from pathlib import Path
from typing import Optional

__all__ = ["example_robots_dir", "example_robot_files", "example_robots_version"]


def example_robots_dir() -> Optional[Path]:
    """The robots/ folder of example-robot-data, or None when the package is not installed."""
    for entry in sys.path:
        candidate = Path(entry) / "cmeel.prefix" / "share" / "example-robot-data" / "robots"
        if candidate.is_dir():
            return candidate
    return None


def example_robot_files() -> list[Path]:
    """Every URDF of example-robot-data (sorted by path), or [] when it is not installed."""
    folder = example_robots_dir()
    return sorted(folder.glob("**/*.urdf")) if folder is not None else []


def example_robots_version() -> Optional[str]:
    try:
        return metadata.version("example-robot-data")
    except metadata.PackageNotFoundError:
        return None
