"""Seeded random trees with modal flexible bodies, and an independent mass
matrix for them: the kinetic energy of every lumped node and rigid body,
assembled from world-frame point velocities built here with numpy (geometric
Jacobians), sharing nothing with the library's recursion."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

import soadyn
from support.trees import random_rotation, random_unit


def skew(p):
    return np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])


def rodrigues(phi):
    theta = np.linalg.norm(phi)
    if theta == 0.0:
        return np.eye(3)
    k = skew(phi / theta)
    return np.eye(3) + np.sin(theta) * k + (1.0 - np.cos(theta)) * k @ k


def left_jacobian(phi):
    """d/dt exp([phi]x) = [Jl(phi) phi_dot]x exp([phi]x) (rotation-vector calculus)."""
    t = np.linalg.norm(phi)
    if t < 1e-6:
        return np.eye(3) + 0.5 * skew(phi)
    k = skew(phi)
    return np.eye(3) + (1 - np.cos(t)) / t**2 * k + (t - np.sin(t)) / t**3 * k @ k


def quaternion_matrix(x, y, z, w):
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def random_flexible_body(rng, n_nodes=6, n_modes=3, damping=False, attachments=("a", "b")):
    """Random lumped body: physical rotary inertias, random 6 x n mode shapes, K SPD."""
    positions = rng.uniform(-0.5, 0.5, size=(n_nodes, 3)) + np.array([0.6, 0.0, 0.0])
    masses = rng.uniform(0.2, 1.0, size=n_nodes)
    rotary = []
    for _ in range(n_nodes):
        R = random_rotation(rng)
        rotary.append(R @ np.diag(rng.uniform(0.01, 0.02, size=3)) @ R.T)
    shapes = rng.normal(scale=0.3, size=(n_nodes, 6, n_modes))
    A = rng.normal(size=(n_modes, n_modes))
    K = A @ A.T + n_modes * np.eye(n_modes) * 20.0
    C = None
    if damping:
        B = rng.normal(size=(n_modes, n_modes))
        C = 0.1 * B @ B.T
    nodes = {name: int(rng.integers(n_nodes)) for name in attachments}
    return soadyn.FlexibleBody(positions, masses, np.array(rotary), shapes, K, C, nodes)


@dataclass
class Part:
    """One body of a test tree, as the oracle sees it."""

    name: str
    parent: str | None            # body name, None for the world
    node: int | None              # attachment node of a flexible parent, None: its body frame
    joint: tuple                  # ("revolute", axis) | ("prismatic", axis) | ("free",) | ("fixed",)
    placement: tuple              # (R, p) in the parent body (or node) frame
    mass: float = 0.0
    com: np.ndarray = field(default_factory=lambda: np.zeros(3))
    inertia: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))
    flexible: soadyn.FlexibleBody | None = None


def _joint(spec):
    kind = spec[0]
    if kind == "revolute":
        return soadyn.Joint.revolute(spec[1])
    if kind == "prismatic":
        return soadyn.Joint.prismatic(spec[1])
    if kind == "free":
        return soadyn.Joint.free()
    return soadyn.Joint.fixed()


def random_flexible_tree(seed, n_bodies=8, floating=False, damping=False, appendages=False):
    """Rigid and flexible bodies in a random tree; children of flexible bodies sit on
    their attachment nodes or on their body frames (`appendages`: on their body frames
    only, so that the flexible bodies are appendages with nothing on their nodes).
    Returns (model, parts)."""
    rng = np.random.default_rng(seed)
    m = soadyn.Model()
    parts: list[Part] = []
    for i in range(n_bodies):
        name = f"b{i}"
        if i == 0:
            parent = None
            joint = ("free",) if floating else ("revolute", random_unit(rng))
        else:
            parent = parts[int(rng.integers(i))].name
            joint = ("revolute", random_unit(rng)) if rng.uniform() < 0.6 else ("prismatic", random_unit(rng))
        node = None
        parent_part = next((p for p in parts if p.name == parent), None)
        parent_ref = parent
        if parent_part is not None and parent_part.flexible is not None and not appendages and rng.uniform() < 0.7:
            attachment = sorted(parent_part.flexible.attachments)[int(rng.integers(2))]
            node = parent_part.flexible.attachments[attachment]
            parent_ref = f"{parent}:{attachment}"
        placement = (random_rotation(rng), rng.uniform(-0.3, 0.3, size=3))
        if i > 0 and rng.uniform() < 0.45:
            if (appendages or not floating) and rng.uniform() < 0.3:
                joint = ("fixed",)  # a clamped flexible body
            body = random_flexible_body(rng, damping=damping)
            m.add_flexible_body(name, parent_ref, body, _joint(joint), placement)
            parts.append(Part(name, parent, node, joint, placement, flexible=body))
        else:
            R = random_rotation(rng)
            inertia = R @ np.diag(rng.uniform(0.02, 0.035, size=3)) @ R.T
            mass, com = rng.uniform(0.5, 2.0), rng.uniform(-0.2, 0.2, size=3)
            m.add_body(name, parent_ref, _joint(joint), placement, mass, com, inertia)
            parts.append(Part(name, parent, node, joint, placement, mass, com, inertia))
    return m, parts


def random_flexible_state(m, seed, eta_scale=0.3):
    rng = np.random.default_rng(seed + 1000)
    q = soadyn.random_configuration(m, seed)
    modal_q = np.array(["mode" in n for n in m.coordinate_names])
    q[modal_q] = rng.uniform(-eta_scale, eta_scale, size=modal_q.sum())
    v = rng.normal(size=m.nv)
    return q, v, rng


def _twist_of_point_motion(omega, velocity, point):
    """Twist (omega, v0) about the world origin of a motion with angular velocity omega
    in which `point` moves with `velocity`: a point x then moves with v0 + omega x x."""
    return np.concatenate([omega, velocity - np.cross(omega, point)])


def _point_jacobian(twists, x):
    """3 x nv velocity Jacobian of world point x moving with the given 6 x nv twists."""
    return twists[3:] + np.cross(twists[:3].T, x).T


def assembled_mass_matrix(m, parts, q):
    """M(q) = sum over every mass element (rigid body, lumped node) of
    m J_x' J_x + J_w' I_world J_w, with the world Jacobians J_x (centre of mass or node
    point) and J_w (spin) built from each DOF's world twist. A node's rotary inertia
    spins with omega + Phi_r eta_dot and keeps the body frame's orientation (the
    library's modelling choice); its point sits at r + Phi_t eta."""
    nv = m.nv
    index = {name: i for i, name in enumerate(m.body_names)}
    pose, twists = {}, {}
    M = np.zeros((nv, nv))
    for part in parts:
        i = index[part.name]
        qi, vi = m.q_index[i], m.v_index[i]
        if part.parent is None:
            R0, p0, T0 = np.eye(3), np.zeros(3), np.zeros((6, nv))
        else:
            R0, p0 = pose[part.parent]
            T0 = twists[part.parent].copy()
            if part.node is not None:  # the node frame of the flexible parent
                parent = next(p for p in parts if p.name == part.parent)
                j = m.body_names.index(part.parent)
                eta = q[m.q_index[j] + _joint_nq(parent.joint):][:parent.flexible.n_modes]
                phi = parent.flexible.mode_shapes[part.node]
                r = parent.flexible.nodes[part.node]
                theta = phi[:3] @ eta
                node_R, node_p = R0 @ rodrigues(theta), p0 + R0 @ (r + phi[3:] @ eta)
                mv = m.v_index[j] + _joint_nv(parent.joint)
                for k in range(parent.flexible.n_modes):
                    omega = R0 @ left_jacobian(theta) @ phi[:3, k]
                    T0[:, mv + k] += _twist_of_point_motion(omega, R0 @ phi[3:, k], node_p)
                R0, p0 = node_R, node_p
        Rj, pj = R0 @ part.placement[0], p0 + R0 @ part.placement[1]
        T = T0
        kind = part.joint[0]
        if kind in ("revolute", "prismatic"):
            axis = Rj @ part.joint[1]
            if kind == "revolute":
                T[:, vi] += np.concatenate([axis, -np.cross(axis, pj)])
                R, p = Rj @ rodrigues(part.joint[1] * q[qi]), pj
            else:
                T[:, vi] += np.concatenate([np.zeros(3), axis])
                R, p = Rj, pj + axis * q[qi]
        elif kind == "free":
            R = Rj @ quaternion_matrix(*q[qi + 3:qi + 7])
            p = pj + Rj @ q[qi:qi + 3]
            for k in range(3):
                T[:, vi + k] += np.concatenate([R[:, k], -np.cross(R[:, k], p)])
                T[:, vi + 3 + k] += np.concatenate([np.zeros(3), R[:, k]])
        else:
            R, p = Rj, pj
        pose[part.name], twists[part.name] = (R, p), T
        if part.flexible is None:
            Jx = _point_jacobian(T, p + R @ part.com)
            M += part.mass * Jx.T @ Jx + T[:3].T @ (R @ part.inertia @ R.T) @ T[:3]
            continue
        body = part.flexible
        mv = vi + _joint_nv(part.joint)
        eta = q[qi + _joint_nq(part.joint):][:body.n_modes]
        for r, mass, J, phi in zip(body.nodes, body.masses, body.rotary_inertias, body.mode_shapes):
            x = p + R @ (r + phi[3:] @ eta)
            Jx = _point_jacobian(T, x)
            Jw = T[:3].copy()
            Jx[:, mv:mv + body.n_modes] += R @ phi[3:]
            Jw[:, mv:mv + body.n_modes] += R @ phi[:3]
            M += mass * Jx.T @ Jx + Jw.T @ (R @ J @ R.T) @ Jw
    return M


def _joint_nq(spec):
    return {"revolute": 1, "prismatic": 1, "free": 7, "fixed": 0}[spec[0]]


def _joint_nv(spec):
    return {"revolute": 1, "prismatic": 1, "free": 6, "fixed": 0}[spec[0]]
