"""URDF loading, on top of the yourdfpy parser (no XML is parsed here).

Decisions:
- Links are added depth-first from the root, so the model's body order is a
  depth-first order (the one Pinocchio needs too).
- revolute and continuous joints become one-coordinate revolute DOFs named
  after the joint (a continuous joint's angle is a plain real number);
  prismatic likewise; floating becomes a free joint; planar becomes a planar
  joint in the plane normal to its axis; fixed joints merge the child link into
  its parent exactly (the link name stays usable as a frame).
- floating_base=True adds a free joint named 'root_joint' between the world
  and the root link; otherwise the root link is welded to the world.
- Dynamics parameters that are not rigid-body dynamics (damping, friction,
  limits, mimic) are not modelled.
- A link without <inertial> has no mass. A moving link must have mass
  somewhere: an <inertial> on it or on a link welded to it (ANYmal's 'base'
  carries its mass on the welded 'base_inertia'); otherwise loading fails.
- package_dirs is accepted for compatibility; meshes are never loaded.
"""
from __future__ import annotations

import os
from pathlib import Path
from xml.etree import ElementTree

import numpy as np

from ._soadyn import Joint
from .model import Model

__all__ = ["load_urdf", "UrdfError"]


class UrdfError(ValueError):
    """A URDF that cannot become a model; the message names the element."""


def _parse(path: Path):
    try:  # yourdfpy's parser recovers from broken XML; a URDF must be well formed
        ElementTree.parse(path)
    except ElementTree.ParseError as exc:
        raise UrdfError(f"malformed URDF '{path}': {exc}") from exc
    try:
        import yourdfpy
    except ImportError as exc:  # pragma: no cover - the dependency is declared
        raise ImportError("load_urdf needs the 'yourdfpy' package (pip install soadyn[urdf])") from exc
    try:
        urdf = yourdfpy.URDF.load(str(path), build_scene_graph=False, load_meshes=False,
                                  build_collision_scene_graph=False, load_collision_meshes=False)
    except Exception as exc:  # yourdfpy raises lxml and its own errors for malformed files
        raise UrdfError(f"malformed URDF '{path}': {exc}") from exc
    return urdf.robot


