"""Replaying a trajectory in the viewer: the samples to show, the frames' trails, the time controls.

- `trajectory_arrays(m, trajectory)`: (t, q) of a soadyn.Trajectory, any object
  with t and q, or a .npz file holding them (what `Trajectory.save` writes),
  checked against the model;
- `resample(t, q, fps)`: the sample shown at each frame of a picture sequence
  at `fps` frames per second of simulated time (the latest sample at or before
  the frame's time, never interpolated across a step);
- `trail_points(m, q, names)`: {name: (N, 3) world positions} of bodies or
  frames over the samples, drawn as the paths they swept.
"""
from __future__ import annotations

import os

import numpy as np

from .._soadyn import forward_kinematics, frame_pose
from ..simulator import read_arrays

__all__ = ["resample", "trail_points", "trajectory_arrays"]

TRAIL_COLOURS = ((230, 90, 30), (30, 150, 90), (150, 60, 200), (20, 130, 210), (200, 40, 110))
MAX_FRAMES = 100_000  # a movie or page of more frames is refused by name


def trajectory_arrays(m, trajectory) -> tuple[np.ndarray, np.ndarray]:
    """(t, q) of `trajectory` (see the module documentation); ValueError naming what does not fit."""
    if isinstance(trajectory, (str, os.PathLike)):
        arrays = read_arrays(trajectory, ("t", "q"))
        t, q = arrays["t"], arrays["q"]
    else:
        t, q = np.asarray(trajectory.t, dtype=float), np.asarray(trajectory.q, dtype=float)
    if t.ndim != 1 or len(t) == 0 or q.shape != (len(t), m.nq):
        raise ValueError(f"viewer: a trajectory of {m.nq} coordinates per sample is needed, got t of shape "
                         f"{t.shape} and q of shape {q.shape}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(q))):
        raise ValueError("viewer: the trajectory holds non-finite times or coordinates")
    if np.any(np.diff(t) < 0):
        raise ValueError("viewer: the trajectory's times must not decrease")
    return t, q


def resample(t, q, fps: float) -> tuple[np.ndarray, np.ndarray]:
    """(frame times, q at each frame) at `fps` frames per second from t[0] to t[-1]."""
    if not (np.isfinite(fps) and fps > 0):
        raise ValueError(f"viewer: fps must be a finite number > 0, got {fps}")
    count = int(np.floor((t[-1] - t[0]) * fps + 1e-9)) + 1
    if count > MAX_FRAMES:
        raise ValueError(f"viewer: {count} frames at {fps} fps; at most {MAX_FRAMES} (lower fps)")
    times = t[0] + np.arange(count) / fps
    index = np.clip(np.searchsorted(t, times + 1e-12, side="right") - 1, 0, len(t) - 1)
    return times, q[index]


def trail_points(m, q, names) -> dict[str, np.ndarray]:
    """{name: (N, 3)} world positions of bodies or frames `names` at every row of q."""
    bodies = {name: i for i, name in enumerate(m.body_names)}
    unknown = [n for n in names if n not in bodies and n not in m.frame_names]
    if unknown:
        raise ValueError(f"viewer: no body or frame named {', '.join(map(repr, unknown))} to trail")
    out = {name: np.empty((len(q), 3)) for name in names}
    for k, qk in enumerate(q):
        poses = None
        for name in names:
            if name in bodies:
                if poses is None:
                    poses = forward_kinematics(m, qk)
                    poses = poses[0] if isinstance(poses, tuple) else poses
                out[name][k] = poses[bodies[name]][:3, 3]
            else:
                out[name][k] = frame_pose(m, qk, name)[:3, 3]
    return out
