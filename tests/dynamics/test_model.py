"""Model building: names, layout, fixed-joint merging, flags, kinematics, integration."""
import numpy as np
import pytest

import soadyn
from support.flexible_trees import random_flexible_body
from support.trees import random_rotation, random_state, random_tree


def test_names_and_layout():
    m = soadyn.Model()
    assert m.add_body("base", None, soadyn.Joint.free(), mass=1, inertia=[1, 1, 1]) == 0
    assert m.add_body("arm", "base", soadyn.Joint.revolute([0, 0, 1], name="shoulder"), mass=1, inertia=[1, 1, 1]) == 1
    assert m.add_body("hand", 1, soadyn.Joint.spherical(), mass=1, inertia=[1, 1, 1]) == 2
    assert (m.nbodies, m.nq, m.nv) == (3, 12, 10)
    assert m.body_names == ["base", "arm", "hand"]
    assert m.joint_names == ["base", "shoulder", "hand"]
    assert m.dof_names == ["base:wx", "base:wy", "base:wz", "base:vx", "base:vy", "base:vz", "shoulder",
                           "hand:wx", "hand:wy", "hand:wz"]
    assert m.coordinate_names[:7] == ["base:px", "base:py", "base:pz", "base:qx", "base:qy", "base:qz", "base:qw"]
    assert m.q_index == [0, 7, 8] and m.v_index == [0, 6, 7]
    assert m.parents == [-1, 0, 1]
    np.testing.assert_array_equal(soadyn.neutral_configuration(m), [0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1])


def test_prescribed_flags_by_mask_name_joint_and_index():
    m, _ = random_tree(0, 6)
    assert not m.prescribed.any()
    m.set_prescribed("b0")  # a joint name selects all its DOFs
    assert m.prescribed[:6].all() and not m.prescribed[6:].any()
    m.set_prescribed("b0:vx", False)
    assert not m.prescribed[3]
    m.set_prescribed([m.nv - 1])
    assert m.prescribed[-1]
    mask = np.arange(m.nv) % 2 == 0
    m.set_prescribed(mask)
    np.testing.assert_array_equal(m.prescribed, mask)
    m.set_prescribed(mask, False)  # the mask names the regular DOFs
    np.testing.assert_array_equal(m.prescribed, ~mask)
    m.set_regular(m.dof_names)
    assert not m.prescribed.any()


