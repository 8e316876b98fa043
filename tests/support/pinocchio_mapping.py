"""soadyn <-> Pinocchio correspondence of coordinates and DOFs, matched by
name joint by joint, shared by the Pinocchio oracle tests (rigid trees in
dynamics/test_pinocchio_oracle.py, flexible trees in flex/test_flexible_pinocchio.py).

Each Pinocchio joint is described by a JointMatch: its joint id, the soadyn
coordinate names of its q and the soadyn DOF names of its v, both in
Pinocchio's order. Nothing assumes that the two libraries order coordinates
alike; the maps are checked to be bijections.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

# A free joint's coordinate and DOF name suffixes: q is (position, quaternion x y z w) in both libraries;
# v is (angular, linear) in soadyn and (linear, angular) in Pinocchio, both in the body frame.
FREE_Q = ("px", "py", "pz", "qx", "qy", "qz", "qw")
FREE_V_PIN = ("vx", "vy", "vz", "wx", "wy", "wz")


@dataclass(frozen=True)
class JointMatch:
    joint_id: int               # Pinocchio joint id
    q_names: tuple              # soadyn coordinate names, Pinocchio's order
    v_names: tuple              # soadyn DOF names, Pinocchio's order
    planar: bool = False        # soadyn (x, y, theta) is Pinocchio's (x, y, cos theta, sin theta)


def free_joint_names(name: str) -> tuple[tuple, tuple]:
    """(q_names, v_names) of a soadyn free joint `name` in Pinocchio's order."""
    return tuple(f"{name}:{c}" for c in FREE_Q), tuple(f"{name}:{c}" for c in FREE_V_PIN)


class PinocchioMapping:
    """Name-matched coordinate and DOF maps between a soadyn Model `m` and a pin.Model."""

    def __init__(self, m, model: pin.Model, joints: list[JointMatch]):
        self.m, self.model, self.joints = m, model, list(joints)
        self.v_of_pin = np.full(model.nv, -1)   # soadyn DOF index of each Pinocchio DOF
        self._q_parts = []                      # (Pinocchio q slice, soadyn coordinate indices, planar)
        for match in self.joints:
            joint = model.joints[match.joint_id]
            assert len(match.v_names) == joint.nv, model.names[match.joint_id]
            assert joint.nq == len(match.q_names) + (1 if match.planar else 0), model.names[match.joint_id]
            self.v_of_pin[joint.idx_v:joint.idx_v + joint.nv] = [m.dof_names.index(n) for n in match.v_names]
            self._q_parts.append((slice(joint.idx_q, joint.idx_q + joint.nq),
                                  np.array([m.coordinate_names.index(n) for n in match.q_names]), match.planar))
        q_indices = sorted(int(k) for _, qi, _ in self._q_parts for k in qi)
        assert q_indices == list(range(m.nq)), "coordinates are not a bijection"
        assert sorted(self.v_of_pin) == list(range(m.nv)), "DOFs are not a bijection"
        assert model.nv == m.nv

    @property
    def perm(self) -> np.ndarray:
        """perm[k] = soadyn DOF index of Pinocchio DOF k."""
        return self.v_of_pin

    def q(self, q_soa) -> np.ndarray:
        q_soa = np.asarray(q_soa)
        q_pin = np.empty(self.model.nq)
        for pin_slice, qi, planar in self._q_parts:
            x = q_soa[qi]
            q_pin[pin_slice] = [x[0], x[1], np.cos(x[2]), np.sin(x[2])] if planar else x
        return q_pin

    def v(self, x_soa) -> np.ndarray:
        """A velocity, acceleration or generalized force in Pinocchio's DOF order."""
        return np.asarray(x_soa)[self.v_of_pin]

    def back(self, x_pin) -> np.ndarray:
        """A Pinocchio DOF vector in soadyn's order."""
        out = np.empty(len(x_pin))
        out[self.v_of_pin] = x_pin
        return out

    def matrix_to_pin(self, M_soa) -> np.ndarray:
        return np.asarray(M_soa)[np.ix_(self.v_of_pin, self.v_of_pin)]

    def matrix_from_pin(self, M_pin) -> np.ndarray:
        out = np.empty_like(M_pin)
        out[np.ix_(self.v_of_pin, self.v_of_pin)] = M_pin
        return out

    def f_ext(self, f_soa, body_joint_ids) -> pin.StdVec_Force:
        """soadyn rows [torque; force] about body i's origin in its frame -> one pin.Force
        (linear, angular) per joint in the joint frame, universe first; body i's wrench goes to
        Pinocchio joint body_joint_ids[i] (its frame being the body frame)."""
        forces = [pin.Force.Zero() for _ in range(self.model.njoints)]
        for i, jid in enumerate(body_joint_ids):
            forces[jid] = pin.Force(f_soa[i, 3:], f_soa[i, :3])
        return pin.StdVec_Force(forces)
