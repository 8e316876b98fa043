"""MJCF loading: MuJoCo's own compiler reads the file, the compiled MjModel becomes a Model.

The `mujoco` package parses and compiles the XML (defaults, include files,
inertia inferred from geoms, mesh processing, `<compiler angle=...>`); no XML
is read here. From the compiled model:

- Bodies keep their names (an unnamed body is 'body<k>', k its MuJoCo id).
  A body with no joint is welded to its parent (a soadyn frame: its inertia
  merges into the parent's). Inertia: body_mass, body_ipos and the principal
  moments body_inertia along body_iquat, as MuJoCo compiled them.
- Joints: hinge -> revolute, slide -> prismatic, ball -> spherical, free ->
  free, each named after the MuJoCo joint (an unnamed one '<body>:joint<i>').
  A joint's anchor (jnt_pos) and axis (jnt_axis) are honoured. Several joints
  in one body become a chain: the first joints move massless intermediate
  bodies named '<body>:<joint>', the last one moves the body itself; MuJoCo
  composes them in the same order (each joint's anchor and axis in the body
  frame as the previous joints left it).
- Coordinates (q, v) and MuJoCo's (qpos, qvel): hinge and slide q = qpos -
  qpos0 (the joint's `ref` is soadyn's zero: the placement absorbs it), v =
  qvel. Ball: q = (x, y, z, w) of qpos's (w, x, y, z), v = qvel (body-frame
  angular velocity in both). Free: q = (position, quaternion x y z w), v =
  (body-frame angular velocity, body-frame linear velocity), while MuJoCo's
  qvel is (world-frame linear velocity, body-frame angular velocity).
  `mjcf_state` and `mujoco_state` convert; `velocity_map` gives the matrix T
  with qvel = T v.
- Springs and dampers: a hinge or slide joint's stiffness (rest springref,
  qpos_spring, measured from ref) and damping become a joint spring named
  after the joint; damping on ball and free joints becomes no element
  (soadyn's joint springs act on scalar coordinates) and is reported.
- armature -> Model.set_armature on every DOF of the joint.
- Effort limits (Model.set_effort_limit): the largest |total actuator
  force| MuJoCo can apply to a hinge, slide or ball joint's DOF through the
  actuators with a joint transmission on it. Actuator k's force (before its
  gear) lies in its forcerange when force-limited, and in gain * ctrlrange
  when its force is gain * ctrl (fixed gain, no bias, no activation
  dynamics: a motor) and ctrl is clamped (ctrl-limited, clampctrl not
  disabled); unbounded otherwise (a position or velocity servo without
  forcerange). DOF i of the joint gets gear[i] times that interval, summed
  over the joint's actuators, clamped to the joint's actuatorfrcrange when
  it is actuator-force-limited (as MuJoCo clamps the total), and the effort
  limit is the larger end in absolute value (forcerange -3 2: 3). A joint
  with actuatorfrcrange and no actuator gets that bound. No limit is set
  where the total is unbounded, nor where it is zero (reported).
- gravity -> Model.gravity.
- `<option><flag .../>` disable flags that switch off what soadyn models are
  honoured: gravity (Model.gravity zero), spring (no joint stiffness),
  damper (no joint damping), equality and constraint (no loops). The other
  disable flags set are reported (they switch off what soadyn does not
  model, or tune MuJoCo's solver).
- equality connect -> a "point" loop, weld -> a "weld" loop (active ones;
  inactive ones are reported), named after the equality ('eq<k>' if
  unnamed). A weld's torquescale is not modelled (reported when not 1).
- Sites become frames named after the site (welded, massless).
- Geoms become model.visuals (soadyn.Visual; meshes as vertices and faces).

What is not multibody dynamics is reported once per load, by name, in an
MjcfIgnoredWarning: contacts (geoms with contype/conaffinity), joint limits,
friction loss, actuators (their force laws: only the effort limits above
are kept; those on tendons, sites, bodies and free joints give none and are
named once more), tendons, sensors, fluid forces (density,
viscosity), gravity compensation, other equality types, disable flags not
honoured.

Bounds: a file or string over 512 MiB or nested more than 256 elements deep
is refused before MuJoCo reads it (bounded_input.py), with an MjcfError
naming it and the limit.

floating_base: None keeps the file's joints; True gives every body attached
to the world without a joint a free joint named '<body>:root'; False welds
bodies attached to the world by a free joint at their qpos0 pose.
"""
from __future__ import annotations

