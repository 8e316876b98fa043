"""Seeded random trees for the tests: every joint type, free-floating roots,
random placements and physical inertias. Bodies are added depth-first so the
same tree can be rebuilt in Pinocchio, which needs that order."""
from __future__ import annotations

import numpy as np

import soadyn

JOINT_KINDS = ("revolute", "prismatic", "helical", "universal", "cylindrical", "planar", "spherical", "free",
               "translation")


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q @ np.diag(np.sign(np.diag(r)))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


def random_unit(rng: np.random.Generator) -> np.ndarray:
    a = rng.normal(size=3)
    return a / np.linalg.norm(a)


def random_inertia(rng: np.random.Generator) -> np.ndarray:
    """Rotational inertia about the COM of a random solid box."""
    a, b, c = rng.uniform(0.1, 1.0, size=3)
    m = 1.0
    principal = m / 12 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
    R = random_rotation(rng)
    return R @ np.diag(principal) @ R.T


def random_joint(rng: np.random.Generator, kind: str) -> soadyn.Joint:
    if kind == "revolute":
        return soadyn.Joint.revolute(random_unit(rng))
    if kind == "prismatic":
        return soadyn.Joint.prismatic(random_unit(rng))
    if kind == "helical":
        return soadyn.Joint.helical(random_unit(rng), float(rng.uniform(-0.3, 0.3)))
    if kind == "universal":
        a1 = random_unit(rng)
        a2 = np.cross(a1, random_unit(rng))  # orthogonal axes, as Pinocchio requires
        return soadyn.Joint.universal(a1, a2 / np.linalg.norm(a2))
    if kind == "cylindrical":
        return soadyn.Joint.cylindrical(random_unit(rng))
    return getattr(soadyn.Joint, kind)()


def random_tree(seed: int, nbodies: int = 12, kinds=JOINT_KINDS, floating: bool = True,
                branching: float = 0.5) -> tuple[soadyn.Model, list[str]]:
    """A random tree; returns the model and the joint kind of every body.

    The root is free-floating when `floating`; every kind in `kinds` appears
    at least once when nbodies allows. Parents are chosen so bodies come in
    depth-first order (each new body hangs off the previous body or one of
    its ancestors).
    """
    rng = np.random.default_rng(seed)
    m = soadyn.Model()
    order = list(kinds) * (nbodies // len(kinds) + 1)
    rng.shuffle(order)
    chosen = (["free"] if floating else []) + order
    chosen = chosen[:nbodies]
    parents: list[int] = []
    for i, kind in enumerate(chosen):
        if i == 0:
            parent = -1
        else:
            # Walk up from the previous body: keeps depth-first order.
            parent = i - 1
            while parent >= 0 and rng.uniform() < branching:
                parent = parents[parent]
            if floating and parent < 0:
                parent = 0
        parents.append(parent)
        placement = (random_rotation(rng), rng.uniform(-0.5, 0.5, size=3))
        m.add_body(f"b{i}", parent, random_joint(rng, kind), placement=placement,
                   mass=float(rng.uniform(0.5, 3.0)), com=rng.uniform(-0.3, 0.3, size=3),
                   inertia=random_inertia(rng) * rng.uniform(0.5, 2.0))
    return m, chosen


def random_state(m: soadyn.Model, seed: int):
    rng = np.random.default_rng(seed + 1000)
    q = soadyn.random_configuration(m, seed)
    v = rng.normal(size=m.nv)
    return q, v, rng
