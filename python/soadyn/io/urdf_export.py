"""URDF export of a model's rigid part, for tools that read URDF (Pinocchio, DART, ROS, viewers).

`save_urdf(m, path, robot_name="soadyn_model")` writes what URDF can hold,
read from the model's own model-file view (model_file.py), so every number is
the model's:
- a body on a revolute joint becomes a link on a `continuous` joint (soadyn's
  revolute joints have no position limits), prismatic a `prismatic` joint
  (position and velocity limits written as +-1e9, which URDF requires and
  nothing enforces), fixed a `fixed` joint; the joint's origin is the
  body's placement in its parent
  (rpy from the rotation), its axis the joint's axis; the DOF's effort limit
  (Model.effort_limits) is the <limit effort>, "0" (URDF's "no limit known")
  for a prismatic joint without one;
- mass, centre of mass and inertia about the COM become <inertial>;
- a free-floating root (a free joint on the world, identity placement)
  becomes the URDF's root link, to be loaded with a floating base (`load_urdf(path,
  floating_base=True)`, Pinocchio's `JointModelFreeFlyer`); other bodies on
  the world hang from a link named `world`;
- frames welded to bodies become massless links on fixed joints
  (`<frame>_joint`), so a reader keeps them as frames;
- visuals of shape box, sphere, cylinder and mesh files become <visual>.

Refused with a UrdfError naming the item: flexible bodies, joints URDF
has no type for (helical, universal, cylindrical, spherical, translation,
planar, a free joint below the root), and names XML 1.0 cannot hold (NUL and
the other C0 control characters but tab, newline and carriage return;
U+FFFE, U+FFFF): no escape exists for them, and a reader refuses the file. Every
other character is written escaped (quotes, <, &, newlines) and reads back
unchanged. Dropped with one UrdfExportWarning
naming them: loops, joint and point springs, armature, prescribed flags, a
floating root's effort limits and visuals URDF cannot draw (capsule,
ellipsoid, plane, inline meshes).
"""
from __future__ import annotations

import json
import os
import re
import warnings
import xml.etree.ElementTree as ET

import numpy as np

from ..model import Model
from .text_files import write_text
from .urdf import UrdfError

__all__ = ["save_urdf", "urdf_text", "UrdfExportWarning"]


class UrdfExportWarning(UserWarning):
    """What a model holds and URDF cannot: named once per export."""


_LIMIT = "1e9"  # the position and velocity limits URDF requires in a <limit>; nothing reads them as dynamics
_NOT_XML = re.compile("[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]")  # outside XML 1.0's Char


def _xml_name(name: str, item: str) -> None:
    """UrdfError naming `item` (which shows `name`) when `name` holds a character XML 1.0 cannot hold."""
    bad = _NOT_XML.search(name)
    if bad:
        raise UrdfError(f"{item}: the name holds U+{ord(bad.group()):04X}, a character XML 1.0 cannot hold (not "
                        f"even escaped); rename it to export a URDF")


def _check_names(data: dict, robot_name: str) -> None:
    """Every body, joint and frame name the URDF will hold can be written into XML (see _xml_name)."""
    _xml_name(robot_name, f"robot name {robot_name!r}")
    for body in data["bodies"]:
        _xml_name(body["name"], f"body {body['name']!r}")
        _xml_name(body["joint"]["name"], f"joint {body['joint']['name']!r} of body {body['name']!r}")
    for frame in data["frames"]:
        _xml_name(frame["name"], f"frame {frame['name']!r}")


def _number_list(values) -> str:
    return " ".join(repr(float(x)) for x in values)


def rpy(R) -> np.ndarray:
    """URDF's roll, pitch, yaw of rotation R = Rz(yaw) Ry(pitch) Rx(roll)."""
    R = np.asarray(R, dtype=float)
    pitch = np.arctan2(-R[2, 0], np.hypot(R[0, 0], R[1, 0]))
    if np.hypot(R[0, 0], R[1, 0]) < 1e-12:  # pitch at +-90 degrees: roll folded into yaw
        return np.array([0.0, pitch, np.arctan2(-R[0, 1], R[1, 1])])
    return np.array([np.arctan2(R[2, 1], R[2, 2]), pitch, np.arctan2(R[1, 0], R[0, 0])])


def _origin(parent: ET.Element, rotation, translation) -> None:
    ET.SubElement(parent, "origin", xyz=_number_list(translation), rpy=_number_list(rpy(rotation)))


def _link(robot: ET.Element, name: str, body: dict | None = None) -> ET.Element:
    link = ET.SubElement(robot, "link", name=name)
    if body is not None and body["mass"] > 0:
        inertial = ET.SubElement(link, "inertial")
        _origin(inertial, np.eye(3), body["com"])
        ET.SubElement(inertial, "mass", value=repr(float(body["mass"])))
        I = body["inertia"]
        ET.SubElement(inertial, "inertia", **{f"i{'xyz'[r]}{'xyz'[c]}": repr(float(I[r][c]))
                                              for r, c in ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))})
    return link


def _joint(robot: ET.Element, name: str, kind: str, parent: str, child: str, placement: dict, axis=None,
           effort=None) -> None:
    joint = ET.SubElement(robot, "joint", name=name, type=kind)
    _origin(joint, placement["rotation"], placement["translation"])
    ET.SubElement(joint, "parent", link=parent)
    ET.SubElement(joint, "child", link=child)
    if axis is not None:
        ET.SubElement(joint, "axis", xyz=_number_list(axis))
    effort = "0" if effort is None else repr(float(effort))
    if kind == "prismatic":
        ET.SubElement(joint, "limit", lower="-" + _LIMIT, upper=_LIMIT, effort=effort, velocity=_LIMIT)
    elif effort != "0":
        ET.SubElement(joint, "limit", effort=effort, velocity=_LIMIT)


