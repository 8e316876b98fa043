"""soadyn's model files (save_model / load_model) and Model pickling.

A saved and reloaded model must be the same model: the same text when saved
again, dynamics equal bit for bit, the same names, flags, force elements,
loops and visuals. A robot loaded from URDF and passed through a model file
still matches Pinocchio reading the URDF itself. Hostile files give a
ModelFileError naming the file and the item at fault; so does a file nested
deeper than the bound (soadyn.bounded_input), at any depth, in the Python
reader and in the C++ one alike.
"""
from __future__ import annotations

import copy
import json
import os
import pickle
import warnings

import numpy as np
import pytest

import soadyn
from soadyn.bounded_input import MAX_NESTING_DEPTH, json_depth
from soadyn.model_file import model_from_json, model_to_json
from support.forked import run_forked
from support.robots import robot_with_oracle
from support.trees import JOINT_KINDS, random_state, random_tree


def assert_same_model(a: soadyn.Model, b: soadyn.Model, seeds=range(3)) -> None:
    assert (b.nq, b.nv, b.nbodies, b.nloops) == (a.nq, a.nv, a.nbodies, a.nloops)
    assert b.body_names == a.body_names and b.dof_names == a.dof_names and b.loop_names == a.loop_names
    assert np.array_equal(b.prescribed, a.prescribed)
    assert np.array_equal(b.armature, a.armature)
    for seed in seeds:
        q, v, rng = random_state(a, seed)
        u = rng.normal(size=a.nv)
        if a.nloops:
            ra, rb = soadyn.constrained_dynamics(a, q, v, u), soadyn.constrained_dynamics(b, q, v, u)
        else:
            ra, rb = soadyn.hybrid_dynamics(a, q, v, u), soadyn.hybrid_dynamics(b, q, v, u)
        for x, y in zip(ra, rb):
            assert np.array_equal(x, y)
        assert soadyn.potential_energy(a, q) == soadyn.potential_energy(b, q)
        assert np.array_equal(soadyn.mass_matrix(a, q), soadyn.mass_matrix(b, q))


def through_file(m: soadyn.Model, tmp_path, **kwargs) -> soadyn.Model:
    path = tmp_path / "model.json"
    soadyn.save_model(m, path, **kwargs)
    loaded = soadyn.load_model(path)
    assert model_to_json(loaded) == path.read_text()
    return loaded


SCENES = {
    "cassini": soadyn.scenes.cassini,
    "four_bar": soadyn.scenes.four_bar,
    "four_bar_point": lambda: soadyn.scenes.four_bar("point"),
    "slider_crank": soadyn.scenes.slider_crank,
    "delta_robot": soadyn.scenes.delta_robot,
    "pendulum_chain": soadyn.scenes.pendulum_chain,
    "cantilever_beam": lambda: soadyn.scenes.cantilever_beam(1.0, 2.0, 1.5, 3),
}


@pytest.mark.parametrize("name", sorted(SCENES))
def test_scene_round_trips_exactly(name, tmp_path):
    m = SCENES[name]()
    assert_same_model(m, through_file(m, tmp_path))


@pytest.mark.parametrize("seed", range(6))
def test_random_tree_of_every_joint_kind_with_flags_springs_and_frames(seed, tmp_path):
    m, _ = random_tree(seed, nbodies=14)
    assert set().union(*(random_tree(s, nbodies=14)[1] for s in range(6))) == set(JOINT_KINDS)  # all kinds covered
    rng = np.random.default_rng(seed)
    m.set_prescribed(rng.uniform(size=m.nv) < 0.3)
    for k in range(m.nv):  # a spring and an armature on the first DOF that takes them
        try:
            m.add_joint_spring("spring", k, stiffness=4.0, damping=0.3, rest=0.2)
            m.set_armature(k, 0.05)
            break
        except ValueError:
            continue
    m.add_point_spring("strut", "b1", None, stiffness=30.0, damping=0.5, placement_b=np.array([0.0, 0.0, 1.0]),
                       force_law=([0.2, 1.0, 3.0], [-5.0, 0.0, 60.0]))
    assert len(soadyn.force_elements(m)) == 2
    loaded = through_file(m, tmp_path)
    assert_same_model(m, loaded)
    for a, b in zip(soadyn.force_elements(m), soadyn.force_elements(loaded), strict=True):
        assert a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)