import os
import warnings
from dataclasses import dataclass
from xml.etree import ElementTree

import numpy as np

from .._soadyn import Joint
from ..bounded_input import parse_xml, read_bytes
from ..model import Model
from ..viz.visuals import Visual

__all__ = ["load_mjcf", "MjcfError", "MjcfIgnoredWarning", "MjcfModel", "load_mjcf_with_map"]

FREE, BALL, SLIDE, HINGE = 0, 1, 2, 3
TRN_JOINT, TRN_JOINT_IN_PARENT = 0, 1  # mjtTrn: the actuator drives a joint (gear in its frame, its parent's)
_SCALAR_OR_BALL_DOFS = {HINGE: 1, SLIDE: 1, BALL: 3}  # the joints whose actuators give effort limits: their DOFs
CONNECT, WELD = 0, 1
GEOM_SHAPES = {0: "plane", 2: "sphere", 3: "capsule", 4: "ellipsoid", 5: "cylinder", 6: "box", 7: "mesh"}
HONOURED_DISABLE_FLAGS = ("gravity", "spring", "damper", "equality", "constraint")


class MjcfError(ValueError):
    """An MJCF file or string MuJoCo cannot compile, or that has no soadyn counterpart; names the item."""


class MjcfIgnoredWarning(UserWarning):
    """Parts of an MJCF model that are not multibody dynamics (contacts, actuators, ...), named."""


def _quat_matrix(wxyz) -> np.ndarray:
    w, x, y, z = np.asarray(wxyz, dtype=float) / np.linalg.norm(wxyz)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


class _Pose:
    """A rigid transform (R, p): x_parent = R x + p."""

    def __init__(self, R=None, p=None):
        self.R = np.eye(3) if R is None else np.asarray(R, dtype=float)
        self.p = np.zeros(3) if p is None else np.asarray(p, dtype=float)

    def __mul__(self, other: "_Pose") -> "_Pose":
        return _Pose(self.R @ other.R, self.R @ other.p + self.p)

    def inverse(self) -> "_Pose":
        return _Pose(self.R.T, -self.R.T @ self.p)

    def pair(self):
        return self.R.copy(), self.p.copy()


@dataclass
class MjcfModel:
    """A loaded model and its correspondence with the MuJoCo model it came from."""
    model: Model
    mujoco_model: object      # the compiled mujoco.MjModel
    joints: list              # per MuJoCo joint id: (kind, soadyn DOF index of its first DOF, soadyn q index)

    def soadyn_state(self, qpos, qvel):
        """(q, v) of soadyn from MuJoCo's (qpos, qvel)."""
        return mjcf_state(self, qpos, qvel)

    def mujoco_state(self, q, v):
        """(qpos, qvel) of MuJoCo from soadyn's (q, v)."""
        return mujoco_state(self, q, v)

    def velocity_map(self, q) -> np.ndarray:
        """T (nv x nv) with qvel = T v at q (the identity but for free joints' linear rows)."""
        return velocity_map(self, q)

    def velocity_map_rate(self, q, v) -> np.ndarray:
        """Tdot v, so that qacc = T qdd + Tdot v: a free joint's linear rows R (w x u), (w, u) its
        body-frame angular and linear velocity."""
        out = np.zeros(self.mujoco_model.nv)
        for j, (kind, vi, qi) in enumerate(self.joints):
            if kind == FREE:
                d = self.mujoco_model.jnt_dofadr[j]
                x, y, z, w = np.asarray(q, dtype=float)[qi + 3:qi + 7]
                out[d:d + 3] = _quat_matrix([w, x, y, z]) @ np.cross(v[vi:vi + 3], v[vi + 3:vi + 6])
        return out


