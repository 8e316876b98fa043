"""Serial arms from a table of standard Denavit-Hartenberg parameters.

Standard (distal) convention, as in Paul's "Robot Manipulators: Mathematics, Programming, and Control"
(1981): link i's frame is its parent's times

    A_i = Rot_z(theta_i) Trans_z(d_i) Trans_x(a_i) Rot_x(alpha_i),

joint i turns theta_i (revolute) or slides d_i (prismatic) along the parent frame's z axis, and the
link's centre of mass and inertia are given in link i's own (distal) frame.

In the Model each link is a body whose frame is its joint frame: the parent's DH frame times
Rot_z(theta) for a revolute joint, times Rot_z(theta_i) Trans_z(d) for a prismatic one. The link's DH
frame sits at the fixed rest of A_i in that body (Trans_z(d_i) Trans_x(a_i) Rot_x(alpha_i), or
Trans_x(a_i) Rot_x(alpha_i) for a prismatic joint): the centre of mass and inertia are carried into the
body frame through it, the next joint is placed there, and the last link's DH frame is a frame named
`tool`. The joint coordinate counts from the table's value: a revolute link's theta_i is theta + q,
a prismatic link's d_i is d + q (q = 0 is the table's configuration).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

from .._soadyn import Joint
from ..model import Model

__all__ = ["DHLink", "dh_model", "dh_transform", "JOINT_KINDS"]

JOINT_KINDS = ("revolute", "prismatic")
"""The joint kinds a DH row may have."""


@dataclass(frozen=True)
class DHLink:
    """One row of a standard Denavit-Hartenberg table, with the link's mass properties.

    kind: "revolute" (theta_i = theta + q) or "prismatic" (d_i = d + q). a, d in m; alpha, theta in rad.
    mass in kg; com (m) and inertia (kg m^2, about the centre of mass: 3 principal moments or a 3x3 matrix)
    in the link's DH frame.
    """

    name: str
    kind: str
    a: float = 0.0
    alpha: float = 0.0
    d: float = 0.0
    theta: float = 0.0
    mass: float = 0.0
    com: Sequence[float] = (0.0, 0.0, 0.0)
    inertia: Sequence = (0.0, 0.0, 0.0)


def _rot_z(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _rot_x(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _fixed_rest(link: DHLink) -> tuple[np.ndarray, np.ndarray]:
    """(R, p) of the link's DH frame in its body (joint) frame: A_i without the joint's own motion."""
    d = link.d if link.kind == "revolute" else 0.0
    return _rot_x(link.alpha), np.array([link.a, 0.0, d])


def _joint_placement(link: DHLink) -> tuple[np.ndarray, np.ndarray]:
    """(R, p) of the joint frame at q = 0 in the parent's DH frame."""
    if link.kind == "revolute":
        return _rot_z(link.theta), np.zeros(3)
    return _rot_z(link.theta), np.array([0.0, 0.0, link.d])


def _check(link: DHLink, row: int) -> None:
    if link.kind not in JOINT_KINDS:
        raise ValueError(f"DH row {row} ('{link.name}'): kind must be 'revolute' or 'prismatic', got {link.kind!r}")
    for key in ("a", "alpha", "d", "theta"):
        value = getattr(link, key)
        if not isinstance(value, (int, float, np.floating, np.integer)) or not np.isfinite(value):
            raise ValueError(f"DH row {row} ('{link.name}'): {key} must be a finite number, got {value!r}")


def _to_body_frame(link: DHLink) -> tuple[np.ndarray, np.ndarray]:
    """(com, inertia about the centre of mass) carried from the link's DH frame into its body frame."""
    R, p = _fixed_rest(link)
    inertia = np.asarray(link.inertia, dtype=float)
    if inertia.shape == (3,):
        inertia = np.diag(inertia)
    if inertia.shape != (3, 3):
        raise ValueError(f"DH link '{link.name}': inertia must be 3 principal moments or a 3x3 matrix, "
                         f"got shape {inertia.shape}")
    return R @ np.asarray(link.com, dtype=float) + p, R @ inertia @ R.T


def dh_model(links: Sequence[DHLink], gravity=(0.0, 0.0, -9.81), *,
             accept_nonphysical_inertia: bool = False) -> Model:
    """A serial arm on the world from DH rows (base frame: DH frame 0; gravity in it, m/s^2).

    Bodies and joints take the rows' names (DOF names are the link names); the last DH frame is the
    frame `tool`. ValueError names a row whose kind or numbers are wrong; Model.add_body's errors
    (NonphysicalInertiaError, unless accept_nonphysical_inertia) name the link.
    """
    if len(links) == 0:
        raise ValueError("dh_model: the DH table has no rows")
    m = Model()
    m.gravity = np.asarray(gravity, dtype=float)
    parent, parent_rest = None, (np.eye(3), np.zeros(3))
    for row, link in enumerate(links, start=1):
        _check(link, row)
        R_joint, p_joint = _joint_placement(link)
        R_parent, p_parent = parent_rest
        placement = (R_parent @ R_joint, R_parent @ p_joint + p_parent)
        joint = Joint.revolute([0.0, 0.0, 1.0]) if link.kind == "revolute" else Joint.prismatic([0.0, 0.0, 1.0])
        com, inertia = _to_body_frame(link)
        m.add_body(link.name, parent, joint, placement, link.mass, com, inertia,
                   accept_nonphysical_inertia=accept_nonphysical_inertia)
        parent, parent_rest = link.name, _fixed_rest(link)
    m.add_body("tool", parent, Joint.fixed(), parent_rest)
    return m


def dh_transform(link: DHLink, q: float) -> np.ndarray:
    """A_i (4x4) of the link at joint coordinate q: its DH frame in its parent's DH frame."""
    theta = link.theta + q if link.kind == "revolute" else link.theta
    d = link.d if link.kind == "revolute" else link.d + q
    A = np.eye(4)
    A[:3, :3] = _rot_z(theta) @ _rot_x(link.alpha)
    A[:3, 3] = _rot_z(theta) @ np.array([link.a, 0.0, d])
    return A
