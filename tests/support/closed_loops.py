"""Random trees closed by loops at a drawn configuration: closed_loop_case closes the trees of
support/pinocchio_trees.py with point and weld loops, in soadyn and as Pinocchio's rigid constraints
(pinocchio_solution solves Pinocchio's constraint dynamics); closed_random_loops closes the random
trees of trees.py with loops of any kind."""
from __future__ import annotations

import numpy as np
import pinocchio as pin

import soadyn
from support.pinocchio_trees import Mapping, build_pinocchio, build_soadyn, random_specs
from support.trees import random_tree


def _pose(T):
    return T[:3, :3], T[:3, 3]


def closed_loop_case(seed, floating, nloops, kinds):
    """The random tree (seed, floating) closed by `nloops` loops of `kinds` (in turn) at q: the soadyn
    model, the Pinocchio model, their Mapping, Pinocchio's constraints, q, v on the loops' tangent
    space, the generator drawn from, and the last loop's frame_a in the world."""
    specs = random_specs(seed, floating)
    m = build_soadyn(specs)
    model = build_pinocchio(specs, m.gravity)
    mapping = Mapping(m, model, specs)
    rng = np.random.default_rng(100 + seed)
    q = soadyn.random_configuration(m, seed)
    poses = soadyn.forward_kinematics(m, q)[0]
    constraints = []
    for k in range(nloops):
        a, b = rng.choice(np.arange(-1, m.nbodies), size=2, replace=False)
        if a < 0:
            a, b = b, a
        kind = kinds[k % len(kinds)]
        Ra = np.linalg.qr(rng.normal(size=(3, 3)))[0]
        Ra *= np.sign(np.linalg.det(Ra))
        pa = rng.uniform(-0.3, 0.3, size=3)
        A_world = poses[a] @ np.block([[Ra, pa[:, None]], [np.zeros((1, 3)), np.ones((1, 1))]])
        B_body = A_world if b < 0 else np.linalg.solve(poses[b], A_world)  # closed at q
        m.add_loop(f"loop{k}", m.body_names[a], None if b < 0 else m.body_names[b], kind,
                   placement_a=(Ra, pa), placement_b=_pose(B_body))
        ctype = pin.ContactType.CONTACT_3D if kind == "point" else pin.ContactType.CONTACT_6D
        constraints.append(pin.RigidConstraintModel(ctype, model, int(a) + 1, pin.SE3(Ra, pa), int(b) + 1,
                                                    pin.SE3(*_pose(B_body)), pin.ReferenceFrame.LOCAL))
    C = soadyn.loop_jacobian(m, q)
    v = rng.normal(size=m.nv)
    v -= np.linalg.pinv(C) @ (C @ v)  # on the tangent space of the loops
    return m, model, mapping, constraints, q, v, rng, A_world


def pinocchio_solution(model, mapping, constraints, q, v, tau):
    """Pinocchio's accelerations (in soadyn's DOF order) and multipliers under torques tau."""
    data = model.createData()
    models = pin.StdVec_RigidConstraintModel()
    for c in constraints:
        models.append(c)
    datas = pin.StdVec_RigidConstraintData()
    for c in constraints:
        datas.append(c.createData())
    pin.initConstraintDynamics(model, data, models, datas)
    settings = pin.ProximalSettings(1e-14, 1e-12, 200)
    ddq = pin.constraintDynamics(model, data, mapping.q(q), mapping.v(v), mapping.v(tau), models, datas,
                                 settings)
    return mapping.back(ddq), np.array(data.lambda_c)


def closed_random_loops(seed, kinds):
    """A random tree with one loop of each kind in `kinds`, closed at the returned q."""
    m, _ = random_tree(seed, nbodies=10)
    rng = np.random.default_rng(seed)
    q = soadyn.random_configuration(m, seed)
    poses = soadyn.forward_kinematics(m, q)[0]
    for k, kind in enumerate(kinds):
        a, b = rng.choice(np.arange(-1, m.nbodies), size=2, replace=False)
        if a < 0:
            a, b = b, a
        R = np.linalg.qr(rng.normal(size=(3, 3)))[0]
        R *= np.sign(np.linalg.det(R))
        p = rng.uniform(-0.3, 0.3, size=3)
        A = poses[a] @ np.block([[R, p[:, None]], [np.zeros((1, 3)), np.ones((1, 1))]])
        B = A if b < 0 else np.linalg.solve(poses[b], A)
        Bp = B.copy()
        length = None
        if kind == "distance":  # frame B's origin 0.4 m away from A's
            Bp[:3, 3] = B[:3, 3] + B[:3, :3] @ (0.4 * np.array([0.6, 0.0, 0.8]))
            length = 0.4
        if kind == "prismatic":  # A's origin on B's z axis, 0.25 m along it
            Bp[:3, 3] = B[:3, 3] - B[:3, 2] * 0.25
        m.add_loop(f"{kind}{k}", m.body_names[a], None if b < 0 else m.body_names[b], kind,
                   placement_a=(R, p), placement_b=(Bp[:3, :3], Bp[:3, 3]), length=length)
    return m, q, rng
