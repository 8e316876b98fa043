"""The viewer's scene graph at a state, headless (no server, no browser).

- `scene_poses(m, q)`: the world pose (4x4) of every node the viewer draws,
  keyed by its viser path: ``/bodies/<body>`` (the body frame),
  ``/frames/<frame>``, ``/visuals/<visual>`` (the shape's frame: its frame's
  pose times its own placement), and the two ends of every loop
  (``/loops/<loop>/a``, ``/b``). Bodies come from `forward_kinematics`,
  frames from `frame_pose`: what is drawn is what the dynamics use.
  Attachment frames of flexible bodies are not among the frames: a flexible
  body is drawn by its body frame and its deformed shape (below).
- `flexible_shapes(m, q, exaggeration)`: the world positions of every
  flexible body's nodes, deformed by its modal coordinates times
  `exaggeration` (1: true size; real appendages deflect millimetres, so
  tens to thousands make a mode visible). The viewer draws each as a
  polyline through its nodes in node order (a beam's nodes are its stations)
  with a point per node; a slider sets the exaggeration.
"""
from __future__ import annotations

import json

import numpy as np

from .._soadyn import forward_kinematics, frame_pose, neutral_configuration
from ..model import Model

__all__ = ["drawn_frames", "flexible_blocks", "flexible_shapes", "loop_anchors", "scene_poses"]


def _transform(R, p) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


def loop_anchors(m: Model) -> list[tuple[str, str, np.ndarray, str, np.ndarray]]:
    """(loop, frame_a, placement_a, frame_b, placement_b) of every loop, from the model-file view."""
    data = json.loads(m._to_json()) if m.nloops else {"loops": []}
    return [(x["name"], x["frame_a"], _transform(x["placement_a"]["rotation"], x["placement_a"]["translation"]),
             x["frame_b"], _transform(x["placement_b"]["rotation"], x["placement_b"]["translation"]))
            for x in data["loops"]]


class _Poser:
    """World poses of named bodies and frames at one state (forward kinematics once)."""

    def __init__(self, m: Model, q):
        self.m, self.q = m, np.asarray(q, dtype=float)
        self.bodies = forward_kinematics(m, self.q)
        self.bodies = self.bodies[0] if isinstance(self.bodies, tuple) else self.bodies
        self.index = {name: i for i, name in enumerate(m.body_names)}

    def __call__(self, name: str) -> np.ndarray:
        if name in ("world", "", None):
            return np.eye(4)
        if name in self.index:
            return self.bodies[self.index[name]]
        return frame_pose(self.m, self.q, name)


def drawn_frames(m: Model) -> list[str]:
    """The frames the viewer draws: every frame that is not a body, except attachment frames of flexible
    bodies (their nodes move with the modal coordinates, which frame_pose does not follow).

    Returns the frame names, in the model's order.
    """
    q0, bodies = neutral_configuration(m), set(m.body_names)
    drawn = []
    for name in m.frame_names:
        if name in bodies:
            continue
        try:
            frame_pose(m, q0, name)
        except ValueError:  # carried by a flexible body
            continue
        drawn.append(name)
    return drawn


def scene_poses(m: Model, q, loops=None, frames=None, visuals=None) -> dict[str, np.ndarray]:
    """World pose (4x4) of every node the viewer draws at configuration q, keyed by viser path
    (`visuals`: the visuals drawn, m.visuals by default)."""
    pose = _Poser(m, q)
    out = {f"/bodies/{name}": pose.bodies[i] for i, name in enumerate(m.body_names)}
    for name in drawn_frames(m) if frames is None else frames:
        out[f"/frames/{name}"] = pose(name)
    for v in m.visuals if visuals is None else visuals:
        out[f"/visuals/{v.name}"] = pose(v.frame) @ _transform(v.rotation, v.translation)
    for name, frame_a, Xa, frame_b, Xb in (loop_anchors(m) if loops is None else loops):
        out[f"/loops/{name}/a"] = pose(frame_a) @ Xa
        out[f"/loops/{name}/b"] = pose(frame_b) @ Xb
    return out


def flexible_blocks(m: Model) -> list[tuple[str, int, object, slice]]:
    """(name, body index, FlexibleBody, slice of its modal coordinates in q) of every flexible body."""
    out = []
    for b, name in enumerate(m.body_names):
        if m.n_modes[b] == 0:
            continue
        end = m.q_index[b + 1] if b + 1 < m.nbodies else m.nq
        out.append((name, b, m.flexible_body(name), slice(end - m.n_modes[b], end)))
    return out


def flexible_shapes(m: Model, q, exaggeration: float = 1.0, blocks=None) -> dict[str, np.ndarray]:
    """{body: (N, 3) world positions of its nodes} for every flexible body at q, the modal coordinates
    scaled by `exaggeration` (the body frame itself stays where q puts it)."""
    if not (np.isfinite(exaggeration) and exaggeration >= 0):
        raise ValueError(f"viewer: the exaggeration must be a finite number >= 0, got {exaggeration}")
    q = np.asarray(q, dtype=float)
    poses = None
    out = {}
    for name, b, body, modal in flexible_blocks(m) if blocks is None else blocks:
        if poses is None:
            poses = _Poser(m, q).bodies
        eta = exaggeration * q[modal]
        local = np.array([body.node_pose(j, eta)[:3, 3] for j in range(body.n_nodes)])
        out[name] = local @ poses[b][:3, :3].T + poses[b][:3, 3]
    return out
