"""URDF export of a model's rigid part (soadyn.urdf_export.save_urdf), checked through Pinocchio.

Pinocchio reads the exported file with its own URDF parser; its ABA, RNEA and
CRBA must agree with the original soadyn model (not the re-imported one) to
1e-12 relative, for robots loaded from URDF (fixed and floating base) and for
random trees of every joint kind URDF has. The file also loads back with
load_urdf into the same dynamics and frames. What URDF cannot hold is refused
or reported by name.
"""
from __future__ import annotations

import warnings
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import soadyn
from soadyn.oracles import PinocchioOracle
from soadyn.urdf_export import UrdfExportWarning, rpy, save_urdf
from support.robots import robot_with_oracle
from support.trees import random_rotation, random_tree


def relative(a, b) -> float:
    return float(np.abs(a - b).max() / max(1.0, np.abs(b).max()))


def assert_pinocchio_agrees(m: soadyn.Model, path, floating: bool, seeds=range(4)) -> float:
    oracle = PinocchioOracle(m, path, floating)
    assert oracle.model.nv == m.nv
    rng = np.random.default_rng(0)
    worst = 0.0
    for seed in seeds:
        q = soadyn.random_configuration(m, seed)
        v, tau = rng.normal(size=m.nv), rng.normal(size=m.nv)
        worst = max(worst, relative(soadyn.forward_dynamics(m, q, v, tau), oracle.forward_dynamics(q, v, tau)),
                    relative(soadyn.inverse_dynamics(m, q, v, tau), oracle.inverse_dynamics(q, v, tau)),
                    relative(soadyn.mass_matrix(m, q), oracle.mass_matrix(q)))
    assert worst <= 1e-12
    return worst


@pytest.mark.parametrize("name,floating", [("panda", False), ("ur5", False), ("solo12", True), ("talos", True)])
def test_exported_robot_matches_pinocchio_and_reloads(name, floating, tmp_path):
    m, _ = robot_with_oracle(name, floating)
    path = tmp_path / f"{name}.urdf"
    save_urdf(m, path, robot_name=name)
    assert_pinocchio_agrees(m, path, floating)
    reloaded = soadyn.load_urdf(path, floating_base=floating)
    assert reloaded.dof_names == m.dof_names
    for seed in range(3):
        q = soadyn.random_configuration(m, seed)
        assert relative(soadyn.mass_matrix(reloaded, q), soadyn.mass_matrix(m, q)) <= 1e-12
        for frame in m.frame_names:
            T0, T1 = soadyn.frame_pose(m, q, frame), soadyn.frame_pose(reloaded, q, frame)
            assert np.abs(T1 - T0).max() <= 1e-12, frame


@pytest.mark.parametrize("seed", range(5))
def test_random_trees_of_urdf_joint_kinds_match_pinocchio(seed, tmp_path):
    m, kinds = random_tree(seed, nbodies=12, kinds=("revolute", "prismatic"), floating=seed % 2 == 0)
    if seed % 2 == 0:  # URDF's floating base has no placement: a placed free root is refused
        with pytest.raises(soadyn.UrdfError, match="body 'b0': a floating root"):
            save_urdf(m, tmp_path / "placed.urdf")
        m.set_parameter("b0.placement", np.eye(4))
    path = tmp_path / "tree.urdf"
    save_urdf(m, path)
    assert_pinocchio_agrees(m, path, floating=seed % 2 == 0)


def test_rpy_reproduces_rotations_including_gimbal_lock():
    rng = np.random.default_rng(1)
    for R in [random_rotation(rng) for _ in range(50)] + [np.array([[0, 0, 1.0], [0, 1.0, 0], [-1.0, 0, 0]])]:
        r, p, y = rpy(R)
        Rz = np.array([[np.cos(y), -np.sin(y), 0], [np.sin(y), np.cos(y), 0], [0, 0, 1]])
        Ry = np.array([[np.cos(p), 0, np.sin(p)], [0, 1, 0], [-np.sin(p), 0, np.cos(p)]])
        Rx = np.array([[1, 0, 0], [0, np.cos(r), -np.sin(r)], [0, np.sin(r), np.cos(r)]])
        assert np.abs(Rz @ Ry @ Rx - R).max() <= 1e-14


