"""Frames and Jacobians against Pinocchio, central differences and each other.

Pinocchio (getFrameJacobian, getFrameJacobianTimeVariation after
computeJointJacobiansTimeVariation, getFrameVelocity, getFrameAcceleration,
getFrameClassicalAcceleration, jacobianCenterOfMass) on the robots of
support/robots.py and on the random trees of support/pinocchio_trees.py (every joint
type), with a welded frame at a random placement on every body. DOFs are
matched by name; a Jacobian's columns follow the DOF map and its rows swap
Pinocchio's [linear; angular] for soadyn's [angular; linear].

Run with `pytest -s` to see the largest relative error per quantity.
"""
from __future__ import annotations

import functools

import numpy as np
import pinocchio as pin
import pytest

import soadyn
from soadyn.oracles import PinocchioOracle
from support.error_log import ErrorLog, rel_error, report_fixture
from support.pinocchio_trees import CASES, CASE_IDS, Mapping, build_pinocchio, build_soadyn, random_specs
from support.robots import robot
from support.trees import JOINT_KINDS, random_rotation

RTOL = 1e-12
REFERENCES = {"world": pin.WORLD, "local": pin.LOCAL, "local_world_aligned": pin.LOCAL_WORLD_ALIGNED}
ROBOT_NAMES = ["ur5", "panda", "solo12", "talos"]

LOG = ErrorLog("Pinocchio", RTOL)
check = LOG.check


report_errors = report_fixture(LOG)


def swap(x):
    """[linear; angular] <-> [angular; linear] rows."""
    x = np.asarray(x)
    return np.concatenate([x[3:], x[:3]])


class Oracle:
    """A soadyn model and the Pinocchio model of the same system, the DOF map between them
    (v_of_pin[k] = soadyn DOF of Pinocchio DOF k) and the frames both know, by name."""

    def __init__(self, m, model, q_map, v_of_pin, frames):
        self.m, self.model, self.q_map, self.v_of_pin, self.frames = m, model, q_map, v_of_pin, frames
        self.data = model.createData()

    def columns(self, J_pin, swap_rows=True):
        """A Pinocchio Jacobian (rows x nv, Pinocchio's DOF order) in soadyn's DOF order."""
        J_pin = np.asarray(J_pin)
        out = np.empty_like(J_pin)
        out[:, self.v_of_pin] = swap(J_pin) if swap_rows else J_pin
        return out

    def run(self, q, v, qdd):
        qp, vp, ap = self.q_map(q), v[self.v_of_pin], qdd[self.v_of_pin]
        pin.forwardKinematics(self.model, self.data, qp, vp, ap)
        pin.updateFramePlacements(self.model, self.data)
        pin.computeJointJacobians(self.model, self.data, qp)
        pin.computeJointJacobiansTimeVariation(self.model, self.data, qp, vp)
        return qp


@functools.lru_cache(maxsize=None)
def robot_oracle(name: str) -> Oracle:
    path, floating = robot(name)
    m = soadyn.load_urdf(path, floating_base=floating)
    o = PinocchioOracle(m, path, floating)
    known = set(m.body_names) | set(m.frame_names)
    frames = [f.name for f in o.model.frames if f.type == pin.FrameType.BODY and f.name in known]
    return Oracle(m, o.model, o.q, o.v_of_pin, frames)


@functools.lru_cache(maxsize=None)
def tree_oracle(seed: int, floating: bool) -> Oracle:
    """A random tree of every joint type, and on every body b<i> a welded frame t<i> at a random
    placement (a zero-mass fixed body in soadyn, a frame in Pinocchio)."""
    specs = random_specs(seed, floating)
    m = build_soadyn(specs)
    model = build_pinocchio(specs, m.gravity)
    rng = np.random.default_rng(seed + 500)
    frames = []
    for s in specs:
        jid = model.getJointId(s.name)
        R, p = random_rotation(rng), rng.uniform(-0.4, 0.4, size=3)
        m.add_body(f"t{s.name}", s.name, soadyn.Joint.fixed(), placement=(R, p))
        model.addFrame(pin.Frame(s.name, jid, 0, pin.SE3.Identity(), pin.FrameType.BODY))
        model.addFrame(pin.Frame(f"t{s.name}", jid, 0, pin.SE3(R, p), pin.FrameType.BODY))
        frames += [s.name, f"t{s.name}"]
    mapping = Mapping(m, model, specs)
    return Oracle(m, model, mapping.q, mapping.v_of_pin, frames)


