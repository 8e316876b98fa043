"""Mesh files of visuals, read for the viewer by trimesh (COLLADA through pycollada, STL, OBJ): scaled, and
coloured by the URDF/MJCF material when the file has no colours of its own; a file that cannot be read is
named with the reason (MeshError)."""
from __future__ import annotations

import importlib.util
import os

import numpy as np

from .visuals import Visual

__all__ = ["MeshError", "read_mesh"]


class MeshError(ValueError):
    """A visual's mesh file that cannot be drawn; the message names the visual, the file and why."""


def read_mesh(v: Visual):
    """The trimesh.Trimesh of mesh visual `v` (its mesh_file, COLLADA, STL, OBJ or any format trimesh reads),
    scaled by v.size; a mesh without colours of its own takes the visual's rgba (the URDF material).
    Raises MeshError naming the visual, the file and the reason."""
    import trimesh

    if not isinstance(v, Visual) or v.mesh_file is None:
        raise MeshError(f"read_mesh needs a Visual with a mesh_file, got {getattr(v, 'name', type(v).__name__)!r}")
    where = f"'{v.name}' ({v.mesh_file})"
    if not os.path.isfile(v.mesh_file):
        raise MeshError(f"{where}: no such file")
    if v.mesh_file.lower().endswith(".dae") and importlib.util.find_spec("collada") is None:
        raise MeshError(f"{where}: COLLADA files need pycollada (pip install 'soadyn[view]')")
    try:
        mesh = trimesh.load(v.mesh_file, force="mesh")
    except Exception as error:  # trimesh's own reason, whatever its type
        raise MeshError(f"{where}: {type(error).__name__}: {' '.join(str(error).split()) or 'unreadable'}") from None
    if len(mesh.faces) == 0:
        raise MeshError(f"{where}: no triangles read{_collada_reason(v.mesh_file)}")
    mesh.apply_scale(v.size if v.size.size == 3 else 1.0)
    if mesh.visual.kind is None:
        mesh.visual.face_colors = np.round(255 * np.clip(v.rgba, 0, 1)).astype(np.uint8)
    return mesh


def _collada_reason(path: str) -> str:
    """Why trimesh read no triangles from a COLLADA file: the first error pycollada reports ("" if none).
    A primitive whose material the file references but does not hold is dropped with it."""
    if not path.lower().endswith(".dae"):
        return ""
    import collada

    errors = collada.common
    try:
        document = collada.Collada(path, ignore=[errors.DaeError])
    except Exception as error:
        return f"; pycollada: {' '.join(str(error).split())}"
    return f"; pycollada: {' '.join(str(document.errors[0]).split())}" if document.errors else ""
