"""Independent oracles for a URDF robot: Pinocchio (PyPI `pin`) and DART
(PyPI `dartpy`), each loaded from the same file with its own parser, with
DOFs matched to soadyn's by name.

Conventions bridged here:
- Pinocchio stores continuous joints as (cos, sin) and a free-flyer's
  velocity as (linear, angular); soadyn as an angle and (angular, linear).
- DART stores a free joint's position as (rotation vector, translation) and
  its velocity as (angular velocity, velocity of the origin) in the world
  frame; soadyn's free-joint velocity is the same pair in the body frame.
  With R the root's rotation: v_dart = [R w; R u], d/dt v_dart =
  [R dw; R (du + w x u)], and the generalized forces are [R n; R f].
- DART applies URDF damping, springs and Coulomb friction inside forward
  dynamics, and clamps commanded forces to the URDF effort limits: all are
  removed to compare rigid-body dynamics. DART gives a link without
  <inertial> a mass of 1 kg where URDF means none: such links get an explicit
  zero <inertial> before DART parses the file. Visual and
  collision geometry is stripped before DART parses the file (no meshes).
- DART does not refresh its cached articulated inertias when actuator types
  change; the oracle marks them stale before every call.
- DART chooses a mode per joint, not per DOF, so a prescribed mask given to
  the DART oracle must treat every DOF of a joint alike.
"""
from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

FREE_DOFS = 6


def _quaternion_matrix(quat: np.ndarray) -> np.ndarray:
    x, y, z, w = np.asarray(quat, dtype=float) / np.linalg.norm(quat)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


class _RootFrames:
    """Free-root quantities between soadyn's body frame and DART's world frame."""

    def __init__(self, quaternion, twist):
        self.R = _quaternion_matrix(quaternion)
        self.w, self.u = np.asarray(twist[:3]), np.asarray(twist[3:6])

    def rotate(self, x):  # twist or wrench, body -> world
        return np.r_[self.R @ x[:3], self.R @ x[3:6]]

    def rotate_back(self, x):  # world -> body
        return np.r_[self.R.T @ x[:3], self.R.T @ x[3:6]]

    def acceleration_to_world(self, a):  # d/dt [R w; R u] = [R dw; R (du + w x u)]
        return np.r_[self.R @ a[:3], self.R @ (a[3:6] + np.cross(self.w, self.u))]

    def acceleration_to_body(self, a):
        return np.r_[self.R.T @ a[:3], self.R.T @ a[3:6] - np.cross(self.w, self.u)]


def _quaternion_to_rotation_vector(quat: np.ndarray) -> np.ndarray:
    """(x, y, z, w) unit quaternion to the rotation vector (angle * axis)."""
    xyz, w = np.asarray(quat[:3], dtype=float), float(quat[3])
    if w < 0:
        xyz, w = -xyz, -w
    s = np.linalg.norm(xyz)
    if s < 1e-12:
        return 2.0 * xyz
    return 2.0 * np.arctan2(s, w) * xyz / s


