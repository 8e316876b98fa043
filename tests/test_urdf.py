"""URDF loading: the mapping on small files, and bad files refused by name."""
import numpy as np
import pytest

import soadyn

LINK = """<link name="{name}"><inertial><origin xyz="{com}" rpy="{rpy}"/><mass value="{mass}"/>
<inertia ixx="{ixx}" ixy="0" ixz="0" iyy="{iyy}" iyz="0" izz="{izz}"/></inertial></link>"""
JOINT = """<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>
<origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="{axis}"/></joint>"""


def link(name, mass=1.0, com="0 0 0.1", rpy="0 0 0", ixx=0.01, iyy=0.01, izz=0.01):
    return LINK.format(name=name, mass=mass, com=com, rpy=rpy, ixx=ixx, iyy=iyy, izz=izz)


def joint(name, parent, child, kind="revolute", xyz="0 0 0.5", rpy="0 0 0", axis="0 1 0"):
    return JOINT.format(name=name, kind=kind, parent=parent, child=child, xyz=xyz, rpy=rpy, axis=axis)


def write(tmp_path, *elements, name="robot.urdf"):
    path = tmp_path / name
    path.write_text('<?xml version="1.0"?>\n<robot name="r">\n' + "\n".join(elements) + "\n</robot>\n")
    return path


def test_chain_with_fixed_and_continuous_joints(tmp_path):
    path = write(tmp_path, link("base"), link("upper"), link("tool", mass=0.5), link("lower"),
                 joint("shoulder", "base", "upper", kind="continuous"),
                 joint("weld", "upper", "tool", kind="fixed", xyz="0.1 0 0"),
                 joint("slide", "tool", "lower", kind="prismatic", axis="0 0 1"))
    m = soadyn.load_urdf(path)
    assert m.dof_names == ["shoulder", "slide"]
    assert m.body_names == ["upper", "lower"] and set(m.frame_names) == {"base", "tool"}
    assert m.masses == [pytest.approx(1.5), pytest.approx(1.0)]
    floating = soadyn.load_urdf(path, floating_base=True)
    assert floating.dof_names[:6] == [f"root_joint:{s}" for s in ("wx", "wy", "wz", "vx", "vy", "vz")]
    assert floating.body_names[0] == "base" and floating.nv == 8


def test_inertial_origin_rotation_is_applied(tmp_path):
    """An inertia given in a rotated COM frame equals the same inertia rotated by hand."""
    rotated = write(tmp_path, link("base"), link("arm", rpy="0 0 1.5707963267948966", ixx=0.01, iyy=0.03, izz=0.02),
                    joint("j", "base", "arm", axis="1 0 0"), name="a.urdf")
    by_hand = write(tmp_path, link("base"), link("arm", ixx=0.03, iyy=0.01, izz=0.02),
                    joint("j", "base", "arm", axis="1 0 0"), name="b.urdf")
    q = np.array([0.3])
    np.testing.assert_allclose(soadyn.mass_matrix(soadyn.load_urdf(rotated), q),
                               soadyn.mass_matrix(soadyn.load_urdf(by_hand), q), rtol=1e-12)


def test_planar_joint_moves_in_the_plane_normal_to_its_axis(tmp_path):
    path = write(tmp_path, link("base"), link("puck", com="0 0 0"), joint("p", "base", "puck", kind="planar", axis="1 0 0"))
    m = soadyn.load_urdf(path)
    assert m.joint_types == ["planar"]
    q = np.array([0.2, -0.4, 0.0])
    poses, _ = soadyn.forward_kinematics(m, q)
    assert poses[0][0, 3] == pytest.approx(0.0, abs=1e-15)  # no motion along the axis


@pytest.mark.parametrize(
    "elements, message",
    [
        ((link("base"), "<link name='arm'/>", joint("j", "base", "arm")), "link 'arm': a moving link has no <inertial>"),
        ((link("base"), link("arm", mass=-1.0), joint("j", "base", "arm")), "link 'arm'.*mass -1 is negative"),
        ((link("base"), link("arm", ixx=1.0, iyy=0.1, izz=0.1), joint("j", "base", "arm")),
         "link 'arm'.*triangle inequality"),
        ((link("base"), link("arm"), joint("j", "base", "elbow")), "joint 'j': child link 'elbow' does not exist"),
        ((link("base"), link("arm"), joint("j", "shoulder", "arm")), "joint 'j': parent link 'shoulder' does not exist"),
        ((link("base"), link("a"), link("b"), joint("j1", "base", "a"), joint("j2", "a", "b"), joint("j3", "b", "a")),
         "link 'a' has two parent joints .*kinematic loops"),
        ((link("a"), link("b"), joint("j1", "a", "b"), joint("j2", "b", "a")), "no root .*kinematic loop"),
        ((link("base"), link("arm"), joint("j", "base", "arm", kind="ball")), "joint 'j': unsupported joint type 'ball'"),
        ((link("base"), link("arm"), joint("j", "base", "arm", axis="0 0 0")), "joint 'j': axis .* is zero"),
        ((link("base"), link("other")), "exactly one root link"),
        ((link("base"), link("base")), "link 'base' is defined twice"),
    ],
)
def test_bad_urdf_names_the_element(tmp_path, elements, message):
    with pytest.raises(soadyn.UrdfError, match=message):
        soadyn.load_urdf(write(tmp_path, *elements))


def test_malformed_xml(tmp_path):
    path = tmp_path / "broken.urdf"
    path.write_text("<robot name='r'><link name='a'></robot>")
    with pytest.raises(soadyn.UrdfError, match="malformed URDF"):
        soadyn.load_urdf(path)


def test_missing_file(tmp_path):
    with pytest.raises(FileNotFoundError, match="nowhere.urdf"):
        soadyn.load_urdf(tmp_path / "nowhere.urdf")
