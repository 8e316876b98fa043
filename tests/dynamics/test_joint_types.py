"""Joint types one by one.

The translation joint (three-DOF Cartesian: q = v = (x, y, z) in the joint
frame, Pinocchio's JointModelTranslation, DART's TranslationalJoint) against
DART's dynamics on chains, against closed-form kinematics and free fall, and
through the simulator. Every joint type's configuration operations (neutral
configuration, integration on its manifold) against Pinocchio's on the
random trees of support/pinocchio_trees.py.

Translation joints also take part, through support/trees.py's JOINT_KINDS, in
every random-tree comparison with Pinocchio (dynamics/test_pinocchio_oracle.py:
kinematics, mass matrix, inverse and forward dynamics, hybrid dynamics,
bias forces, energies) and in the hybrid-dynamics checks
(dynamics/test_hybrid_dynamics.py).
"""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import soadyn
from soadyn import Joint, MotionSource, Simulator
from support import pinocchio_trees
from support.trees import random_inertia, random_rotation, random_unit

GRAVITY = np.array([0.3, -0.2, -9.81])


def test_translation_joint_sizes_and_names():
    joint = Joint.translation(name="slide")
    assert (joint.type, joint.nq, joint.nv, joint.name) == ("translation", 3, 3, "slide")
    assert repr(joint) == "Joint.translation(name='slide')"
    m = soadyn.Model()
    m.add_body("cart", None, joint, mass=1.0, inertia=np.eye(3))
    m.add_body("pole", "cart", Joint.revolute([0, 1, 0]), mass=1.0, inertia=np.eye(3))
    assert m.joint_types == ["translation", "revolute"]
    assert m.coordinate_names == ["slide:x", "slide:y", "slide:z", "pole"]
    assert m.dof_names == ["slide:x", "slide:y", "slide:z", "pole"]
    assert m.dof_index("slide:y") == 1
    with pytest.raises(TypeError):
        Joint.translation([1, 0, 0])  # no axis: it translates along all three


def single_body(rotation: np.ndarray, translation: np.ndarray) -> soadyn.Model:
    """One body on a translation joint whose frame is rotated by `rotation` in the world."""
    rng = np.random.default_rng(3)
    m = soadyn.Model()
    m.gravity = GRAVITY
    m.add_body("body", None, Joint.translation(), placement=(rotation, translation), mass=2.5,
               com=rng.uniform(-0.3, 0.3, size=3), inertia=random_inertia(rng))
    return m


def test_translation_kinematics_closed_form():
    """Pose (R, p + R q), body-frame velocity (0, qdot): the body keeps the joint frame's orientation."""
    rng = np.random.default_rng(1)
    R, p = random_rotation(rng), rng.uniform(-1, 1, size=3)
    m = single_body(R, p)
    q, v = rng.normal(size=3), rng.normal(size=3)
    poses, velocities = soadyn.forward_kinematics(m, q, v)
    expected = np.eye(4)
    expected[:3, :3], expected[:3, 3] = R, p + R @ q
    np.testing.assert_allclose(poses[0], expected, rtol=0, atol=1e-15)
    np.testing.assert_allclose(velocities[0], np.r_[np.zeros(3), v], rtol=0, atol=1e-15)
    np.testing.assert_array_equal(soadyn.integrate(m, q, v, 0.25), q + 0.25 * v)
    np.testing.assert_array_equal(soadyn.neutral_configuration(m), np.zeros(3))


def test_translation_free_fall_matches_closed_form():
    """A body on a translation joint under gravity: q(t) = q0 + v0 t + R' g t^2 / 2 in the joint
    frame (no torque: the joint cannot rotate the body, so its COM offset plays no part).
    Runge-Kutta integrates the quadratic exactly, up to round-off."""
    rng = np.random.default_rng(2)
    R = random_rotation(rng)
    m = single_body(R, rng.uniform(-1, 1, size=3))
    g_joint = R.T @ GRAVITY
    q0, v0 = rng.normal(size=3), rng.normal(size=3)
    np.testing.assert_allclose(soadyn.forward_dynamics(m, q0, v0, np.zeros(3)), g_joint, rtol=0, atol=1e-14)
    for integrator in ("rk4", "dopri5"):
        sim = Simulator(m, 1e-2, integrator)
        sim.set_state(q0, v0)
        tr = sim.run(2.0)
        t = tr.t[:, None]
        np.testing.assert_allclose(tr.q, q0 + v0 * t + 0.5 * g_joint * t * t, rtol=0, atol=1e-12)
        np.testing.assert_allclose(tr.v, v0 + g_joint * t, rtol=0, atol=1e-12)


