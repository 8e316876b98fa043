"""A movie of a campaign's worst run: the run with the largest value of a metric, recomputed in full
from the stored spec (as `replay` does) and rendered by the viewer in a headless Chromium.

Metrics are errors, peaks and drifts, so the largest value is the worst; failed runs have no
value and are not candidates (their error is in the table). The run is simulated again at its
own step and every step kept, then shown at the movie's frame rate; a built-in scene is drawn
with its visuals.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .. import scenes
from .errors import CampaignError
from .simulate import draw, prepare

__all__ = ["MovieError", "worst_run", "worst_run_movie"]


class MovieError(CampaignError):
    """The worst-run movie cannot be made for this metric (named in the message)."""


def worst_run(spec, table, metric: str) -> tuple[int, float]:
    """(run id, value) of the finished run with the largest finite `metric`; MovieError naming the metric
    when the spec has no such metric or no run has a value."""
    if metric not in spec.metrics:
        raise MovieError(f"no metric {metric!r} in this campaign (its metrics: "
                            f"{', '.join(spec.metrics)})")
    values = np.array([np.nan if x is None else x for x in table[metric].to_pylist()], dtype=float)
    ok = np.array([s == "ok" for s in table["status"].to_pylist()]) & np.isfinite(values)
    if not ok.any():
        raise MovieError(f"no finished run has a value of {metric!r}")
    row = int(np.argmax(np.where(ok, values, -np.inf)))
    return int(table["run_id"][row].as_py()), float(values[row])


def worst_run_movie(spec, table, metric: str, target: Path, fps: float = 30.0, width: int = 960,
                    height: int = 540) -> tuple[Path, int, float]:
    """Write target/worst_<metric>_run<id>.mp4 of the run worst_run picks: (path, run id, value)."""
    from ..viz.viewer import Viewer

    run_id, value = worst_run(spec, table, metric)
    sim = prepare(spec, draw(spec, run_id))
    trajectory = sim.run(spec.duration)
    model = sim._model
    if spec.scene in scenes.SCENES:
        model.visuals = scenes.SCENES[spec.scene]().visuals
    path = Path(target) / f"worst_{metric}_run{run_id}.mp4"
    viewer = Viewer(model, host="127.0.0.1", port=0, q=trajectory.q[0], frames=False, environment=False)
    try:
        viewer.save_movie(path, trajectory, fps, width, height)
    finally:
        viewer.close()
    return path, run_id, value