def test_urdf_robot_through_a_model_file_still_matches_pinocchio(tmp_path):
    m, oracle = robot_with_oracle("panda", False)
    loaded = through_file(m, tmp_path)
    assert "panda_hand_tcp" in [name for name in loaded.frame_names]
    rng = np.random.default_rng(3)
    for seed in range(3):
        q = soadyn.random_configuration(loaded, seed)
        v, tau = rng.normal(size=loaded.nv), rng.normal(size=loaded.nv)
        expected = oracle.forward_dynamics(q, v, tau)
        assert np.abs(soadyn.forward_dynamics(loaded, q, v, tau) - expected).max() <= 1e-9 * max(
            1.0, np.abs(expected).max())
        assert np.array_equal(soadyn.frame_pose(loaded, q, "panda_hand_tcp"), soadyn.frame_pose(m, q, "panda_hand_tcp"))


def test_mjcf_model_keeps_its_visuals_and_metadata(tmp_path):
    import gymnasium
    path = os.path.join(os.path.dirname(gymnasium.__file__), "envs", "mujoco", "assets", "ant.xml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", soadyn.MjcfIgnoredWarning)
        m = soadyn.load_mjcf(path)
    assert m.visuals
    loaded = through_file(m, tmp_path, metadata={"source": "ant.xml", "runs": [1, 2]})
    assert_same_model(m, loaded)
    assert len(loaded.visuals) == len(m.visuals)
    for a, b in zip(m.visuals, loaded.visuals):
        assert (a.name, a.frame, a.shape, a.mesh_file) == (b.name, b.frame, b.shape, b.mesh_file)
        for key in ("size", "rotation", "translation", "rgba"):
            assert np.array_equal(getattr(a, key), getattr(b, key))
    assert soadyn.model_file.metadata(loaded) == {"source": "ant.xml", "runs": [1, 2]}
    again = through_file(loaded, tmp_path)  # metadata kept by a second save
    assert soadyn.model_file.metadata(again) == {"source": "ant.xml", "runs": [1, 2]}


def test_mesh_visual_with_vertices_round_trips(tmp_path):
    m = soadyn.scenes.four_bar()
    m.visuals = [soadyn.Visual("tri", "crank", "mesh", vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], faces=[[0, 1, 2]])]
    (b,) = through_file(m, tmp_path).visuals
    assert np.array_equal(b.vertices, m.visuals[0].vertices) and np.array_equal(b.faces, [[0, 1, 2]])


def test_models_pickle_and_deepcopy_through_the_format():
    m = soadyn.scenes.cassini()
    m.set_prescribed(["scan_platform:rz"] if "scan_platform:rz" in m.dof_names else [m.dof_names[-1]])
    m.visuals = [soadyn.Visual("box", m.body_names[0], "box", size=[1, 2, 3])]
    for other in (pickle.loads(pickle.dumps(m)), copy.deepcopy(m), copy.copy(m)):
        assert other is not m
        assert_same_model(m, other, seeds=range(1))
        assert other.visuals[0].name == "box"


def test_saved_text_is_documented_json():
    text = model_to_json(soadyn.scenes.four_bar())
    data = json.loads(text)
    assert data["format"] == "soadyn-model" and data["version"] == 1
    assert list(data) == ["format", "version", "gravity", "bodies", "frames", "loops", "joint_springs",
                          "point_springs", "prescribed", "armature", "description"]
    assert data["loops"][0]["kind"] == "revolute"


def four_bar_text() -> dict:
    return json.loads(model_to_json(soadyn.scenes.four_bar()))


