"""The URDF inertia policy: welded links merged before the physical check,
rounding tolerated, and inertia="strict" | "repair" | "accept"."""
import warnings

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import soadyn
from soadyn.check import relative_difference
from soadyn.oracles import PinocchioOracle
from soadyn.urdf import UrdfRepairWarning
from soadyn.urdf_inertia import physical_moments, repaired_inertia
from support.urdf_text import joint as any_joint, link, write

TOLERANCE = 1e-9


def joint(*args, kind="continuous", **kwargs):
    """Continuous by default: urdfdom (Pinocchio's parser) needs <limit> on a revolute joint."""
    return any_joint(*args, kind=kind, **kwargs)


def inertial_link(name, mass, com="0 0 0", ixx=0.0, iyy=0.0, izz=0.0, ixy=0.0, ixz=0.0, iyz=0.0):
    return (f"<link name='{name}'><inertial><origin xyz='{com}'/><mass value='{mass}'/><inertia ixx='{ixx}' "
            f"ixy='{ixy}' ixz='{ixz}' iyy='{iyy}' iyz='{iyz}' izz='{izz}'/></inertial></link>")


def assert_matches_pinocchio(model, path, floating, seed=3):
    """M, RNEA and ABA against Pinocchio, which merges the same welded links itself."""
    oracle = PinocchioOracle(model, path, floating)
    rng = np.random.default_rng(seed)
    for k in range(3):
        q = soadyn.random_configuration(model, seed + k)
        v, tau = rng.normal(size=(2, model.nv))
        assert relative_difference(soadyn.mass_matrix(model, q), oracle.mass_matrix(q)) < TOLERANCE
        assert relative_difference(soadyn.inverse_dynamics(model, q, v, tau), oracle.inverse_dynamics(q, v, tau)) < TOLERANCE
        assert relative_difference(soadyn.forward_dynamics(model, q, v, tau), oracle.forward_dynamics(q, v, tau)) < TOLERANCE


def test_dummy_root_is_checked_with_its_welded_trunk(tmp_path):
    """go1, hyq, anymal_b, b1: a root of mass 1e-6 whose inertia is all 1e-6 (moments 0, 0, 3e-6) with the trunk welded."""
    path = write(tmp_path, inertial_link("base", 1e-6, ixx=1e-6, iyy=1e-6, izz=1e-6, ixy=1e-6, ixz=1e-6, iyz=1e-6),
                 link("trunk", mass=5.0, com="0.01 0 0", ixx=0.02, iyy=0.05, izz=0.06),
                 joint("floating_base", "base", "trunk", kind="fixed", xyz="0 0 0"),
                 link("thigh"), joint("hip", "trunk", "thigh", xyz="0.2 0.1 0"))
    model = soadyn.load_urdf(path, floating_base=True)
    assert model.body_names == ["base", "thigh"] and model.masses[0] == pytest.approx(5.000001)
    assert_matches_pinocchio(model, path, True)


def test_moving_link_is_checked_with_its_welded_children(tmp_path):
    """allegro, icub, alex: a moving link that violates the triangle inequality alone, made physical by its welded tip."""
    path = write(tmp_path, link("palm"), inertial_link("finger", 0.05, ixx=2.30064e-06, iyy=3.48527e-06, izz=7.2659e-06),
                 link("tip", mass=0.02, com="0 0 0.03", ixx=1e-6, iyy=1e-6, izz=1e-6),
                 joint("knuckle", "palm", "finger", axis="0 0 1"), joint("tip_weld", "finger", "tip", kind="fixed"))
    with pytest.raises(soadyn.NonphysicalInertiaError):  # alone, the finger is not physical
        m = soadyn.Model()
        m.add_body("finger", None, soadyn.Joint.revolute([0, 0, 1]), mass=0.05, inertia=[2.30064e-06, 3.48527e-06, 7.2659e-06])
    for floating in (False, True):
        model = soadyn.load_urdf(path, floating_base=floating)
        assert model.frame_names[-1] == "tip"
        assert_matches_pinocchio(model, path, floating)


