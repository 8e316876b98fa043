"""The Stanford arm scene against Pinocchio and the Denavit-Hartenberg definition.

Pinocchio's model is built here from the same DH rows with Pinocchio's own SE3 and Inertia algebra
(joint placements, the link's mass properties carried from its DH frame into the joint frame), so a
mistake in soadyn's DH conversion shows up as a mismatch. Checked: the hand's pose against the product
of the A_i matrices; the drive forces of the cycloidal rest-to-rest motion (Saha, Shah & Nandihal 2013,
Eqs. 34-35; every DOF prescribed, as in their Fig. 5) against Pinocchio's RNEA at the closed-form q, v, a
of Eq. 34; forward dynamics against ABA; the free fall from the same start (their Fig. 6) against the
same RK4 steps taken with Pinocchio's ABA.
"""
from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

import soadyn
from soadyn.io.denavit_hartenberg import DHLink, dh_model, dh_transform
from soadyn.stanford_arm import MOTION_DURATION, MOTION_END, MOTION_START, STANFORD_ARM_LINKS

GRAVITY = 9.81


def _pin_dh_rest(link: DHLink) -> pin.SE3:
    """The fixed part of A_i after the joint: Trans_z(d) (revolute only) Trans_x(a) Rot_x(alpha)."""
    d = link.d if link.kind == "revolute" else 0.0
    along_z = pin.SE3(np.eye(3), np.array([0.0, 0.0, d]))
    along_x = pin.SE3(np.eye(3), np.array([link.a, 0.0, 0.0]))
    twist = pin.SE3(pin.utils.rotate("x", link.alpha), np.zeros(3))
    return along_z * along_x * twist


def _pin_joint_offset(link: DHLink) -> pin.SE3:
    """Rot_z(theta) (and Trans_z(d) for a prismatic joint): the joint frame at q = 0 in the parent's DH frame."""
    d = link.d if link.kind == "prismatic" else 0.0
    return pin.SE3(pin.utils.rotate("z", link.theta), np.array([0.0, 0.0, d]))


def pinocchio_arm(links) -> pin.Model:
    model = pin.Model()
    model.gravity = pin.Motion(np.array([0.0, 0.0, -GRAVITY, 0.0, 0.0, 0.0]))
    parent, rest = 0, pin.SE3.Identity()
    for link in links:
        joint = pin.JointModelRZ() if link.kind == "revolute" else pin.JointModelPZ()
        parent = model.addJoint(parent, joint, rest * _pin_joint_offset(link), link.name)
        rest = _pin_dh_rest(link)
        inertia_in_dh = pin.Inertia(link.mass, np.asarray(link.com, float), np.diag(np.asarray(link.inertia, float)))
        model.appendBodyToJoint(parent, rest.act(inertia_in_dh), pin.SE3.Identity())
    return model


@pytest.fixture(scope="module")
def arms():
    m = soadyn.scenes.stanford_arm()
    p = pinocchio_arm(STANFORD_ARM_LINKS)
    assert m.dof_names == [p.names[j] for j in range(1, p.njoints)]
    return m, p, p.createData()


def cycloid(t: float):
    """q, v, a of Eq. 34 at time t, for every DOF."""
    T, delta, w = MOTION_DURATION, MOTION_END - MOTION_START, 2.0 * np.pi / MOTION_DURATION
    q = MOTION_START + delta / T * (t - np.sin(w * t) / w)
    v = delta / T * (1.0 - np.cos(w * t))
    a = delta / T * w * np.sin(w * t)
    return q, v, a


def test_the_hand_sits_where_the_product_of_the_dh_matrices_puts_it(arms):
    m = arms[0]
    rng = np.random.default_rng(3)
    for _ in range(20):
        q = rng.uniform(-np.pi, np.pi, 6)
        q[2] = rng.uniform(0.3, 1.3)
        expected = np.eye(4)
        for link, qi in zip(STANFORD_ARM_LINKS, q):
            expected = expected @ dh_transform(link, qi)
        np.testing.assert_allclose(soadyn.frame_pose(m, q, "tool"), expected, rtol=0, atol=1e-14)


def test_prescribed_cycloid_drive_forces_equal_pinocchio_rnea(arms):
    m, p, d = arms
    m = m.copy()
    m.set_prescribed([True] * 6)
    sim = soadyn.Simulator(m, dt=0.01, integrator="rk4")
    sim.set_state(MOTION_START, np.zeros(6))
    for dof, source in enumerate(soadyn.scenes.stanford_arm_motion()):
        sim.prescribe(dof, source)
    run = sim.run(MOTION_DURATION)
    worst = 0.0
    for k in range(0, len(run.tau), 25):
        q, v, a = cycloid(run.t[k])
        np.testing.assert_allclose(run.q[k], q, rtol=0, atol=1e-13)
        np.testing.assert_allclose(run.v[k], v, rtol=0, atol=1e-13)
        expected = pin.rnea(p, d, q, v, a)
        worst = max(worst, float(np.max(np.abs(run.tau[k] - expected))))
    assert worst <= 1e-11, worst
    # the arm holds itself against gravity: the forces are not all small
    assert np.max(np.abs(run.tau)) > 10.0


def test_forward_dynamics_equals_pinocchio_aba(arms):
    m, p, d = arms
    rng = np.random.default_rng(11)
    for _ in range(20):
        q, v, tau = rng.normal(size=6), rng.normal(size=6), rng.normal(size=6) * 5
        q[2] = rng.uniform(0.3, 1.3)
        expected = pin.aba(p, d, q, v, tau)
        np.testing.assert_allclose(soadyn.forward_dynamics(m, q, v, tau), expected, rtol=1e-11,
                                   atol=1e-11 * np.max(np.abs(expected)))


def test_free_fall_matches_rk4_on_pinocchio_aba(arms):
    m, p, d = arms
    dt, steps = 1e-3, 500
    sim = soadyn.Simulator(m, dt=dt, integrator="rk4")
    sim.set_state(MOTION_START, np.zeros(6))
    run = sim.run(steps * dt)

    def rate(x):
        return np.concatenate([x[6:], pin.aba(p, d, x[:6], x[6:], np.zeros(6))])

    x = np.concatenate([MOTION_START, np.zeros(6)])
    for _ in range(steps):
        k1 = rate(x)
        k2 = rate(x + dt / 2 * k1)
        k3 = rate(x + dt / 2 * k2)
        k4 = rate(x + dt * k3)
        x = x + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    np.testing.assert_allclose(run.q[-1], x[:6], rtol=0, atol=1e-9)
    np.testing.assert_allclose(run.v[-1], x[6:], rtol=0, atol=1e-8)
    assert np.max(np.abs(run.q[-1] - MOTION_START)) > 0.1  # it did fall


def test_a_bad_dh_row_is_named():
    with pytest.raises(ValueError, match=r"row 2 \('b'\): kind"):
        dh_model([DHLink("a", "revolute", mass=1.0, inertia=(1, 1, 1)), DHLink("b", "spherical")])
    with pytest.raises(ValueError, match=r"row 1 \('a'\): alpha must be a finite number"):
        dh_model([DHLink("a", "revolute", alpha=float("nan"), mass=1.0, inertia=(1, 1, 1))])
    with pytest.raises(ValueError, match="no rows"):
        dh_model([])
    with pytest.raises(soadyn.NonphysicalInertiaError, match="wrist_2"):
        dh_model(STANFORD_ARM_LINKS)  # link 5's table inertia breaks the triangle inequality
