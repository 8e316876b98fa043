"""Bodies with a constant inertia in their root's frame (cpp/include/soadyn/
constant_tree_inertia.hxx): on a bus, reaction wheels and a turntable whose mass
is symmetric about their axes. The bus flies free, or turns or slides on a joint
about a coordinate axis (a fixed-base robot's first joint). The forward and hybrid
dynamics and the mass matrix read those inertias formed once, in the bus's body
frame, where the world's gravity must be carried; Pinocchio, which forms every
inertia per call in its own frames, is the oracle. Gravity is oblique so that every
component counts. Changing a parameter (set_parameter) must refresh the stored
inertias, and break or restore a body's symmetry.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin
import pytest

import soadyn
from support.error_log import ErrorLog, report_fixture
from support.pinocchio_mapping import JointMatch, PinocchioMapping, free_joint_names
from support.trees import random_inertia, random_rotation, random_unit

RTOL = 1e-10
GRAVITY = np.array([0.7, -1.9, -9.4])
STATES = range(6)

LOG = ErrorLog("Pinocchio", RTOL)
check = LOG.check
report_errors = report_fixture(LOG)


@dataclass
class Body:
    name: str
    parent: int               # body index, -1: the world
    axis: np.ndarray | None   # revolute (or prismatic) axis; None: free joint
    rotation: np.ndarray
    translation: np.ndarray
    mass: float
    com: np.ndarray
    inertia: np.ndarray
    constant: bool            # expected: inertia constant in the bus frame
    prismatic: bool = False


def axis(k: int, sign: float = 1.0) -> np.ndarray:
    e = np.zeros(3)
    e[k] = sign
    return e


def symmetric_inertia(k: int, axial: float, transverse: float) -> np.ndarray:
    d = np.full(3, transverse)
    d[k] = axial
    return np.diag(d)


# The bus's joint: free, or about a coordinate axis of its frame (a robot's first joint).
ROOTS = {"free": (None, False), "revolute": (axis(0, -1.0), False), "prismatic": (axis(1), True)}


def spacecraft(root: str = "free") -> list[Body]:
    """A bus with five symmetric rotors (constant inertias) and five bodies that are not, in
    depth-first order (Pinocchio's mass matrix needs each subtree's DOFs contiguous)."""
    rng = np.random.default_rng(7)
    root_axis, root_prismatic = ROOTS[root]

    def body(name, parent, joint_axis, mass, com, inertia, constant):
        return Body(name, parent, joint_axis, random_rotation(rng), rng.uniform(-1.0, 1.0, 3), mass,
                    np.asarray(com, dtype=float), inertia, constant)

    return [
        Body("bus", -1, root_axis, random_rotation(np.random.default_rng(11)), np.zeros(3), 900.0,
             np.array([0.1, -0.05, 0.6]), random_inertia(rng) * 300.0, True, root_prismatic),
        body("wheel_x", 0, axis(0), 8.0, [0.03, 0, 0], symmetric_inertia(0, 0.09, 0.05), True),
        body("wheel_y", 0, axis(1, -1.0), 8.0, [0, -0.02, 0], symmetric_inertia(1, 0.09, 0.05), True),
        body("wheel_z", 0, axis(2), 8.0, [0, 0, 0], symmetric_inertia(2, 0.09, 0.05), True),
        # Carried by a turning body: moves in the bus frame whatever its mass.
        body("spinner", 3, axis(2), 2.0, [0, 0, 0], symmetric_inertia(2, 0.02, 0.01), False),
        body("turntable", 0, axis(2, -1.0), 60.0, [0, 0, 0.2], symmetric_inertia(2, 4.0, 2.5), True),
        body("platform", 5, axis(0), 20.0, [0.1, 0.2, 0.0], random_inertia(rng), False),
        # On the bus, but not symmetric about the axis.
        body("arm", 0, axis(2), 15.0, [0, 0, 0.4], np.diag([1.0, 1.1, 0.3]), False),
        body("offset", 0, axis(1), 5.0, [1e-3, 0, 0], symmetric_inertia(1, 0.2, 0.1), False),
        # Symmetric about an axis that is not a coordinate axis of its frame.
        body("tilted", 0, random_unit(rng), 3.0, [0, 0, 0], np.eye(3) * 0.1, False),
    ]


def build_soadyn(bodies: list[Body]) -> soadyn.Model:
    m = soadyn.Model()
    m.gravity = GRAVITY
    for b in bodies:
        joint = (soadyn.Joint.free() if b.axis is None else
                 soadyn.Joint.prismatic(b.axis) if b.prismatic else soadyn.Joint.revolute(b.axis))
        m.add_body(b.name, b.parent, joint, placement=(b.rotation, b.translation), mass=b.mass, com=b.com,
                   inertia=b.inertia)
    return m


def build_pinocchio(bodies: list[Body]) -> pin.Model:
    model = pin.Model()
    model.gravity.linear = GRAVITY
    for b in bodies:
        joint = (pin.JointModelFreeFlyer() if b.axis is None else
                 pin.JointModelPrismaticUnaligned(b.axis) if b.prismatic else pin.JointModelRevoluteUnaligned(b.axis))
        jid = model.addJoint(b.parent + 1, joint, pin.SE3(b.rotation, b.translation), b.name)
        model.appendBodyToJoint(jid, pin.Inertia(b.mass, b.com, b.inertia), pin.SE3.Identity())
    return model


class Case:
    def __init__(self, bodies: list[Body]):
        self.bodies = bodies
        self.m = build_soadyn(bodies)
        self.model = build_pinocchio(bodies)
        self.data = self.model.createData()
        joints = []
        for i, b in enumerate(bodies):
            jid = self.model.getJointId(b.name)
            if b.axis is None:
                q_names, v_names = free_joint_names(b.name)
            else:
                q_names = v_names = (self.m.dof_names[self.m.v_index[i]],)
            joints.append(JointMatch(jid, q_names, v_names))
        self.map = PinocchioMapping(self.m, self.model, joints)
        self.joint_ids = [self.model.getJointId(b.name) for b in bodies]

    def rebuild_oracle(self) -> None:
        """Pinocchio's model from the bodies as they now are (after a parameter change)."""
        self.model = build_pinocchio(self.bodies)
        self.data = self.model.createData()

    def state(self, k: int):
        rng = np.random.default_rng(100 + k)
        q = soadyn.random_configuration(self.m, k)
        return q, rng.normal(size=self.m.nv) * 2.0, rng.normal(size=self.m.nv), rng.normal(size=(self.m.nbodies, 6))


