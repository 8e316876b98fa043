"""URDF loading: the links and joints read by urdf_reader become a Model.

Decisions:
- Links are added depth-first from the root, children in file order, so the
  model's body order is a depth-first order (the one Pinocchio needs too).
  Every traversal is iterative: a chain of any length loads.
- revolute and continuous joints become one-coordinate revolute DOFs named
  after the joint (a continuous joint's angle is a plain real number);
  prismatic likewise; floating becomes a free joint; planar becomes a planar
  joint in the plane normal to its axis; fixed joints weld the child link to
  its parent (the link name stays usable as a frame).
- floating_base=True adds a free joint named 'root_joint' between the world
  and the root link; otherwise the root link is welded to the world. A root
  link named 'world' is the ground itself (with floating_base=True its single
  fixed joint is replaced by the free joint).
- With joint_damping=True, a revolute, continuous or prismatic joint's
  <dynamics damping> becomes a joint damper (Model.add_joint_spring with
  stiffness 0) named after the joint. Coulomb friction (<dynamics
  friction>) is not a viscous term and is not modelled, nor is damping on
  planar and floating joints: one UrdfIgnoredWarning per load names the
  joints whose values were ignored. By default (joint_damping=False) the
  model is the rigid-body one, as Pinocchio's dynamics algorithms read the
  same file, and <dynamics> is ignored. Position and velocity limits and
  mimic are not modelled.
- A revolute, continuous or prismatic joint's <limit effort> becomes its
  DOF's effort limit (Model.set_effort_limit); effort="0" or no <limit>
  means no limit known and sets none. One number cannot bound the forces
  and torques of a planar or floating joint: their effort is not set, and
  is named in a UrdfIgnoredWarning.
- <visual> shapes become model.visuals (urdf_visuals.py; package_dirs
  resolves package:// mesh names); meshes are referenced by path, not read.

Inertia ("URDF inertia policy" in docs/guides/urdf.md): a body of the model is a moving
link together with every link welded to it through fixed joints; their
inertias are merged first and the body is checked once, merged. The
`inertia` argument decides what happens to a body that is not physical:
"strict" (default) refuses it, naming the link and the option to use;
"repair" makes the smallest change that makes it physical
(urdf_inertia.repaired_inertia) and warns (UrdfRepairWarning) naming the
link; "accept" keeps the file's numbers (Model.add_body's explicit
accept_nonphysical_inertia opt-in). A moving body none of whose links has an
<inertial> is refused by "strict", given urdf_inertia.minimal_inertial by
"repair" and left massless by "accept". Links welded to the world never
move: their inertia is not used.
"""
from __future__ import annotations

import os
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._soadyn import Joint, NonphysicalInertiaError
from ..model import Model
from .urdf_inertia import merge_parts, minimal_inertial, repaired_inertia
from .urdf_reader import UrdfError, UrdfJoint, UrdfRobot, read_urdf
from .urdf_visuals import read_visuals

__all__ = ["load_urdf", "UrdfError", "UrdfRepairWarning", "UrdfIgnoredWarning", "INERTIA_POLICIES"]

INERTIA_POLICIES = ("strict", "repair", "accept")
"""load_urdf's `inertia` choices for a link whose inertia is not physical: refuse it, repair it (with a
UrdfRepairWarning naming the link), or accept it as written."""


class UrdfRepairWarning(UserWarning):
    """load_urdf(..., inertia='repair') changed a link's inertia; the message names the link."""


class UrdfIgnoredWarning(UserWarning):
    """load_urdf ignored joint dynamics it cannot model (Coulomb friction, the effort of a planar or floating
    joint); the message names the joints."""


_ONE_DOF_TYPES = ("revolute", "continuous", "prismatic")  # damping and effort apply to one coordinate


def _add_joint_dampers(model: Model, joints, path) -> None:
    """<dynamics damping> of one-DOF joints as joint dampers; one warning naming the joints whose friction (or
    damping on a joint type without a scalar coordinate) is ignored."""
    ignored = []
    for joint in joints:
        if joint.damping > 0 and joint.type in _ONE_DOF_TYPES:
            model.add_joint_spring(joint.name, joint.name, 0.0, damping=joint.damping)
        elif joint.damping > 0 and joint.type != "fixed":
            ignored.append(f"'{joint.name}' (damping on a {joint.type} joint)")
        if joint.friction > 0 and joint.type != "fixed":
            ignored.append(f"'{joint.name}' (friction {joint.friction:g})")
    _warn_ignored(path, "joint dynamics", ignored)