def random_state(m, seed):
    rng = np.random.default_rng(seed + 7)
    return soadyn.random_configuration(m, seed), rng.normal(size=m.nv), rng.normal(size=m.nv)


def universal_rate_columns(m) -> np.ndarray:
    """The DOFs whose Jacobian column turns with the joint's own coordinates: the first DOF of each
    universal joint (its subspace R2(q1)' a1). Pinocchio 4.1's computeJointJacobiansTimeVariation
    forms dJ/dt as V x J only, without this rate (test_pinocchio_omits_the_universal_subspace_rate),
    so those columns are checked against central differences and Pinocchio's accelerations instead."""
    mask = np.zeros(m.nv, dtype=bool)
    for i, kind in enumerate(m.joint_types):
        if kind == "universal":
            mask[m.v_index[i]] = True
    return mask


def compare_with_pinocchio(o: Oracle, seed: int):
    q, v, qdd = random_state(o.m, seed)
    qp = o.run(q, v, qdd)
    for frame in o.frames:
        fid = o.model.getFrameId(frame)
        check("pose", soadyn.frame_pose(o.m, q, frame), o.data.oMf[fid].homogeneous)
        for ref, rf in REFERENCES.items():
            check(f"J {ref}", soadyn.frame_jacobian(o.m, q, frame, ref),
                  o.columns(pin.getFrameJacobian(o.model, o.data, fid, rf)))
            J = soadyn.frame_jacobian(o.m, q, frame, ref)
            dJ = soadyn.frame_jacobian_time_variation(o.m, q, v, frame, ref)
            exact = ~universal_rate_columns(o.m)
            check(f"dJ/dt {ref}", dJ[:, exact],
                  o.columns(pin.getFrameJacobianTimeVariation(o.model, o.data, fid, rf))[:, exact])
            # Every column, universal joints' included, through the acceleration Pinocchio forms
            # from its joints' own velocity-product terms.
            pin_acceleration = (pin.getFrameClassicalAcceleration if ref == "local_world_aligned"
                                else pin.getFrameAcceleration)(o.model, o.data, fid, rf).vector
            check(f"J qdd + dJ/dt v {ref}", J @ qdd + dJ @ v, swap(pin_acceleration))
            check(f"velocity {ref}", soadyn.frame_velocity(o.m, q, v, frame, ref),
                  swap(pin.getFrameVelocity(o.model, o.data, fid, rf).vector))
            check(f"acceleration {ref}", soadyn.frame_acceleration(o.m, q, v, qdd, frame, ref),
                  swap(pin.getFrameAcceleration(o.model, o.data, fid, rf).vector))
            check(f"classical acceleration {ref}",
                  soadyn.frame_acceleration(o.m, q, v, qdd, frame, ref, classical=True),
                  swap(pin.getFrameClassicalAcceleration(o.model, o.data, fid, rf).vector))
    check("centre-of-mass J", soadyn.center_of_mass_jacobian(o.m, q),
          o.columns(pin.jacobianCenterOfMass(o.model, o.data, qp), swap_rows=False))


# ---------------------------------------------------------------------------
# Against Pinocchio
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("name", ROBOT_NAMES)
def test_robot_frames_against_pinocchio(name):
    o = robot_oracle(name)
    assert len(o.frames) >= o.m.nbodies  # every link: the bodies and the welded ones
    for seed in range(3):
        compare_with_pinocchio(o, seed)


def test_panda_hand_tcp_is_a_welded_frame_pinocchio_agrees_with():
    o = robot_oracle("panda")
    assert "panda_hand_tcp" in o.frames and "panda_hand_tcp" not in o.m.body_names
    q, v, qdd = random_state(o.m, 11)
    o.run(q, v, qdd)
    fid = o.model.getFrameId("panda_hand_tcp")
    check("pose", soadyn.frame_pose(o.m, q, "panda_hand_tcp"), o.data.oMf[fid].homogeneous)
    J = soadyn.frame_jacobian(o.m, q, "panda_hand_tcp", "local_world_aligned")
    check("J local_world_aligned", J, o.columns(pin.getFrameJacobian(o.model, o.data, fid, pin.LOCAL_WORLD_ALIGNED)))
    # The tool centre point is 0.1034 m beyond the hand: its frame is not the hand's.
    hand = soadyn.frame_pose(o.m, q, "panda_hand")
    assert np.linalg.norm(soadyn.frame_pose(o.m, q, "panda_hand_tcp")[:3, 3] - hand[:3, 3]) == pytest.approx(0.1034)