def _free_rotation(mj, q, qi) -> np.ndarray:
    x, y, z, w = q[qi + 3:qi + 7]
    return _quat_matrix([w, x, y, z])


def mjcf_state(loaded: MjcfModel, qpos, qvel):
    mj, m = loaded.mujoco_model, loaded.model
    qpos, qvel = np.asarray(qpos, dtype=float), np.asarray(qvel, dtype=float)
    q, v = np.zeros(m.nq), np.zeros(m.nv)
    for j, (kind, vi, qi) in enumerate(loaded.joints):
        if kind is None:
            continue
        a, d = mj.jnt_qposadr[j], mj.jnt_dofadr[j]
        if kind in (HINGE, SLIDE):
            q[qi], v[vi] = qpos[a] - mj.qpos0[a], qvel[d]
        elif kind == BALL:
            w, x, y, z = qpos[a:a + 4]
            q[qi:qi + 4], v[vi:vi + 3] = (x, y, z, w), qvel[d:d + 3]
        else:
            w, x, y, z = qpos[a + 3:a + 7]
            q[qi:qi + 3], q[qi + 3:qi + 7] = qpos[a:a + 3], (x, y, z, w)
            R = _quat_matrix([w, x, y, z])
            v[vi:vi + 3], v[vi + 3:vi + 6] = qvel[d + 3:d + 6], R.T @ qvel[d:d + 3]
    return q, v


def mujoco_state(loaded: MjcfModel, q, v):
    mj = loaded.mujoco_model
    q, v = np.asarray(q, dtype=float), np.asarray(v, dtype=float)
    qpos, qvel = mj.qpos0.copy(), np.zeros(mj.nv)
    for j, (kind, vi, qi) in enumerate(loaded.joints):
        if kind is None:
            continue
        a, d = mj.jnt_qposadr[j], mj.jnt_dofadr[j]
        if kind in (HINGE, SLIDE):
            qpos[a], qvel[d] = q[qi] + mj.qpos0[a], v[vi]
        elif kind == BALL:
            x, y, z, w = q[qi:qi + 4]
            qpos[a:a + 4], qvel[d:d + 3] = (w, x, y, z), v[vi:vi + 3]
        else:
            x, y, z, w = q[qi + 3:qi + 7]
            qpos[a:a + 3], qpos[a + 3:a + 7] = q[qi:qi + 3], (w, x, y, z)
            qvel[d:d + 3] = _quat_matrix([w, x, y, z]) @ v[vi + 3:vi + 6]
            qvel[d + 3:d + 6] = v[vi:vi + 3]
    return qpos, qvel


def velocity_map(loaded: MjcfModel, q) -> np.ndarray:
    mj, m = loaded.mujoco_model, loaded.model
    T = np.zeros((mj.nv, m.nv))
    for j, (kind, vi, qi) in enumerate(loaded.joints):
        if kind is None:
            continue
        d = mj.jnt_dofadr[j]
        if kind in (HINGE, SLIDE):
            T[d, vi] = 1.0
        elif kind == BALL:
            T[d:d + 3, vi:vi + 3] = np.eye(3)
        else:
            x, y, z, w = np.asarray(q, dtype=float)[qi + 3:qi + 7]
            T[d:d + 3, vi + 3:vi + 6] = _quat_matrix([w, x, y, z])
            T[d + 3:d + 6, vi:vi + 3] = np.eye(3)
    return T