# Hybrid dynamics' prescribed bodies: rotors and a body on one; then the bus itself (a free
# root whose six DOFs are prescribed: its acceleration is the world's, carried into its frame,
# plus its given one) and a wheel.
PRESCRIBED_SETS = (("turntable", "wheel_y", "platform"), ("bus", "wheel_x"))


def prescribed_copies(c: Case) -> list:
    copies = []
    for names in PRESCRIBED_SETS:
        mask = np.zeros(c.m.nv, dtype=bool)
        for name in names:
            b = c.m.body_names.index(name)
            end = c.m.v_index[b + 1] if b + 1 < c.m.nbodies else c.m.nv
            mask[c.m.v_index[b]:end] = True
        m = c.m.copy()
        m.set_prescribed(mask)
        copies.append((m, mask))
    return copies


def compare_all(c: Case, label: str) -> None:
    """Forward, inverse and hybrid dynamics and the mass matrix at STATES, against Pinocchio."""
    for k in STATES:
        q, v, x, f = c.state(k)
        q_pin, v_pin = c.map.q(q), c.map.v(v)
        check(f"{label}: forward_dynamics", c.map.v(soadyn.forward_dynamics(c.m, q, v, x)),
              pin.aba(c.model, c.data, q_pin, v_pin, c.map.v(x)))
        check(f"{label}: forward_dynamics f_ext", c.map.v(soadyn.forward_dynamics(c.m, q, v, x, f_ext=f)),
              pin.aba(c.model, c.data, q_pin, v_pin, c.map.v(x), c.map.f_ext(f, c.joint_ids)))
        check(f"{label}: inverse_dynamics", c.map.v(soadyn.inverse_dynamics(c.m, q, v, x)),
              pin.rnea(c.model, c.data, q_pin, v_pin, c.map.v(x)))
        M_pin = pin.crba(c.model, c.data, q_pin)
        check(f"{label}: mass_matrix", c.map.matrix_to_pin(soadyn.mass_matrix(c.m, q)),
              np.triu(M_pin) + np.triu(M_pin, 1).T)
        for prescribed, mask in [(c.m, np.zeros(c.m.nv, dtype=bool))] + prescribed_copies(c):
            qdd, tau = soadyn.hybrid_dynamics(prescribed, q, v, x)
            np.testing.assert_array_equal(qdd[mask], x[mask])
            np.testing.assert_array_equal(tau[~mask], x[~mask])
            check(f"{label}: hybrid_dynamics", c.map.v(tau), pin.rnea(c.model, c.data, q_pin, v_pin, c.map.v(qdd)))
            # The wrenches need every body's orientation, the wheels' too (whose constant
            # terms let the sweeps skip it otherwise), and so does f_ext.
            for f_ext, fext_pin in ((None, ()), (f, (c.map.f_ext(f, c.joint_ids),))):
                qdd, tau, wrenches = soadyn.hybrid_dynamics(prescribed, q, v, x, f_ext=f_ext, joint_wrenches=True)
                check(f"{label}: hybrid_dynamics with wrenches", c.map.v(tau),
                      pin.rnea(c.model, c.data, q_pin, v_pin, c.map.v(qdd), *fext_pin))
                check(f"{label}: joint wrenches", wrenches,
                      np.array([np.r_[c.data.f[j].angular, c.data.f[j].linear] for j in c.joint_ids]))