@pytest.mark.parametrize("seed,floating", CASES, ids=CASE_IDS)
def test_random_tree_frames_against_pinocchio(seed, floating):
    o = tree_oracle(seed, floating)
    assert set(o.m.joint_types) >= set(JOINT_KINDS)
    compare_with_pinocchio(o, seed)


# ---------------------------------------------------------------------------
# Central differences and self-consistency
# ---------------------------------------------------------------------------

def along(m, q, v, t):
    return soadyn.integrate(m, q, v, t)


def pose_rate(m, q, v, frame, h=1e-6):
    """d/dt of the frame's pose along q (+) v t, by central differences."""
    return (soadyn.frame_pose(m, along(m, q, v, h), frame) - soadyn.frame_pose(m, along(m, q, v, -h), frame)) / (2 * h)


def jacobian_rate(m, q, v, frame, ref, h=1e-6):
    return (soadyn.frame_jacobian(m, along(m, q, v, h), frame, ref)
            - soadyn.frame_jacobian(m, along(m, q, v, -h), frame, ref)) / (2 * h)


def differences_agree(m, q, v, frame, fd_tol=1e-7):
    """J against the pose's rate and dJ/dt against J's rate, by central differences."""
    T = soadyn.frame_pose(m, q, frame)
    dT = pose_rate(m, q, v, frame)
    omega_world = dT[:3, :3] @ T[:3, :3].T
    Jv = soadyn.frame_jacobian(m, q, frame, "local_world_aligned") @ v
    assert rel_error(Jv[3:], dT[:3, 3]) < fd_tol, frame
    assert rel_error(Jv[:3], [omega_world[2, 1], omega_world[0, 2], omega_world[1, 0]]) < fd_tol, frame
    for ref in REFERENCES:
        dJ = soadyn.frame_jacobian_time_variation(m, q, v, frame, ref)
        assert rel_error(dJ, jacobian_rate(m, q, v, frame, ref)) < fd_tol, (frame, ref)


def self_consistent(m, q, v, qdd, frame):
    """J v is the frame's velocity; J qdd + dJ/dt v its acceleration (spatial for world and local,
    classical for local_world_aligned, whose origin moves with the frame)."""
    for ref in REFERENCES:
        J = soadyn.frame_jacobian(m, q, frame, ref)
        dJ = soadyn.frame_jacobian_time_variation(m, q, v, frame, ref)
        assert rel_error(J @ v, soadyn.frame_velocity(m, q, v, frame, ref)) < RTOL, (frame, ref)
        classical = ref == "local_world_aligned"
        a = soadyn.frame_acceleration(m, q, v, qdd, frame, ref, classical=classical)
        assert rel_error(J @ qdd + dJ @ v, a) < RTOL, (frame, ref)


@pytest.mark.parametrize("seed,floating", CASES[:4], ids=CASE_IDS[:4])
def test_random_tree_against_central_differences(seed, floating):
    o = tree_oracle(seed, floating)
    q, v, qdd = random_state(o.m, seed)
    for frame in o.frames:
        differences_agree(o.m, q, v, frame)
        self_consistent(o.m, q, v, qdd, frame)


@pytest.mark.parametrize("name", ["panda", "solo12"])
def test_robot_against_central_differences(name):
    o = robot_oracle(name)
    q, v, qdd = random_state(o.m, 5)
    for frame in o.frames:
        differences_agree(o.m, q, v, frame)
        self_consistent(o.m, q, v, qdd, frame)


def single_joint_chain(kind: str):
    """The joint `kind` (universal with non-orthogonal axes) followed by a revolute joint at an
    offset: the second column turns with the first joint's motion."""
    rng = np.random.default_rng(3)
    J = soadyn.Joint
    a = rng.normal(size=3)
    joint = {
        "revolute": lambda: J.revolute(a), "prismatic": lambda: J.prismatic(a), "helical": lambda: J.helical(a, 0.2),
        "universal": lambda: J.universal(a, np.cross(a, [0.3, 1.0, 0.2]) + 0.4 * a), "cylindrical": lambda: J.cylindrical(a),
        "planar": J.planar, "spherical": J.spherical, "free": J.free, "translation": J.translation,
    }[kind]()
    m = soadyn.Model()
    inertia = np.diag([0.1, 0.2, 0.25])
    m.add_body("first", None, joint, placement=(random_rotation(rng), [0.1, -0.2, 0.3]), mass=1.0, inertia=inertia)
    m.add_body("second", "first", J.revolute([0.2, 0.5, -1.0]), placement=(random_rotation(rng), [0.4, 0.1, -0.2]),
               mass=1.5, com=[0.1, 0.0, 0.2], inertia=inertia)
    m.add_body("tip", "second", J.fixed(), placement=(random_rotation(rng), [0.3, 0.2, 0.1]))
    return m