def _frame_with_z(axis: np.ndarray) -> np.ndarray:
    """A rotation whose third column is the unit `axis`."""
    z = axis / np.linalg.norm(axis)
    helper = np.array([1.0, 0, 0]) if abs(z[0]) < 0.9 else np.array([0, 1.0, 0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def _axis(joint) -> np.ndarray:
    axis = np.array([1.0, 0, 0]) if joint.axis is None else np.asarray(joint.axis, dtype=float)
    if not np.all(np.isfinite(axis)) or np.linalg.norm(axis) == 0:
        raise UrdfError(f"joint '{joint.name}': axis {axis} is zero or not finite")
    return axis / np.linalg.norm(axis)


def _joint(joint):
    """The soadyn joint for a URDF joint, and the rotation from the link frame to the body frame."""
    kind = joint.type
    if kind in ("revolute", "continuous"):
        return Joint.revolute(_axis(joint), name=joint.name), np.eye(3)
    if kind == "prismatic":
        return Joint.prismatic(_axis(joint), name=joint.name), np.eye(3)
    if kind == "fixed":
        return Joint.fixed(name=joint.name), np.eye(3)
    if kind == "floating":
        return Joint.free(name=joint.name), np.eye(3)
    if kind == "planar":  # our planar joint moves in its frame's x-y plane: turn z onto the axis
        R = _frame_with_z(_axis(joint))
        return Joint.planar(name=joint.name), R
    raise UrdfError(f"joint '{joint.name}': unsupported joint type '{kind}'")


def _has_welded_inertial(name: str, links, children) -> bool:
    """Whether the link or a link welded to it (through fixed joints) has an <inertial>."""
    if links[name].inertial is not None and links[name].inertial.mass is not None:
        return True
    return any(_has_welded_inertial(j.child, links, children) for j in children[name] if j.type == "fixed")


def _mass_properties(link, link_to_body: np.ndarray):
    """(mass, com, inertia about the com) in the body frame; zero without an <inertial>."""
    inertial = link.inertial
    if inertial is None or inertial.mass is None:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    origin = np.eye(4) if inertial.origin is None else np.asarray(inertial.origin, dtype=float)
    inertia = np.zeros((3, 3)) if inertial.inertia is None else np.asarray(inertial.inertia, dtype=float)
    R = link_to_body @ origin[:3, :3]
    return float(inertial.mass), link_to_body @ origin[:3, 3], R @ inertia @ R.T


def _topology(robot):
    """Children lists and the root link; refuses unknown links, loops and forests by name."""
    links = {}
    for link in robot.links:
        if link.name in links:
            raise UrdfError(f"link '{link.name}' is defined twice")
        links[link.name] = link
    children: dict[str, list] = {name: [] for name in links}
    parent_of: dict[str, str] = {}
    for joint in robot.joints:
        for role in ("parent", "child"):
            if getattr(joint, role) not in links:
                raise UrdfError(f"joint '{joint.name}': {role} link '{getattr(joint, role)}' does not exist")
        if joint.child in parent_of:
            raise UrdfError(f"link '{joint.child}' has two parent joints ('{parent_of[joint.child]}' and "
                            f"'{joint.name}'): kinematic loops are not supported")
        parent_of[joint.child] = joint.name
        children[joint.parent].append(joint)
    roots = [name for name in links if name not in parent_of]
    if len(roots) != 1:
        raise UrdfError(f"the URDF must have exactly one root link, found {roots or 'no root (a kinematic loop)'}")
    return links, children, roots[0]


def _add_base(model: Model, links, children, root: str, floating_base: bool) -> list:
    """Adds the base body; returns the joints to add next, as (joint, parent link-to-body rotation).

    A root link named 'world' is the ground itself. With floating_base=True
    its single fixed joint is replaced by the free root joint.
    """
    base, placement, todo = root, None, children[root]
    if root == "world":
        if not floating_base:
            return [(joint, np.eye(3)) for joint in reversed(todo)]
        if len(todo) != 1 or todo[0].type != "fixed":
            raise UrdfError("floating_base=True needs the 'world' link to have a single fixed joint to the base")
        weld = todo[0]
        origin = np.eye(4) if weld.origin is None else np.asarray(weld.origin, dtype=float)
        base, todo, placement = weld.child, children[weld.child], (origin[:3, :3], origin[:3, 3])
    root_joint = Joint.free(name="root_joint") if floating_base else Joint.fixed(name="root_joint")
    if floating_base and not _has_welded_inertial(base, links, children):
        raise UrdfError(f"link '{base}': a moving link has no <inertial> (nor has any link welded to it)")
    mass, com, inertia = _mass_properties(links[base], np.eye(3))
    model.add_body(base, None, root_joint, placement=placement, mass=mass, com=com, inertia=inertia)
    return [(joint, np.eye(3)) for joint in reversed(todo)]


def load_urdf(path, floating_base: bool = False, package_dirs=None) -> Model:
    """A Model from a URDF file (see the module documentation for the mapping)."""
    del package_dirs  # meshes are never loaded
    path = Path(os.fspath(path))
    if not path.is_file():
        raise FileNotFoundError(f"URDF file '{path}' does not exist")
    links, children, root = _topology(_parse(path))
    model = Model()
    stack = _add_base(model, links, children, root, floating_base)
    visited = {root} | {joint.parent for joint, _ in stack}
    while stack:
        joint, parent_link_to_body = stack.pop()
        if joint.child in visited:  # pragma: no cover - _topology already refuses loops
            raise UrdfError(f"joint '{joint.name}' closes a kinematic loop")
        visited.add(joint.child)
        soadyn_joint, joint_to_link = _joint(joint)
        origin = np.eye(4) if joint.origin is None else np.asarray(joint.origin, dtype=float)
        placement = (parent_link_to_body @ origin[:3, :3] @ joint_to_link, parent_link_to_body @ origin[:3, 3])
        link_to_body = joint_to_link.T
        if joint.type != "fixed" and not _has_welded_inertial(joint.child, links, children):
            raise UrdfError(f"link '{joint.child}': a moving link has no <inertial> (nor has any link welded to it)")
        mass, com, inertia = _mass_properties(links[joint.child], link_to_body)
        try:
            model.add_body(joint.child, joint.parent, soadyn_joint, placement=placement, mass=mass, com=com,
                           inertia=inertia)
        except ValueError as exc:
            raise UrdfError(f"link '{joint.child}' (joint '{joint.name}'): {exc}") from exc
        stack.extend((child, link_to_body) for child in reversed(children[joint.child]))
    if visited != set(links):
        raise UrdfError(f"links not connected to the root '{root}': {sorted(set(links) - visited)}")
    return model