def edited(change) -> str:
    data = four_bar_text()
    change(data)
    return json.dumps(data)


HOSTILE = {
    "truncated": (lambda: model_to_json(soadyn.scenes.four_bar())[:700], "not valid JSON"),
    "empty": (lambda: "", "not valid JSON"),
    "a list": (lambda: "[1, 2]", "expected an object"),
    "newer version": (lambda: edited(lambda d: d.update(version=99)), "version"),
    "string mass": (lambda: edited(lambda d: d["bodies"][0].update(mass="1.5")), "/bodies/0/mass"),
    "null com": (lambda: edited(lambda d: d["bodies"][1].update(com=None)), "/bodies/1/com"),
    "NaN inertia": (lambda: model_to_json(soadyn.scenes.four_bar()).replace("0.0001805", "NaN", 1),
                    "not valid JSON"),
    "huge number": (lambda: model_to_json(soadyn.scenes.four_bar()).replace("0.0001805", "1e400", 1),
                    "not valid JSON"),
    "negative mass": (lambda: edited(lambda d: d["bodies"][0].update(mass=-1.0)), "crank"),
    "misspelt key": (lambda: edited(lambda d: d["bodies"][0].update(masss=1.0)), "masss"),
    "unknown joint": (lambda: edited(lambda d: d["bodies"][0]["joint"].update(type="hinge")), "hinge"),
    "unknown parent": (lambda: edited(lambda d: d["bodies"][1].update(parent="ghost")), "ghost"),
    "short axis": (lambda: edited(lambda d: d["bodies"][0]["joint"].update(axis=[0, 1])), "/bodies/0/joint/axis"),
    "unknown loop kind": (lambda: edited(lambda d: d["loops"][0].update(kind="glue")), "/loops/0"),
    "unknown prescribed DOF": (lambda: edited(lambda d: d.update(prescribed=["nope"])), "nope"),
    "bad visual": (lambda: edited(lambda d: d["description"].update(visuals=[{"name": "v", "frame": "crank",
                                                                             "shape": "blob"}])), "blob"),
    "description not an object": (lambda: edited(lambda d: d.update(description=[1])), "description"),
    "inconsistent spatial inertia": (lambda: edited(lambda d: d["bodies"][0]["spatial_inertia"][3].__setitem__(3, 9.0)),
                                     "spatial_inertia"),
}


@pytest.mark.parametrize("case", sorted(HOSTILE))
def test_hostile_model_files_are_refused_naming_the_item(case, tmp_path):
    make_text, named = HOSTILE[case]
    path = tmp_path / "hostile.json"
    path.write_text(make_text())
    with pytest.raises(soadyn.ModelFileError) as error:
        soadyn.load_model(path)
    assert named in str(error.value) and str(path) in str(error.value)


def test_unreadable_and_unwritable_paths_are_named(tmp_path):
    with pytest.raises(soadyn.ModelFileError, match="missing.json"):
        soadyn.load_model(tmp_path / "missing.json")
    (tmp_path / "binary.json").write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(soadyn.ModelFileError, match="binary.json"):
        soadyn.load_model(tmp_path / "binary.json")
    with pytest.raises(soadyn.ModelFileError, match="no_such_dir"):
        soadyn.save_model(soadyn.scenes.four_bar(), tmp_path / "no_such_dir" / "m.json")
    with pytest.raises(soadyn.ModelFileError, match="metadata"):
        soadyn.save_model(soadyn.scenes.four_bar(), tmp_path / "m.json", metadata={"x": float("nan")})


def test_loaded_model_simulates_like_the_original():
    m = soadyn.scenes.four_bar()
    loaded = model_from_json(model_to_json(m))
    q, v = soadyn.scenes.four_bar_state(0.3, 1.0)
    runs = []
    for model in (m, loaded):
        sim = soadyn.Simulator(model, dt=1e-3)
        sim.set_state(q, v)
        runs.append(sim.run(0.2).q)
    assert np.array_equal(runs[0], runs[1])


