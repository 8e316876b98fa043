"""How a campaign run starts: the start state and the drives of a built-in scene (as
`soadyn hil` flies it, soadyn.hil.scene_simulator), or rest at the neutral configuration
for a model file."""
from __future__ import annotations

import numpy as np

from .. import scenes
from .._soadyn import neutral_configuration

SCENE_NAMES = tuple(sorted(scenes.SCENES))


def start_state(scene: str | None, model) -> tuple[np.ndarray, np.ndarray]:
    """(q, v) a run starts from: pendulum-chain at 0.3 rad per joint, the loop scenes assembled at
    rest, cassini and model files at rest in the neutral configuration."""
    if scene == "pendulum-chain":
        return np.full(model.nq, 0.3), np.zeros(model.nv)
    if scene in scenes.LOOP_SCENE_STARTS:
        q, v = scenes.LOOP_SCENE_STARTS[scene][1]()
        return np.array(q, dtype=float), np.array(v, dtype=float)
    return np.array(neutral_configuration(model), dtype=float), np.zeros(model.nv)


def drive(sim, scene: str | None) -> None:
    """The scene's own motion sources: cassini's turntable at 3 rpm and its engine gimbal under
    velocity commands (scenes.drive_cassini); no other scene has any."""
    if scene == "cassini":
        scenes.drive_cassini(sim)
