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

__all__ = ["example_robot", "example_robots_dir", "example_robot_files", "example_robots_version"]


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
    """The installed example-robot-data package's version, or None when it is not installed."""
    try:
        return metadata.version("example-robot-data")
    except metadata.PackageNotFoundError:
        return None


def example_robot(name: str) -> Path:
    """The example-robot-data URDF named `name` (its file name without .urdf, as `soadyn robots` lists it).
    ValueError when no file or several files have that name, naming the candidates."""
    files = example_robot_files()
    if not files:
        raise ValueError(f"no example robot {name!r}: example-robot-data is not installed "
                         f"(pip install example-robot-data)")
    exact = [f for f in files if f.stem == name]
    if len(exact) == 1:
        return exact[0]
    if exact:
        raise ValueError(f"example robot {name!r} names {len(exact)} files; give the path of one: "
                         + ", ".join(map(str, exact)))
    close = sorted({f.stem for f in files if f.stem.startswith(name) or name in f.stem})
    hint = f"; did you mean {', '.join(close[:8])}?" if close else "; `soadyn robots` lists them"
    raise ValueError(f"no example robot {name!r}{hint}")