def test_translation_dof_follows_a_motion_source():
    """A prescribed translation DOF takes its coordinate from the source (q' = v); the other two
    still fall freely (the mass matrix of one body on a translation joint is m I)."""
    R = random_rotation(np.random.default_rng(4))
    m = single_body(R, np.zeros(3))
    g_joint = R.T @ GRAVITY
    sim = Simulator(m, 1e-3, "rk4")
    times = np.linspace(0.0, 1.0, 6)
    source = MotionSource.spline(times, 0.2 * np.sin(3 * times))
    sim.prescribe("body:y", source)
    tr = sim.run(1.0)
    y = np.array([source.sample(t) for t in tr.t])  # position, velocity, acceleration
    np.testing.assert_allclose(tr.q[:, 1], y[:, 0], rtol=0, atol=1e-12)
    np.testing.assert_allclose(tr.v[:, 1], y[:, 1], rtol=0, atol=1e-12)
    t = tr.t
    for k in (0, 2):
        np.testing.assert_allclose(tr.q[:, k], 0.5 * g_joint[k] * t * t, rtol=0, atol=1e-12)
    # The drive force on y holds the body on its path: m (y'' - g_y).
    np.testing.assert_allclose(tr.tau[:, 1], 2.5 * (y[:-1, 2] - g_joint[1]), rtol=0, atol=1e-9)


# ---------------------------------------------------------------------------
# Configuration operations of every joint type against Pinocchio
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("seed,floating", pinocchio_trees.CASES, ids=pinocchio_trees.CASE_IDS)
def test_neutral_and_integrate_match_pinocchio(seed, floating):
    """Neutral configuration and q (+) v dt on each joint's manifold (vector spaces, SE(2), SO(3),
    SE(3)) against pin.neutral and pin.integrate. Integrated configurations are compared by the body
    poses they give (a quaternion and its negative are the same rotation)."""
    c = pinocchio_trees.make_case(seed, floating)
    assert "translation" in c.m.joint_types
    np.testing.assert_array_equal(c.map.q(soadyn.neutral_configuration(c.m)), pin.neutral(c.model))
    for dt in (0.1, 1.3):
        v = c.rng.normal(size=c.m.nv)
        q_next = soadyn.integrate(c.m, c.q, v, dt)
        pin.forwardKinematics(c.model, c.data, pin.integrate(c.model, c.q_pin, c.map.v(v) * dt))
        theirs = np.array([c.data.oMi[j].homogeneous for j in c.map.joint_ids])
        np.testing.assert_allclose(soadyn.forward_kinematics(c.m, q_next)[0], theirs, rtol=0, atol=1e-12)


# ---------------------------------------------------------------------------
# Translation joints against DART
# ---------------------------------------------------------------------------

CHAIN_KINDS = ("translation", "revolute", "translation", "revolute", "revolute", "translation")


def random_chain(seed: int):
    """Specs of a serial chain mixing translation and revolute joints (root on a translation joint)."""
    rng = np.random.default_rng(seed)
    return [dict(kind=kind, axis=random_unit(rng), rotation=random_rotation(rng),
                 translation=rng.uniform(-0.5, 0.5, size=3), mass=float(rng.uniform(0.5, 3.0)),
                 com=rng.uniform(-0.3, 0.3, size=3), inertia=random_inertia(rng) * rng.uniform(0.5, 2.0))
            for kind in CHAIN_KINDS]


def soadyn_chain(specs) -> soadyn.Model:
    m = soadyn.Model()
    m.gravity = GRAVITY
    for i, s in enumerate(specs):
        joint = Joint.translation() if s["kind"] == "translation" else Joint.revolute(s["axis"])
        m.add_body(f"b{i}", i - 1, joint, placement=(s["rotation"], s["translation"]), mass=s["mass"],
                   com=s["com"], inertia=s["inertia"])
    return m