# --- bounds: nesting depth and size (soadyn.bounded_input) ---------------------------------------------------

def nested_model_file(depth: int) -> str:
    """The four-bar's model-file text with metadata that nests the file `depth` levels deep (the file's object
    is level 1, its description 2, the metadata 3, the arrays in it 4 and on)."""
    text = model_to_json(soadyn.scenes.four_bar(), metadata={"deep": "@@"})
    return text.replace('"@@"', "[" * (depth - 3) + "]" * (depth - 3))


def test_model_file_nested_to_the_limit_loads_and_one_level_more_is_refused(tmp_path):
    path = tmp_path / "deepest.json"
    path.write_text(nested_model_file(MAX_NESTING_DEPTH))
    assert json_depth(path.read_text()) == MAX_NESTING_DEPTH
    metadata = soadyn.model_file.metadata(soadyn.load_model(path))
    assert json_depth(json.dumps(metadata)) == MAX_NESTING_DEPTH - 2
    path.write_text(nested_model_file(MAX_NESTING_DEPTH + 1))
    with pytest.raises(soadyn.ModelFileError, match=f"JSON nested {MAX_NESTING_DEPTH + 1} levels deep, more than "
                                                    f"the {MAX_NESTING_DEPTH} levels") as error:
        soadyn.load_model(path)
    assert str(path) in str(error.value)


def refused_as_too_deep(load, source: str):
    """A forked case: load() must raise ModelFileError naming `source` and the depth limit."""
    def run_case(seed: int) -> str:
        try:
            load()
        except soadyn.ModelFileError as error:
            assert source in str(error) and str(MAX_NESTING_DEPTH) in str(error), str(error)
            return "ModelFileError"
        raise AssertionError("a model file nested too deeply was loaded")
    return run_case


@pytest.mark.parametrize("depth", [10_000, 200_000])
def test_deeply_nested_model_file_is_refused_without_crashing(depth, tmp_path):
    """Once a RecursionError (10,000 levels) and a SIGSEGV (200,000 levels): run in a child process, so a
    crash fails this test instead of ending the run."""
    path = tmp_path / "deep.json"
    path.write_text(nested_model_file(depth))
    assert run_forked(refused_as_too_deep(lambda: soadyn.load_model(path), str(path)), 0, timeout=60) == "expected"


@pytest.mark.parametrize("depth", [MAX_NESTING_DEPTH + 1, 10_000, 200_000])
def test_cpp_model_reader_bounds_nesting_itself(depth):
    """The C++ reader (what C++ programs and campaign workers call) refuses the same depths as the Python
    check in front of it, by name and limit, without crashing (it once died of SIGSEGV at 200,000 levels)."""
    text = nested_model_file(depth)
    load = refused_as_too_deep(lambda: soadyn.Model()._load_json(text, "deep.json"), "deep.json")
    assert run_forked(load, 0, timeout=60) == "expected"


def deep_metadata(levels: int) -> dict:
    metadata: dict = {}
    for _ in range(levels - 1):
        metadata = {"a": metadata}
    return metadata


@pytest.mark.parametrize("levels", [MAX_NESTING_DEPTH - 1, 100_000])
def test_metadata_too_deep_for_a_reader_is_refused_when_saved(levels, tmp_path):
    """Metadata is the one part of a model file a caller nests: a file a reader would refuse is never written."""
    soadyn.save_model(soadyn.scenes.four_bar(), tmp_path / "ok.json", metadata=deep_metadata(MAX_NESTING_DEPTH - 2))
    assert soadyn.load_model(tmp_path / "ok.json").nbodies == 3
    with pytest.raises(soadyn.ModelFileError, match=f"metadata .*more than the {MAX_NESTING_DEPTH} levels") as error:
        soadyn.save_model(soadyn.scenes.four_bar(), tmp_path / "deep.json", metadata=deep_metadata(levels))
    assert "deep.json" in str(error.value) and not (tmp_path / "deep.json").exists()
