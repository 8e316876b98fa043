"""MuJoCo as an oracle for `soadyn check`, on MJCF files and on URDF files.

MJCF: the MjModel load_mjcf compiled, with the state maps of soadyn.mjcf.
URDF: MuJoCo's own URDF importer reads the file (visual and collision
geometry stripped first, as for DART: no meshes), a free joint 'root_joint'
is added to the root body for a floating base (MjSpec), and joints are
matched to soadyn's DOFs by name.

What MuJoCo computes beyond multibody dynamics is switched off in the
oracle's copy of the model: contacts, equality constraints (soft in MuJoCo;
loops are compared by their KKT system in tests/io/test_mjcf.py), joint limits,
friction loss, actuation, fluid forces and gravity compensation. A URDF's
damping, which MuJoCo imports and soadyn's load_urdf leaves out by default,
is zeroed too. Springs, dampers and armature of an MJCF file stay: soadyn
models them.
"""
from __future__ import annotations

import copy

import numpy as np

from ..io.mjcf import FREE, HINGE, SLIDE, MjcfModel
from .oracles import without_geometry


def _without_constraints(mj):
    import mujoco

    mj = copy.deepcopy(mj)
    flags = mujoco.mjtDisableBit
    for bit in (flags.mjDSBL_CONTACT, flags.mjDSBL_EQUALITY, flags.mjDSBL_FRICTIONLOSS, flags.mjDSBL_LIMIT,
                flags.mjDSBL_ACTUATION):
        mj.opt.disableflags |= int(bit)
    mj.opt.density = 0.0
    mj.opt.viscosity = 0.0
    mj.body_gravcomp[:] = 0.0
    return mj


class MujocoOracle:
    """Forward and inverse dynamics and the mass matrix of MuJoCo, in soadyn's coordinates."""

    def __init__(self, loaded: MjcfModel):
        import mujoco

        self.mujoco = mujoco
        self.loaded = loaded
        self.mj = _without_constraints(loaded.mujoco_model)
        self.data = mujoco.MjData(self.mj)

    def _state(self, q, v):
        qpos, qvel = self.loaded.mujoco_state(q, v)
        self.data.qpos[:], self.data.qvel[:] = qpos, qvel
        return self.loaded.velocity_map(q), self.loaded.velocity_map_rate(q, v)

    def forward_dynamics(self, q, v, tau):
        T, rate = self._state(q, v)
        self.data.qfrc_applied[:] = T @ tau  # T is orthogonal: T^-T = T
        self.mujoco.mj_forward(self.mj, self.data)
        return T.T @ (self.data.qacc - rate)

    def inverse_dynamics(self, q, v, qdd):
        T, rate = self._state(q, v)
        self.data.qacc[:] = T @ qdd + rate
        self.mujoco.mj_inverse(self.mj, self.data)
        return T.T @ self.data.qfrc_inverse

    def mass_matrix(self, q):
        T, _ = self._state(q, np.zeros(self.loaded.model.nv))
        self.mujoco.mj_forward(self.mj, self.data)
        M = np.zeros((self.mj.nv, self.mj.nv))
        unit, column = np.zeros(self.mj.nv), np.zeros(self.mj.nv)
        for k in range(self.mj.nv):
            unit[:] = 0.0
            unit[k] = 1.0
            self.mujoco.mj_mulM(self.mj, self.data, column, unit)
            M[:, k] = column
        return T.T @ M @ T


def urdf_in_mujoco(model, path, floating_base: bool) -> MjcfModel:
    """The URDF compiled by MuJoCo, its joints matched to `model`'s (load_urdf's) by name."""
    import mujoco

    spec = mujoco.MjSpec.from_string(without_geometry(path))
    if floating_base:
        spec.worldbody.first_body().add_freejoint(name="root_joint")
    mj = spec.compile()
    mj.dof_damping[:] = 0.0
    mj.jnt_stiffness[:] = 0.0
    joints = []
    for j in range(mj.njnt):
        name = mujoco.mj_id2name(mj, mujoco.mjtObj.mjOBJ_JOINT, j)
        kind = int(mj.jnt_type[j])
        if kind == FREE:
            body = model.body_index(model.body_names[0]) if model.nbodies else -1
            if not floating_base or body < 0:
                raise ValueError(f"MuJoCo joint '{name}' (free) has no soadyn counterpart")
            joints.append((FREE, model.v_index[body], model.q_index[body]))
            continue
        dof = model.dof_index(name)
        if kind not in (HINGE, SLIDE) or dof < 0:
            raise ValueError(f"MuJoCo joint '{name}' has no matching soadyn DOF")
        joints.append((kind, dof, model.coordinate_names.index(name)))
    return MjcfModel(model, mj, joints)


__all__ = ["MujocoOracle", "urdf_in_mujoco"]