def _check_bounds(xml, label: str) -> None:
    """MjcfError naming `label` when the XML is beyond the bounds of bounded_input.py (size, element depth).
    A document expat finds malformed is left to MuJoCo's compiler, which names the fault: its part before
    the fault was within the bounds, and MuJoCo's parser stops at the fault too. Files pulled in by
    <include> are MuJoCo's to read (its parser refuses elements nested about 500 deep)."""
    try:
        parse_xml(xml, label, MjcfError)
    except ElementTree.ParseError:
        pass


def _compile(path_or_xml):
    """(MjModel, label) by MuJoCo's compiler; MjcfError naming the file on failure."""
    import mujoco

    text = str(path_or_xml) if not isinstance(path_or_xml, os.PathLike) else None
    if text is not None and "<mujoco" in text:
        label = "MJCF string"
        _check_bounds(text, label)
        try:
            return mujoco.MjModel.from_xml_string(text), label
        except Exception as exc:  # mujoco raises ValueError with the compiler's message
            raise MjcfError(f"{label}: MuJoCo cannot compile it: {exc}") from exc
    path = os.fspath(path_or_xml)
    if not os.path.isfile(path):
        raise MjcfError(f"MJCF file '{path}' does not exist")
    label = f"MJCF file '{path}'"
    _check_bounds(read_bytes(path, label, MjcfError, "file"), label)
    try:
        return mujoco.MjModel.from_xml_path(path), label
    except Exception as exc:
        raise MjcfError(f"{label}: MuJoCo cannot compile it: {exc}") from exc


def _disabled_flags(mj) -> set:
    """The <option><flag> disable flags set in the compiled model, named as MJCF names them ("gravity")."""
    import mujoco

    return {name.lower() for bit, name in enumerate(mujoco.mjDISABLESTRING) if int(mj.opt.disableflags) >> bit & 1}


def _name(mj, kind, index: int, fallback: str) -> str:
    import mujoco

    name = mujoco.mj_id2name(mj, kind, index)
    return name if name else fallback


