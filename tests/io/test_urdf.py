"""URDF loading: the mapping on small files, and bad files refused by name."""
import warnings

import numpy as np
import pytest

import soadyn
from soadyn.bounded_input import MAX_NESTING_DEPTH
from soadyn.urdf import UrdfIgnoredWarning
from support.urdf_text import joint, link, write


def limit(effort):
    return f'<limit lower="-1" upper="1" effort="{effort}" velocity="2"/>'


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


def test_links_welded_under_a_planar_joint_keep_their_place_in_the_link_frame(tmp_path):
    """The planar joint's body frame is its link frame turned so z is the axis:
    a welded link's origin (and what hangs below it) is given in the link frame."""
    path = write(tmp_path, link("base"), link("puck", com="0 0 0"), link("tip", com="0 0 0"), link("arm"),
                 joint("p", "base", "puck", kind="planar", axis="1 0 0", xyz="0 0 0"),
                 joint("w", "puck", "tip", kind="fixed", xyz="0.3 0.1 0.2"),
                 joint("r", "tip", "arm", xyz="0 0 0.5"))
    m = soadyn.load_urdf(path)
    poses, _ = soadyn.forward_kinematics(m, soadyn.neutral_configuration(m))
    arm = m.body_names.index("arm")
    np.testing.assert_allclose(poses[arm][:3, 3], [0.3, 0.1, 0.7], atol=1e-15)
    np.testing.assert_allclose(poses[arm][:3, :3], np.eye(3), atol=1e-15)


@pytest.mark.parametrize(
    "elements, message",
    [
        ((link("base"), "<link name='arm'/>", joint("j", "base", "arm")),
         r"link 'arm' \(joint 'j'\): a moving link has no <inertial>.*inertia='repair'"),
        ((link("base"), link("arm", mass=-1.0), joint("j", "base", "arm")), "link 'arm'.*mass -1 is negative"),
        ((link("base"), link("arm", ixx=1.0, iyy=0.1, izz=0.1), joint("j", "base", "arm")),
         "link 'arm'.*triangle inequality"),
        ((link("base"), link("arm"), joint("j", "base", "elbow")), "joint 'j': child link 'elbow' does not exist"),
        ((link("base"), link("arm"), joint("j", "shoulder", "arm")), "joint 'j': parent link 'shoulder' does not exist"),
        ((link("base"), link("a"), link("b"), joint("j1", "base", "a"), joint("j2", "a", "b"), joint("j3", "b", "a")),
         "link 'a' has two parent joints .*kinematic loops"),
        ((link("a"), link("b"), joint("j1", "a", "b"), joint("j2", "b", "a")), "found none.*kinematic loop"),
        ((link("base"), link("arm"), joint("j", "base", "arm", kind="ball")), "joint 'j': unsupported joint type 'ball'"),
        ((link("base"), link("arm"), joint("j", "base", "arm", axis="0 0 0")), "joint 'j': axis .* is zero"),
        ((link("base"), link("other")), "exactly one root link"),
        ((link("base"), link("base")), "link 'base' is defined twice"),
        ((link("base"), link("arm"), joint("j", "base", "arm"), joint("j", "arm", "base")), "joint 'j' is defined twice"),
        ((link("base"), link("arm"), joint("j", "base", "arm", axis="0 1")),
         r"joint 'j': <axis xyz='0 1'> has 2 numbers, expected 3"),
        ((link("base"), link("arm"), joint("j", "base", "arm", xyz="1")), r"joint 'j': <origin xyz='1'> has 1 numbers"),
        ((link("base"), link("arm"), joint("j", "base", "arm", rpy="0 0 0 1")), r"joint 'j': <origin rpy='0 0 0 1'>"),
        ((link("base"), link("arm"), joint("j", "base", "arm", axis="nan 0 1")), r"joint 'j': <axis xyz='nan 0 1'> is not finite"),
        ((link("base"), link("arm", mass="abc"), joint("j", "base", "arm")), r"link 'arm': <mass value='abc'> is not a number"),
        ((link("base"), link("arm", com="0 0 1e999"), joint("j", "base", "arm")), r"link 'arm' <inertial>: <origin xyz='0 0 1e999'> is not finite"),
        ((link("base"), "<link name='arm'><inertial><mass value='1'/></inertial></link>", joint("j", "base", "arm")),
         r"link 'arm' <inertial>: <inertia> is missing"),
        ((link("base"), "<link name='arm'><inertial><inertia ixx='1' iyy='1' izz='1' ixy='0' ixz='0'/><mass value='1'/></inertial></link>",
          joint("j", "base", "arm")), r"link 'arm': <inertia> has no 'iyz' attribute"),
        ((link("base"), "<link/>"), r"link number 2: <link> has no name"),
        ((link("base"), link("arm"), "<joint name='j' type='revolute'><child link='arm'/></joint>"), r"joint 'j': <parent> is missing"),
        ((link("base"), link("arm"), "<joint name='j'><parent link='base'/><child link='arm'/></joint>"), r"joint 'j': <joint> has no 'type' attribute"),
        ((link("base"), link("arm"), "<joint type='fixed'><parent link='base'/><child link='arm'/></joint>"), r"joint number 1: <joint> has no name"),
        ((), r"the robot has no <link>"),
        ((link("base"), link("arm"), joint("j", "base", "arm", extra=limit(-5))),
         r"joint 'j': <limit> effort=-5.0 must be non-negative"),
        ((link("base"), link("arm"), joint("j", "base", "arm", extra=limit("nan"))),
         r"joint 'j' <limit>: <limit effort='nan'> is not finite"),
        ((link("base"), link("arm"), joint("j", "base", "arm", extra=limit("inf"))),
         r"joint 'j' <limit>: <limit effort='inf'> is not finite"),
        ((link("base"), link("arm"), joint("j", "base", "arm", extra=limit("strong"))),
         r"joint 'j' <limit>: <limit effort='strong'> is not a number"),
        ((link("base"), link("arm"), joint("j", "base", "arm", extra=limit(1) + limit(2))),
         r"joint 'j': 2 <limit> elements, expected one"),
        ((link("base"), link("arm"), joint("weld", "base", "arm", kind="fixed", extra=limit(-1))),
         r"joint 'weld': <limit> effort=-1.0 must be non-negative"),
    ],
)
def test_bad_urdf_names_the_element(tmp_path, elements, message):
    """Every refusal is a UrdfError naming the file and the element at fault."""
    path = write(tmp_path, *elements)
    with pytest.raises(soadyn.UrdfError, match=message) as error:
        soadyn.load_urdf(path)
    assert str(path) in str(error.value)