def constant_flags(c: Case) -> list[bool]:
    return [bool(x) for x in c.m.constant_tree_inertia]


def leaf_hinge_names(c: Case) -> list[str]:
    return [name for name, flag in zip(c.m.body_names, c.m.constant_leaf_hinge) if flag]


@pytest.mark.parametrize("root", sorted(ROOTS))
def test_which_bodies_have_constant_inertia(root):
    c = Case(spacecraft(root))
    assert constant_flags(c) == [b.constant for b in c.bodies]
    # Of those, the leaves that turn read their hinge step's D, G and P+ formed once:
    # wheel_z and the turntable carry bodies, so their articulated inertias move.
    assert leaf_hinge_names(c) == ["wheel_x", "wheel_y"]


def test_a_wheel_with_armature_forms_its_hinge_step_per_call():
    """Armature changes D: the wheel with one takes the general step; Pinocchio's
    model.armature is the oracle, and the wheel without keeps the constant terms."""
    c = Case(spacecraft())
    wheel = c.m.body_names.index("wheel_x")
    dof = c.m.v_index[wheel]
    armature = np.zeros(c.m.nv)
    armature[dof] = 0.37
    c.m.set_armature(dof, armature[dof])
    c.model.armature[:] = c.map.v(armature)
    c.data = c.model.createData()
    for k in STATES:
        q, v, x, f = c.state(k)
        q_pin, v_pin = c.map.q(q), c.map.v(v)
        check("armature: forward_dynamics", c.map.v(soadyn.forward_dynamics(c.m, q, v, x, f_ext=f)),
              pin.aba(c.model, c.data, q_pin, v_pin, c.map.v(x), c.map.f_ext(f, c.joint_ids)))
        for prescribed, mask in prescribed_copies(c):
            qdd, tau = soadyn.hybrid_dynamics(prescribed, q, v, x)
            check("armature: hybrid_dynamics", c.map.v(tau), pin.rnea(c.model, c.data, q_pin, v_pin, c.map.v(qdd)))


@pytest.mark.parametrize("root", sorted(ROOTS))
def test_dynamics_match_pinocchio_with_constant_inertias(root):
    c = Case(spacecraft(root))
    assert sum(constant_flags(c)) == 5
    compare_all(c, f"{root} bus")


def test_dynamics_do_not_depend_on_the_root_pose_through_the_stored_inertias():
    """The same relative state with the bus turned and moved: hinge accelerations of a
    gravity-free spacecraft are the same (its dynamics do not know where it is)."""
    c = Case(spacecraft())
    c.m.gravity = np.zeros(3)
    q, v, x, _ = c.state(0)
    turned = q.copy()
    turned[0:3] += [3.0, -40.0, 2.5]
    quaternion = np.random.default_rng(3).normal(size=4)
    turned[3:7] = quaternion / np.linalg.norm(quaternion)
    np.testing.assert_allclose(soadyn.forward_dynamics(c.m, turned, v, x), soadyn.forward_dynamics(c.m, q, v, x),
                               rtol=0, atol=1e-12)


@pytest.mark.parametrize("change", ["wheel asymmetric", "wheel com off the axis", "bus inertia", "wheel placement"])
def test_a_parameter_change_refreshes_the_stored_inertias(change):
    c = Case(spacecraft())
    wheel = c.bodies[1]
    if change == "wheel asymmetric":
        wheel.inertia = np.diag([0.09, 0.05, 0.051])
        c.m.set_parameter("wheel_x.inertia", wheel.inertia)
        expected = False
    elif change == "wheel com off the axis":
        wheel.com = np.array([0.03, 0.0, 0.01])
        c.m.set_parameter("wheel_x.com", wheel.com)
        expected = False
    elif change == "bus inertia":
        bus = c.bodies[0]
        bus.inertia = bus.inertia * 1.5 + np.eye(3) * 10.0
        c.m.set_parameter("bus.inertia", bus.inertia)
        expected = True
    else:
        wheel.translation = wheel.translation + [0.2, -0.1, 0.3]
        placement = np.eye(4)
        placement[:3, :3], placement[:3, 3] = wheel.rotation, wheel.translation
        c.m.set_parameter("wheel_x.placement", placement)
        expected = True
    assert constant_flags(c)[1 if change != "bus inertia" else 0] == expected
    assert leaf_hinge_names(c) == (["wheel_x", "wheel_y"] if expected else ["wheel_y"])
    c.rebuild_oracle()
    compare_all(c, change)


