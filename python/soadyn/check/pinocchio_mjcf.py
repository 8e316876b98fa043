"""Pinocchio as an oracle on MJCF files: its own MJCF parser (pin.buildModelFromMJCF).

Pinocchio reads rigid-body data and armature; it has no joint springs or
dampers, so `soadyn check` compares it with the soadyn model's rigid part
(force elements set to zero). Its joints are matched to soadyn's through the
MuJoCo joints they come from: a body with several MJCF joints is one
Pinocchio composite joint named 'Composite_<first joint>', whose DOFs are
that body's joints in file order. A joint kind the map does not know, a
DOF count or a total mass that differs from MuJoCo's compiled model (the
parser drops some bodies' joints, and ignores <compiler settotalmass>) is
refused by name (ValueError), and `soadyn check` reports the oracle as not
compared, with the reason.
"""
from __future__ import annotations

import numpy as np

from ..io.mjcf import BALL, FREE, MjcfModel
from .oracles import PinocchioOracle

COMPOSITE = "Composite_"


class PinocchioMjcfOracle(PinocchioOracle):
    def __init__(self, loaded: MjcfModel, path):  # noqa: D107 - see the module docstring
        import mujoco
        import pinocchio as pin

        self.pin, self.soadyn = pin, loaded.model
        self.model = pin.buildModelFromMJCF(str(path))
        self.data = self.model.createData()
        mj = loaded.mujoco_model
        if self.model.nv != mj.nv:
            raise ValueError(f"Pinocchio's MJCF parser builds {self.model.nv} DOFs where MuJoCo compiles {mj.nv}")
        pin_mass, mj_mass = pin.computeTotalMass(self.model), float(np.sum(mj.body_mass))
        if abs(pin_mass - mj_mass) > 1e-9 * max(1.0, mj_mass):
            raise ValueError(f"Pinocchio's MJCF parser gives a total mass of {pin_mass:.6g} kg where MuJoCo "
                             f"compiles {mj_mass:.6g} kg (for example <compiler settotalmass>)")
        self.model.gravity.linear = np.asarray(loaded.model.gravity, dtype=float)
        joint_id = {mujoco.mj_id2name(mj, mujoco.mjtObj.mjOBJ_JOINT, j): j for j in range(mj.njnt)}
        self.v_of_pin = np.zeros(self.model.nv, dtype=int)
        self.q_parts = []
        for jid in range(1, self.model.njoints):
            joint, name = self.model.joints[jid], self.model.names[jid]
            if name.startswith(COMPOSITE):
                first = joint_id.get(name[len(COMPOSITE):])
                if first is None:
                    raise ValueError(f"Pinocchio joint '{name}' matches no MuJoCo joint")
                body = mj.jnt_bodyid[first]
                members = range(mj.body_jntadr[body], mj.body_jntadr[body] + mj.body_jntnum[body])
                self._scalar_joints(loaded, list(members), joint.idx_q, joint.idx_v, name)
                continue
            j = joint_id.get(name)
            if j is None:
                raise ValueError(f"Pinocchio joint '{name}' matches no MuJoCo joint")
            kind, vi, qi = loaded.joints[j]
            if kind == FREE:
                self.v_of_pin[joint.idx_v:joint.idx_v + 6] = vi + np.array([3, 4, 5, 0, 1, 2])
                self.q_parts.append((joint.idx_q, 7, qi, "free"))
            elif kind == BALL:
                self.v_of_pin[joint.idx_v:joint.idx_v + 3] = vi + np.arange(3)
                self.q_parts.append((joint.idx_q, 4, qi, "free"))  # (x, y, z, w) in both: copied as is
            else:
                self.v_of_pin[joint.idx_v] = vi
                self.q_parts.append((joint.idx_q, joint.nq, qi, "scalar"))

    def _scalar_joints(self, loaded, members, idx_q, idx_v, name) -> None:
        for k, j in enumerate(members):
            kind, vi, qi = loaded.joints[j]
            if kind in (FREE, BALL):
                raise ValueError(f"Pinocchio joint '{name}': a ball or free joint inside a composite is not mapped")
            self.v_of_pin[idx_v + k] = vi
            self.q_parts.append((idx_q + k, 1, qi, "scalar"))

    def q(self, q: np.ndarray) -> np.ndarray:
        out = np.zeros(self.model.nq)
        for start, nq, k, kind in self.q_parts:
            if kind == "free":
                out[start:start + nq] = q[k:k + nq]
            elif nq == 2:
                out[start:start + 2] = np.cos(q[k]), np.sin(q[k])
            else:
                out[start] = q[k]
        return out
