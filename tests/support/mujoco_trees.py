"""The random trees of support/pinocchio_trees.py (BodySpec) as MuJoCo models, and soadyn's
coordinates and velocities mapped to MuJoCo's: the MuJoCo counterpart of build_pinocchio and
its Mapping.

MuJoCo joints for soadyn's: revolute -> hinge, prismatic -> slide,
universal -> two hinges in one body (applied in order, axes in the body
frame: Rot(a1, q0) Rot(a2, q1)), cylindrical -> hinge + slide,
translation -> three slides, planar -> slide x, slide y, hinge z,
spherical -> ball, free -> a freejoint at the root (MuJoCo refuses it
elsewhere) and three slides + a ball below it. Coordinates: MuJoCo
quaternions are (w, x, y, z), soadyn's (x, y, z, w); a freejoint's position
and orientation are the body's pose in the world (soadyn's are relative to
the joint's placement). Velocities: a ball's is the body-frame angular
velocity in both; a freejoint's is (world linear velocity of the body
origin, body-frame angular velocity), soadyn's (body-frame angular, body-
frame linear); planar: MuJoCo's slides move along the parent frame's x, y,
soadyn's (vx, vy) are body-frame. So v_mujoco = T(q) v and
qacc_mujoco = T qdd + Tdot v, and the equations in soadyn's coordinates
use T' M T, T' (h + M Tdot v), J T and Jdot v_mujoco + J Tdot v.
"""
from __future__ import annotations

import dataclasses

import mujoco
import numpy as np

import soadyn
from support.pinocchio_trees import BodySpec


def rot_z(angle: float) -> np.ndarray:
    """The rotation by `angle` about z."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


# ---------------------------------------------------------------------------
# The same tree in MJCF
# ---------------------------------------------------------------------------

def _numbers(x) -> str:
    return " ".join(repr(float(a)) for a in np.ravel(x))


def _quat_wxyz(R: np.ndarray) -> np.ndarray:
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(R, dtype=float).ravel())
    return quat


AXES = np.eye(3)


def mujoco_joints(s: BodySpec, root: bool) -> list[tuple[str, np.ndarray | None]]:
    """(MJCF joint type, axis) of each MuJoCo joint standing for soadyn body s's joint, in order."""
    return {
        "revolute": [("hinge", s.axis)],
        "prismatic": [("slide", s.axis)],
        "universal": [("hinge", s.axis), ("hinge", s.axis2)],
        "cylindrical": [("hinge", s.axis), ("slide", s.axis)],
        "translation": [("slide", a) for a in AXES],
        "planar": [("slide", AXES[0]), ("slide", AXES[1]), ("hinge", AXES[2])],
        "spherical": [("ball", None)],
        "free": [("free", None)] if root else [("slide", a) for a in AXES] + [("ball", None)],
    }[s.kind]


def mjcf(specs: list[BodySpec], sites: list[tuple[str, int, np.ndarray, np.ndarray]], gravity) -> str:
    """MJCF of the tree with the given sites (name, body index or -1 for the world, R, p) and gravity.
    Inertias are set exactly (inertial fullinertia); there are no geoms."""
    children = {i: [] for i in range(-1, len(specs))}
    for i, s in enumerate(specs):
        children[s.parent].append(i)

    def site_xml(body: int) -> str:
        return "".join(f'<site name="{n}" pos="{_numbers(p)}" quat="{_numbers(_quat_wxyz(R))}"/>'
                       for n, b, R, p in sites if b == body)

    def body_xml(i: int) -> str:
        s = specs[i]
        joints = "".join(f'<joint name="{s.name}:{k}" type="{kind}"' + ("" if axis is None else
                         f' axis="{_numbers(axis)}"') + "/>"
                         for k, (kind, axis) in enumerate(mujoco_joints(s, s.parent < 0)))
        I = s.inertia
        inertial = (f'<inertial pos="{_numbers(s.com)}" mass="{s.mass!r}" fullinertia="'
                    f'{_numbers([I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]])}"/>')
        return (f'<body name="{s.name}" pos="{_numbers(s.translation)}" quat="{_numbers(_quat_wxyz(s.rotation))}">'
                + joints + inertial + site_xml(i) + "".join(body_xml(c) for c in children[i]) + "</body>")

    return ('<mujoco><compiler angle="radian" inertiafromgeom="false"/>'
            f'<option gravity="{_numbers(gravity)}"/>'
            "<worldbody>" + site_xml(-1) + "".join(body_xml(c) for c in children[-1]) + "</worldbody></mujoco>")