def test_a_restored_symmetry_makes_the_inertia_constant_again():
    c = Case(spacecraft())
    arm = c.bodies[7]
    assert arm.name == "arm" and not constant_flags(c)[7]
    arm.inertia = np.diag([1.0, 1.0, 0.3])
    c.m.set_parameter("arm.inertia", arm.inertia)
    assert constant_flags(c)[7]
    c.rebuild_oracle()
    compare_all(c, "arm made symmetric")


def test_parameter_changes_refresh_the_stored_shortcuts_both_ways():
    """Per body the model also stores the shape of its placement's rotation (the identity or a
    quarter-turn axis permutation spare the rotation product of its base) and whether its
    inertia about its centre of mass is exactly diagonal (R I_c R' from R's columns). A stale
    fact would give wrong dynamics, so each is turned on and off by set_parameter and every call
    compared with Pinocchio. A rotation within machine epsilon of a permutation (URDF's rpy of
    pi/2, whose cosines are 6e-17) is applied as one; one 1e-9 away is not, and the comparison's
    1e-10 would see it if it were."""
    c = Case(spacecraft())
    rng = np.random.default_rng(21)
    arm, platform = c.bodies[7], c.bodies[6]
    assert (arm.name, platform.name) == ("arm", "platform") and arm.parent == 0 and platform.parent == 5
    compare_all(c, "as built")
    # The arm's diagonal inertia made full, the platform's full one made diagonal.
    arm.inertia = random_inertia(rng)
    assert np.count_nonzero(arm.inertia - np.diag(np.diag(arm.inertia))) == 6
    c.m.set_parameter("arm.inertia", arm.inertia)
    platform.inertia = np.diag([0.4, 0.5, 0.6])
    c.m.set_parameter("platform.inertia", platform.inertia)
    c.rebuild_oracle()
    compare_all(c, "inertias exchanged")
    # The platform sits on the turntable, so its base is composed on every call: its
    # placement's rotation made the identity, then turned again.
    quarter_turn = rotation_z(np.pi / 2) @ rotation_x(-np.pi / 2)
    assert 0 < np.min(np.abs(quarter_turn[quarter_turn != np.round(quarter_turn)])) < 1e-16
    for label, rotation, shape in (("identity", np.eye(3), "identity"),
                                   ("turned", random_rotation(rng), "general"),
                                   ("a quarter turn, exact", np.round(quarter_turn), "axis_permutation"),
                                   ("a quarter turn, rounded", quarter_turn, "axis_permutation"),
                                   ("nearly a quarter turn", rotation_z(np.pi / 2 + 1e-9) @ rotation_x(-np.pi / 2),
                                    "general")):
        platform.rotation = rotation
        placement = np.eye(4)
        placement[:3, :3], placement[:3, 3] = rotation, platform.translation
        c.m.set_parameter("platform.placement", placement)
        assert c.m.placement_axes[6] == shape, label
        c.rebuild_oracle()
        compare_all(c, f"platform placement {label}")


def rotation_x(angle: float) -> np.ndarray:
    return np.array([[1, 0, 0], [0, np.cos(angle), -np.sin(angle)], [0, np.sin(angle), np.cos(angle)]])


def rotation_z(angle: float) -> np.ndarray:
    return np.array([[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0], [0, 0, 1]])


def test_a_faint_gravity_is_carried_into_the_root_frame():
    """At rest with no torque the accelerations are linear in gravity: a gravity 1e-14 of
    the oblique one (a free-falling probe's tidal residue, below any `isZero` precision)
    gives 1e-14 of its accelerations, not zero."""
    c = Case(spacecraft())
    q, _, _, _ = c.state(1)
    rest = np.zeros(c.m.nv)
    full = soadyn.forward_dynamics(c.m, q, rest, rest)
    c.m.gravity = GRAVITY * 1e-14
    faint = soadyn.forward_dynamics(c.m, q, rest, rest)
    assert np.max(np.abs(full)) > 1.0
    np.testing.assert_allclose(faint * 1e14, full, rtol=1e-9, atol=1e-9 * np.max(np.abs(full)))
    c.m.gravity = np.zeros(3)
    assert np.array_equal(soadyn.forward_dynamics(c.m, q, rest, rest), rest)