def test_rounding_level_negative_moment_counts_as_zero(tmp_path):
    """icub's l_ankle_2: a point mass whose inertia carries a product of 1.35525e-20 (a moment of -1.4e-20)."""
    icub = write(tmp_path, link("shank"), inertial_link("ankle", 0.2675, com="0.008 0 0.0553", ixz=1.35525e-20),
                 joint("l_ankle_roll", "shank", "ankle", axis="1 0 0"), name="icub.urdf")
    model = soadyn.load_urdf(icub)
    assert model.masses == [pytest.approx(0.2675)]
    assert_matches_pinocchio(model, icub, False)
    real = write(tmp_path, link("shank"), inertial_link("ankle", 0.2675, com="0.008 0 0.0553", ixz=1e-6),
                 joint("l_ankle_roll", "shank", "ankle", axis="1 0 0"), name="real.urdf")
    with pytest.raises(soadyn.UrdfError, match=r"link 'ankle' \(joint 'l_ankle_roll'\): .*not positive semidefinite"):
        soadyn.load_urdf(real)


def romeo_like(tmp_path):
    """romeo_small's kind of defect: the largest moment above the sum of the other two."""
    return write(tmp_path, link("torso"), link("arm", ixx=1.0, iyy=0.1, izz=0.1), joint("shoulder", "torso", "arm"),
                 link("hand", mass=0.5), joint("wrist", "arm", "hand", axis="1 0 0"))


def test_strict_refuses_and_names_the_options(tmp_path):
    path = romeo_like(tmp_path)
    with pytest.raises(soadyn.UrdfError) as error:
        soadyn.load_urdf(path)
    message = str(error.value)
    for part in (str(path), "link 'arm'", "joint 'shoulder'", "triangle inequality", "inertia='repair'",
                 "inertia='accept'"):
        assert part in message


def test_repair_projects_the_moments_and_warns_by_link(tmp_path):
    """Moments (1, 0.1, 0.1) violate l1 <= l2 + l3 by d = 0.8: each moves by d / 3 (0.7333, 0.3667, 0.3667)."""
    with pytest.warns(UrdfRepairWarning, match=r"link 'arm' \(joint 'shoulder'\): non-physical inertia repaired"):
        repaired = soadyn.load_urdf(romeo_like(tmp_path), inertia="repair")
    d = 0.8 / 3
    by_hand = write(tmp_path, link("torso"), link("arm", ixx=1.0 - d, iyy=0.1 + d, izz=0.1 + d),
                    joint("shoulder", "torso", "arm"), link("hand", mass=0.5), joint("wrist", "arm", "hand", axis="1 0 0"),
                    name="by_hand.urdf")
    q = np.array([0.4, -0.7])
    np.testing.assert_allclose(soadyn.mass_matrix(repaired, q), soadyn.mass_matrix(soadyn.load_urdf(by_hand), q),
                               rtol=1e-12)