def _visual(link: ET.Element, v) -> bool:
    """A <visual> for `v` in `link`; False when URDF has no such geometry."""
    if v.shape == "mesh" and v.mesh_file is None or v.shape not in ("box", "sphere", "cylinder", "mesh"):
        return False
    _xml_name(v.name, f"visual {v.name!r}")
    if v.mesh_file is not None:
        _xml_name(v.mesh_file, f"mesh file {v.mesh_file!r} of visual {v.name!r}")
    visual = ET.SubElement(link, "visual", name=v.name)
    _origin(visual, v.rotation, v.translation)
    geometry = ET.SubElement(visual, "geometry")
    if v.shape == "box":
        ET.SubElement(geometry, "box", size=_number_list(v.size))
    elif v.shape == "sphere":
        ET.SubElement(geometry, "sphere", radius=repr(float(v.size[0])))
    elif v.shape == "cylinder":
        ET.SubElement(geometry, "cylinder", radius=repr(float(v.size[0])), length=repr(float(v.size[1])))
    else:
        scale = v.size if v.size.size == 3 else np.ones(3)
        ET.SubElement(geometry, "mesh", filename=v.mesh_file, scale=_number_list(scale))
    material = ET.SubElement(visual, "material", name=f"{v.name}_colour")
    ET.SubElement(material, "color", rgba=_number_list(v.rgba))
    return True


def _floating_root(bodies: list) -> str | None:
    roots = [b for b in bodies if b["parent"] == "world"]
    if len(roots) == 1 and roots[0]["joint"]["type"] == "free":
        return roots[0]["name"]
    return None


def _dropped(data: dict, m: Model) -> list[str]:
    dropped = [f"loop '{x['name']}'" for x in data["loops"]]
    dropped += [f"joint spring '{x['name']}'" for x in data["joint_springs"]]
    dropped += [f"point spring '{x['name']}'" for x in data["point_springs"]]
    dropped += [f"armature of '{dof}'" for dof in data["armature"]]
    if data["prescribed"]:
        dropped.append(f"prescribed flags ({', '.join(data['prescribed'])})")
    return dropped


def urdf_text(m: Model, robot_name: str = "soadyn_model") -> str:
    """The URDF of the rigid part of `m` (see the module's documentation)."""
    if not isinstance(m, Model):
        raise TypeError(f"urdf_text needs a soadyn.Model, got {type(m).__name__}")
    data = json.loads(m._to_json())  # the model-file view: every body, joint and number the model holds
    bodies = data["bodies"]
    _check_names(data, robot_name)
    floating = _floating_root(bodies)
    efforts = dict(data.get("effort_limits", {}))  # DOF name -> effort limit; what remains is not exported
    robot = ET.Element("robot", name=robot_name)
    links: dict[str, ET.Element] = {}
    if floating is None or any(b["parent"] == "world" and b["name"] != floating for b in bodies):
        links["world"] = _link(robot, "world")
    for body in bodies:
        name, joint = body["name"], body["joint"]
        if "flexible" in body:
            raise UrdfError(f"body '{name}': a flexible body has no URDF form (export its rigid part only)")
        links[name] = _link(robot, name, body)
        if name == floating:
            X = body["placement"]
            if not (np.array_equal(X["rotation"], np.eye(3)) and not np.any(X["translation"])):
                raise UrdfError(f"body '{name}': a floating root exports only with an identity placement (URDF's "
                                f"floating base has none; its coordinates would mean another pose)")
            continue
        kind = joint["type"]
        if kind not in ("revolute", "prismatic", "fixed"):
            raise UrdfError(f"joint '{joint['name']}' of body '{name}': URDF has no {kind} joint "
                            f"(exportable: revolute, prismatic, fixed, and a free joint at the root)")
        urdf_kind = {"revolute": "continuous"}.get(kind, kind)
        _joint(robot, joint["name"], urdf_kind, body["parent"], name, body["placement"], joint.get("axis"),
               efforts.pop(joint["name"], None) if kind != "fixed" else None)  # a one-DOF joint's DOF: its name
    for frame in data["frames"]:
        links[frame["name"]] = _link(robot, frame["name"])
        _joint(robot, f"{frame['name']}_joint", "fixed", frame["body"], frame["name"], frame["placement"])
    dropped = _dropped(data, m) + [f"effort limit of '{dof}'" for dof in efforts]
    for v in m.visuals:
        if v.frame not in links or not _visual(links[v.frame], v):
            dropped.append(f"visual '{v.name}' ({v.shape} on '{v.frame}')")
    if dropped:
        warnings.warn(f"URDF export of '{robot_name}' leaves out what URDF cannot hold: {'; '.join(dropped)}",
                      UrdfExportWarning, stacklevel=3)
    ET.indent(robot)
    return '<?xml version="1.0"?>\n' + ET.tostring(robot, encoding="unicode") + "\n"


def save_urdf(m: Model, path, robot_name: str = "soadyn_model") -> None:
    """Write the URDF of the rigid part of `m` to `path` (the module's docstring lists what is exported).

    Lengths in m, masses in kg, inertias in kg m^2 about the centre of mass. What URDF cannot hold (loops,
    springs, armature, prescribed flags) is dropped with one UrdfExportWarning naming it. Raises TypeError for
    a non-Model, and UrdfError naming the path and the item for what URDF cannot describe (a flexible body, a
    joint kind without a URDF counterpart, a name XML cannot hold) and for a path that cannot be written.
    """
    try:
        text = urdf_text(m, robot_name)
    except UrdfError as exc:
        raise UrdfError(f"{os.fspath(path)}: cannot export the URDF: {exc}") from exc
    write_text(path, text, UrdfError, "URDF")