def test_what_urdf_cannot_hold_is_refused_or_named(tmp_path):
    with pytest.raises(soadyn.UrdfError, match="flexible body"):
        save_urdf(soadyn.scenes.cassini(), tmp_path / "c.urdf")
    m = soadyn.Model()
    m.add_body("ball", None, soadyn.Joint.spherical(name="shoulder"), mass=1.0, inertia=[1, 1, 1])
    with pytest.raises(soadyn.UrdfError, match="joint 'shoulder'.*spherical"):
        save_urdf(m, tmp_path / "s.urdf")
    four_bar = soadyn.scenes.four_bar()
    four_bar.add_joint_spring("crank_spring", "crank", 2.0)
    four_bar.set_prescribed(["crank"])
    four_bar.visuals = [soadyn.Visual("pin", "crank", "capsule", size=[0.01, 0.02]),
                        soadyn.Visual("rod", "coupler", "cylinder", size=[0.01, 0.1])]
    with pytest.warns(UrdfExportWarning) as record:
        save_urdf(four_bar, tmp_path / "f.urdf")
    message = str(record[0].message)
    for item in ("loop 'cut'" if "cut" in four_bar.loop_names else f"loop '{four_bar.loop_names[0]}'",
                 "joint spring 'crank_spring'", "prescribed flags (crank)", "visual 'pin'"):
        assert item in message
    assert "visual 'rod'" not in message
    root = ET.parse(tmp_path / "f.urdf").getroot()
    (cylinder,) = root.iter("cylinder")
    assert float(cylinder.get("radius")) == 0.01 and float(cylinder.get("length")) == 0.1
    with pytest.raises(soadyn.UrdfError, match="no_dir"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UrdfExportWarning)
            save_urdf(four_bar, tmp_path / "no_dir" / "f.urdf")


def named_chain(body: str, joint: str, frame: str) -> soadyn.Model:
    m = soadyn.Model()
    m.add_body(body, None, soadyn.Joint.revolute([0, 0, 1], name=joint), mass=1.0, com=[0.1, 0, 0],
               inertia=[0.1, 0.2, 0.3])
    m.add_body("arm", body, soadyn.Joint.prismatic([1, 0, 0], name="slide"), placement=np.array([0.0, 0.0, 0.5]),
               mass=0.5, com=[0, 0.1, 0], inertia=[0.1, 0.1, 0.1])
    m.add_body(frame, "arm", soadyn.Joint.fixed(), placement=np.array([0.2, 0.0, 0.0]))
    return m


# Characters XML escapes (quotes, <, >, &, newline, tab, carriage return), leading spaces, and unicode beyond
# the basic plane: written escaped, read back unchanged.
ESCAPED_NAMES = ["q\"uo'te", "<tag>&amp;", "line\nbreak\ttab\rreturn", "  spaced  ", "\u00fcn\u00efc\u00f6de \u2603",
                 "\U0001f916 robot", "del\x7f and \x85"]


@pytest.mark.parametrize("name", ESCAPED_NAMES)
def test_names_xml_escapes_round_trip(name, tmp_path):
    m = named_chain(f"body {name}", f"joint {name}", f"frame {name}")
    m.visuals = [soadyn.Visual(f"visual {name}", f"body {name}", "mesh", mesh_file=f"meshes/{name}.stl")]
    save_urdf(m, tmp_path / "names.urdf", robot_name=name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the mesh file does not exist: drawn as axes
        loaded = soadyn.load_urdf(tmp_path / "names.urdf")
    assert loaded.body_names == m.body_names and loaded.dof_names == m.dof_names
    assert loaded.frame_names == m.frame_names
    (visual,) = loaded.visuals
    assert visual.name == f"visual {name}" and visual.mesh_file == f"meshes/{name}.stl"
    assert ET.parse(tmp_path / "names.urdf").getroot().get("name") == name


@pytest.mark.parametrize("bad", ["\x00", "\x01", "\x1f", "\ufffe", "\uffff"])
@pytest.mark.parametrize("item", ["body", "joint", "frame", "visual", "mesh file", "robot name"])
def test_names_xml_cannot_hold_are_refused_naming_the_item(bad, item, tmp_path):
    """NUL and the other characters XML 1.0 forbids have no escape: refused by name, never a file no reader
    reads."""
    names = {key: key.replace(" ", "_") for key in ("body", "joint", "frame", "visual", "mesh file", "robot name")}
    names[item] = f"{names[item]}{bad}name"
    m = named_chain(names["body"], names["joint"], names["frame"])
    m.visuals = [soadyn.Visual(names["visual"], names["body"], "mesh", mesh_file=names["mesh file"])]
    path = tmp_path / "bad.urdf"
    with pytest.raises(soadyn.UrdfError) as error:
        save_urdf(m, path, robot_name=names["robot name"])
    message = str(error.value)
    assert str(path) in message and f"{item} {names[item]!r}" in message
    assert f"U+{ord(bad):04X}, a character XML 1.0 cannot hold" in message
    assert not path.exists()