def test_world_root_with_two_welded_links(tmp_path):
    """Fixed base: links welded to the ground are frames; floating: the base would be ambiguous."""
    path = write(tmp_path, link("world"), link("a"), link("b"), joint("j1", "world", "a", kind="fixed"),
                 joint("j2", "world", "b", kind="fixed"), link("c"), joint("j3", "b", "c"))
    m = soadyn.load_urdf(path)
    assert m.frame_names == ["a", "b"] and m.dof_names == ["j3"]
    with pytest.raises(soadyn.UrdfError, match="floating_base=True needs the 'world' link to have a single fixed joint"):
        soadyn.load_urdf(path, floating_base=True)


@pytest.mark.parametrize("text, message", [
    ("<robot name='r'><link name='a'></robot>", "malformed URDF"),
    ("<foo/>", r"the root element is <foo>, not <robot>"),
    ("", "malformed URDF"),
    ("<robot/>", "the robot has no <link>"),
])
def test_malformed_xml(tmp_path, text, message):
    path = tmp_path / "broken.urdf"
    path.write_text(text)
    with pytest.raises(soadyn.UrdfError, match=message):
        soadyn.load_urdf(path)


def test_long_chains_load_without_recursion(tmp_path):
    """1500 fixed links under a link without <inertial>, and 1500 moving links: no RecursionError."""
    n = 1500
    welded = ["<link name='l0'/>"] + [link(f"w{k}", mass=0.0, ixx=0, iyy=0, izz=0) for k in range(n)] + [link("tip")]
    welded += [joint("j0", "l0", "w0", kind="fixed")] + [joint(f"f{k}", f"w{k}", f"w{k + 1}", kind="fixed")
                                                          for k in range(n - 1)]
    welded += [joint("last", f"w{n - 1}", "tip", kind="fixed")]
    m = soadyn.load_urdf(write(tmp_path, *welded, name="welded.urdf"), floating_base=True)
    assert m.nbodies == 1 and m.masses == [pytest.approx(1.0)] and len(m.frame_names) == n + 1
    chain = [link("l0")] + [link(f"l{k + 1}") for k in range(n)] + [joint(f"j{k}", f"l{k}", f"l{k + 1}") for k in range(n)]
    m = soadyn.load_urdf(write(tmp_path, *chain, name="chain.urdf"))
    assert m.nv == n and m.dof_names[-1] == f"j{n - 1}"