@pytest.mark.parametrize("kind", JOINT_KINDS)
def test_every_joint_type_subspace_rate(kind):
    """dJ/dt includes the rate of each joint's motion subspace: universal's turns with q1,
    the others are constant in the body frame (planar, spherical and free take body twists)."""
    m = single_joint_chain(kind)
    for seed in range(3):
        q, v, qdd = random_state(m, seed)
        for frame in ("first", "second", "tip"):
            differences_agree(m, q, v, frame)
            self_consistent(m, q, v, qdd, frame)


def test_universal_subspace_rate_is_not_the_joint_bias_alone():
    """With the universal joint's first rate zero its bias qd0 qd1 (R2' a1) x a2 vanishes, but its
    subspace still turns with qd1: a rate taken from the bias would miss it. (In world axes the first
    column, the fixed axis a1, does not move at all: the subspace rate cancels V x J there.)"""
    m = single_joint_chain("universal")
    q, v, _ = random_state(m, 1)
    v[0] = 0.0
    assert abs(v[1]) > 0.1
    for ref in REFERENCES:
        assert rel_error(soadyn.frame_jacobian_time_variation(m, q, v, "tip", ref),
                         jacobian_rate(m, q, v, "tip", ref)) < 1e-7, ref
    assert np.abs(soadyn.frame_jacobian_time_variation(m, q, v, "tip", "world")[:, 0]).max() < 1e-14
    assert np.abs(soadyn.frame_jacobian_time_variation(m, q, v, "tip", "local")[:, 0]).max() > 1e-2


def test_pinocchio_omits_the_universal_subspace_rate():
    """Why universal columns of dJ/dt are not compared with Pinocchio's column by column: its dJ/dt
    column differs from the central difference of its own J, where soadyn's agrees."""
    o = tree_oracle(0, True)
    q, v, qdd = random_state(o.m, 0)
    o.run(q, v, qdd)
    column = int(np.flatnonzero(universal_rate_columns(o.m))[0])
    frame = next(f for f in o.frames if abs(soadyn.frame_jacobian(o.m, q, f, "world")[:, column]).max() > 0)
    fid = o.model.getFrameId(frame)
    h = 1e-6

    def pin_jacobian(t):
        qp = pin.integrate(o.model, o.q_map(q), t * v[o.v_of_pin])
        return o.columns(pin.computeFrameJacobian(o.model, o.model.createData(), qp, fid, pin.WORLD))

    pin_fd = (pin_jacobian(h) - pin_jacobian(-h)) / (2 * h)
    pin_dJ = o.columns(pin.getFrameJacobianTimeVariation(o.model, o.data, fid, pin.WORLD))
    ours = soadyn.frame_jacobian_time_variation(o.m, q, v, frame, "world")
    assert rel_error(ours[:, column], pin_fd[:, column]) < 1e-7
    assert rel_error(pin_dJ[:, column], pin_fd[:, column]) > 1e-3


def test_center_of_mass_jacobian_against_central_differences():
    o = tree_oracle(2, True)
    q, v, _ = random_state(o.m, 2)
    h = 1e-6
    rate = (soadyn.center_of_mass(o.m, along(o.m, q, v, h)) - soadyn.center_of_mass(o.m, along(o.m, q, v, -h))) / (2 * h)
    assert rel_error(soadyn.center_of_mass_jacobian(o.m, q) @ v, rate) < 1e-7


def test_loop_model_frames():
    """On a loop model the Jacobians are the spanning tree's: at a closed state with consistent
    velocities, every body's Jacobians match their central differences and each other."""
    m = soadyn.scenes.four_bar()
    q, v = soadyn.scenes.four_bar_state(0.7, 1.3)
    qdd = np.random.default_rng(0).normal(size=m.nv)
    for frame in m.body_names:
        differences_agree(m, q, v, frame)
        self_consistent(m, q, v, qdd, frame)
    assert np.abs(soadyn.loop_residual(m, q)).max() < 1e-9


