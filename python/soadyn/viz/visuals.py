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

__all__ = ["Visual", "SHAPES"]

SHAPES = ("box", "sphere", "cylinder", "capsule", "ellipsoid", "plane", "mesh")


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