def test_load_urdf_arguments_are_checked(tmp_path):
    path = write(tmp_path, link("base"), link("arm"), joint("j", "base", "arm"))
    with pytest.raises(ValueError, match=r"inertia must be one of \('strict', 'repair', 'accept'\), got 'lax'"):
        soadyn.load_urdf(path, inertia="lax")
    with pytest.raises(TypeError, match="floating_base must be a bool, got str"):
        soadyn.load_urdf(path, floating_base="yes")


def test_missing_file(tmp_path):
    with pytest.raises(FileNotFoundError, match="nowhere.urdf"):
        soadyn.load_urdf(tmp_path / "nowhere.urdf")


@pytest.mark.parametrize("where", ["link", "visual geometry"])
def test_xml_nested_deeper_than_the_bound_is_refused_naming_the_limit(tmp_path, where):
    """100,000 nested elements inside a link or a visual's geometry: a UrdfError naming the file and the
    limit, not a tree of 100,000 levels for the readers to walk."""
    deep = "<x>" * 100_000 + "</x>" * 100_000
    inside = deep if where == "link" else f"<visual><geometry>{deep}</geometry></visual>"
    path = write(tmp_path, link("base"), f'<link name="deep">{inside}</link>')
    with pytest.raises(soadyn.UrdfError, match=f"nested more than {MAX_NESTING_DEPTH} elements deep") as error:
        soadyn.load_urdf(path)
    assert str(path) in str(error.value)
    shallow = "<x>" * (MAX_NESTING_DEPTH - 2) + "</x>" * (MAX_NESTING_DEPTH - 2)  # under <robot><link>: at the limit
    assert soadyn.load_urdf(write(tmp_path, link("base"), f"<link name='s'>{shallow}</link>",
                                  joint("j", "base", "s", kind="fixed"))).frame_names == ["base", "s"]


def effort_limits(m) -> dict:
    return dict(zip(m.dof_names, m.effort_limits))


def test_limit_effort_gives_the_dofs_effort_limits(tmp_path):
    """<limit effort> of revolute, continuous and prismatic joints (a mimic one too) becomes the DOF's effort
    limit; effort 0 and a missing <limit> or effort set none, nor does a fixed joint's effort. Model files and
    URDF export keep them."""
    links = [link(name) for name in ("base", "a", "b", "c", "d", "e", "f", "g", "tool")]
    joints = [joint("revolute", "base", "a", extra=limit(87)),
              joint("continuous", "a", "b", kind="continuous", extra='<limit effort="12.5" velocity="1"/>'),
              joint("slide", "b", "c", kind="prismatic", axis="0 0 1", extra=limit("2e3")),
              joint("passive", "c", "d", extra=limit(0)),
              joint("unlimited", "d", "e", kind="prismatic", axis="1 0 0"),
              joint("no_effort", "e", "f", extra='<limit lower="-1" upper="1" velocity="1"/>'),
              joint("mimic", "f", "g", extra=limit(3) + '<mimic joint="revolute" multiplier="2"/>'),
              joint("weld", "g", "tool", kind="fixed", extra=limit(40))]
    path = write(tmp_path, *links, *joints)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m = soadyn.load_urdf(path)
    expected = {"revolute": 87.0, "continuous": 12.5, "slide": 2000.0, "mimic": 3.0}
    assert m.dof_names == ["revolute", "continuous", "slide", "passive", "unlimited", "no_effort", "mimic"]
    assert effort_limits(m) == {dof: expected.get(dof, np.inf) for dof in m.dof_names}
    soadyn.save_model(m, tmp_path / "model.json")
    assert effort_limits(soadyn.load_model(tmp_path / "model.json")) == effort_limits(m)
    soadyn.save_urdf(m, tmp_path / "exported.urdf")
    assert effort_limits(soadyn.load_urdf(tmp_path / "exported.urdf")) == effort_limits(m)


def test_planar_joint_effort_is_reported_not_set(tmp_path):
    """One number cannot bound a planar joint's two forces and one torque: no limit, one warning naming it."""
    path = write(tmp_path, link("base"), link("puck"),
                 joint("plane", "base", "puck", kind="planar", axis="0 0 1", extra=limit(9)))
    with pytest.warns(UrdfIgnoredWarning,
                      match=r"effort limits not modelled, ignored: 'plane' \(effort 9 on a planar joint\)") as record:
        m = soadyn.load_urdf(path)
    assert len(record) == 1 and str(path) in str(record[0].message)
    assert m.nv == 3 and np.all(m.effort_limits == np.inf)
