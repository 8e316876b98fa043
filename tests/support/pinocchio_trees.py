"""Seeded random trees built identically in soadyn and Pinocchio.

soadyn's Python model does not expose axes, placements or inertias, so each
tree is drawn once as an explicit list of BodySpec parameters and both
libraries are built from that list. DOFs are matched joint by joint through
the body name b<i> (soadyn body name == Pinocchio joint name), never by
assuming the two libraries order coordinates the same way. make_case gives
both models of one of CASES (test ids CASE_IDS) at a random configuration.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

import soadyn
from support.pinocchio_mapping import JointMatch, PinocchioMapping, free_joint_names
from support.trees import JOINT_KINDS, random_inertia, random_rotation, random_unit

SEEDS = range(6)
CASES = [(seed, floating) for seed in SEEDS for floating in (True, False)]
CASE_IDS = [f"seed{seed}-{'floating' if floating else 'fixed'}" for seed, floating in CASES]


# ---------------------------------------------------------------------------
# Random tree parameters
# ---------------------------------------------------------------------------

@dataclass(frozen=True)
class BodySpec:
    name: str
    parent: int          # body index, -1 = world
    kind: str            # one of JOINT_KINDS
    axis: np.ndarray     # revolute/prismatic/helical/cylindrical axis; first universal axis
    axis2: np.ndarray    # second universal axis (orthogonal to axis)
    pitch: float         # helical: metres of travel per radian
    rotation: np.ndarray  # joint frame in the parent body frame: (rotation, translation)
    translation: np.ndarray
    mass: float
    com: np.ndarray      # body frame
    inertia: np.ndarray  # 3x3 about the COM, body frame


def coordinate_axes_pair(i: int) -> tuple[np.ndarray, np.ndarray]:
    """Two orthogonal signed coordinate axes, varied with i: universal joints of
    even seeds take them (the axis-aligned kernel), odd seeds random axes."""
    k = i % 3
    a1, a2 = np.zeros(3), np.zeros(3)
    a1[k] = 1.0 if (i // 3) % 2 == 0 else -1.0
    a2[(k + 1 + i % 2) % 3] = -1.0 if (i // 2) % 2 == 0 else 1.0
    return a1, a2


def random_specs(seed: int, floating: bool) -> list[BodySpec]:
    """12-20 bodies in depth-first order with every joint kind present.

    Each new body hangs off the previous body or one of its ancestors, which
    keeps the depth-first order Pinocchio needs (contiguous subtrees).
    """
    rng = np.random.default_rng(seed)
    nbodies = int(rng.integers(12, 21))
    root = ["free"] if floating else []
    # One of each kind plus random extras, shuffled below the (optional) free root.
    rest = list(JOINT_KINDS) + [str(k) for k in
                                rng.choice(JOINT_KINDS, size=nbodies - len(JOINT_KINDS) - len(root))]
    rng.shuffle(rest)
    kinds = root + rest

    specs: list[BodySpec] = []
    for i, kind in enumerate(kinds):
        parent = i - 1
        while parent >= 0 and rng.uniform() < 0.5:
            parent = specs[parent].parent
        if floating and i > 0 and parent < 0:
            parent = 0  # a single floating base carries everything
        a1 = random_unit(rng)
        a2 = np.cross(a1, random_unit(rng))
        if kind == "universal" and seed % 2 == 0:
            a1, a2 = coordinate_axes_pair(i)
        specs.append(BodySpec(
            name=f"b{i}", parent=parent, kind=kind,
            axis=a1, axis2=a2 / np.linalg.norm(a2), pitch=float(rng.uniform(-0.3, 0.3)),
            rotation=random_rotation(rng), translation=rng.uniform(-0.5, 0.5, size=3),
            mass=float(rng.uniform(0.5, 3.0)), com=rng.uniform(-0.3, 0.3, size=3),
            inertia=random_inertia(rng) * rng.uniform(0.5, 2.0)))
    return specs


# ---------------------------------------------------------------------------
# Building both models from the same specs
# ---------------------------------------------------------------------------

def soadyn_joint(s: BodySpec) -> soadyn.Joint:
    J = soadyn.Joint
    return {
        "revolute": lambda: J.revolute(s.axis),
        "prismatic": lambda: J.prismatic(s.axis),
        "helical": lambda: J.helical(s.axis, s.pitch),
        "universal": lambda: J.universal(s.axis, s.axis2),
        "cylindrical": lambda: J.cylindrical(s.axis),
        "planar": J.planar,
        "spherical": J.spherical,
        "free": J.free,
        "translation": J.translation,
    }[s.kind]()


def pin_joint(s: BodySpec):
    """The Pinocchio joint with the same motion as soadyn's (conventions checked numerically:
    HelicalUnaligned translates pitch*q along the axis, Universal is Rot(a1,q0)*Rot(a2,q1),
    Planar places the body at (x, y, 0) rotated by Rz(theta), Translation at q with q = v)."""
    if s.kind == "cylindrical":
        # No cylindrical joint in Pinocchio: a revolute then a prismatic about the same axis
        # (they commute), giving q = v layout (angle, offset) like soadyn.
        joint = pin.JointModelComposite(2)
        joint.addJoint(pin.JointModelRevoluteUnaligned(s.axis))
        joint.addJoint(pin.JointModelPrismaticUnaligned(s.axis))
        return joint
    return {
        "revolute": lambda: pin.JointModelRevoluteUnaligned(s.axis),
        "prismatic": lambda: pin.JointModelPrismaticUnaligned(s.axis),
        "helical": lambda: pin.JointModelHelicalUnaligned(s.axis, s.pitch),
        "universal": lambda: pin.JointModelUniversal(s.axis, s.axis2),
        "planar": pin.JointModelPlanar,
        "spherical": pin.JointModelSpherical,
        "free": pin.JointModelFreeFlyer,
        "translation": pin.JointModelTranslation,
    }[s.kind]()


def build_soadyn(specs: list[BodySpec]) -> soadyn.Model:
    m = soadyn.Model()
    for s in specs:
        m.add_body(s.name, s.parent, soadyn_joint(s), placement=(s.rotation, s.translation),
                   mass=s.mass, com=s.com, inertia=s.inertia)
    return m


def build_pinocchio(specs: list[BodySpec], gravity: np.ndarray) -> pin.Model:
    model = pin.Model()
    model.gravity.linear = np.asarray(gravity, dtype=float)
    for s in specs:
        # Pinocchio joint 0 is the universe, so soadyn body k is joint k + 1 (world -1 -> 0).
        # soadyn's body frame is the joint frame moved by the joint, i.e. Pinocchio's joint
        # frame, so the body's inertia is attached with the identity placement.
        jid = model.addJoint(s.parent + 1, pin_joint(s), pin.SE3(s.rotation, s.translation), s.name)
        model.appendBodyToJoint(jid, pin.Inertia(s.mass, s.com, s.inertia), pin.SE3.Identity())
    return model


# ---------------------------------------------------------------------------
# Coordinate and DOF mapping
# ---------------------------------------------------------------------------

class Mapping(PinocchioMapping):
    """soadyn <-> Pinocchio configuration and DOF correspondence, joint by joint: the
    Pinocchio joint of body b<i> is named b<i> and carries the body's coordinates and DOFs."""

    def __init__(self, m: soadyn.Model, model: pin.Model, specs: list[BodySpec]):
        self.specs = specs
        self.joint_ids = []
        joints = []
        q_ranges = _segments(m.q_index, m.nq)
        v_ranges = _segments(m.v_index, m.nv)
        for i, s in enumerate(specs):
            assert m.body_names[i] == s.name and m.joint_types[i] == s.kind
            jid = model.getJointId(s.name)
            assert model.parents[jid] == s.parent + 1
            q_names = tuple(m.coordinate_names[k] for k in q_ranges[i])
            v_names = tuple(m.dof_names[k] for k in v_ranges[i])
            if s.kind == "free":
                q_names, v_names = free_joint_names(s.name)
            # Every other kind has the same layout in both (quaternions (x, y, z, w)), but
            # the planar joint's angle, which Pinocchio stores as (cos, sin).
            joints.append(JointMatch(jid, q_names, v_names, planar=s.kind == "planar"))
            self.joint_ids.append(jid)
        super().__init__(m, model, joints)
        assert model.njoints == m.nbodies + 1

    def matrix(self, M_soa: np.ndarray) -> np.ndarray:
        return self.matrix_to_pin(M_soa)

    def f_ext(self, f_soa: np.ndarray) -> list:
        return super().f_ext(f_soa, self.joint_ids)


def _segments(starts, total: int) -> list[range]:
    """Per-body index ranges from the start indices (bodies are stored contiguously)."""
    ends = list(starts[1:]) + [total]
    return [range(a, b) for a, b in zip(starts, ends)]


@dataclass
class Case:
    specs: list[BodySpec]
    m: soadyn.Model
    model: pin.Model
    data: pin.Data
    map: Mapping
    rng: np.random.Generator
    q: np.ndarray      # soadyn configuration
    q_pin: np.ndarray


@functools.lru_cache(maxsize=None)
def _built(seed: int, floating: bool):
    specs = random_specs(seed, floating)
    m = build_soadyn(specs)
    model = build_pinocchio(specs, m.gravity)
    return specs, m, model, Mapping(m, model, specs)


def make_case(seed: int, floating: bool) -> Case:
    specs, m, model, mapping = _built(seed, floating)
    q = soadyn.random_configuration(m, seed)
    return Case(specs, m, model, model.createData(), mapping, np.random.default_rng(seed + 100),
                q, mapping.q(q))