class PinocchioOracle:
    """Pinocchio's model of the URDF with index maps to and from soadyn's DOFs."""

    def __init__(self, model, path: str, floating_base: bool):
        import pinocchio as pin

        self.pin = pin
        self.model = (pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer()) if floating_base
                      else pin.buildModelFromUrdf(str(path)))
        self.data = self.model.createData()
        self.model.gravity.linear = np.asarray(model.gravity, dtype=float)
        self.soadyn = model
        self.v_of_pin = np.zeros(self.model.nv, dtype=int)  # soadyn velocity index of each Pinocchio DOF
        self.q_parts = []  # (pin idx_q, pin nq, soadyn coordinate index, kind)
        for jid in range(1, self.model.njoints):
            joint, name = self.model.joints[jid], self.model.names[jid]
            if joint.nv == FREE_DOFS:
                base = model.v_index[0]
                self.v_of_pin[joint.idx_v:joint.idx_v + 6] = base + np.array([3, 4, 5, 0, 1, 2])
                self.q_parts.append((joint.idx_q, 7, model.q_index[0], "free"))
                continue
            dof = model.dof_index(name)
            if dof < 0 or joint.nv != 1:
                raise ValueError(f"Pinocchio joint '{name}' has no matching soadyn DOF")
            self.v_of_pin[joint.idx_v] = dof
            self.q_parts.append((joint.idx_q, joint.nq, model.coordinate_names.index(name), "scalar"))

    def q(self, q: np.ndarray) -> np.ndarray:
        out = np.zeros(self.model.nq)
        for start, nq, k, kind in self.q_parts:
            if kind == "free":
                out[start:start + 7] = q[k:k + 7]
            elif nq == 2:  # continuous: (cos, sin)
                out[start:start + 2] = np.cos(q[k]), np.sin(q[k])
            else:
                out[start] = q[k]
        return out

    def to_pin(self, x: np.ndarray) -> np.ndarray:
        return np.asarray(x)[self.v_of_pin]

    def from_pin(self, x: np.ndarray) -> np.ndarray:
        out = np.empty(len(x))
        out[self.v_of_pin] = x
        return out

    def forward_dynamics(self, q, v, tau):
        return self.from_pin(self.pin.aba(self.model, self.data, self.q(q), self.to_pin(v), self.to_pin(tau)))

    def inverse_dynamics(self, q, v, qdd):
        return self.from_pin(self.pin.rnea(self.model, self.data, self.q(q), self.to_pin(v), self.to_pin(qdd)))

    def mass_matrix(self, q):
        M = self.pin.crba(self.model, self.data, self.q(q))
        M = np.triu(M) + np.triu(M, 1).T
        out = np.empty_like(M)
        out[np.ix_(self.v_of_pin, self.v_of_pin)] = M
        return out