# ---------------------------------------------------------------------------
# Lookup and refusals
# ---------------------------------------------------------------------------

def test_frames_by_index_and_world():
    m = single_joint_chain("universal")
    q, v, _ = random_state(m, 0)
    for index, name in enumerate(m.body_names):
        assert np.array_equal(soadyn.frame_jacobian(m, q, index), soadyn.frame_jacobian(m, q, name))
        assert np.array_equal(soadyn.frame_jacobian(m, q, np.int64(index)), soadyn.frame_jacobian(m, q, name))
    assert np.array_equal(soadyn.frame_pose(m, q, "world"), np.eye(4))
    assert not np.any(soadyn.frame_jacobian(m, q, "world", "world"))
    assert not np.any(soadyn.frame_velocity(m, q, v, "world"))


def test_bad_frames_and_references_are_named():
    m = single_joint_chain("revolute")
    q, v, _ = random_state(m, 0)
    with pytest.raises(ValueError, match="'no_such_link'"):
        soadyn.frame_jacobian(m, q, "no_such_link")
    with pytest.raises(ValueError, match="frame index 7"):
        soadyn.frame_pose(m, q, 7)
    with pytest.raises(ValueError, match="frame index -1"):
        soadyn.frame_velocity(m, q, v, -1)
    with pytest.raises(ValueError, match="'global'"):
        soadyn.frame_jacobian(m, q, "tip", "global")
    with pytest.raises(ValueError, match=r"frame index 4294967296 "):
        soadyn.frame_pose(m, q, 2**32)
    for not_a_frame in (1.5, True, None, np.array([0])):
        with pytest.raises(TypeError, match="frame"):
            soadyn.frame_pose(m, q, not_a_frame)
    with pytest.raises(ValueError, match="q has shape"):
        soadyn.frame_pose(m, q[:-1], "tip")


def test_flexible_frames_are_refused_by_name():
    from support.flexible_trees import random_flexible_tree

    m, parts = random_flexible_tree(4, n_bodies=8)
    flexible = [p.name for p in parts if p.flexible is not None]
    assert flexible
    q = soadyn.random_configuration(m, 0)
    for name in flexible:
        with pytest.raises(ValueError, match=f"flexible body '{name}'"):
            soadyn.frame_jacobian(m, q, name)
        with pytest.raises(ValueError, match=f"flexible body '{name}'"):
            soadyn.frame_pose(m, q, f"{name}:a")
    with pytest.raises(ValueError, match="flexible"):
        soadyn.center_of_mass_jacobian(m, q)
    rigid_on_rigid = [p.name for p in parts if p.flexible is None and not any(
        a.flexible is not None for a in _ancestors(parts, p))]
    assert rigid_on_rigid
    soadyn.frame_jacobian(m, q, rigid_on_rigid[0])  # rigid path: supported


def _ancestors(parts, part):
    by_name = {p.name: p for p in parts}
    while part.parent is not None:
        part = by_name[part.parent]
        yield part


def test_non_finite_results_raise_naming_the_call():
    """Finite inputs whose results overflow raise DynamicsError, never return inf or NaN."""
    m = soadyn.Model()
    m.add_body("slider_a", None, soadyn.Joint.prismatic([1, 0, 0]), mass=1.0, inertia=[1, 1, 1])
    m.add_body("slider_b", "slider_a", soadyn.Joint.prismatic([1, 0, 0]), mass=1.0, inertia=[1, 1, 1])
    m.add_body("arm", "slider_b", soadyn.Joint.revolute([0, 0, 1]), mass=1.0, inertia=[1, 1, 1])
    q, v = np.array([1e308, 1e308, 0.3]), np.array([1e308, 1e308, 1.0])
    with pytest.raises(soadyn.DynamicsError, match="frame_pose"):
        soadyn.frame_pose(m, q, "arm")
    with pytest.raises(soadyn.DynamicsError, match=r"frame_jacobian: the column of 'slider_b' is not finite"):
        soadyn.frame_jacobian(m, q, "arm", "world")
    with pytest.raises(soadyn.DynamicsError, match="frame_velocity"):
        soadyn.frame_velocity(m, np.zeros(3), v, "arm", "world")
    with pytest.raises(soadyn.DynamicsError, match="center_of_mass_jacobian"):
        soadyn.center_of_mass_jacobian(m, q)
