"""What `soadyn view` can show, by name: the built-in scenes, model files (.json), MJCF (.xml), URDF (.urdf)
and the example robots by the names `soadyn robots` lists; and the state each is first shown in."""
from __future__ import annotations

import os

import numpy as np

from .. import scenes
from .._soadyn import neutral_configuration
from ..io.example_robots import example_robot
from ..io.mjcf import load_mjcf
from ..io.model_file import load_model
from ..io.urdf import load_urdf
from ..loops import assemble
from ..model import Model

__all__ = ["BUILT_IN_SCENES", "load_any", "start_state"]


def _scene_builders() -> dict:
    return {"cassini": scenes.cassini, "four-bar": scenes.four_bar, "slider-crank": scenes.slider_crank,
            "delta-robot": scenes.delta_robot, "stanford-arm": scenes.stanford_arm}


BUILT_IN_SCENES = tuple(_scene_builders())
"""The scene names `soadyn view` and Viewer sources take."""


def load_any(source: str) -> Model:
    """A model from a built-in scene name, a model file (.json), an MJCF (.xml), a URDF (.urdf), or the name of
    an example-robot-data URDF (`soadyn robots` lists them: ur5_robot, talos_reduced, ...).

    Raises ValueError naming the source when it is none of these (with the closest example robots), and the
    reader's error (ModelFileError, MjcfError, UrdfError) naming the file and the item for a file it cannot
    read.
    """
    builders = _scene_builders()
    if source in builders:
        return builders[source]()
    extension = os.path.splitext(source)[1].lower()
    if extension == ".json":
        return load_model(source)
    if extension == ".xml":
        return load_mjcf(source)
    if extension == ".urdf":
        return load_urdf(source)
    if extension == "" and os.sep not in source:
        try:
            return load_urdf(example_robot(source))
        except ValueError as error:
            raise ValueError(f"'{source}': not a built-in scene ({', '.join(builders)}) nor a .json, .xml or .urdf "
                             f"file; {error}") from None
    raise ValueError(f"'{source}': not a built-in scene ({', '.join(builders)}) nor a .json, .xml or .urdf file")


def start_state(source: str, m: Model) -> tuple[np.ndarray, np.ndarray]:
    """The state `soadyn view` shows first: the loop scenes closed, every other model at rest in q0.

    Returns fresh (q (nq,), v (nv,)) arrays; DynamicsError names a loop that cannot be closed from q0.
    """
    closed = {"four-bar": lambda: scenes.four_bar_state(0.5), "slider-crank": lambda: scenes.slider_crank_state(0.5),
              "delta-robot": lambda: scenes.delta_robot_state([0.0, 0.0, -0.6])}
    if source in closed:
        q, v = closed[source]()
        return np.asarray(q, dtype=float), np.asarray(v, dtype=float)
    q = neutral_configuration(m)
    if m.nloops:  # any other loop model: closed from q0 by Gauss-Newton
        q = assemble(m, q)
    return q, np.zeros(m.nv)