def test_fixed_joint_merges_mass_properties_exactly():
    """A welded tool equals the same link with the combined inertia (parallel-axis theorem by hand)."""
    rng = np.random.default_rng(4)
    R_tool, p_tool = random_rotation(rng), np.array([0.1, -0.2, 0.5])
    m1, c1, I1 = 1.5, np.array([0.0, 0.1, 0.2]), np.diag([0.02, 0.03, 0.04])
    m2, c2, I2 = 0.7, np.array([0.05, 0.0, -0.1]), np.diag([0.01, 0.012, 0.015])
    welded = soadyn.Model()
    welded.add_body("link", None, soadyn.Joint.revolute([0, 1, 0]), mass=m1, com=c1, inertia=I1)
    assert welded.add_body("tool", "link", soadyn.Joint.fixed(), placement=(R_tool, p_tool),
                           mass=m2, com=c2, inertia=I2) == -1
    welded.add_body("finger", "tool", soadyn.Joint.prismatic([1, 0, 0]), placement=[0, 0, 0.1], mass=0.2,
                    inertia=[1e-3, 1e-3, 1e-3])
    assert welded.nbodies == 2 and welded.frame_names == ["tool"]

    c2_link = R_tool @ c2 + p_tool
    mass = m1 + m2
    com = (m1 * c1 + m2 * c2_link) / mass

    def shifted(I, mass_k, c_k):  # parallel-axis theorem to the combined COM
        d = c_k - com
        return I + mass_k * (d @ d * np.eye(3) - np.outer(d, d))

    inertia = shifted(I1, m1, c1) + shifted(R_tool @ I2 @ R_tool.T, m2, c2_link)
    merged = soadyn.Model()
    merged.add_body("link", None, soadyn.Joint.revolute([0, 1, 0]), mass=mass, com=com, inertia=inertia)
    merged.add_body("finger", "link", soadyn.Joint.prismatic([1, 0, 0]),
                    placement=(R_tool, R_tool @ [0, 0, 0.1] + p_tool), mass=0.2, inertia=[1e-3, 1e-3, 1e-3])
    q, v, tau = np.array([0.3, 0.1]), np.array([-0.5, 0.2]), np.array([0.7, -0.1])
    np.testing.assert_allclose(soadyn.mass_matrix(welded, q), soadyn.mass_matrix(merged, q), rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(soadyn.forward_dynamics(welded, q, v, tau), soadyn.forward_dynamics(merged, q, v, tau),
                               rtol=1e-12)
    assert soadyn.potential_energy(welded, q) == pytest.approx(soadyn.potential_energy(merged, q), rel=1e-13)


def test_fixed_to_world_is_a_frame_and_carries_placement():
    m = soadyn.Model()
    m.add_body("pedestal", None, soadyn.Joint.fixed(), placement=[0, 0, 1.0], mass=50.0, inertia=[1, 1, 1])
    m.add_body("link", "pedestal", soadyn.Joint.revolute([0, 0, 1]), mass=1.0, com=[0.5, 0, 0])
    poses, _ = soadyn.forward_kinematics(m, [np.pi / 2])
    np.testing.assert_allclose(poses[0][:3, 3], [0, 0, 1.0], atol=1e-15)
    np.testing.assert_allclose(soadyn.center_of_mass(m, [np.pi / 2]), [0, 0.5, 1.0], atol=1e-15)


def test_forward_kinematics_chain_closed_form():
    m = soadyn.Model()
    m.add_body("l1", None, soadyn.Joint.revolute([0, 0, 1]), mass=1)
    m.add_body("l2", "l1", soadyn.Joint.revolute([0, 0, 1]), placement=[1.0, 0, 0], mass=1)
    m.add_body("l3", "l2", soadyn.Joint.prismatic([1, 0, 0]), placement=[0.5, 0, 0], mass=1)
    q, v = np.array([0.3, 0.4, 0.2]), np.array([1.0, 2.0, 0.5])
    poses, vel = soadyn.forward_kinematics(m, q, v)
    a, b = q[0], q[0] + q[1]
    tip = np.array([np.cos(a), np.sin(a), 0]) + (0.5 + q[2]) * np.array([np.cos(b), np.sin(b), 0])
    np.testing.assert_allclose(poses[2][:3, 3], tip, atol=1e-15)
    # Body-frame velocity of l3: angular 3 rad/s about z; linear = R' d(tip)/dt.
    dtip = v[0] * np.array([-np.sin(a), np.cos(a), 0]) + v[2] * np.array([np.cos(b), np.sin(b), 0]) \
        + (0.5 + q[2]) * (v[0] + v[1]) * np.array([-np.sin(b), np.cos(b), 0])
    np.testing.assert_allclose(vel[2], np.r_[0, 0, 3.0, poses[2][:3, :3].T @ dtip], atol=1e-14)


def test_integrate_free_joint_constant_twist_is_a_screw():
    """A constant body twist (w, u) for time t moves the body along the exact screw (SE(3) exponential)."""
    m = soadyn.Model()
    m.add_body("body", None, soadyn.Joint.free(), mass=1, inertia=[1, 1, 1])
    w, speed, t = 2.0, 3.0, 0.9
    q = soadyn.integrate(m, soadyn.neutral_configuration(m), [0, 0, w, speed, 0, 0], t)
    # Circle of radius speed / w in the x-y plane; heading w t.
    np.testing.assert_allclose(q[:3], [speed / w * np.sin(w * t), speed / w * (1 - np.cos(w * t)), 0], atol=1e-15)
    np.testing.assert_allclose(q[3:], [0, 0, np.sin(w * t / 2), np.cos(w * t / 2)], atol=1e-15)


def test_integrate_keeps_quaternions_unit_and_composes():
    m, _ = random_tree(1, 10)
    q, v, _ = random_state(m, 1)
    q1 = soadyn.integrate(m, soadyn.integrate(m, q, v, 0.01), v, 0.01)
    q2 = soadyn.integrate(m, q, v, 0.02)
    # Constant-velocity steps compose exactly for joints whose velocity is constant in the body frame.
    for i, kind in enumerate(m.joint_types):
        s = slice(m.q_index[i], m.q_index[i + 1] if i + 1 < m.nbodies else m.nq)
        np.testing.assert_allclose(q1[s], q2[s], atol=1e-14, err_msg=kind)
    for i, kind in enumerate(m.joint_types):
        if kind in ("spherical", "free"):
            quat = q2[m.q_index[i] + (3 if kind == "free" else 0):][:4]
            assert abs(np.linalg.norm(quat) - 1) < 1e-15


def test_copy_is_independent():
    m, _ = random_tree(2, 5)
    c = m.copy()
    c.set_prescribed("b1")
    c.gravity = [0, 0, -1.62]
    assert not m.prescribed.any() and m.gravity[2] == -9.81
    q, v, rng = random_state(m, 2)
    tau = rng.normal(size=m.nv)
    c.gravity = m.gravity
    c.set_regular("b1")
    np.testing.assert_array_equal(soadyn.forward_dynamics(c, q, v, tau), soadyn.forward_dynamics(m, q, v, tau))


def test_welded_parts_need_only_leave_the_body_physical():
    """A CAD piece welded to a body may violate the triangle inequality alone; the merged body may not."""
    m = soadyn.Model()
    m.add_body("link", None, soadyn.Joint.revolute([0, 0, 1]), mass=2.0, inertia=[0.1, 0.1, 0.1])
    m.add_body("sliver", "link", soadyn.Joint.fixed(), mass=0.01, inertia=[1e-5, 6e-4, 1.3e-3])
    with pytest.raises(ValueError, match="principal moments .* triangle inequality"):
        m.add_body("moving_sliver", "link", soadyn.Joint.revolute([1, 0, 0]), mass=0.01, inertia=[1e-5, 6e-4, 1.3e-3])
    with pytest.raises(ValueError, match="body 'link' with 'slab' welded to it: principal moments"):
        m.add_body("slab", "link", soadyn.Joint.fixed(), mass=0.01, inertia=[0.0, 0.0, 1.0])
    assert m.frame_names == ["sliver"]  # the refused weld left the body unchanged
    assert m.masses == [pytest.approx(2.01)]


def test_spatial_inertia_must_be_finite_at_build_time():
    """mass * com overflows long before mass or com: refused when added, naming the body, not reported later as singular."""
    m = soadyn.Model()
    m.add_body("link", None, soadyn.Joint.revolute([0, 0, 1]), mass=1.0, inertia=[1, 1, 1])
    with pytest.raises(ValueError, match="body 'far': spatial inertia about the body frame origin is not finite"):
        m.add_body("far", "link", soadyn.Joint.revolute([0, 1, 0]), mass=1.0, com=[1e200, 0, 0], inertia=[1, 1, 1])
    with pytest.raises(ValueError, match="body 'heavy': spatial inertia .* is not finite"):
        m.add_body("heavy", "link", soadyn.Joint.revolute([0, 1, 0]), mass=1e300, com=[1e10, 0, 0], inertia=[1, 1, 1])
    with pytest.raises(ValueError, match="body 'far_weld': spatial inertia .* is not finite"):
        m.add_body("far_weld", "link", soadyn.Joint.fixed(), mass=1.0, com=[0, 1e200, 0])
    with pytest.raises(ValueError, match="body 'link' with 'overflow' welded to it: spatial inertia .* is not finite"):
        m.add_body("overflow", "link", soadyn.Joint.fixed(), placement=[1e160, 0, 0], mass=1e10)
    assert (m.nbodies, m.frame_names, m.masses) == (1, [], [1.0])  # nothing of the refused bodies remains
    np.testing.assert_allclose(soadyn.forward_dynamics(m, [0.0], [0.0], [1.0]), [1.0])


def test_accept_nonphysical_inertia_is_an_explicit_opt_in():
    m = soadyn.Model()
    with pytest.raises(soadyn.NonphysicalInertiaError, match="body 'rod': principal moments .* triangle inequality"):
        m.add_body("rod", None, soadyn.Joint.revolute([0, 0, 1]), mass=1.0, inertia=[1, 0.1, 0.1])
    assert issubclass(soadyn.NonphysicalInertiaError, ValueError)
    assert m.add_body("rod", None, soadyn.Joint.revolute([0, 0, 1]), mass=1.0, inertia=[1, 0.1, 0.1],
                      accept_nonphysical_inertia=True) == 0
    # a weld into the accepted body needs the opt-in too: the merged body is checked again
    with pytest.raises(soadyn.NonphysicalInertiaError, match="body 'rod' with 'tag' welded to it"):
        m.add_body("tag", "rod", soadyn.Joint.fixed(), mass=0.01)
    m.add_body("tag", "rod", soadyn.Joint.fixed(), mass=0.01, accept_nonphysical_inertia=True)
    # the opt-in covers physics only: finite and non-negative stay required
    for bad, message in ((dict(mass=-1.0), "mass -1 is negative"), (dict(com=[1e200, 0, 0]), "not finite")):
        args = dict(mass=1.0, inertia=[1, 0.1, 0.1], accept_nonphysical_inertia=True) | bad
        with pytest.raises(ValueError, match=f"body 'x': .*{message}"):
            m.add_body("x", "rod", soadyn.Joint.revolute([1, 0, 0]), **args)
    assert m.nbodies == 1 and m.masses == [pytest.approx(1.01)]


class _NotANumber:
    pass


@pytest.mark.parametrize("argument, value", [
    ("mass", "1.0"), ("mass", 1 + 0j), ("mass", [1.0]), ("mass", None), ("mass", True), ("mass", np.array([1.0, 2.0])),
    ("com", [1 + 1j, 0, 0]), ("com", ["1", "0", "0"]), ("com", "100"), ("com", [None, 0, 0]), ("com", [True, False, True]),
    ("inertia", np.ones(3, dtype=complex)), ("inertia", ["1", "1", "1"]), ("inertia", _NotANumber()),
    ("placement", np.eye(4, dtype=complex)), ("placement", "0 0 1"), ("placement", (np.eye(3), ["0", "0", "1"])),
    ("placement", ([[1, 0, 0], [0, 1, 0], [0, 0, "1"]], None)), ("placement", [[1, 2], [3]]),
    ("parent", 1.5), ("parent", True), ("parent", ["base"]),
    ("joint", "revolute"), ("name", 7), ("name", None), ("accept_nonphysical_inertia", "yes"),
])
def test_add_body_argument_of_the_wrong_type_is_a_type_error(argument, value):
    """numpy would read '1.0' as a number and drop an imaginary part: every wrong type is refused by name."""
    m = soadyn.Model()
    m.add_body("base", None, soadyn.Joint.revolute([0, 0, 1]), mass=1.0, inertia=[1, 1, 1])
    args = dict(name="arm", parent="base", joint=soadyn.Joint.revolute([0, 1, 0]), mass=1.0, com=[0, 0, 0.1],
                inertia=[1, 1, 1])
    args[argument] = value
    body = "arm" if argument != "name" else ""
    pattern = f"body '{body}': {argument}" if argument not in ("name",) else "body name must be a str"
    if argument == "accept_nonphysical_inertia":
        pattern = "body 'arm': accept_nonphysical_inertia must be a bool"
    with pytest.raises(TypeError, match=pattern):
        m.add_body(args.pop("name"), args.pop("parent"), args.pop("joint"), **args)
    assert m.nbodies == 1 and m.frame_names == []


@pytest.mark.parametrize("argument, value", [
    ("name", 3), ("body", "beam"), ("joint", "fixed"), ("placement", [1j, 0, 0]), ("parent", 2.0),
])
def test_add_flexible_body_argument_of_the_wrong_type_is_a_type_error(argument, value):
    m = soadyn.Model()
    args = dict(name="beam", parent=None, body=random_flexible_body(np.random.default_rng(0)), joint=None,
                placement=None)
    args[argument] = value
    pattern = "body name must be a str" if argument == "name" else f"body 'beam': {argument}"
    with pytest.raises(TypeError, match=pattern):
        m.add_flexible_body(**args)
    assert m.nbodies == 0
