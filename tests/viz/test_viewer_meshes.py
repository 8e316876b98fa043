"""The viewer's mesh files: every example-robot-data robot's meshes are read, and what cannot be read says why.

- Every URDF of example-robot-data that loads has each of its mesh visuals (COLLADA, STL, OBJ) read by
  `read_mesh` into triangles, except the meshes listed in UNREADABLE, whose MeshError names the visual,
  the file and pycollada's reason; the census test prints the counts (pytest -s).
- A mesh is scaled by the visual's size, and a mesh without colours of its own takes the visual's rgba.
- A missing file, a file trimesh cannot parse and a COLLADA file without pycollada's triangles are
  refused by MeshError naming the visual, the file and the reason; the Viewer draws them as axes and
  names them in one warning.
"""
from __future__ import annotations

import warnings

import numpy as np
import pytest

import soadyn
from soadyn.viz.viewer import MeshError, Viewer, read_mesh
from support.robots import robot, robots_dir

FILES = sorted(robots_dir().glob("**/*.urdf"))

# Meshes trimesh reads no triangle from, and the reason their MeshError gives: anymal_b's foot
# references a texture surface the file does not hold, and pycollada drops the primitives bound to it.
UNREADABLE = {"anymal_b_simple_description/meshes/foot/anymal_foot.dae": "Missing surface carbon_uv_texture"}


# The URDFs the loader refuses (tests/io/test_urdf_robots.py gives their reasons).
REFUSED = {"human_description/robots/human.urdf", "romeo_description/urdf/romeo_small.urdf",
           "romeo_description/urdf/romeo_laas_small.urdf", "ur_description/urdf/ur3.urdf"}
PARSED: set[str] = set()  # mesh files this process has read: a file several robots share is parsed once


def loaded(path):
    """The model of a URDF, or None for a file the loader refuses."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return soadyn.load_urdf(path)
    except ValueError:  # UrdfError and the inertia checks' errors
        return None


def mesh_visuals(m):
    return [v for v in m.visuals if v.shape == "mesh" and v.vertices is None]


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(robots_dir())))
def test_every_mesh_of_a_robot_that_loads_is_read(path):
    relative = str(path.relative_to(robots_dir()))
    m = loaded(path)
    if m is None:
        assert relative in REFUSED
        return
    for v in mesh_visuals(m):
        known = [reason for file, reason in UNREADABLE.items() if v.mesh_file.endswith(file)]
        if known:
            with pytest.raises(MeshError, match=known[0]) as refused:
                read_mesh(v)
            assert f"'{v.name}' ({v.mesh_file})" in str(refused.value)
        elif v.mesh_file not in PARSED:
            mesh = read_mesh(v)
            assert len(mesh.faces) > 0 and np.all(np.isfinite(mesh.vertices)), v.mesh_file
            PARSED.add(v.mesh_file)


def test_census_of_the_robots_meshes(capsys):
    models = [m for m in map(loaded, FILES) if m is not None]
    visuals = [v for m in models for v in mesh_visuals(m)]
    unreadable = [v for v in visuals if any(v.mesh_file.endswith(file) for file in UNREADABLE)]
    with capsys.disabled():
        print(f"\nexample-robot-data: {len(models)} of {len(FILES)} URDFs load; {len(visuals) - len(unreadable)} of "
              f"{len(visuals)} mesh visuals read ({len({v.mesh_file for v in visuals})} distinct files)")
    assert len(models) == len(FILES) - len(REFUSED) and len(visuals) >= 1000 and len(unreadable) <= 8


def test_mesh_is_scaled_and_coloured_by_its_visual(tmp_path):
    stl = tmp_path / "tetra.stl"
    stl.write_text("solid t\n" + "".join(
        f"facet normal 0 0 0\nouter loop\n{a}\n{b}\n{c}\nendloop\nendfacet\n"
        for a, b, c in [("vertex 0 0 0", "vertex 1 0 0", "vertex 0 1 0"), ("vertex 0 0 0", "vertex 0 1 0", "vertex 0 0 1"),
                        ("vertex 0 0 0", "vertex 0 0 1", "vertex 1 0 0"), ("vertex 1 0 0", "vertex 0 0 1", "vertex 0 1 0")])
        + "endsolid t\n")
    v = soadyn.Visual("tetra", "world", "mesh", mesh_file=str(stl), size=[2.0, 3.0, 4.0], rgba=[1.0, 0.5, 0.0, 1.0])
    mesh = read_mesh(v)
    assert np.allclose(mesh.bounds, [[0, 0, 0], [2, 3, 4]])
    assert np.all(mesh.visual.face_colors == [255, 128, 0, 255])


def test_ur5_collada_meshes_keep_their_own_material():
    path, floating = robot("ur5")
    m = soadyn.load_urdf(path, floating_base=floating)
    meshes = [read_mesh(v) for v in m.visuals if v.shape == "mesh"]
    assert len(meshes) == 7 and all(mesh.visual.kind is not None for mesh in meshes)


def test_unreadable_meshes_are_named_with_the_reason(tmp_path):
    garbage = tmp_path / "broken.obj"
    garbage.write_text("this is not a mesh\n")
    cases = {
        "missing": (str(tmp_path / "absent.stl"), "no such file"),
        "garbage": (str(garbage), "no triangles read|Error"),
    }
    with pytest.raises(MeshError, match="needs a Visual with a mesh_file, got 'cube'"):
        read_mesh(soadyn.Visual("cube", "world", "box", size=[1, 1, 1]))
    with pytest.raises(MeshError, match="got 'str'"):
        read_mesh("a path")
    for name, (file, reason) in cases.items():
        with pytest.raises(MeshError, match=reason) as refused:
            read_mesh(soadyn.Visual(name, "world", "mesh", mesh_file=file))
        assert str(refused.value).startswith(f"'{name}' ({file}): ")


def test_viewer_draws_an_unreadable_mesh_as_axes_and_names_it(tmp_path):
    m = soadyn.Model()
    m.add_body("link", None, soadyn.Joint.revolute([0, 0, 1]), mass=1.0, com=[0, 0, 0], inertia=np.eye(3) * 0.1)
    m.visuals = [soadyn.Visual("ghost", "link", "mesh", mesh_file=str(tmp_path / "ghost.dae"))]
    with pytest.warns(UserWarning, match=r"'ghost' \(.*ghost\.dae\): no such file"):
        viewer = Viewer(m, port=0)
    try:
        assert "/visuals/ghost" in viewer.handles
    finally:
        viewer.close()