# ---------------------------------------------------------------------------
# Coordinates: q and v of soadyn -> MuJoCo
# ---------------------------------------------------------------------------

def _quat_matrix(quat_xyzw: np.ndarray) -> np.ndarray:
    R = np.empty(9)
    mujoco.mju_quat2Mat(R, quat_xyzw[[3, 0, 1, 2]])
    return R.reshape(3, 3)


@dataclasses.dataclass
class MujocoState:
    qpos: np.ndarray
    T: np.ndarray        # v_mujoco = T v  (nv x nv)
    T_dot_v: np.ndarray  # d/dt(T) v


def mujoco_state(m: soadyn.Model, model: mujoco.MjModel, specs: list[BodySpec], q, v) -> MujocoState:
    qpos, T, T_dot_v = np.zeros(model.nq), np.zeros((model.nv, m.nv)), np.zeros(model.nv)
    for i, s in enumerate(specs):
        qs = np.asarray(q)[m.q_index[i]:m.q_index[i] + len(_joint_coordinates(m, i))]
        vi = m.v_index[i]
        jid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, f"{s.name}:0")
        qa, da = model.jnt_qposadr[jid], model.jnt_dofadr[jid]  # a body's joints are contiguous in both
        nvj = len(_joint_dofs(m, i))
        if s.kind in ("free", "planar"):
            if s.kind == "free":   # soadyn q (p, quaternion xyzw), v (w, u) both body-frame
                R_joint = _quat_matrix(qs[3:])
                omega, u = np.asarray(v)[vi:vi + 3], np.asarray(v)[vi + 3:vi + 6]
                if s.parent < 0:   # freejoint: world pose of the body
                    qpos[qa:qa + 3] = s.rotation @ qs[:3] + s.translation
                    qpos[qa + 3:qa + 7] = _quat_wxyz(s.rotation @ R_joint)
                    R_lin = s.rotation @ R_joint
                else:              # slides along the placement's axes, then a ball
                    qpos[qa:qa + 3] = qs[:3]
                    qpos[qa + 3:qa + 7] = qs[[6, 3, 4, 5]]
                    R_lin = R_joint
                T[da:da + 3, vi + 3:vi + 6] = R_lin              # MuJoCo linear = R u
                T[da + 3:da + 6, vi:vi + 3] = np.eye(3)          # MuJoCo angular = w (body frame)
                T_dot_v[da:da + 3] = R_lin @ np.cross(omega, u)  # d/dt(R) u = R (w x u)
            else:                  # planar: (x, y) rates = Rz(theta) (vx, vy)
                qpos[qa:qa + 3] = qs
                R2 = rot_z(qs[2])[:2, :2]
                vxy, wz = np.asarray(v)[vi:vi + 2], v[vi + 2]
                T[da:da + 2, vi:vi + 2] = R2
                T[da + 2, vi + 2] = 1.0
                T_dot_v[da:da + 2] = wz * R2 @ np.array([-vxy[1], vxy[0]])
        elif s.kind == "spherical":
            qpos[qa:qa + 4] = qs[[3, 0, 1, 2]]
            T[da:da + 3, vi:vi + 3] = np.eye(3)
        else:                      # hinges and slides: q and v one to one
            qpos[qa:qa + len(qs)] = qs
            T[da:da + nvj, vi:vi + nvj] = np.eye(nvj)
    return MujocoState(qpos, T, T_dot_v)


def _joint_coordinates(m: soadyn.Model, i: int) -> range:
    end = m.q_index[i + 1] if i + 1 < m.nbodies else m.nq
    return range(m.q_index[i], end)


def _joint_dofs(m: soadyn.Model, i: int) -> range:
    end = m.v_index[i + 1] if i + 1 < m.nbodies else m.nv
    return range(m.v_index[i], end)
