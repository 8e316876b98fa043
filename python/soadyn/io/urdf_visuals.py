"""URDF <visual> elements as soadyn.Visual, for the viewer and model files.

Read per link: <origin> (default identity), <geometry> box (size), sphere
(radius), cylinder (radius, length) or mesh (filename, scale), and the colour
of an inline <material><color rgba> or of a robot-level <material> of that
name (grey otherwise). Mesh file names are resolved: ``package://pkg/rest``
against `package_dirs` and then every directory above the URDF that holds a
``pkg`` folder, ``file://`` and relative names against the URDF's folder; an
unresolved name is kept as written (the viewer draws it as axes and says so).

Visuals are not dynamics: a visual that cannot be read (missing geometry,
bad numbers) is left out and named in one UrdfIgnoredWarning per load, never
an error, so a real-world robot whose visual section is sloppy still loads.
"""
from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from ..viz.visuals import Visual
from .urdf_reader import read_root, rpy_matrix

__all__ = ["read_visuals", "resolve_mesh"]

_GREY = (0.7, 0.7, 0.7, 1.0)


class _Bad(ValueError):
    pass


def _numbers(element, name: str, count: int, default=None) -> np.ndarray:
    text = element.get(name) if element is not None else None
    if text is None:
        if default is None:
            raise _Bad(f"<{element.tag}> has no '{name}'")
        return np.array(default, dtype=float)
    try:
        values = [float(t) for t in text.split()]
    except ValueError:
        raise _Bad(f"<{element.tag} {name}='{text}'> is not numbers") from None
    if len(values) != count or not all(math.isfinite(v) for v in values):
        raise _Bad(f"<{element.tag} {name}='{text}'> is not {count} finite numbers")
    return np.array(values)


def resolve_mesh(filename: str, urdf_path: Path, package_dirs=()) -> str:
    """The path of a URDF mesh reference (see the module documentation); unresolved names are kept."""
    if filename.startswith("package://"):
        package, _, rest = filename[len("package://"):].partition("/")
        for directory in [Path(d) for d in package_dirs]:  # the caller's package roots first
            if (directory / package / rest).is_file():
                return str(directory / package / rest)
        for directory in urdf_path.resolve().parents:  # then the folders above the URDF
            if (directory / package / rest).is_file():
                return str(directory / package / rest)
            if directory.name == package and (directory / rest).is_file():
                return str(directory / rest)
        return filename
    if filename.startswith("file://"):
        filename = filename[len("file://"):]
    path = Path(filename) if os.path.isabs(filename) else urdf_path.parent / filename
    return str(path) if path.is_file() else filename


def _colour(visual, materials: dict) -> tuple:
    material = visual.find("material")
    if material is None:
        return _GREY
    colour = material.find("color")
    if colour is not None:
        return tuple(_numbers(colour, "rgba", 4))
    return materials.get(material.get("name"), _GREY)


def _visual(element, link: str, index: int, materials: dict, urdf_path: Path, package_dirs) -> Visual:
    origin = element.find("origin")
    R = rpy_matrix(*_numbers(origin, "rpy", 3, (0.0, 0.0, 0.0)))
    p = _numbers(origin, "xyz", 3, (0.0, 0.0, 0.0))
    geometry = element.find("geometry")
    shapes = list(geometry) if geometry is not None else []
    if len(shapes) != 1:
        raise _Bad("<geometry> must hold one shape")
    shape = shapes[0]
    name = element.get("name") or f"{link}/visual{index}"
    common = dict(name=name, frame=link, rotation=R, translation=p, rgba=_colour(element, materials))
    if shape.tag == "box":
        return Visual(shape="box", size=_numbers(shape, "size", 3), **common)
    if shape.tag == "sphere":
        return Visual(shape="sphere", size=_numbers(shape, "radius", 1), **common)
    if shape.tag == "cylinder":
        return Visual(shape="cylinder", size=np.r_[_numbers(shape, "radius", 1), _numbers(shape, "length", 1)],
                      **common)
    if shape.tag == "mesh":
        filename = shape.get("filename")
        if not filename:
            raise _Bad("<mesh> has no filename")
        return Visual(shape="mesh", size=_numbers(shape, "scale", 3, (1.0, 1.0, 1.0)),
                      mesh_file=resolve_mesh(filename, urdf_path, package_dirs), **common)
    raise _Bad(f"unknown geometry <{shape.tag}>")


def read_visuals(urdf_path, package_dirs=()) -> tuple[list[Visual], list[str]]:
    """(visuals, what was left out) of every link of the URDF at `urdf_path` (already parsed once by the
    loader, so the XML is known to be well formed)."""
    urdf_path = Path(urdf_path)
    root = read_root(urdf_path)
    materials = {}
    for material in root.findall("material"):
        colour = material.find("color")
        try:
            if material.get("name") and colour is not None:
                materials[material.get("name")] = tuple(_numbers(colour, "rgba", 4))
        except _Bad:
            continue
    visuals, ignored, names = [], [], set()
    for link in root.findall("link"):
        for index, element in enumerate(link.findall("visual")):
            try:
                visual = _visual(element, link.get("name"), index, materials, urdf_path, package_dirs)
            except (_Bad, ValueError) as exc:
                ignored.append(f"visual {index} of link '{link.get('name')}' ({exc})")
                continue
            if visual.name in names:  # URDF visual names need not be unique
                visual.name = f"{link.get('name')}/visual{index}"
            names.add(visual.name)
            visuals.append(visual)
    return visuals, ignored