def test_mode_switches_and_armature_move_wheels_in_and_out_of_the_bus_sum():
    """The bus's articulated inertia starts with the sum of its constant leaves' terms
    (ModelTpl::refresh_leaf_presums): a regular wheel's P+, a prescribed wheel's P. One
    model switched back and forth between prescribed sets, then given armature on a
    prescribed and on a regular wheel, must move each wheel in and out of the sums under
    the flags (hybrid dynamics) and with every DOF regular (forward dynamics);
    Pinocchio's RNEA of the hybrid solution and its ABA are the oracles at every switch."""
    c = Case(spacecraft())
    names = c.m.body_names
    wheels = [names.index("wheel_x"), names.index("wheel_y")]

    def mask_of(*bodies):
        mask = np.zeros(c.m.nv, dtype=bool)
        for name in bodies:
            b = names.index(name)
            end = c.m.v_index[b + 1] if b + 1 < c.m.nbodies else c.m.nv
            mask[c.m.v_index[b]:end] = True
        return mask

    # (prescribed bodies, armature of wheel_x and wheel_y) -> expected (flags, all regular) per wheel
    steps = [
        ((), (0.0, 0.0), [(True, True), (True, True)]),
        (("wheel_x",), (0.0, 0.0), [(True, True), (True, True)]),  # prescribed: its P, under the flags
        (("bus",), (0.0, 0.0), [(False, True), (False, True)]),    # the bus forms no P under the flags
        ((), (0.0, 0.0), [(True, True), (True, True)]),
        (("wheel_y", "turntable"), (0.0, 0.2), [(True, True), (True, False)]),  # armature: P passes, D changes
        (("wheel_y",), (0.3, 0.2), [(False, False), (True, False)]),
        ((), (0.0, 0.0), [(True, True), (True, True)]),
    ]
    for bodies, (arm_x, arm_y), expected in steps:
        mask = mask_of(*bodies)
        c.m.set_prescribed(mask)
        armature = np.zeros(c.m.nv)
        for wheel, value in zip(wheels, (arm_x, arm_y)):
            armature[c.m.v_index[wheel]] = value
            c.m.set_armature(c.m.v_index[wheel], value)
        assert [c.m.leaf_terms_presummed[w] for w in wheels] == expected, bodies
        c.model.armature[:] = c.map.v(armature)
        c.data = c.model.createData()
        label = f"prescribed {bodies or 'none'}, armature {arm_x}, {arm_y}"
        for k in STATES:
            q, v, x, f = c.state(k)
            q_pin, v_pin = c.map.q(q), c.map.v(v)
            qdd, tau = soadyn.hybrid_dynamics(c.m, q, v, x)
            np.testing.assert_array_equal(qdd[mask], x[mask])
            check(f"{label}: hybrid_dynamics", c.map.v(tau), pin.rnea(c.model, c.data, q_pin, v_pin, c.map.v(qdd)))
            qdd, tau = soadyn.hybrid_dynamics(c.m, q, v, x, f_ext=f)
            check(f"{label}: hybrid_dynamics f_ext", c.map.v(tau),
                  pin.rnea(c.model, c.data, q_pin, v_pin, c.map.v(qdd), c.map.f_ext(f, c.joint_ids)))
            check(f"{label}: forward_dynamics", c.map.v(soadyn.forward_dynamics(c.m, q, v, x)),
                  pin.aba(c.model, c.data, q_pin, v_pin, c.map.v(x)))


@pytest.mark.parametrize("value", [np.nan, np.inf, -0.5])
def test_a_refused_armature_leaves_the_wheel_sums_as_they_were(value):
    """set_armature refuses a non-finite or negative armature, naming the DOF, before
    it changes anything: the wheel stays in both sums and the dynamics still match Pinocchio."""
    c = Case(spacecraft())
    wheel = c.m.body_names.index("wheel_x")
    dof = c.m.v_index[wheel]
    before = c.m.leaf_terms_presummed[wheel]
    with pytest.raises(ValueError, match=c.m.dof_names[dof]):
        c.m.set_armature(dof, value)
    assert c.m.leaf_terms_presummed[wheel] == before == (True, True)
    q, v, x, _ = c.state(0)
    qdd, tau = soadyn.hybrid_dynamics(c.m, q, v, x)
    assert np.all(np.isfinite(qdd))
    check("refused armature: forward_dynamics", c.map.v(soadyn.forward_dynamics(c.m, q, v, x)),
          pin.aba(c.model, c.data, c.map.q(q), c.map.v(v), c.map.v(x)))
