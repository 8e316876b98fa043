"""The C++ tree reads as its architecture: each folder of cpp/include/soadyn/
includes only its own folder and the layers below it, cpp/src/ mirrors the
include folders, and the scenes stay out of the core.

The layers, bottom up (CONTRIBUTING.md, "Where code lives"). Folders of the
same rank may not include each other.
"""
import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
INCLUDE = ROOT / "cpp" / "include" / "soadyn"
SOURCES = ROOT / "cpp" / "src"

LAYERS = {
    "core": 0,         # status, validation, processor features, interrupts: no dynamics
    "spatial": 1,      # spatial vectors, transforms, inertias
    "linalg": 2,       # the small factorisations of the sweeps and the loop solves
    "joints": 3,       # one header per joint type, with its own fast paths
    "flex": 3,         # flexible bodies: modal integrals, beams
    "model": 4,        # Model, Data, derived caches, loops and force elements as data, parameters, model files
    "sweeps": 5,       # the recursions' steps and the path chooser (internal)
    "algorithms": 6,   # public entry points: kinematics, RNEA, CRBA, ABA, hybrid, energy, frames, equation terms
    "constraints": 7,  # closed loops: closure, assembly, constrained dynamics and impulses
    "sim": 8,          # integrators, charts, motion sources, events, the Simulator
    "analysis": 9,     # derivatives, statics, sensitivity, modes, linearization (of a Simulator step)
    "realtime": 10,    # the HIL runner, UDP link, scheduling, state snapshot
    "parallel": 10,    # thread pool, batched dynamics, rollouts
    "embed": 11,       # Plant and the C API: a simulator driven by an embedding host
    "fmu": 12,         # the FMU binary's parts (variables, instance, model description, saved states)
}
UMBRELLA = "soadyn.hpp"  # the one header at the root: includes the public entry points
INCLUDE_LINE = re.compile(r'^\s*#\s*include\s*[<"]([^">]+)[">]', re.MULTILINE)


def soadyn_includes(path):
    """The soadyn headers `path` includes, as paths below cpp/include/soadyn/."""
    found = []
    for target in INCLUDE_LINE.findall(path.read_text()):
        if target.startswith("soadyn/"):
            found.append(target[len("soadyn/"):])
        elif target.startswith("soadyn_scenes/"):
            found.append(target)
    return found


def folder_of(relative):
    parts = pathlib.PurePosixPath(relative).parts
    return parts[0] if len(parts) > 1 else None


def layer_violations(files, folder_of_file):
    """(file, included header, why) for each include that breaks the layering."""
    bad = []
    for path in files:
        own = folder_of_file(path)
        for target in soadyn_includes(path):
            if target.startswith("soadyn_scenes/"):
                bad.append((path, target, "the scenes are not part of the library"))
                continue
            if not (INCLUDE / target).is_file():
                bad.append((path, target, "no such header"))
                continue
            other = folder_of(target)
            if other is None:
                bad.append((path, target, "nothing includes the umbrella header inside the library"))
            elif other == own:
                continue
            elif LAYERS[other] >= LAYERS[own]:
                bad.append((path, target, f"{own}/ (layer {LAYERS[own]}) may not include {other}/ "
                                          f"(layer {LAYERS[other]})"))
    return bad


def header_files():
    return sorted(p for p in INCLUDE.rglob("*") if p.suffix in (".hpp", ".hxx", ".h"))


def source_files():
    return sorted(SOURCES.rglob("*.cpp"))


def describe(bad):
    return "\n".join(f"{p.relative_to(ROOT)} includes {t}: {why}" for p, t, why in bad)


def test_every_header_sits_in_a_layer_folder():
    loose = [p.relative_to(INCLUDE).as_posix() for p in header_files()
             if folder_of(p.relative_to(INCLUDE).as_posix()) is None and p.name != UMBRELLA]
    unknown = sorted({folder_of(p.relative_to(INCLUDE).as_posix()) for p in header_files()} - set(LAYERS) - {None})
    assert not loose, f"headers outside a layer folder: {loose}"
    assert not unknown, f"folders of cpp/include/soadyn/ without a layer (add them to LAYERS and CONTRIBUTING.md): {unknown}"


def test_headers_include_only_lower_layers():
    bad = layer_violations([p for p in header_files() if p.name != UMBRELLA],
                           lambda p: folder_of(p.relative_to(INCLUDE).as_posix()))
    assert not bad, describe(bad)


def test_sources_mirror_the_include_folders_and_their_rule():
    files = source_files()
    assert files, "no C++ sources found under cpp/src"
    loose = [p.relative_to(SOURCES).as_posix() for p in files if p.parent == SOURCES]
    assert not loose, f"sources outside a folder of cpp/src/: {loose}"
    unmatched = sorted({p.parent.name for p in files} - {d.name for d in INCLUDE.iterdir() if d.is_dir()})
    assert not unmatched, f"cpp/src/ folders without an include folder of the same name: {unmatched}"
    bad = layer_violations(files, lambda p: p.relative_to(SOURCES).parts[0])
    assert not bad, describe(bad)


def test_the_umbrella_header_names_no_internal_folder():
    internal = [t for t in soadyn_includes(INCLUDE / UMBRELLA)
                if folder_of(t) in ("sweeps", "linalg") or t.startswith("soadyn_scenes/")]
    assert not internal, f"{UMBRELLA} includes internal headers or the scenes: {internal}"


def test_scenes_are_outside_the_core_library():
    cmake = (ROOT / "CMakeLists.txt").read_text()
    core = re.search(r"set\(SOADYN_CORE_SOURCES(.*?)\)", cmake, re.DOTALL)
    assert core is not None, "SOADYN_CORE_SOURCES in CMakeLists.txt"
    assert "scenes" not in core.group(1), "a scene source is compiled into soadyn::core"
    assert not list(INCLUDE.rglob("scenes*")), "scene headers inside cpp/include/soadyn/"


@pytest.mark.parametrize("header, target, expected", [
    ("model/x.hpp", "sweeps/body_updates.hpp", "model/ (layer 4) may not include sweeps/ (layer 5)"),
    ("realtime/x.hpp", "parallel/thread_pool.hpp", "realtime/ (layer 10) may not include parallel/ (layer 10)"),
    ("algorithms/x.hpp", "soadyn.hpp", "nothing includes the umbrella header"),
    ("sim/x.hpp", "soadyn_scenes/scenes.hpp", "the scenes are not part of the library"),
])
def test_the_rule_finds_a_planted_violation(tmp_path, header, target, expected):
    planted = tmp_path / header
    planted.parent.mkdir(parents=True)
    planted.write_text(f'#pragma once\n#include "{target if target.startswith("soadyn_") else "soadyn/" + target}"\n')
    bad = layer_violations([planted], lambda p: p.parent.name)
    assert len(bad) == 1 and expected in bad[0][2], bad


def test_only_joints_name_a_joint_fast_path():
    """The joints' fast paths are chosen in joints/ alone (joints/fast_path_updates.hpp): elsewhere a fast-path tag
    is read through joint_fast_path.hpp's predicates, never compared with or switched on by name."""
    fast_path_name = re.compile(r"\bJointFastPath::\w+")
    found = []
    for path in sorted([*INCLUDE.rglob("*.h*"), *SOURCES.rglob("*.cpp"), *(ROOT / "bindings").rglob("*.*pp")]):
        if (INCLUDE / "joints") in path.parents:
            continue
        for number, line in enumerate(path.read_text().splitlines(), 1):
            code = line.split("//")[0]
            if fast_path_name.search(code):
                found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert not found, "joint fast paths named outside joints/:\n" + "\n".join(found)
