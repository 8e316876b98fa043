"""Flexible bodies against Pinocchio as an exact oracle.

A lumped flexible body whose every mode moves a single node along (or about)
a single axis is a rigid tree: the reference body (the nodes no mode moves)
on the body's hinge, and for each moved node a chain at its undeformed
position r of a prismatic joint along u (the mode that translates it) then a
revolute joint about a (the mode that rotates it), whose last body carries
the node's point mass and rotary inertia. The node then sits at r + u eta_k
rotated by exp([a eta_l]x), which is soadyn's node pose. Rotary inertias are
isotropic (j I), so that soadyn's choice of keeping them in the undeformed
orientation is immaterial. The elastic forces -K eta - C eta_dot, which
soadyn applies internally, are given to Pinocchio as joint torques of the
modal joints (K symmetric positive definite and coupled, C positive
semidefinite or zero).

Each tree is drawn once as a list of parts and both libraries are built
from it. Coordinates and DOFs are matched by name: the Pinocchio joint of
mode k of body F is named 'F:mode<k>', like soadyn's modal DOF.

Run with `pytest -s` to see the largest relative error per quantity.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin
import pytest

import soadyn
from support.error_log import ErrorLog, report_fixture
from support.pinocchio_mapping import FREE_Q, FREE_V_PIN, JointMatch, PinocchioMapping
from support.trees import random_inertia, random_rotation, random_unit

RTOL = 1e-10
LAYOUTS = ("floating", "fixed", "flexible_root", "appendages")
SEEDS = (0, 1, 2)
STATES = (0, 1, 2)
MODELS = [(layout, seed) for layout in LAYOUTS for seed in SEEDS]
CASES = [(layout, seed, state) for layout, seed in MODELS for state in STATES]
CASE_IDS = [f"{layout}-seed{seed}-state{state}" for layout, seed, state in CASES]



# ---------------------------------------------------------------------------
# Tree parameters
# ---------------------------------------------------------------------------

@dataclass
class FlexSpec:
    """Lumped body whose mode k moves node modes[k][0]: ('t', u) translates it along u,
    ('r', a) rotates it about a (unit axes, body frame)."""

    positions: np.ndarray   # (N, 3)
    masses: np.ndarray      # (N,)
    spins: np.ndarray       # (N,) isotropic rotary inertia j (J = j I)
    modes: list             # [(node, 't' | 'r', axis)] in mode order
    K: np.ndarray
    C: np.ndarray | None
    attachments: dict       # name -> node

    @property
    def n_modes(self) -> int:
        return len(self.modes)

    def mode_shapes(self) -> np.ndarray:
        phi = np.zeros((len(self.masses), 6, self.n_modes))
        for k, (node, kind, axis) in enumerate(self.modes):
            phi[node, :3, k] = axis if kind == "r" else 0.0
            phi[node, 3:, k] = axis if kind == "t" else 0.0
        return phi

    def node_modes(self, node: int) -> dict:
        """{'t': k, 'r': l} for the modes moving `node`."""
        return {kind: k for k, (j, kind, _) in enumerate(self.modes) if j == node}

    def soadyn_body(self) -> soadyn.FlexibleBody:
        rotary = np.array([j * np.eye(3) for j in self.spins])
        return soadyn.FlexibleBody(self.positions, self.masses, rotary, self.mode_shapes(), self.K, self.C,
                                   self.attachments)


# Per node: which modes move it. Every kind appears; attachments go to a node moved by a
# translation and a rotation, to a node moved by one mode, and to a node no mode moves.
NODE_PLAN = ("", "t", "r", "tr", "tr", "", "t", "r")

# The order in which node_plan gives nodes their modes.
MODE_ORDER = ((1, "t"), (1, "r"), (3, "t"), (4, "r"), (6, "t"), (6, "r"), (7, "t"), (2, "r"), (5, "t"), (5, "r"))


def node_plan(n_modes: int) -> tuple:
    """Eight nodes moved by n_modes modes (n_modes <= 10); from two on, a node has both kinds."""
    plan = [""] * len(NODE_PLAN)
    for node, kind in MODE_ORDER[:n_modes]:
        plan[node] += kind
    return tuple(plan)


def random_flexible(rng: np.random.Generator, damping: bool, modal: bool = False,
                    plan: tuple = NODE_PLAN) -> FlexSpec:
    plan = list(plan)
    rng.shuffle(plan)
    n_nodes = len(plan)
    positions = rng.uniform(-0.4, 0.4, size=(n_nodes, 3)) + np.array([0.5, 0.0, 0.0])
    masses = rng.uniform(0.2, 1.0, size=n_nodes)
    spins = rng.uniform(0.01, 0.05, size=n_nodes)
    modes = [(j, kind, random_unit(rng)) for j, kinds in enumerate(plan) for kind in kinds]
    modes = [modes[i] for i in rng.permutation(len(modes))]  # mode numbers do not follow the nodes
    n = len(modes)
    A = rng.normal(size=(n, n))
    K = A @ A.T + 5.0 * np.eye(n) * rng.uniform(1.0, 4.0)
    C = None
    if modal:  # uncoupled modes with modal damping: diagonal K and C
        K = np.diag(rng.uniform(5.0, 20.0, size=n))
        C = np.diag(rng.uniform(0.05, 0.5, size=n))
    elif damping:
        B = rng.normal(size=(n, max(n - 2, 1)))  # rank-deficient (from 3 modes on): positive semidefinite
        C = 0.2 * B @ B.T
    # A node of one of those kinds (any node in a plan with none: appendages carry nothing).
    pick = lambda kinds: int(rng.choice([j for j, k in enumerate(plan) if k in kinds] or list(range(n_nodes))))
    attachments = {"a": pick(("tr",)), "b": pick(("t", "r")), "c": pick(("",))}
    return FlexSpec(positions, masses, spins, modes, K, C, attachments)


@dataclass
class Part:
    name: str
    parent: str | None     # None (world), a body name or a frame '<flexible>:<attachment>'
    joint: tuple           # ('revolute', axis) | ('prismatic', axis) | ('free',) | ('fixed',)
    placement: tuple       # (R, p) of the joint frame in the parent frame
    mass: float = 0.0
    com: np.ndarray = field(default_factory=lambda: np.zeros(3))
    inertia: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))
    flexible: FlexSpec | None = None


# name, parent, joint kind, body kind ('rigid' | 'flexible' | 'flexible-damped' |
# 'flexible-modal': diagonal K and C).
LAYOUT_PARTS = {
    # Free-floating rigid root carrying flexible bodies, with children on moved and unmoved
    # nodes and on the flexible body's reference frame.
    "floating": [
        ("b0", None, "free", "rigid"),
        ("f1", "b0", "revolute", "flexible-damped"),
        ("c1", "f1:a", "revolute", "rigid"),
        ("c2", "f1", "prismatic", "rigid"),
        ("f2", "f1:b", "prismatic", "flexible"),
        ("c3", "f2:a", "revolute", "rigid"),
        ("c4", "f1:c", "prismatic", "rigid"),
        ("c5", "f2:b", "prismatic", "rigid"),
        ("c6", "b0", "revolute", "rigid"),
    ],
    # Fixed base: a hinged flexible root, a clamped flexible body on one of its nodes and a
    # hinged flexible body on a node of the clamped one.
    "fixed": [
        ("f1", None, "revolute", "flexible-damped"),
        ("c1", "f1:a", "revolute", "rigid"),
        ("f2", "f1:b", "fixed", "flexible-damped"),
        ("c2", "f2:a", "prismatic", "rigid"),
        ("c3", "f1", "revolute", "rigid"),
        ("f3", "f2:c", "revolute", "flexible-modal"),
        ("c4", "c1", "revolute", "rigid"),
        ("c5", "f3:a", "revolute", "rigid"),
        ("c6", "f1:c", "revolute", "rigid"),
    ],
    # A free-floating flexible root.
    "flexible_root": [
        ("f0", None, "free", "flexible"),
        ("c1", "f0:a", "revolute", "rigid"),
        ("f1", "f0:b", "revolute", "flexible-damped"),
        ("c2", "f1:c", "prismatic", "rigid"),
        ("c3", "f0", "revolute", "rigid"),
    ],
    # Appendages: flexible bodies with nothing on their nodes (the tree-frame sweeps
    # eliminate their modes in the body frame, or in the root's frame for a boom welded
    # to the root): a boom clamped to a free-floating rigid root, a hinged one carrying a
    # body on its reference frame, one on a sliding body.
    "appendages": [
        ("b0", None, "free", "rigid"),
        ("f1", "b0", "fixed", "flexible-damped"),
        ("f2", "b0", "revolute", "flexible-modal"),
        ("c1", "f2", "prismatic", "rigid"),
        ("c2", "b0", "revolute", "rigid"),
        ("f3", "c2", "prismatic", "flexible-damped"),
    ],
}


def random_parts(layout: str, seed: int, n_modes: int | None = None) -> list[Part]:
    """n_modes: every flexible body's mode count (node_plan), else NODE_PLAN's."""
    rng = np.random.default_rng(seed + 17 * LAYOUTS.index(layout))
    plan = NODE_PLAN if n_modes is None else node_plan(n_modes)
    parts = []
    for name, parent, kind, body in LAYOUT_PARTS[layout]:
        joint = (kind, random_unit(rng)) if kind in ("revolute", "prismatic") else (kind,)
        placement = (random_rotation(rng), rng.uniform(-0.4, 0.4, size=3))
        if body == "rigid":
            parts.append(Part(name, parent, joint, placement, mass=float(rng.uniform(0.5, 2.0)),
                              com=rng.uniform(-0.3, 0.3, size=3),
                              inertia=random_inertia(rng) * rng.uniform(0.3, 1.0)))
        else:
            parts.append(Part(name, parent, joint, placement,
                              flexible=random_flexible(rng, damping=body == "flexible-damped",
                                                       modal=body == "flexible-modal", plan=plan)))
    return parts


# ---------------------------------------------------------------------------
# Building both models
# ---------------------------------------------------------------------------

def soadyn_joint(joint: tuple):
    kind = joint[0]
    if kind == "revolute":
        return soadyn.Joint.revolute(joint[1])
    if kind == "prismatic":
        return soadyn.Joint.prismatic(joint[1])
    if kind == "free":
        return soadyn.Joint.free()
    return None


def build_soadyn(parts: list[Part]) -> soadyn.Model:
    m = soadyn.Model()
    m.gravity = [0.0, 0.0, -9.81]
    for p in parts:
        if p.flexible is not None:
            m.add_flexible_body(p.name, p.parent, p.flexible.soadyn_body(), joint=soadyn_joint(p.joint),
                                placement=p.placement)
        else:
            m.add_body(p.name, p.parent, soadyn_joint(p.joint), p.placement, p.mass, p.com, p.inertia)
    return m


@dataclass
class PinJoint:
    """A Pinocchio joint to be added, with the bodies it carries and its DOF names."""

    name: str
    model: object
    parent: "PinJoint | None"   # None: the universe
    placement: pin.SE3
    inertias: list = field(default_factory=list)   # [(pin.Inertia, placement in the joint frame)]
    children: list = field(default_factory=list)

    def coordinate_names(self):
        return [f"{self.name}:{c}" for c in FREE_Q] if self.model.nq == 7 else [self.name]

    def dof_names(self):
        return [f"{self.name}:{c}" for c in FREE_V_PIN] if self.model.nv == 6 else [self.name]


def pin_joint_model(joint: tuple):
    kind = joint[0]
    if kind == "revolute":
        return pin.JointModelRevoluteUnaligned(joint[1])
    if kind == "prismatic":
        return pin.JointModelPrismaticUnaligned(joint[1])
    return pin.JointModelFreeFlyer()


class PinTree:
    """The rigid-tree equivalent of the parts. A frame is an anchor (PinJoint or None for
    the universe, placement in that joint's frame): clamped bodies and nodes no mode moves
    have no joint of their own."""

    def __init__(self, parts: list[Part]):
        self.roots: list[PinJoint] = []
        self.anchors: dict[str, tuple] = {}   # body name or '<flexible>:<attachment>' -> anchor
        self.body_anchor: dict[str, tuple] = {}
        for p in parts:
            self._add(p)

    def _new_joint(self, name, model, anchor) -> PinJoint:
        parent, placement = anchor
        joint = PinJoint(name, model, parent, placement)
        (parent.children if parent is not None else self.roots).append(joint)
        return joint

    def _add(self, p: Part):
        parent_joint, parent_placement = self.anchors[p.parent] if p.parent is not None else (None, pin.SE3.Identity())
        X = parent_placement * pin.SE3(p.placement[0], p.placement[1])
        if p.joint[0] == "fixed":
            anchor = (parent_joint, X)
        else:
            anchor = (self._new_joint(p.name, pin_joint_model(p.joint), (parent_joint, X)), pin.SE3.Identity())
        self.anchors[p.name] = self.body_anchor[p.name] = anchor
        owner, offset = anchor
        assert owner is not None, "no part is welded to the world"
        if p.flexible is None:
            owner.inertias.append((pin.Inertia(p.mass, p.com, p.inertia), offset))
            return
        body = p.flexible
        node_anchor = []
        for j, (r, mass, spin) in enumerate(zip(body.positions, body.masses, body.spins)):
            node = (owner, offset * pin.SE3(np.eye(3), r))
            moves = body.node_modes(j)
            if "t" in moves:
                k = moves["t"]
                node = (self._new_joint(f"{p.name}:mode{k + 1}",
                                        pin.JointModelPrismaticUnaligned(body.modes[k][2]), node), pin.SE3.Identity())
            if "r" in moves:
                k = moves["r"]
                node = (self._new_joint(f"{p.name}:mode{k + 1}",
                                        pin.JointModelRevoluteUnaligned(body.modes[k][2]), node), pin.SE3.Identity())
            node[0].inertias.append((pin.Inertia(mass, np.zeros(3), spin * np.eye(3)), node[1]))
            node_anchor.append(node)
        for attachment, j in body.attachments.items():
            self.anchors[f"{p.name}:{attachment}"] = node_anchor[j]

    def build(self, gravity) -> tuple[pin.Model, dict]:
        """Joints added depth-first (Pinocchio needs contiguous subtrees); returns the model
        and the joint id of every PinJoint name."""
        model = pin.Model()
        model.gravity.linear = np.asarray(gravity, dtype=float)
        ids = {}

        def add(joint: PinJoint, parent_id: int):
            jid = model.addJoint(parent_id, joint.model, joint.placement, joint.name)
            ids[joint.name] = jid
            for inertia, placement in joint.inertias:
                model.appendBodyToJoint(jid, inertia, placement)
            for child in joint.children:
                add(child, jid)

        for root in self.roots:
            add(root, 0)
        return model, ids

    def joints(self):
        stack, out = list(reversed(self.roots)), []
        while stack:
            j = stack.pop()
            out.append(j)
            stack.extend(reversed(j.children))
        return out


class Mapping(PinocchioMapping):
    """Name-matched coordinate and DOF maps between soadyn and Pinocchio, plus the modal
    coordinates and elastic forces of the flexible bodies."""

    def __init__(self, m: soadyn.Model, model: pin.Model, tree: PinTree, ids: dict, parts: list[Part]):
        joints = []
        for joint in tree.joints():
            assert model.names[ids[joint.name]] == joint.name
            joints.append(JointMatch(ids[joint.name], tuple(joint.coordinate_names()), tuple(joint.dof_names())))
        super().__init__(m, model, joints)
        # Modal coordinates and DOFs of each flexible body, in mode order, and their K and C.
        self.modal = []
        for p in parts:
            if p.flexible is not None:
                names = [f"{p.name}:mode{k + 1}" for k in range(p.flexible.n_modes)]
                self.modal.append((np.array([m.coordinate_names.index(n) for n in names]),
                                   np.array([m.dof_names.index(n) for n in names]),
                                   p.flexible.K,
                                   p.flexible.C if p.flexible.C is not None else np.zeros_like(p.flexible.K)))
        self.modal_dofs = np.zeros(m.nv, dtype=bool)
        for _, vi, _, _ in self.modal:
            self.modal_dofs[vi] = True

    def matrix(self, M_pin):
        return self.matrix_from_pin(M_pin)

    def elastic(self, q, v):
        """The elastic modal forces -K eta - C eta_dot, soadyn's DOF order (zero on hinges)."""
        f = np.zeros(self.m.nv)
        for qi, vi, K, C in self.modal:
            f[vi] = -K @ q[qi] - C @ v[vi]
        return f

    def strain_energy(self, q):
        return sum(0.5 * q[qi] @ K @ q[qi] for qi, _, K, _ in self.modal)


@functools.lru_cache(maxsize=None)
def built(layout: str, seed: int, n_modes: int | None = None):
    parts = random_parts(layout, seed, n_modes)
    m = build_soadyn(parts)
    tree = PinTree(parts)
    model, ids = tree.build(m.gravity)
    return parts, m, model, tree, ids, Mapping(m, model, tree, ids, parts)


@dataclass
class Case:
    parts: list
    m: soadyn.Model
    model: pin.Model
    data: pin.Data
    tree: PinTree
    ids: dict
    map: Mapping
    rng: np.random.Generator
    q: np.ndarray
    v: np.ndarray
    q_pin: np.ndarray
    v_pin: np.ndarray


def make_case(layout: str, seed: int, state: int, n_modes: int | None = None) -> Case:
    parts, m, model, tree, ids, mapping = built(layout, seed, n_modes)
    s = 100 * seed + state
    rng = np.random.default_rng(1000 + s + 7919 * LAYOUTS.index(layout))
    q = soadyn.random_configuration(m, s)
    for qi, _, _, _ in mapping.modal:  # eta of 0.1 - 0.5: finite rotations of the nodes
        q[qi] = rng.uniform(0.1, 0.5, size=len(qi)) * rng.choice([-1.0, 1.0], size=len(qi))
    v = rng.normal(size=m.nv)
    return Case(parts, m, model, model.createData(), tree, ids, mapping, rng, q, v,
                mapping.q(q), mapping.v(v))


# ---------------------------------------------------------------------------
# Comparison with error log
# ---------------------------------------------------------------------------

LOG = ErrorLog("Pinocchio (flexible trees)", RTOL)
check = LOG.check


report_errors = report_fixture(LOG)


parametrize_cases = pytest.mark.parametrize("layout,seed,state", CASES, ids=CASE_IDS)


# Bodies with uncoupled, modally damped modes (the diagonal elastic forces): one on a
# node of a clamped body, one appendage.
MODAL_BODIES = {layout: {name for name, _, _, body in parts if body == "flexible-modal"}
                for layout, parts in LAYOUT_PARTS.items()}

# ---------------------------------------------------------------------------
# Tests
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("layout,seed", MODELS, ids=[f"{l}-seed{s}" for l, s in MODELS])
def test_trees_cover_the_flexible_features(layout, seed):
    """Translational and rotational modes, nodes with both, unmoved nodes, coupled K
    (diagonal K and C on the modal bodies), children on moved and unmoved nodes and on
    reference frames, and the same number of DOFs, coordinates and total mass in both
    models."""
    parts, m, model, tree, ids, mapping = built(layout, seed)
    assert model.nv == m.nv and model.nq == m.nq
    flexible = [p for p in parts if p.flexible is not None]
    assert len(flexible) >= 2
    for p in flexible:
        body = p.flexible
        kinds = [kind for _, kind, _ in body.modes]
        assert {"t", "r"} <= set(kinds)
        moved = {j for j, _, _ in body.modes}
        assert any(set(body.node_modes(j)) == {"t", "r"} for j in moved)
        assert len(moved) < len(body.masses)
        coupling = np.abs(body.K - np.diag(np.diag(body.K))).max()
        damping_coupling = 0.0 if body.C is None else np.abs(body.C - np.diag(np.diag(body.C))).max()
        if p.name in MODAL_BODIES[layout]:
            assert coupling == 0.0 and damping_coupling == 0.0 and np.all(np.diag(body.C) > 0)
        else:
            assert coupling > 0.1
        assert np.all(np.linalg.eigvalsh(body.K) > 0)
        np.testing.assert_array_equal(body.soadyn_body().mode_shapes, body.mode_shapes())
    on_node = [p for p in parts if p.parent is not None and ":" in p.parent]
    on_frame = [p for p in parts if any(p.parent == f.name for f in flexible)]
    assert on_frame
    # Appendages welded to the free root have their modes eliminated in the root's
    # frame, with the integrals held there: the oracle checks that path on f1.
    welded = [p.name for p in flexible if layout == "appendages" and p.joint[0] == "fixed" and p.parent == "b0"]
    assert [name for name, flag in zip(m.body_names, m.appendage_in_root_frame) if flag] == welded
    if layout == "appendages":
        assert welded == ["f1"]
        assert not on_node
        assert {p.joint[0] for p in flexible} == {"fixed", "revolute", "prismatic"}
    else:
        assert on_node
        assert any(p.flexible is not None for p in on_node)
    total = sum(p.mass for p in parts) + sum(p.flexible.masses.sum() for p in flexible)
    assert sum(inertia.mass for inertia in model.inertias) == pytest.approx(total, rel=1e-14)
    if layout in ("floating", "flexible_root"):
        assert m.joint_types[0] == "free"


@parametrize_cases
def test_body_poses_and_velocities(layout, seed, state):
    """Reference frames of flexible bodies and rigid bodies (on deformed nodes): validates
    the node chains and the coordinate maps on their own."""
    c = make_case(layout, seed, state)
    poses, vel = soadyn.forward_kinematics(c.m, c.q, c.v)
    pin.forwardKinematics(c.model, c.data, c.q_pin, c.v_pin)
    for p in c.parts:
        i = c.m.body_names.index(p.name)
        joint, offset = c.tree.body_anchor[p.name]
        jid = c.ids[joint.name]
        check("body poses", poses[i], (c.data.oMi[jid] * offset).homogeneous)
        twist = offset.actInv(c.data.v[jid])
        check("body velocities", vel[i], np.r_[twist.angular, twist.linear])


@parametrize_cases
def test_mass_matrix(layout, seed, state):
    c = make_case(layout, seed, state)
    M = pin.crba(c.model, c.data, c.q_pin)
    M = np.triu(M) + np.triu(M, 1).T  # Pinocchio fills the upper triangle only
    check("mass_matrix", soadyn.mass_matrix(c.m, c.q), c.map.matrix(M))


@parametrize_cases
@pytest.mark.parametrize("modal_force", [False, True], ids=["hinge_tau", "hinge_and_modal_tau"])
def test_forward_dynamics(layout, seed, state, modal_force):
    """soadyn applies -K eta - C eta_dot itself; Pinocchio receives it as modal joint torques."""
    c = make_case(layout, seed, state)
    tau = c.rng.normal(size=c.m.nv)
    if not modal_force:
        tau[c.map.modal_dofs] = 0.0
    qdd = soadyn.forward_dynamics(c.m, c.q, c.v, tau)
    tau_pin = c.map.v(tau + c.map.elastic(c.q, c.v))
    check("forward_dynamics", qdd, c.map.back(pin.aba(c.model, c.data, c.q_pin, c.v_pin, tau_pin)))


@parametrize_cases
def test_inverse_dynamics(layout, seed, state):
    """On modal DOFs soadyn returns the external modal force: rnea + K eta + C eta_dot."""
    c = make_case(layout, seed, state)
    qdd = c.rng.normal(size=c.m.nv)
    tau = soadyn.inverse_dynamics(c.m, c.q, c.v, qdd)
    ref = c.map.back(pin.rnea(c.model, c.data, c.q_pin, c.v_pin, c.map.v(qdd))) - c.map.elastic(c.q, c.v)
    check("inverse_dynamics", tau, ref)


@parametrize_cases
def test_bias_forces(layout, seed, state):
    """h includes the elastic forces: M qdd + h = tau."""
    c = make_case(layout, seed, state)
    ref = c.map.back(pin.nonLinearEffects(c.model, c.data, c.q_pin, c.v_pin)) - c.map.elastic(c.q, c.v)
    check("bias_forces", soadyn.bias_forces(c.m, c.q, c.v), ref)


@parametrize_cases
def test_energies(layout, seed, state):
    c = make_case(layout, seed, state)
    check("kinetic_energy", soadyn.kinetic_energy(c.m, c.q, c.v),
          pin.computeKineticEnergy(c.model, c.data, c.q_pin, c.v_pin))
    # Both gravity potentials are -sum m g.c with zero at the world origin; soadyn adds the strain.
    check("potential_energy", soadyn.potential_energy(c.m, c.q),
          pin.computePotentialEnergy(c.model, c.data, c.q_pin) + c.map.strain_energy(c.q))


@parametrize_cases
def test_hybrid_dynamics(layout, seed, state):
    """Random masks of prescribed hinge DOFs against the partitioned solve of
    M qdd + h = tau + f_elastic with Pinocchio's M and h; modal DOFs stay regular."""
    c = make_case(layout, seed, state)
    M = pin.crba(c.model, c.data, c.q_pin)
    M = c.map.matrix(np.triu(M) + np.triu(M, 1).T)
    h = c.map.back(pin.nonLinearEffects(c.model, c.data, c.q_pin, c.v_pin)) - c.map.elastic(c.q, c.v)
    hinge = ~c.map.modal_dofs
    try:
        for fraction in (0.3, 0.7, 1.0):
            mask = (c.rng.uniform(size=c.m.nv) < fraction) & hinge
            c.m.set_prescribed(mask)
            u = c.rng.normal(size=c.m.nv)
            qdd, tau = soadyn.hybrid_dynamics(c.m, c.q, c.v, u)
            p, r = mask, ~mask
            expected_qdd = np.where(p, u, 0.0)
            expected_qdd[r] = np.linalg.solve(M[np.ix_(r, r)], u[r] - h[r] - M[np.ix_(r, p)] @ u[p])
            expected_tau = M @ expected_qdd + h
            check("hybrid qdd", qdd, expected_qdd)
            check("hybrid tau", tau, expected_tau)
            np.testing.assert_array_equal(tau[r], u[r])
    finally:
        c.m.set_prescribed(np.zeros(c.m.nv, dtype=bool))


def pinocchio_wrenches(c: Case, f_ext: np.ndarray) -> list:
    """soadyn's body-frame wrenches about each body origin as Pinocchio joint forces: a
    wrench on a flexible body acts on its reference frame, anchored like a rigid body's."""
    fext = [pin.Force.Zero() for _ in range(c.model.njoints)]
    for p in c.parts:
        joint, offset = c.tree.body_anchor[p.name]
        w = f_ext[c.m.body_names.index(p.name)]
        fext[c.ids[joint.name]] += offset.act(pin.Force(w[3:], w[:3]))
    return fext


@parametrize_cases
def test_external_wrenches(layout, seed, state):
    """Forward and hybrid dynamics with a wrench on every body, rigid and flexible."""
    check_external_wrenches(make_case(layout, seed, state))


@pytest.mark.parametrize("n_modes", range(1, 10))
def test_appendages_of_every_mode_count(n_modes):
    """The appendage step is compiled for each mode count up to six (max_fixed_appendage_modes)
    and generic beyond: the appendages layout (a boom welded to the free root, one hinged,
    one on a sliding body) with every flexible body at n_modes modes, with and without
    wrenches."""
    c = make_case("appendages", 0, 0, n_modes)
    assert [p.flexible.n_modes for p in c.parts if p.flexible is not None] == [n_modes] * 3
    assert sum(c.m.appendage_in_root_frame) == 1
    tau = c.rng.normal(size=c.m.nv)
    qdd = soadyn.forward_dynamics(c.m, c.q, c.v, tau)
    tau_pin = c.map.v(tau + c.map.elastic(c.q, c.v))
    check("forward_dynamics, n modes", qdd, c.map.back(pin.aba(c.model, c.data, c.q_pin, c.v_pin, tau_pin)))
    check_external_wrenches(c)


@pytest.mark.parametrize("n_modes", (2, 4, 7))
def test_a_lock_impulse_on_appendages(n_modes):
    """Locking a hinge is a plastic impact: the appendage step without velocities (the
    impulse sweeps). With Pinocchio's M, v+ = v + M^-1 e_k lambda and v+_k = 0."""
    c = make_case("appendages", 1, 0, n_modes)
    M = pin.crba(c.model, c.data, c.q_pin)
    M = c.map.matrix(np.triu(M) + np.triu(M, 1).T)
    k = c.m.dof_index("f2")  # the hinge of the boom on a revolute joint
    column = np.linalg.solve(M, np.eye(c.m.nv)[k])
    expected = c.v - column * c.v[k] / column[k]
    sim = soadyn.Simulator(c.m, 1e-3)
    sim.set_state(c.q, c.v)
    sim.lock(k)
    check("lock impulse, n modes", sim.v, expected)
    assert sim.v[k] == 0.0 and sim.energy_lost > 0.0


def check_external_wrenches(c: Case):
    f_ext = c.rng.normal(size=(c.m.nbodies, 6))
    fext = pinocchio_wrenches(c, f_ext)
    tau = c.rng.normal(size=c.m.nv)
    qdd = soadyn.forward_dynamics(c.m, c.q, c.v, tau, f_ext=f_ext)
    tau_pin = c.map.v(tau + c.map.elastic(c.q, c.v))
    check("forward_dynamics f_ext", qdd, c.map.back(pin.aba(c.model, c.data, c.q_pin, c.v_pin, tau_pin, fext)))
    M = pin.crba(c.model, c.data, c.q_pin)
    M = c.map.matrix(np.triu(M) + np.triu(M, 1).T)
    zero = np.zeros(c.model.nv)
    h = c.map.back(pin.rnea(c.model, c.data, c.q_pin, c.v_pin, zero, fext)) - c.map.elastic(c.q, c.v)
    mask = (c.rng.uniform(size=c.m.nv) < 0.5) & ~c.map.modal_dofs
    try:
        c.m.set_prescribed(mask)
        u = c.rng.normal(size=c.m.nv)
        qdd, tau = soadyn.hybrid_dynamics(c.m, c.q, c.v, u, f_ext=f_ext)
    finally:
        c.m.set_prescribed(np.zeros(c.m.nv, dtype=bool))
    p, r = mask, ~mask
    expected_qdd = np.where(p, u, 0.0)
    expected_qdd[r] = np.linalg.solve(M[np.ix_(r, r)], u[r] - h[r] - M[np.ix_(r, p)] @ u[p])
    check("hybrid qdd f_ext", qdd, expected_qdd)
    check("hybrid tau f_ext", tau, M @ expected_qdd + h)
