"""Links and joints drawn for bodies that have no visuals of their own.

A model built in code (the pendulum chain, the loop scenes, a Stanford arm)
or a URDF without <visual> still has a shape: its kinematic tree. Every body
without a visual gets
- a rod (cylinder) from its origin to each point the body carries: the
  origins of its children's joints, the anchors of the loops cut on it, and,
  for a body that carries nothing, twice its centre of mass (the far end of
  a uniform rod);
- a marker of its own joint at its origin: a short cylinder along a revolute
  axis, a box along a prismatic axis, a ball for a spherical, universal or
  planar joint (none for a fixed or free joint).
The world carries the ground: rods from the first world-fixed joint or loop
anchor to the others (the four-bar's ground link). Flexible bodies are left
out: the viewer draws their deformed nodes.

Rod radius: 5% of the median rod length, so a 0.1 m four-bar and a 1 m
pendulum chain look alike. Everything is read from the model-file view of
the model (`Model._to_json`), the same data the dynamics use.
"""
from __future__ import annotations

import json

import numpy as np

from .visuals import Visual, rotation_z_to

__all__ = ["link_radius", "link_visuals"]

ROD_COLOUR = (0.55, 0.60, 0.68, 1.0)
JOINT_COLOUR = (0.95, 0.55, 0.15, 1.0)
GROUND_COLOUR = (0.30, 0.30, 0.30, 1.0)
RADIUS_PER_LENGTH = 0.05
EPSILON = 1e-9


def _carried_points(data: dict) -> dict[str, list[np.ndarray]]:
    """{body or "world": points it carries, in its frame}: children's joint origins and loop anchors."""
    points: dict[str, list[np.ndarray]] = {"world": []}
    for body in data["bodies"]:
        points.setdefault(body["name"], [])
        points.setdefault(body["parent"], []).append(np.asarray(body["placement"]["translation"], dtype=float))
    frames = {f["name"]: f for f in data["frames"]}
    for loop in data["loops"]:
        for side in ("a", "b"):
            name, offset = loop[f"frame_{side}"], np.asarray(loop[f"placement_{side}"]["translation"], dtype=float)
            if name in frames:  # a named frame: its placement on its body, then the loop's offset in it
                frame = frames[name]
                R, p = np.asarray(frame["placement"]["rotation"]), np.asarray(frame["placement"]["translation"])
                name, offset = frame["body"], p + R @ offset
            points.setdefault(name or "world", []).append(offset)
    return points


def link_radius(m) -> float:
    """The rod radius of model m's link figures: 5% of the median rod length (0.01 m without rods)."""
    data = json.loads(m._to_json())
    lengths = [np.linalg.norm(p) for points in _carried_points(data).values() for p in points]
    lengths = [x for x in lengths if x > EPSILON]
    return RADIUS_PER_LENGTH * float(np.median(lengths)) if lengths else 0.01


def _rod(name: str, frame: str, start, end, radius: float, rgba) -> Visual | None:
    start, end = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    length = float(np.linalg.norm(end - start))
    if length <= EPSILON:
        return None
    return Visual(name, frame, "cylinder", size=[radius, length], rotation=rotation_z_to(end - start),
                  translation=(start + end) / 2, rgba=rgba)


def _joint_marker(body: dict, radius: float) -> Visual | None:
    joint, name = body["joint"], f"{body['name']}/joint"
    kind = joint["type"]
    if kind in ("revolute", "continuous"):
        return Visual(name, body["name"], "cylinder", size=[1.6 * radius, 3.0 * radius],
                      rotation=rotation_z_to(joint["axis"]), rgba=JOINT_COLOUR)
    if kind == "prismatic":
        return Visual(name, body["name"], "box", size=[2.4 * radius, 2.4 * radius, 6.0 * radius],
                      rotation=rotation_z_to(joint["axis"]), rgba=JOINT_COLOUR)
    if kind in ("fixed", "free", "weld"):
        return None
    return Visual(name, body["name"], "sphere", size=[1.8 * radius], rgba=JOINT_COLOUR)


def link_visuals(m, radius: float | None = None) -> list[Visual]:
    """Rods and joint markers (soadyn.Visual, named "<body>/rod<k>", "<body>/joint", "world/ground<k>") for
    every rigid body of m without a visual on it or on its frames; `radius` defaults to link_radius(m)."""
    data = json.loads(m._to_json())
    radius = link_radius(m) if radius is None else float(radius)
    frame_body = {f["name"]: f["body"] for f in data["frames"]}
    dressed = {frame_body.get(v.frame, v.frame) for v in m.visuals}
    carried = _carried_points(data)
    out: list[Visual] = []
    for body in data["bodies"]:
        name = body["name"]
        if name in dressed or "flexible" in body:
            continue
        points = [p for p in carried[name] if np.linalg.norm(p) > EPSILON]
        com = np.asarray(body.get("com", np.zeros(3)), dtype=float)
        if not points and np.linalg.norm(com) > EPSILON:
            points = [2.0 * com]
        out += [rod for k, p in enumerate(points)
                if (rod := _rod(f"{name}/rod{k}", name, np.zeros(3), p, radius, ROD_COLOUR)) is not None]
        marker = _joint_marker(body, radius)
        if marker is not None:
            out.append(marker)
    if "world" not in dressed:
        ground = carried["world"]
        out += [rod for k, p in enumerate(ground[1:])
                if (rod := _rod(f"world/ground{k}", "world", ground[0], p, 0.8 * radius, GROUND_COLOUR)) is not None]
    return out
