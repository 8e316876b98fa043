"""What a model looks like: shapes attached to its bodies and frames, for viewers.

A description (URDF <visual>, MJCF <geom>) can say how each body is drawn;
loaders keep it on the model as ``model.visuals``, a list of `Visual`.
Visuals never enter the dynamics: they are description data that model files
carry and viewers draw.

Shape conventions (all lengths in metres, in the frame of ``placement``):
- ``"box"``: ``size`` = full extents (x, y, z);
- ``"sphere"``: ``size`` = (radius,);
- ``"cylinder"``: ``size`` = (radius, length), axis z, centred;
- ``"capsule"``: ``size`` = (radius, length of the cylindrical part), axis z, centred;
- ``"ellipsoid"``: ``size`` = radii (x, y, z);
- ``"plane"``: ``size`` = full extents (x, y), normal z (0 means unbounded);
- ``"mesh"``: either ``vertices`` (n, 3) and ``faces`` (m, 3) given directly,
  or ``mesh_file`` (a path) with ``size`` = the scale (sx, sy, sz).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

__all__ = ["Visual", "SHAPES", "revolved_mesh", "rotation_z_to"]

SHAPES = ("box", "sphere", "cylinder", "capsule", "ellipsoid", "plane", "mesh")
"""The shapes a Visual may have."""


@dataclass
class Visual:
    """One drawn shape, rigidly attached to body or frame ``frame`` ("world" for the world)."""

    name: str
    frame: str
    shape: str
    size: np.ndarray = field(default_factory=lambda: np.zeros(0))
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))  # shape frame in `frame`
    translation: np.ndarray = field(default_factory=lambda: np.zeros(3))
    rgba: np.ndarray = field(default_factory=lambda: np.array([0.7, 0.7, 0.7, 1.0]))
    mesh_file: Optional[str] = None
    vertices: Optional[np.ndarray] = None
    faces: Optional[np.ndarray] = None

    def __post_init__(self) -> None:
        if self.shape not in SHAPES:
            raise ValueError(f"visual '{self.name}': unknown shape '{self.shape}' (known: {', '.join(SHAPES)})")
        self.size = np.asarray(self.size, dtype=float).reshape(-1)
        self.rotation = np.asarray(self.rotation, dtype=float).reshape(3, 3)
        self.translation = np.asarray(self.translation, dtype=float).reshape(3)
        self.rgba = np.asarray(self.rgba, dtype=float).reshape(4)
        if self.vertices is not None:
            self.vertices = np.asarray(self.vertices, dtype=float).reshape(-1, 3)
        if self.faces is not None:
            self.faces = np.asarray(self.faces, dtype=np.int64).reshape(-1, 3)
        arrays = [self.size, self.rotation, self.translation, self.rgba]
        if self.vertices is not None:
            arrays.append(self.vertices)
        if not all(np.all(np.isfinite(a)) for a in arrays):
            raise ValueError(f"visual '{self.name}': non-finite size, placement, colour or vertices")
        if self.shape == "mesh" and self.mesh_file is None and (self.vertices is None or self.faces is None):
            raise ValueError(f"visual '{self.name}': a mesh needs mesh_file or vertices and faces")


def revolved_mesh(radii, heights, segments: int = 32) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, faces) of the surface swept by the profile (radii[k], heights[k]) about the z axis: a dish,
    a cone or a nozzle as an inline mesh Visual, without a mesh library (scenes build without the view extra).
    The profile is an open polyline; a radius of 0 closes the surface on the axis."""
    radii, heights = np.asarray(radii, dtype=float), np.asarray(heights, dtype=float)
    if radii.ndim != 1 or radii.shape != heights.shape or len(radii) < 2 or segments < 3 or np.any(radii < 0):
        raise ValueError("revolved_mesh: a profile of at least two (radius >= 0, height) points and 3 segments")
    angle = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    rings = np.stack([np.outer(radii, np.cos(angle)), np.outer(radii, np.sin(angle)),
                      np.repeat(heights[:, None], segments, axis=1)], axis=-1).reshape(-1, 3)
    k, j = np.meshgrid(np.arange(len(radii) - 1), np.arange(segments), indexing="ij")
    a, b = k * segments + j, k * segments + (j + 1) % segments
    c, d = a + segments, b + segments
    faces = np.concatenate([np.stack([a, b, d], -1).reshape(-1, 3), np.stack([a, d, c], -1).reshape(-1, 3)])
    return rings, faces


def rotation_z_to(direction) -> np.ndarray:
    """A rotation taking the z axis onto `direction` (placing a cylinder, whose axis is z, along it)."""
    d = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    helper = np.array([1.0, 0.0, 0.0]) if abs(d[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, d)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(d, x), d])
