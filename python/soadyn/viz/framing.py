"""Where the viewer's camera starts: on the model's bounding box, from a side that shows it best.

- `visual_corners(v, mesh)`: the 8 corners of a visual's box in its shape
  frame (primitives from their sizes, meshes from their vertices);
- `up_direction(m)`: against gravity (z without gravity): up on the screen;
- `framed_camera(points, up, fov)`: a camera position and look-at point
  that show every point in a vertical field of view `fov` (radians). The
  camera looks at the centre of the points' box along its thinnest axis that
  is not up (a planar mechanism is seen face on), raised 25 degrees and
  turned 30 degrees so that depth shows, from the nearest distance at which
  each point's projection is inside the picture (perspective, a 4:3 page).
"""
from __future__ import annotations

import itertools

import numpy as np

__all__ = ["framed_camera", "up_direction", "visual_corners"]

MARGIN = 1.1  # the model takes 1/MARGIN of the view's width or height
ASPECT = 4.0 / 3.0  # a page's canvas is at least this wide for its height
ELEVATION = np.radians(25.0)
AZIMUTH = np.radians(30.0)
CENTRING_PASSES = 2
MINIMUM_RADIUS = 1e-3  # a model of one point is framed as a millimetre ball


def _half_extents(v, mesh) -> tuple[np.ndarray, np.ndarray]:
    """(centre, half extents) of visual v's box in its shape frame."""
    if mesh is not None:
        vertices = np.asarray(mesh.vertices if hasattr(mesh, "vertices") else mesh, dtype=float)
        lo, hi = vertices.min(axis=0), vertices.max(axis=0)
        return (lo + hi) / 2, (hi - lo) / 2
    size = v.size
    if v.shape == "box":
        return np.zeros(3), size / 2
    if v.shape == "sphere":
        return np.zeros(3), np.full(3, size[0])
    if v.shape == "ellipsoid":
        return np.zeros(3), size.copy()
    if v.shape in ("cylinder", "capsule"):
        ends = size[1] / 2 + (size[0] if v.shape == "capsule" else 0.0)
        return np.zeros(3), np.array([size[0], size[0], ends])
    if v.shape == "plane":  # an unbounded plane does not stretch the frame
        return np.zeros(3), np.array([size[0] / 2, size[1] / 2, 0.0]) if np.all(size[:2] > 0) else np.zeros(3)
    return np.zeros(3), np.zeros(3)


def visual_corners(v, mesh=None) -> np.ndarray:
    """(8, 3) corners of visual v's bounding box in its shape frame; `mesh`: its vertices (or a mesh object
    with .vertices) when the visual is a mesh."""
    if v.shape == "mesh" and mesh is None:
        mesh = v.vertices
    centre, half = _half_extents(v, mesh)
    return np.array([centre + np.array(signs) * half for signs in itertools.product((-1.0, 1.0), repeat=3)])


def up_direction(m) -> np.ndarray:
    """The unit vector against m's gravity, or z when there is none."""
    g = np.asarray(m.gravity, dtype=float)
    norm = np.linalg.norm(g)
    return -g / norm if norm > 0 else np.array([0.0, 0.0, 1.0])


def framed_camera(points, up, fov: float, aspect: float = ASPECT) -> tuple[np.ndarray, np.ndarray]:
    """(position, look_at) of a camera that shows every one of `points` (N, 3) in a vertical field of view
    `fov` (radians) on a picture `aspect` times as wide as tall (see the module documentation)."""
    points, up = np.asarray(points, dtype=float).reshape(-1, 3), np.asarray(up, dtype=float)
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre, extent = (lo + hi) / 2, hi - lo
    candidates = [axis for axis in np.eye(3) if abs(axis @ up) < 0.9]
    face = min(candidates, key=lambda axis: abs(axis @ extent))
    face = face - (face @ up) * up
    face /= np.linalg.norm(face)
    side = np.cross(up, face)
    horizontal = np.cos(AZIMUTH) * face + np.sin(AZIMUTH) * side
    direction = np.cos(ELEVATION) * horizontal + np.sin(ELEVATION) * up  # from the centre to the camera
    right = np.cross(up, direction)
    right /= np.linalg.norm(right)
    screen_up = np.cross(direction, right)
    axes = np.array([right, screen_up, direction])
    for _ in range(CENTRING_PASSES):  # centre the picture on the points' projected extent, then refit
        distance, u, v = _fit(points - centre, axes, fov, aspect)
        centre = centre + distance * ((u.max() + u.min()) / 2 * right + (v.max() + v.min()) / 2 * screen_up)
    distance = _fit(points - centre, axes, fov, aspect)[0]
    return centre + distance * direction, centre


def _fit(offsets, axes, fov: float, aspect: float) -> tuple[float, np.ndarray, np.ndarray]:
    """The camera distance at which every offset (from the look-at point) is in the picture, and the
    tangents (u, v) of their view angles from there; axes: the screen's right, up and the view's back."""
    x, y, depth = (offsets @ axes.T).T  # depth: towards the camera
    tan_v = np.tan(fov / 2)
    needed = np.maximum(np.abs(x) / (aspect * tan_v), np.abs(y) / tan_v)
    distance = MARGIN * max(float(np.max(depth + needed)), MINIMUM_RADIUS / tan_v)
    return distance, x / (distance - depth), y / (distance - depth)