def dart_chain(specs):
    """The same chain in DART: joint frame placed in the parent body, child body frame = joint frame."""
    import dartpy as dart

    skeleton = dart.dynamics.Skeleton("chain")
    skeleton.setGravity(GRAVITY)
    parent, joints = None, []
    for i, s in enumerate(specs):
        placement = dart.math.Isometry3()
        placement.set_rotation(s["rotation"])
        placement.set_translation(s["translation"])
        body_properties = dart.dynamics.BodyNodeProperties(dart.dynamics.BodyNodeAspectProperties(f"b{i}"))
        if s["kind"] == "translation":
            generic = dart.dynamics.GenericJointProperties_R3()
            generic.mName, generic.mT_ParentBodyToJoint = f"b{i}", placement
            joint, body = skeleton.createTranslationalJointAndBodyNodePair(
                parent, dart.dynamics.TranslationalJointProperties(generic), body_properties)
        else:
            properties = dart.dynamics.RevoluteJointProperties()
            properties.mName, properties.mAxis, properties.mT_ParentBodyToJoint = f"b{i}", s["axis"], placement
            joint, body = skeleton.createRevoluteJointAndBodyNodePair(parent, properties, body_properties)
        body.setInertia(dart.dynamics.Inertia(s["mass"], s["com"], s["inertia"]))
        joints.append(joint)
        parent = body
    return skeleton, joints


def dart_hybrid(skeleton, joints, q, v, u, prescribed_joints):
    """DART's hybrid dynamics: ACCELERATION actuators on the prescribed joints, FORCE on the others.
    Chains put DOFs in body order, each joint's in its own order, in both libraries."""
    import dartpy as dart

    start = 0
    for k, joint in enumerate(joints):
        n = joint.getNumDofs()
        joint.setActuatorType(dart.dynamics.ActuatorType.ACCELERATION if prescribed_joints[k]
                              else dart.dynamics.ActuatorType.FORCE)
        for d in range(n):
            joint.setCommand(d, float(u[start + d]))
        start += n
    skeleton.setPositions(q)
    skeleton.setVelocities(v)
    skeleton.dirtyArticulatedInertia(0)
    skeleton.computeForwardDynamics()
    return skeleton.getAccelerations(), skeleton.getForces()


@pytest.mark.parametrize("seed", range(4))
def test_translation_chains_match_dart(seed):
    """Forward, inverse and hybrid dynamics (random whole-joint masks, as DART switches them)
    of chains with translation joints, against DART's TranslationalJoint."""
    specs = random_chain(seed)
    m = soadyn_chain(specs)
    skeleton, joints = dart_chain(specs)
    assert skeleton.getNumDofs() == m.nv == 12
    rng = np.random.default_rng(seed + 50)
    dofs_of_joint = [[m.dof_index(n) for n in m.dof_names if n == f"b{i}" or n.startswith(f"b{i}:")]
                     for i in range(len(specs))]
    for trial in range(3):
        q = soadyn.random_configuration(m, 10 * seed + trial)
        v, u = rng.normal(size=m.nv), rng.normal(size=m.nv)
        for prescribed_joints in ([False] * 6, [True] * 6, list(rng.uniform(size=6) < 0.5)):
            mask = np.zeros(m.nv, dtype=bool)
            for k, flag in enumerate(prescribed_joints):
                mask[dofs_of_joint[k]] = flag
            mm = m.copy()
            mm.set_prescribed(mask)
            qdd, tau = soadyn.hybrid_dynamics(mm, q, v, u)
            qdd_dart, tau_dart = dart_hybrid(skeleton, joints, q, v, u, prescribed_joints)
            scale = max(1.0, np.max(np.abs(tau_dart)), np.max(np.abs(qdd_dart)))
            np.testing.assert_allclose(qdd, qdd_dart, rtol=0, atol=1e-10 * scale)
            np.testing.assert_allclose(tau, tau_dart, rtol=0, atol=1e-10 * scale)
        skeleton.setPositions(q)
        M = skeleton.getMassMatrix()
        np.testing.assert_allclose(soadyn.mass_matrix(m, q), M, rtol=0, atol=1e-10 * np.max(np.abs(M)))