def _add_effort_limits(model: Model, joints, path) -> None:
    """<limit effort> of one-DOF joints as their DOF's effort limit; one warning naming the planar and
    floating joints whose effort is ignored."""
    ignored = []
    for joint in joints:
        if joint.effort > 0 and joint.type in _ONE_DOF_TYPES:
            model.set_effort_limit(joint.name, joint.effort)
        elif joint.effort > 0 and joint.type != "fixed":
            ignored.append(f"'{joint.name}' (effort {joint.effort:g} on a {joint.type} joint)")
    _warn_ignored(path, "effort limits", ignored)


def _warn_ignored(path, what: str, ignored: list) -> None:
    """One UrdfIgnoredWarning naming the file and the `ignored` items, if any, attributed to load_urdf's caller."""
    if ignored:
        warnings.warn(f"URDF '{path}': {what} not modelled, ignored: {', '.join(ignored)}", UrdfIgnoredWarning,
                      stacklevel=4)


def _frame_with_z(axis: np.ndarray) -> np.ndarray:
    """A rotation whose third column is the unit `axis`."""
    z = axis / np.linalg.norm(axis)
    helper = np.array([1.0, 0, 0]) if abs(z[0]) < 0.9 else np.array([0, 1.0, 0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def _joint(joint: UrdfJoint):
    """The soadyn joint for a moving URDF joint, and the rotation from the link frame to the body frame."""
    if joint.type in ("revolute", "continuous"):
        return Joint.revolute(joint.axis, name=joint.name), np.eye(3)
    if joint.type == "prismatic":
        return Joint.prismatic(joint.axis, name=joint.name), np.eye(3)
    if joint.type == "floating":
        return Joint.free(name=joint.name), np.eye(3)
    # planar: our planar joint moves in its frame's x-y plane: turn z onto the axis
    return Joint.planar(name=joint.name), _frame_with_z(joint.axis).T


@dataclass
class _Topology:
    children: dict  # link name -> its child joints, in file order
    parent_joint: dict  # link name -> the joint whose child it is
    root: str


def _topology(robot: UrdfRobot) -> _Topology:
    """Children lists and the root link; refuses unknown links, loops and forests by name."""
    where = f"URDF '{robot.path}'"
    children: dict[str, list] = {name: [] for name in robot.links}
    parent_joint: dict[str, UrdfJoint] = {}
    for joint in robot.joints:
        for role in ("parent", "child"):
            if getattr(joint, role) not in robot.links:
                raise UrdfError(f"{where}: joint '{joint.name}': {role} link '{getattr(joint, role)}' does not exist")
        if joint.child in parent_joint:
            raise UrdfError(f"{where}: link '{joint.child}' has two parent joints ('{parent_joint[joint.child].name}' "
                            f"and '{joint.name}'): kinematic loops are not supported")
        parent_joint[joint.child] = joint
        children[joint.parent].append(joint)
    roots = [name for name in robot.links if name not in parent_joint]
    if len(roots) != 1:
        found = roots if roots else "none: every link has a parent joint (a kinematic loop)"
        raise UrdfError(f"{where}: the URDF must have exactly one root link, found {found}")
    reached, stack = {roots[0]}, [roots[0]]
    while stack:
        for joint in children[stack.pop()]:
            reached.add(joint.child)
            stack.append(joint.child)
    if len(reached) != len(robot.links):
        unreached = [name for name in robot.links if name not in reached]
        raise UrdfError(f"{where}: links not connected to the root '{roots[0]}' (a kinematic loop): {unreached}")
    return _Topology(children, parent_joint, roots[0])


@dataclass
class _Group:
    """A moving link and the links welded to it: one body of the model."""
    link: str
    welds: list = field(default_factory=list)  # fixed joints inside the group, parents first
    exits: list = field(default_factory=list)  # (moving joint, parent link-to-body rotation), depth-first order
    poses: dict = field(default_factory=dict)  # link name -> (R, p) of the link frame in the body frame


def _group(topology: _Topology, link: str, link_to_body: np.ndarray) -> _Group:
    """The links welded to `link`, depth-first in file order, with their poses in the body frame."""
    group = _Group(link, poses={link: (link_to_body, np.zeros(3))})
    stack = [(joint, link_to_body) for joint in reversed(topology.children[link])]
    while stack:
        joint, parent_to_body = stack.pop()
        if joint.type != "fixed":
            group.exits.append((joint, parent_to_body))
            continue
        R, p = group.poses[joint.parent]
        group.poses[joint.child] = (R @ joint.rotation, R @ joint.translation + p)
        group.welds.append(joint)
        # a welded link is a frame: its children are placed in its own frame
        stack.extend((child, np.eye(3)) for child in reversed(topology.children[joint.child]))
    return group


class _Loader:
    def __init__(self, robot: UrdfRobot, policy: str):
        self.robot, self.policy = robot, policy
        self.topology = _topology(robot)
        self.model = Model()
        self.accept = policy == "accept"

    def where(self, link: str, joint: str) -> str:
        return f"URDF '{self.robot.path}': link '{link}' (joint '{joint}')"

    def merged(self, group: _Group):
        """(mass, com, inertia about the com) of the group in the body frame, and whether any link has <inertial>."""
        parts = []
        for name, (R, p) in group.poses.items():
            inertial = self.robot.links[name].inertial
            if inertial is not None:
                parts.append((inertial.mass, R @ inertial.com + p, R @ inertial.inertia @ R.T))
        return merge_parts(parts), bool(parts)

    def add_group(self, group: _Group, parent, joint: Joint, joint_name: str, placement, moving: bool):
        where = self.where(group.link, joint_name)
        if moving:
            (mass, com, inertia), has_inertial = self.merged(group)
            if not has_inertial:
                mass, com, inertia = self.without_inertial(where)
            self.add_body(group.link, parent, joint, placement, mass, com, inertia, where)
        else:  # welded to the world: never moves, its inertia is not used
            self.call(where, group.link, parent, joint, placement)
        self.add_welds(group)

    def add_welds(self, group: _Group):
        """The welded links of the group as massless frames (their inertia is already in the body), each placed
        by its pose in the body frame: the body frame is not the link frame under a planar joint."""
        for weld in group.welds:
            self.call(self.where(weld.child, weld.name), weld.child, group.link, Joint.fixed(name=weld.name),
                      group.poses[weld.child])

    def without_inertial(self, where: str):
        hint = ("load_urdf(..., inertia='repair') gives it a minimal mass and inertia, inertia='accept' "
                "keeps it massless")
        if self.policy == "strict":
            raise UrdfError(f"{where}: a moving link has no <inertial>, nor has any link welded to it; {hint}")
        if self.policy == "accept":
            return 0.0, np.zeros(3), np.zeros((3, 3))
        mass, moment = minimal_inertial(self.robot.links.values())
        warnings.warn(f"{where}: a moving link has no <inertial>, nor has any link welded to it: given mass "
                      f"{mass:.3g} and principal moments {moment:.3g}", UrdfRepairWarning, stacklevel=6)
        return mass, np.zeros(3), moment * np.eye(3)

    def add_body(self, link: str, parent, joint: Joint, placement, mass, com, inertia, where: str):
        """A moving body with its merged inertia, under the inertia policy."""
        try:
            self.model.add_body(link, parent, joint, placement=placement, mass=mass, com=com, inertia=inertia,
                                accept_nonphysical_inertia=self.accept)
            return
        except NonphysicalInertiaError as exc:
            if self.policy == "strict":
                raise UrdfError(f"{where}: {exc} (every link welded to it merged); load_urdf(..., "
                                f"inertia='repair') makes the smallest change that makes it physical, "
                                f"inertia='accept' keeps the file's values") from exc
        except ValueError as exc:
            raise UrdfError(f"{where}: {exc}") from exc
        fixed, before, after = repaired_inertia(inertia)
        if mass == 0:  # inertia without mass
            mass = minimal_inertial(self.robot.links.values())[0]
        warnings.warn(f"{where}: non-physical inertia repaired: principal moments "
                      f"{np.array2string(before, precision=6)} -> {np.array2string(after, precision=6)}, "
                      f"mass {mass:.6g}", UrdfRepairWarning, stacklevel=6)
        self.call(where, link, parent, joint, placement, mass=mass, com=com, inertia=fixed)

    def call(self, where: str, link: str, parent, joint: Joint, placement, **inertial):
        """model.add_body, its ValueError turned into a UrdfError naming the file, link and joint."""
        try:
            self.model.add_body(link, parent, joint, placement=placement, accept_nonphysical_inertia=self.accept,
                                **inertial)
        except ValueError as exc:
            raise UrdfError(f"{where}: {exc}") from exc

    def load(self, floating_base: bool) -> Model:
        root, topology = self.topology.root, self.topology
        if root == "world" and not floating_base:  # the ground itself: its welded links are frames of the world
            world = _group(topology, root, np.eye(3))
            self.add_welds(world)
            return self.add_moving(world.exits)
        base, placement = root, None
        if root == "world":
            todo = topology.children[root]
            if len(todo) != 1 or todo[0].type != "fixed":
                raise UrdfError(f"URDF '{self.robot.path}': floating_base=True needs the 'world' link to have a "
                                f"single fixed joint to the base")
            base, placement = todo[0].child, (todo[0].rotation, todo[0].translation)
        root_joint = Joint.free(name="root_joint") if floating_base else Joint.fixed(name="root_joint")
        group = _group(topology, base, np.eye(3))
        self.add_group(group, None, root_joint, "root_joint", placement, moving=floating_base)
        return self.add_moving(group.exits)

    def add_moving(self, exits) -> Model:
        stack = list(reversed(exits))
        while stack:
            joint, parent_to_body = stack.pop()
            soadyn_joint, link_to_body = _joint(joint)
            placement = (parent_to_body @ joint.rotation @ link_to_body.T, parent_to_body @ joint.translation)
            group = _group(self.topology, joint.child, link_to_body)
            self.add_group(group, joint.parent, soadyn_joint, joint.name, placement, moving=True)
            stack.extend(reversed(group.exits))
        return self.model


def load_urdf(path, floating_base: bool = False, package_dirs=None, inertia: str = "strict",
              joint_damping: bool = False) -> Model:
    """A Model from a URDF file (see the module documentation for the mapping).

    inertia: "strict" (default) refuses a body that is not physical once its
    welded links are merged; "repair" makes the smallest change that makes it
    physical and warns (UrdfRepairWarning) naming the link; "accept" keeps
    the file's values (the dynamics may then be singular). Every failure to
    read or build the model is a UrdfError naming the file and the element.
    A one-DOF joint's <limit effort> (not 0) becomes its DOF's effort limit (Model.effort_limits).
    joint_damping=True: each one-DOF joint's <dynamics damping> becomes a joint damper named after the joint
    (soadyn.force_elements); friction is not modelled and is reported once (UrdfIgnoredWarning).
    """
    if package_dirs is None:
        package_dirs = ()
    elif isinstance(package_dirs, (str, os.PathLike)):
        package_dirs = (package_dirs,)
    if not isinstance(inertia, str) or inertia not in INERTIA_POLICIES:
        raise ValueError(f"inertia must be one of {INERTIA_POLICIES}, got {inertia!r}")
    if not isinstance(floating_base, (bool, np.bool_)):
        raise TypeError(f"floating_base must be a bool, got {type(floating_base).__name__}")
    if not isinstance(joint_damping, (bool, np.bool_)):
        raise TypeError(f"joint_damping must be a bool, got {type(joint_damping).__name__}")
    path = Path(os.fspath(path))
    if not path.is_file():
        raise FileNotFoundError(f"URDF file '{path}' does not exist")
    robot = read_urdf(path)
    model = _Loader(robot, inertia).load(bool(floating_base))
    _add_effort_limits(model, robot.joints, path)
    if joint_damping:
        _add_joint_dampers(model, robot.joints, path)
    _add_visuals(model, path, package_dirs)
    return model


def _add_visuals(model: Model, path: Path, package_dirs) -> None:
    """The links' <visual> shapes on the bodies and frames named after them (urdf_visuals.py)."""
    visuals, ignored = read_visuals(path, package_dirs)
    places = set(model.body_names) | set(model.frame_names) | {"world"}
    model.visuals = [v for v in visuals if v.frame in places]
    if ignored:
        warnings.warn(f"URDF '{path}': visuals not read: {'; '.join(ignored)}", UrdfIgnoredWarning, stacklevel=3)