class DartOracle:
    """DART's skeleton of the URDF; hybrid dynamics through ACCELERATION actuators."""

    def __init__(self, model, path: str, floating_base: bool):
        import dartpy as dart

        self.dart = dart
        loader = dart.utils.DartLoader()
        options = loader.getOptions()
        options.mDefaultRootJointType = (dart.utils.DartLoaderRootJointType.FLOATING if floating_base
                                         else dart.utils.DartLoaderRootJointType.FIXED)
        loader.setOptions(options)
        path = Path(path).resolve()
        urdf_text = without_geometry(path, drop_world=floating_base)
        self.skeleton = loader.parseSkeletonString(urdf_text, dart.common.Uri("file://" + str(path)))
        if self.skeleton is None:
            raise ValueError(f"DART could not load '{path}'")
        self.skeleton.setGravity(np.asarray(model.gravity, dtype=float))
        self.floating = floating_base
        self.soadyn = model
        n = self.skeleton.getNumDofs()
        self.v_of_dart = np.zeros(n, dtype=int)
        self.q_of_dart = np.zeros(n, dtype=int)
        first = FREE_DOFS if floating_base else 0
        self.v_of_dart[:first] = model.v_index[0] + np.arange(first)
        for i in range(first, n):
            name = self.skeleton.getDof(i).getName()
            dof = model.dof_index(name)
            if dof < 0:
                raise ValueError(f"DART DOF '{name}' has no matching soadyn DOF")
            self.v_of_dart[i] = dof
            self.q_of_dart[i] = model.coordinate_names.index(name)
        for j in range(self.skeleton.getNumJoints()):
            joint = self.skeleton.getJoint(j)
            for k in range(joint.getNumDofs()):
                joint.setDampingCoefficient(k, 0.0)
                joint.setSpringStiffness(k, 0.0)
                joint.setCoulombFriction(k, 0.0)
                joint.setForceLowerLimit(k, -np.inf)
                joint.setForceUpperLimit(k, np.inf)

    def _positions(self, q):
        out = np.asarray(q)[self.q_of_dart].astype(float)
        if self.floating:
            k = self.soadyn.q_index[0]
            out[:3] = _quaternion_to_rotation_vector(q[k + 3:k + 7])
            out[3:6] = q[k:k + 3]
        return out

    def hybrid_dynamics(self, q, v, u, prescribed):
        """(qdd, tau) in soadyn's DOF order; `prescribed` must be uniform within each joint."""
        sk = self.skeleton
        q, v, u = (np.asarray(x, dtype=float) for x in (q, v, u))
        root = _RootFrames(q[self.soadyn.q_index[0] + 3:][:4], v[:6]) if self.floating else None
        commands = u[self.v_of_dart]
        velocities = v[self.v_of_dart]
        if root:
            commands[:6] = root.acceleration_to_world(commands[:6]) if prescribed[0] else root.rotate(commands[:6])
            velocities[:6] = root.rotate(velocities[:6])
        self._set_actuators(prescribed, commands)
        sk.setPositions(self._positions(q))
        sk.setVelocities(velocities)
        # DART caches articulated inertias across actuator-type changes (they
        # depend on the types): mark them stale, else a new mask reuses old ones.
        for tree in range(sk.getNumTrees()):
            sk.dirtyArticulatedInertia(tree)
        sk.computeForwardDynamics()
        qdd_dart, tau_dart = sk.getAccelerations(), sk.getForces()
        if root:
            qdd_dart[:6] = root.acceleration_to_body(qdd_dart[:6])
            tau_dart[:6] = root.rotate_back(tau_dart[:6])
        qdd, tau = np.empty(len(v)), np.empty(len(v))
        qdd[self.v_of_dart] = qdd_dart
        tau[self.v_of_dart] = tau_dart
        return qdd, tau

    def _set_actuators(self, prescribed, commands):
        for j in range(self.skeleton.getNumJoints()):
            joint = self.skeleton.getJoint(j)
            if joint.getNumDofs() == 0:
                continue
            dart_dofs = [joint.getIndexInSkeleton(k) for k in range(joint.getNumDofs())]
            modes = {bool(prescribed[self.v_of_dart[i]]) for i in dart_dofs}
            if len(modes) != 1:
                raise ValueError(f"DART joint '{joint.getName()}' cannot mix prescribed and regular DOFs")
            joint.setActuatorType(self.dart.dynamics.ActuatorType.ACCELERATION if modes.pop()
                                  else self.dart.dynamics.ActuatorType.FORCE)
            for k, i in enumerate(dart_dofs):
                joint.setCommand(k, float(commands[i]))

    def joint_groups(self):
        """Lists of soadyn DOF indices that DART switches together."""
        groups = []
        for j in range(self.skeleton.getNumJoints()):
            joint = self.skeleton.getJoint(j)
            if joint.getNumDofs():
                groups.append([int(self.v_of_dart[joint.getIndexInSkeleton(k)]) for k in range(joint.getNumDofs())])
        return groups


def without_geometry(path: Path, drop_world: bool = False) -> str:
    """The URDF text for DART: no <visual> or <collision> (no mesh is ever
    loaded) and an explicit zero <inertial> where a link has none. With
    `drop_world`, a root link named 'world' and its weld are removed: DART
    ignores the floating-root option when they are present, while soadyn then
    puts its free joint in place of the weld (an identity weld is required)."""
    root = ET.parse(path).getroot()
    if drop_world:
        _drop_world_link(root)
    for link in root.iter("link"):
        for tag in ("visual", "collision"):
            for element in link.findall(tag):
                link.remove(element)
        if link.find("inertial") is None:
            inertial = ET.SubElement(link, "inertial")
            ET.SubElement(inertial, "mass", value="0")
            ET.SubElement(inertial, "inertia", ixx="0", ixy="0", ixz="0", iyy="0", iyz="0", izz="0")
    return ET.tostring(root, encoding="unicode")


def _drop_world_link(root) -> None:
    for link in root.findall("link"):
        if link.get("name") == "world":
            root.remove(link)
    for joint in root.findall("joint"):
        parent = joint.find("parent")
        if parent is None or parent.get("link") != "world":
            continue
        origin = joint.find("origin")
        values = [float(x) for key in ("xyz", "rpy") for x in (origin.get(key, "0 0 0") if origin is not None
                                                                else "0 0 0").split()]
        if any(values):
            raise ValueError(f"the DART oracle needs the weld '{joint.get('name')}' to the world to be the identity")
        root.remove(joint)
