"""The robots shipped by the PyPI package example-robot-data, located through
the cmeel prefix it installs into (the package has no Python module)."""
from __future__ import annotations

import sys
from pathlib import Path

ROBOTS = {  # name: (path below robots/, floating base)
    "ur5": ("ur_description/urdf/ur5_robot.urdf", False),
    "panda": ("panda_description/urdf/panda.urdf", False),
    "solo12": ("solo_description/robots/solo12.urdf", True),
    "anymal_c": ("anymal_c_simple_description/urdf/anymal.urdf", True),
    "talos": ("talos_data/robots/talos_reduced.urdf", True),
}


def robots_dir() -> Path:
    for entry in sys.path:
        candidate = Path(entry) / "cmeel.prefix" / "share" / "example-robot-data" / "robots"
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError("example-robot-data is not installed (pip install example-robot-data)")


def robot(name: str) -> tuple[Path, bool]:
    relative, floating = ROBOTS[name]
    return robots_dir() / relative, floating