def test_accept_keeps_the_file_values(tmp_path):
    """Pinocchio keeps a URDF's values as they are: the accepted model equals it."""
    path = romeo_like(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model = soadyn.load_urdf(path, inertia="accept")
    assert_matches_pinocchio(model, path, False)


def test_moving_link_without_inertial(tmp_path):
    """human.urdf: intermediate links without <inertial>. strict refuses, repair gives 1e-6 of the mean link mass, accept none."""
    path = write(tmp_path, link("pelvis", mass=10.0), "<link name='hip_virtual'/>", link("thigh", mass=4.0),
                 joint("hip_x", "pelvis", "hip_virtual", axis="1 0 0"), joint("hip_y", "hip_virtual", "thigh"))
    with pytest.raises(soadyn.UrdfError, match=r"link 'hip_virtual' \(joint 'hip_x'\): a moving link has no <inertial>"
                                              r".*inertia='repair'.*inertia='accept'"):
        soadyn.load_urdf(path)
    with pytest.warns(UrdfRepairWarning, match=r"link 'hip_virtual' \(joint 'hip_x'\): .*no <inertial>.*given mass 7e-06"):
        repaired = soadyn.load_urdf(path, inertia="repair")
    assert repaired.masses == [pytest.approx(7e-6), 4.0]
    accepted = soadyn.load_urdf(path, inertia="accept")
    assert accepted.masses == [0.0, 4.0]
    assert_matches_pinocchio(accepted, path, False)  # a massless link between two joints is harmless


def test_massless_link_with_inertia_is_given_mass_by_repair(tmp_path):
    path = write(tmp_path, link("base"), inertial_link("arm", 0.0, ixx=1e-3, iyy=1e-3, izz=1e-3), joint("j", "base", "arm"))
    with pytest.raises(soadyn.UrdfError, match="massless body with nonzero inertia.*inertia='repair'"):
        soadyn.load_urdf(path)
    with pytest.warns(UrdfRepairWarning, match="link 'arm'"):
        assert soadyn.load_urdf(path, inertia="repair").masses == [pytest.approx(1e-6)]


def test_links_welded_to_the_ground_are_not_checked(tmp_path):
    """A fixed-base root never moves: its (non-physical) inertia is not used; floating, it is refused."""
    path = write(tmp_path, link("base", ixx=1.0, iyy=0.1, izz=0.1), link("arm"), joint("j", "base", "arm"))
    assert soadyn.load_urdf(path).body_names == ["arm"]
    with pytest.raises(soadyn.UrdfError, match=r"link 'base' \(joint 'root_joint'\): .*triangle"):
        soadyn.load_urdf(path, floating_base=True)


def test_negative_mass_is_refused_under_every_policy(tmp_path):
    """A welded part of negative mass could hide in a positive merged mass: it is refused when read."""
    path = write(tmp_path, link("base"), link("arm", mass=2.0), link("ballast", mass=-1.0),
                 joint("j", "base", "arm"), joint("w", "arm", "ballast", kind="fixed"))
    for policy in ("strict", "repair", "accept"):
        with pytest.raises(soadyn.UrdfError, match="link 'ballast': mass -1 is negative"):
            soadyn.load_urdf(path, inertia=policy)


moments = st.lists(st.floats(-10, 10, allow_nan=False), min_size=3, max_size=3).map(np.array)


@settings(max_examples=300, deadline=None)
@given(moments, st.lists(st.floats(0, 10), min_size=3, max_size=3))
def test_physical_moments_is_the_nearest_physical_point(x, y):
    """The projection is in the cone, leaves cone points alone, and is no farther than another cone point."""
    p = physical_moments(x)
    scale = max(1.0, np.max(np.abs(x)))
    assert np.all(p + 1e-12 * scale >= 0)
    for k in range(3):
        assert p[k] <= p[(k + 1) % 3] + p[(k + 2) % 3] + 1e-12 * scale
    y = np.sort(y)
    y[2] = min(y[2], y[0] + y[1])  # a point of the cone
    assert np.linalg.norm(p - x) <= np.linalg.norm(y - x) + 1e-12 * scale
    np.testing.assert_allclose(physical_moments(p), p, atol=1e-12 * scale)


def test_repaired_inertia_keeps_the_principal_axes():
    rng = np.random.default_rng(0)
    R = np.linalg.qr(rng.normal(size=(3, 3)))[0]
    inertia = R @ np.diag([-0.1, 0.2, 1.0]) @ R.T
    fixed, before, after = repaired_inertia(inertia)
    np.testing.assert_allclose(before, [-0.1, 0.2, 1.0], atol=1e-14)
    np.testing.assert_allclose(fixed, R @ np.diag(after) @ R.T, atol=1e-14)
    assert after.min() >= -1e-15 and after[2] <= after[0] + after[1] + 1e-15
