"""The URDF file format read into plain values, every number checked.

The XML is parsed by the standard library (xml.etree.ElementTree), its size
and element depth bounded (bounded_input.py: a file over 512 MiB or nested
more than 256 elements deep is a UrdfError naming the file and the limit);
this module reads the URDF elements the dynamics needs and refuses, by file and
element name, everything it cannot read exactly: a missing or non-numeric
attribute, a vector with the wrong number of components, a non-finite
number, a negative mass, an unknown joint type, a duplicate name. Nothing
is guessed or broadcast (a general URDF parser happily turns xyz="1" into
(1, 1, 1) and drops a fourth rpy angle).

Read, per the URDF specification (wiki.ros.org/urdf/XML):
- <link name>: its <inertial> (<origin xyz rpy>, <mass value>, <inertia ixx
  ixy ixz iyy iyz izz>, all required but the origin); <visual> is read by
  urdf_visuals.py, collision and everything else is ignored.
- <joint name type>: <parent link>, <child link>, <origin xyz rpy> (default
  identity), <axis xyz> (default 1 0 0; read only for the types that have an
  axis), <dynamics> damping and friction, and <limit effort> (the largest
  force or torque; 0 when <limit> or its effort is absent: URDF's "no limit
  known", as files give fixed and passive joints). Like <dynamics>, a
  negative, non-numeric or non-finite effort is refused. The position and
  velocity limits, mimic, calibration and safety are ignored.
- rpy are fixed-axis roll, pitch, yaw: R = Rz(yaw) Ry(pitch) Rx(roll).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from xml.etree import ElementTree

import numpy as np

from ..bounded_input import parse_xml, read_bytes

__all__ = ["UrdfError", "UrdfInertial", "UrdfLink", "UrdfJoint", "UrdfRobot", "read_urdf", "JOINT_TYPES"]

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
_TYPES_WITH_AXIS = ("revolute", "continuous", "prismatic", "planar")


class UrdfError(ValueError):
    """A URDF that cannot become a model; the message names the file and the element at fault."""


@dataclass(frozen=True)
class UrdfInertial:
    mass: float
    com: np.ndarray  # centre of mass in the link frame
    inertia: np.ndarray  # about the centre of mass, in the link frame (the inertial origin's rotation applied)


@dataclass(frozen=True)
class UrdfLink:
    name: str
    inertial: UrdfInertial | None


@dataclass(frozen=True)
class UrdfJoint:
    name: str
    type: str
    parent: str
    child: str
    rotation: np.ndarray  # child link frame in the parent link frame
    translation: np.ndarray
    axis: np.ndarray  # unit, in the child link frame
    damping: float = 0.0   # <dynamics damping>: viscous, N m s/rad or N s/m
    friction: float = 0.0  # <dynamics friction>: Coulomb (not modelled)
    effort: float = 0.0    # <limit effort>: the largest |force| or |torque|, N or N m; 0: no limit known


@dataclass(frozen=True)
class UrdfRobot:
    path: Path
    links: dict  # name -> UrdfLink, in file order
    joints: list  # UrdfJoint, in file order


def rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """R = Rz(yaw) Ry(pitch) Rx(roll), the URDF convention."""
    cr, sr, cp, sp, cy, sy = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch), math.cos(yaw), math.sin(yaw)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


class _Reader:
    def __init__(self, path: Path):
        self.path = path

    def error(self, where: str, what: str) -> UrdfError:
        return UrdfError(f"URDF '{self.path}': {where}: {what}")

    def single(self, element, tag: str, where: str, required: bool):
        found = element.findall(tag)
        if len(found) > 1:
            raise self.error(where, f"{len(found)} <{tag}> elements, expected one")
        if not found and required:
            raise self.error(where, f"<{tag}> is missing")
        return found[0] if found else None

    def attribute(self, element, name: str, where: str) -> str:
        value = element.get(name)
        if value is None:
            raise self.error(where, f"<{element.tag}> has no '{name}' attribute")
        return value

    def numbers(self, element, name: str, count: int, where: str, default=None) -> list[float]:
        text = element.get(name) if element is not None else None
        if text is None:
            if default is None:
                raise self.error(where, f"<{element.tag}> has no '{name}' attribute")
            return list(default)
        tokens = text.split()
        if len(tokens) != count:
            raise self.error(where, f"<{element.tag} {name}='{text}'> has {len(tokens)} numbers, expected {count}")
        try:
            values = [float(t) for t in tokens]
        except ValueError:
            expected = "a number" if count == 1 else f"{count} numbers"
            raise self.error(where, f"<{element.tag} {name}='{text}'> is not {expected}") from None
        if not all(math.isfinite(v) for v in values):
            raise self.error(where, f"<{element.tag} {name}='{text}'> is not finite")
        return values

    def origin(self, element, where: str):
        origin = self.single(element, "origin", where, required=False)
        xyz = self.numbers(origin, "xyz", 3, where, default=(0.0, 0.0, 0.0))
        rpy = self.numbers(origin, "rpy", 3, where, default=(0.0, 0.0, 0.0))
        return rpy_matrix(*rpy), np.array(xyz)

    def inertial(self, link, where: str) -> UrdfInertial | None:
        inertial = self.single(link, "inertial", where, required=False)
        if inertial is None:
            return None
        R, com = self.origin(inertial, where + " <inertial>")
        (mass,) = self.numbers(self.single(inertial, "mass", where + " <inertial>", True), "value", 1, where)
        if mass < 0:
            raise self.error(where, f"mass {mass:g} is negative")
        element = self.single(inertial, "inertia", where + " <inertial>", True)
        xx, xy, xz, yy, yz, zz = (self.numbers(element, key, 1, where)[0]
                                  for key in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
        inertia = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
        return UrdfInertial(mass, com, R @ inertia @ R.T)

    def name(self, element, kind: str, index: int) -> str:
        name = element.get("name")
        if not name:
            raise self.error(f"{kind} number {index + 1}", f"<{kind}> has no name")
        return name

    def joint(self, element, index: int) -> UrdfJoint:
        name = self.name(element, "joint", index)
        where = f"joint '{name}'"
        kind = self.attribute(element, "type", where)
        if kind not in JOINT_TYPES:
            raise self.error(where, f"unsupported joint type '{kind}' (supported: {', '.join(JOINT_TYPES)})")
        parent = self.attribute(self.single(element, "parent", where, True), "link", where + " <parent>")
        child = self.attribute(self.single(element, "child", where, True), "link", where + " <child>")
        R, p = self.origin(element, where)
        axis = np.array([1.0, 0.0, 0.0])
        if kind in _TYPES_WITH_AXIS:
            axis = np.array(self.numbers(self.single(element, "axis", where, False), "xyz", 3, where,
                                         default=(1.0, 0.0, 0.0)))
            norm = float(np.linalg.norm(axis))
            if not norm > 0:
                raise self.error(where, f"axis {axis.tolist()} is zero")
            axis = axis / norm
        damping, friction = self.dynamics(element, where)
        limit = self.single(element, "limit", where, False)
        effort = self.non_negative(limit, "effort", where) if limit is not None else 0.0
        return UrdfJoint(name, kind, parent, child, R, p, axis, damping, friction, effort)

    def non_negative(self, element, name: str, where: str) -> float:
        """The number attribute `name` of `element`, 0 when absent; finite and non-negative."""
        value = self.numbers(element, name, 1, f"{where} <{element.tag}>", default=(0.0,))[0]
        if not value >= 0:
            raise self.error(where, f"<{element.tag}> {name}={value} must be non-negative")
        return value

    def dynamics(self, element, where: str) -> tuple[float, float]:
        """(damping, friction) of a joint's <dynamics>, 0 when absent; both finite and non-negative."""
        dynamics = self.single(element, "dynamics", where, False)
        if dynamics is None:
            return 0.0, 0.0
        return self.non_negative(dynamics, "damping", where), self.non_negative(dynamics, "friction", where)

    def robot(self) -> UrdfRobot:
        root = read_root(self.path)
        if root.tag != "robot":
            raise UrdfError(f"URDF '{self.path}': the root element is <{root.tag}>, not <robot>")
        links: dict[str, UrdfLink] = {}
        for index, element in enumerate(root.findall("link")):
            name = self.name(element, "link", index)
            if name in links:
                raise UrdfError(f"URDF '{self.path}': link '{name}' is defined twice")
            links[name] = UrdfLink(name, self.inertial(element, f"link '{name}'"))
        if not links:
            raise UrdfError(f"URDF '{self.path}': the robot has no <link>")
        joints, joint_names = [], set()
        for index, element in enumerate(root.findall("joint")):
            joint = self.joint(element, index)
            if joint.name in joint_names:
                raise UrdfError(f"URDF '{self.path}': joint '{joint.name}' is defined twice")
            joint_names.add(joint.name)
            joints.append(joint)
        return UrdfRobot(self.path, links, joints)


def read_root(path: Path) -> ElementTree.Element:
    """The root element of the URDF file at `path`; UrdfError naming the file when it cannot be read, is
    not well-formed XML or is beyond the bounds of bounded_input.py."""
    label = f"URDF '{path}'"
    data = read_bytes(path, label, UrdfError, "file")
    try:
        return parse_xml(data, label, UrdfError)
    except ElementTree.ParseError as exc:
        raise UrdfError(f"malformed URDF '{path}': {exc}") from exc


def read_urdf(path: Path) -> UrdfRobot:
    """The links and joints of the URDF file at `path`; UrdfError naming the element at fault."""
    return _Reader(path).robot()