class _Loader:
    def __init__(self, mj, label: str, floating_base):
        import mujoco

        self.mj, self.label, self.floating_base = mj, label, floating_base
        self.mjt = mujoco.mjtObj
        self.m = Model()
        self.disabled = _disabled_flags(mj)
        self.m.gravity = np.zeros(3) if "gravity" in self.disabled else np.array(mj.opt.gravity, dtype=float)
        # Per MuJoCo body: the soadyn body or frame it became and the MuJoCo body frame in it.
        self.frame_of = {0: ("world", _Pose())}
        self.joints: list = [(None, -1, -1)] * mj.njnt
        self.joint_names: list = [""] * mj.njnt
        self.ignored: dict = {}
        self.body_names = [self.body_name(b) for b in range(mj.nbody)]

    def body_name(self, b: int) -> str:
        return "world" if b == 0 else _name(self.mj, self.mjt.mjOBJ_BODY, b, f"body{b}")

    def joint_name(self, j: int, body: str, i: int) -> str:
        return _name(self.mj, self.mjt.mjOBJ_JOINT, j, f"{body}:joint{i}")

    def ignore(self, what: str, name: str) -> None:
        self.ignored.setdefault(what, []).append(name)

    def inertia(self, b: int, offset: _Pose):
        """(mass, com, inertia about the com) of MuJoCo body b in a soadyn frame where the MuJoCo body
        frame is `offset`."""
        mj = self.mj
        Ri = _quat_matrix(mj.body_iquat[b])
        com = offset.R @ mj.body_ipos[b] + offset.p
        I = offset.R @ Ri @ np.diag(mj.body_inertia[b]) @ Ri.T @ offset.R.T
        return float(mj.body_mass[b]), com, 0.5 * (I + I.T)

    def add_body(self, b: int) -> None:
        mj = self.mj
        name = self.body_names[b]
        parent_name, parent_offset = self.frame_of[int(mj.body_parentid[b])]
        parent = None if parent_name == "world" else parent_name
        # The MuJoCo body frame in the parent soadyn frame before the body's joints move it.
        here = parent_offset * _Pose(_quat_matrix(mj.body_quat[b]), mj.body_pos[b])
        joints = list(range(mj.body_jntadr[b], mj.body_jntadr[b] + mj.body_jntnum[b]))
        kinds = [int(mj.jnt_type[j]) for j in joints]
        if self.floating_base is True and parent is None and not joints:
            self.add_free_root(b, name, here)
            return
        if self.floating_base is False and parent is None and kinds == [FREE]:
            here = self.free_pose(joints[0])  # welded where qpos0 puts it
            joints, kinds = [], []
        if not joints:
            mass, com, inertia = self.inertia(b, _Pose())
            self.m.add_body(name, parent, Joint.fixed(), placement=here.pair(), mass=mass, com=com, inertia=inertia)
            self.frame_of[b] = (name, _Pose())
            return
        if FREE in kinds and (len(joints) > 1 or parent is not None):
            raise MjcfError(f"{self.label}: body '{name}': a free joint must be the only joint of a body "
                            "attached to the world")
        for i, (j, kind) in enumerate(zip(joints, kinds)):
            last = i == len(joints) - 1
            joint_name = self.joint_name(j, name, i)
            child = name if last else f"{name}:{joint_name}"
            if kind == FREE:
                joint, anchor = Joint.free(name=joint_name), _Pose()
                here = _Pose()  # a free joint's coordinates are the body's world pose
            else:
                anchor = _Pose(None, mj.jnt_pos[j])
                joint = self.scalar_or_ball_joint(j, kind, joint_name)
            # MuJoCo moves a hinge or slide by qpos - qpos0 from the compiled body pose (the file's
            # pose, at ref): soadyn's zero is that pose, so the placement needs no ref term.
            placement = here * anchor
            # The MuJoCo body frame in the new soadyn body's frame: the anchor taken back out.
            offset = anchor.inverse()
            mass, com, inertia = self.inertia(b, offset) if last else (0.0, np.zeros(3), np.zeros((3, 3)))
            self.m.add_body(child, parent, joint, placement=placement.pair(), mass=mass, com=com, inertia=inertia)
            self.record_joint(j, kind, child, joint_name)
            parent, here = child, offset
        self.frame_of[b] = (name, here)

    def free_pose(self, j: int) -> _Pose:
        a = self.mj.jnt_qposadr[j]
        return _Pose(_quat_matrix(self.mj.qpos0[a + 3:a + 7]), self.mj.qpos0[a:a + 3])

    def add_free_root(self, b: int, name: str, here: _Pose) -> None:
        mass, com, inertia = self.inertia(b, _Pose())
        # The body starts at its file pose: the free joint's zero is the world frame, so put the pose in q0.
        self.m.add_body(name, None, Joint.free(name=f"{name}:root"), placement=here.pair(), mass=mass, com=com,
                        inertia=inertia)
        self.frame_of[b] = (name, _Pose())

    def scalar_or_ball_joint(self, j: int, kind: int, joint_name: str):
        axis = np.asarray(self.mj.jnt_axis[j], dtype=float)
        if kind == HINGE:
            return Joint.revolute(axis, name=joint_name)
        if kind == SLIDE:
            return Joint.prismatic(axis, name=joint_name)
        return Joint.spherical(name=joint_name)

    def record_joint(self, j: int, kind: int, body: str, joint_name: str) -> None:
        k = self.m.body_index(body)
        self.joints[j] = (kind, self.m.v_index[k], self.m.q_index[k])
        self.joint_names[j] = joint_name

    def add_joint_forces(self) -> None:
        mj, m = self.mj, self.m
        for j, (kind, vi, _) in enumerate(self.joints):
            if kind is None:
                continue
            joint_name = self.joint_names[j]
            d, nd = mj.jnt_dofadr[j], {HINGE: 1, SLIDE: 1, BALL: 3, FREE: 6}[kind]
            armature = mj.dof_armature[d:d + nd]
            for k in range(nd):
                if armature[k] != 0.0:
                    m.set_armature(vi + k, float(armature[k]))
            stiffness, damping = float(mj.jnt_stiffness[j]), mj.dof_damping[d:d + nd]
            if "spring" in self.disabled:
                stiffness = 0.0
            if "damper" in self.disabled:
                damping = np.zeros(nd)
            if kind in (HINGE, SLIDE):
                if stiffness != 0.0 or damping[0] != 0.0:
                    a = mj.jnt_qposadr[j]
                    rest = float(mj.qpos_spring[a] - mj.qpos0[a])
                    m.add_joint_spring(joint_name, vi, stiffness, damping=float(damping[0]), rest=rest)
            else:
                if stiffness != 0.0:
                    self.ignore("stiffness of ball and free joints", joint_name)
                if np.any(damping != 0.0):
                    self.ignore("damping of ball and free joints", joint_name)
            if mj.jnt_limited[j]:
                self.ignore("joint limits", joint_name)
            if np.any(mj.dof_frictionloss[d:d + nd] != 0.0):
                self.ignore("friction loss", joint_name)

    def actuator_name(self, k: int) -> str:
        """An unnamed actuator is named by the joint it drives, if it drives one."""
        mj = self.mj
        target = mj.actuator_trnid[k, 0] if int(mj.actuator_trntype[k]) == TRN_JOINT else -1
        driven = f":{_name(mj, self.mjt.mjOBJ_JOINT, target, f'joint{target}')}" if target >= 0 else ""
        return _name(mj, self.mjt.mjOBJ_ACTUATOR, k, f"actuator{k}{driven}")

    def actuator_force_range(self, k: int) -> tuple:
        """(lo, hi) of actuator k's force before its gear (see the module docstring); infinite where unbounded."""
        import mujoco

        mj, lo, hi = self.mj, -np.inf, np.inf
        gain_times_ctrl = (int(mj.actuator_gaintype[k]) == mujoco.mjtGain.mjGAIN_FIXED
                           and int(mj.actuator_biastype[k]) == mujoco.mjtBias.mjBIAS_NONE
                           and int(mj.actuator_dyntype[k]) == mujoco.mjtDyn.mjDYN_NONE)
        if gain_times_ctrl and mj.actuator_ctrllimited[k] and "clampctrl" not in self.disabled:
            lo, hi = sorted(float(mj.actuator_gainprm[k, 0]) * mj.actuator_ctrlrange[k])
        if mj.actuator_forcelimited[k]:
            lo, hi = np.clip([lo, hi], *mj.actuator_forcerange[k])
        return lo, hi

    def add_effort_limits(self) -> None:
        """Effort limits of the joints' DOFs from their actuators and actuatorfrcrange (the module docstring);
        the actuators that give none are reported."""
        mj, ranges = self.mj, {}  # MuJoCo joint id -> (lo, hi) per DOF of the sum of its actuators' forces
        for k in range(mj.nu):
            j, trn = int(mj.actuator_trnid[k, 0]), int(mj.actuator_trntype[k])
            kind = self.joints[j][0] if trn in (TRN_JOINT, TRN_JOINT_IN_PARENT) else None
            if kind not in _SCALAR_OR_BALL_DOFS or (kind == BALL and trn != TRN_JOINT):  # a ball's gear in its parent
                self.ignore("actuators not on a hinge, slide or ball joint, giving no effort limit",
                            self.actuator_name(k))
                continue
            gear = mj.actuator_gear[k, :_SCALAR_OR_BALL_DOFS[kind]]
            ends, moving = np.zeros((len(gear), 2)), gear != 0.0  # a zero gear passes no force (0 * inf: nan)
            ends[moving] = np.sort(np.outer(gear[moving], self.actuator_force_range(k)), axis=1)
            ranges[j] = ranges.get(j, 0.0) + ends
        for j, (kind, vi, _) in enumerate(self.joints):
            if kind not in _SCALAR_OR_BALL_DOFS or (j not in ranges and not mj.jnt_actfrclimited[j]):
                continue
            lo, hi = ranges.get(j, np.tile([-np.inf, np.inf], (_SCALAR_OR_BALL_DOFS[kind], 1))).T
            if mj.jnt_actfrclimited[j]:  # MuJoCo clamps the joint's total actuator force
                lo, hi = np.clip([lo, hi], *mj.jnt_actfrcrange[j])
            effort = np.maximum(np.abs(lo), np.abs(hi))
            if np.any(effort == 0.0):
                self.ignore("joints whose actuators can apply no force, given no effort limit", self.joint_names[j])
            for i in np.flatnonzero(np.isfinite(effort) & (effort > 0.0)):
                self.m.set_effort_limit(vi + int(i), float(effort[i]))

    def add_sites(self) -> None:
        mj = self.mj
        taken = set(self.m.body_names) | set(self.m.frame_names)
        for s in range(mj.nsite):
            name = _name(mj, self.mjt.mjOBJ_SITE, s, f"site{s}")
            if name in taken:
                self.ignore("sites whose name is taken by a body", name)
                continue
            frame, offset = self.frame_of[int(mj.site_bodyid[s])]
            pose = offset * _Pose(_quat_matrix(mj.site_quat[s]), mj.site_pos[s])
            self.m.add_body(name, None if frame == "world" else frame, Joint.fixed(), placement=pose.pair())
            taken.add(name)

    def add_loops(self) -> None:
        mj = self.mj
        if {"equality", "constraint"} & self.disabled:  # MuJoCo enforces none of them
            return
        for e in range(mj.neq):
            name = _name(mj, self.mjt.mjOBJ_EQUALITY, e, f"eq{e}")
            kind = int(mj.eq_type[e])
            if kind not in (CONNECT, WELD) or int(mj.eq_objtype[e]) != int(self.mjt.mjOBJ_BODY):
                self.ignore("equality constraints other than connect and weld between bodies", name)
                continue
            if not mj.eq_active0[e]:
                self.ignore("inactive equality constraints", name)
                continue
            b1, b2 = int(mj.eq_obj1id[e]), int(mj.eq_obj2id[e])
            f1, o1 = self.frame_of[b1]
            f2, o2 = self.frame_of[b2]
            data = mj.eq_data[e]
            if kind == CONNECT:  # anchor in body 1 (data[0:3]) and the same point in body 2 (data[3:6])
                pa, pb = _Pose(None, data[0:3]), _Pose(None, data[3:6])
                self.m.add_loop(name, f1, None if f2 == "world" else f2, "point",
                                placement_a=(o1 * pa).pair(), placement_b=(o2 * pb).pair())
                continue
            # weld: frame B = body 2 at anchor data[0:3]; frame A = body 1 at relpose (data[3:6], quat data[6:10])
            # of body 2 in body 1, moved to the same anchor.
            if data[10] != 1.0:
                self.ignore("weld torquescale (modelled as 1)", name)
            rel = _Pose(_quat_matrix(data[6:10]), data[3:6])
            anchor = _Pose(None, data[0:3])
            self.m.add_loop(name, f1, None if f2 == "world" else f2, "weld",
                            placement_a=(o1 * rel * anchor).pair(), placement_b=(o2 * anchor).pair())

    def add_visuals(self) -> None:
        mj, visuals = self.mj, []
        for g in range(mj.ngeom):
            name = _name(self.mj, self.mjt.mjOBJ_GEOM, g, f"geom{g}")
            shape = GEOM_SHAPES.get(int(mj.geom_type[g]))
            if mj.geom_contype[g] or mj.geom_conaffinity[g]:
                self.ignore("contacts", name)
            if shape is None:
                self.ignore("geoms without a drawing (height fields, signed distance fields)", name)
                continue
            frame, offset = self.frame_of[int(mj.geom_bodyid[g])]
            pose = offset * _Pose(_quat_matrix(mj.geom_quat[g]), mj.geom_pos[g])
            size = np.asarray(mj.geom_size[g], dtype=float)
            extra = {}
            if shape == "box":
                size = 2 * size
            elif shape == "sphere":
                size = size[:1]
            elif shape in ("cylinder", "capsule"):
                size = np.array([size[0], 2 * size[1]])
            elif shape == "plane":
                size = 2 * size[:2]
            elif shape == "mesh":
                mesh = int(mj.geom_dataid[g])
                v0, nvert = mj.mesh_vertadr[mesh], mj.mesh_vertnum[mesh]
                f0, nface = mj.mesh_faceadr[mesh], mj.mesh_facenum[mesh]
                extra = {"vertices": np.array(mj.mesh_vert[v0:v0 + nvert]), "faces": np.array(mj.mesh_face[f0:f0 + nface])}
                size = np.ones(3)
            visuals.append(Visual(name=name, frame=frame, shape=shape, size=size, rotation=pose.R,
                                  translation=pose.p, rgba=np.array(mj.geom_rgba[g], dtype=float), **extra))
        self.m.visuals = visuals

    def report_rest(self) -> None:
        mj = self.mj
        for k in range(mj.nu):
            self.ignore("actuators", self.actuator_name(k))
        for what, count, kind in (("tendons", mj.ntendon, self.mjt.mjOBJ_TENDON),
                                  ("sensors", mj.nsensor, self.mjt.mjOBJ_SENSOR)):
            for k in range(count):
                self.ignore(what, _name(mj, kind, k, f"{what[:-1]}{k}"))
        if mj.opt.density or mj.opt.viscosity:
            self.ignore("fluid forces", f"density {mj.opt.density:g}, viscosity {mj.opt.viscosity:g}")
        for b in range(1, mj.nbody):
            if mj.body_gravcomp[b]:
                self.ignore("gravity compensation", self.body_names[b])
        for flag in sorted(self.disabled - set(HONOURED_DISABLE_FLAGS)):
            self.ignore("disable flags without a soadyn counterpart", flag)
        if self.ignored:
            parts = [f"{len(names)} {what} ({', '.join(names[:6])}{', ...' if len(names) > 6 else ''})"
                     for what, names in self.ignored.items()]
            warnings.warn(f"{self.label}: not modelled (not multibody dynamics, or no soadyn counterpart): "
                          + "; ".join(parts), MjcfIgnoredWarning, stacklevel=3)

    def load(self) -> MjcfModel:
        for b in range(1, self.mj.nbody):  # MuJoCo orders bodies parent before child
            self.add_body(b)
        self.add_joint_forces()
        self.add_effort_limits()
        self.add_sites()
        self.add_loops()
        self.add_visuals()
        self.report_rest()
        return MjcfModel(self.m, self.mj, self.joints)


def load_mjcf_with_map(path_or_xml, floating_base=None) -> MjcfModel:
    """load_mjcf, returning the MjcfModel (the model, the MjModel and the state maps).

    Raises as load_mjcf does (MjcfError naming the file and the element).
    """
    if floating_base not in (None, True, False):
        raise TypeError(f"floating_base must be None, True or False, got {floating_base!r}")
    mj, label = _compile(path_or_xml)
    try:
        return _Loader(mj, label, floating_base).load()
    except (ValueError, TypeError) as exc:
        if isinstance(exc, MjcfError):
            raise
        raise MjcfError(f"{label}: {exc}") from exc


def load_mjcf(path_or_xml, floating_base=None) -> Model:
    """A Model from an MJCF file path or an MJCF XML string (see the module docstring).

    MuJoCo's compiler reads the file; joints, springs, dampers, armature, gravity and
    connect/weld equalities become soadyn's; what is not dynamics is reported once in an
    MjcfIgnoredWarning. MjcfError (a ValueError) names a file MuJoCo cannot compile or an
    item without a soadyn counterpart."""
    return load_mjcf_with_map(path_or_xml, floating_base).model
