"""The robots shipped by the PyPI package example-robot-data, located through
the cmeel prefix it installs into (the package has no Python module)."""
from __future__ import annotations

import functools
from pathlib import Path

from soadyn.io.example_robots import example_robots_dir

ROBOTS = {  # name: (path below robots/, floating base)
    "ur5": ("ur_description/urdf/ur5_robot.urdf", False),
    "panda": ("panda_description/urdf/panda.urdf", False),
    "solo12": ("solo_description/robots/solo12.urdf", True),
    "anymal_c": ("anymal_c_simple_description/urdf/anymal.urdf", True),
    "talos": ("talos_data/robots/talos_reduced.urdf", True),
}


def robots_dir() -> Path:
    folder = example_robots_dir()
    if folder is None:
        raise FileNotFoundError("example-robot-data is not installed (pip install example-robot-data)")
    return folder


def robot(name: str) -> tuple[Path, bool]:
    relative, floating = ROBOTS[name]
    return robots_dir() / relative, floating


@functools.lru_cache(maxsize=None)
def robot_with_oracle(name: str, floating: bool):
    """(soadyn model, PinocchioOracle) of an example-robot-data robot, built once per session."""
    import soadyn
    from soadyn.oracles import PinocchioOracle

    path, _ = robot(name)
    m = soadyn.load_urdf(path, floating_base=floating)
    return m, PinocchioOracle(m, path, floating)


def matrix_from_pin(oracle, A_pin):
    """A Pinocchio (nv, nv) matrix with rows and columns in soadyn's DOF order."""
    import numpy as np

    out = np.empty_like(A_pin)
    out[np.ix_(oracle.v_of_pin, oracle.v_of_pin)] = A_pin
    return out
