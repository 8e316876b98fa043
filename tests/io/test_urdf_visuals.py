"""URDF <visual> elements become model.visuals (soadyn.urdf_visuals), for the viewer and model files."""
from __future__ import annotations

import os
import warnings

import numpy as np
import pytest

import soadyn
from soadyn.urdf import UrdfIgnoredWarning
from support.robots import robot

URDF = """<?xml version="1.0"?>
<robot name="shapes">
  <material name="blue"><color rgba="0 0 1 1"/></material>
  <link name="base">
    <inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
    <visual name="plate"><origin xyz="0 0 0.1" rpy="0 0 1.5707963267948966"/>
      <geometry><box size="0.4 0.2 0.02"/></geometry><material name="blue"/></visual>
  </link>
  <link name="arm">
    <inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
    <visual><geometry><cylinder radius="0.03" length="0.5"/></geometry>
      <material name="red"><color rgba="1 0 0 0.5"/></material></visual>
    <visual><geometry><mesh filename="package://shapes_pkg/meshes/arm.stl" scale="0.001 0.001 0.001"/></geometry></visual>
    <visual><geometry><mesh filename="meshes/missing.stl"/></geometry></visual>
    <visual><geometry><sphere radius="oops"/></geometry></visual>
  </link>
  <link name="tool">
    <visual><geometry><sphere radius="0.05"/></geometry></visual>
  </link>
  <joint name="shoulder" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/></joint>
  <joint name="tool_mount" type="fixed"><parent link="arm"/><child link="tool"/><origin xyz="0 0 0.5"/></joint>
</robot>
"""


def test_visuals_of_every_geometry_with_materials_and_package_meshes(tmp_path):
    package = tmp_path / "shapes_pkg"
    (package / "meshes").mkdir(parents=True)
    (package / "meshes" / "arm.stl").write_text("solid arm\nendsolid arm\n")
    (package / "urdf").mkdir()
    path = package / "urdf" / "shapes.urdf"
    path.write_text(URDF)
    with pytest.warns(UrdfIgnoredWarning, match=r"visual 3 of link 'arm'.*oops"):
        m = soadyn.load_urdf(path)
    by_name = {v.name: v for v in m.visuals}
    assert sorted(by_name) == ["arm/visual0", "arm/visual1", "arm/visual2", "plate", "tool/visual0"]
    plate = by_name["plate"]
    assert plate.frame == "base" and plate.shape == "box" and np.array_equal(plate.size, [0.4, 0.2, 0.02])
    assert np.allclose(plate.rotation, [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-15)
    assert np.array_equal(plate.translation, [0, 0, 0.1]) and np.array_equal(plate.rgba, [0, 0, 1, 1])
    cylinder = by_name["arm/visual0"]
    assert cylinder.frame == "arm" and np.array_equal(cylinder.size, [0.03, 0.5])
    assert np.array_equal(cylinder.rgba, [1, 0, 0, 0.5])
    mesh = by_name["arm/visual1"]
    assert mesh.mesh_file == str(package / "meshes" / "arm.stl") and np.array_equal(mesh.size, [1e-3] * 3)
    assert by_name["arm/visual2"].mesh_file == "meshes/missing.stl"  # unresolved: kept as written
    assert by_name["tool/visual0"].frame == "tool" and "tool" in m.frame_names
    loaded = soadyn.load_model(tmp_path / "m.json") if soadyn.save_model(m, tmp_path / "m.json") is None else None
    assert [v.name for v in loaded.visuals] == [v.name for v in m.visuals]


def test_example_robot_meshes_resolve_and_the_viewer_draws_them():
    path, _ = robot("panda")
    m = soadyn.load_urdf(path)
    meshes = [v for v in m.visuals if v.shape == "mesh"]
    assert len(meshes) >= 8 and all(os.path.isfile(v.mesh_file) for v in meshes)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # meshes trimesh cannot read are drawn as axes (named in a warning)
        viewer = soadyn.Viewer(m, port=0)
    try:
        assert {f"/visuals/{v.name}" for v in m.visuals} <= set(viewer.handles)
    finally:
        viewer.close()
