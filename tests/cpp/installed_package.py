"""The installed C++ package, as a C++ user gets it (CTest tests installed_package_*).

  installed_package.py --build-dir B --source-dir S --scratch D install
      `cmake --install B --component cpp` into D/home/.local; checks the package's files, its version
      (the one of pyproject.toml) and that soadyn::core needs neither threads nor sockets.
  ... example
      configures examples/cpp against that prefix alone, builds it and runs it: the cassini scene paced
      in real time for 10 s, and the four-bar (a closed loop) paced for 4 s.
  ... readme
      takes the C++ program, its CMakeLists.txt and its build command from the manual's C++ guide as
      written, builds it with HOME=D/home (so "$HOME/.local" is the prefix above) and runs it; its results
      must match the closed-form pendulum.
  ... c_api
      builds the C API guide's C program with its CMakeLists.txt (docs/guides/c-api.md) against the prefix,
      linking soadyn::c_api, and runs it on examples/models/double_pendulum.json: its result must match the
      closed form.

No CMAKE_PREFIX_PATH names Eigen: soadynConfig.cmake must find it by itself. The library is not compiled
again: the prefix is installed from the build tree that `pip install` made.
"""
from __future__ import annotations

import argparse
import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

from check_summary import CheckFailed, require  # beside this file

TIMEOUT = 600  # seconds


def find_tool(name: str, module: str, attribute: str) -> str:
    """The tool installed by the PyPI package `module` (next to this Python), else the one on PATH."""
    try:
        package = __import__(module)
        candidate = Path(getattr(package, attribute)) / name
        if candidate.is_file():
            return str(candidate)
    except (ImportError, AttributeError):
        pass
    found = shutil.which(name)
    require(found is not None, f"{name} on PATH (install the test extra: pip install '.[test]')")
    return found


def run(command: list, cwd: Path | None = None, env: dict | None = None, shell: bool = False,
        show_output: bool = True) -> str:
    shown = command if shell else " ".join(str(part) for part in command)
    print(f"$ {shown}", flush=True)
    result = subprocess.run(command, cwd=cwd, env=env, shell=shell, capture_output=True, text=True, timeout=TIMEOUT,
                            executable="/bin/bash" if shell else None)
    output = result.stdout + result.stderr
    if show_output or result.returncode != 0:
        print(output, end="", flush=True)
    require(result.returncode == 0, f"exit code 0 of: {shown}")
    return output


def configure_args() -> list:
    """The generator for the user-side builds: Ninja when the test extra brought it."""
    try:
        ninja = find_tool("ninja", "ninja", "BIN_DIR")
    except CheckFailed:
        return []
    return ["-G", "Ninja", f"-DCMAKE_MAKE_PROGRAM={ninja}"]


def pyproject_version(source: Path) -> str:
    text = (source / "pyproject.toml").read_text()
    try:
        import tomllib
        return tomllib.loads(text)["project"]["version"]
    except ImportError:  # Python < 3.11
        match = re.search(r'^\[project\][^\[]*?^version = "([^"]+)"', text, re.MULTILINE | re.DOTALL)
        require(match is not None, "a version in pyproject.toml's [project] table")
        return match.group(1)


def prefix_of(scratch: Path) -> Path:
    return scratch / "home" / ".local"


def install(build: Path, source: Path, scratch: Path) -> None:
    if scratch.exists():
        shutil.rmtree(scratch)
    prefix = prefix_of(scratch)
    run([find_tool("cmake", "cmake", "CMAKE_BIN_DIR"), "--install", str(build), "--component", "cpp",
         "--prefix", str(prefix)])
    config_dirs = [d / "cmake" / "soadyn" for d in (prefix / "lib", prefix / "lib64")
                   if (d / "cmake" / "soadyn" / "soadynConfig.cmake").is_file()]
    require(len(config_dirs) == 1, f"one soadynConfig.cmake under {prefix}/lib*/cmake/soadyn")
    config_dir = config_dirs[0]
    libraries = config_dir.parent.parent
    require((libraries / "libsoadyn.a").is_file() and (libraries / "libsoadyn_realtime.a").is_file(),
            "libsoadyn.a (soadyn::core) and libsoadyn_realtime.a (soadyn::realtime)")
    require((prefix / "include" / "soadyn" / "soadyn.hpp").is_file(), "the headers")
    require((libraries / "libsoadyn_c_api.so").is_file() and
            (prefix / "include" / "soadyn" / "embed" / "c_api.h").is_file(),
            "the C API (libsoadyn_c_api.so, soadyn/embed/c_api.h)")
    require((libraries / "libsoadyn_scenes.a").is_file() and
            (prefix / "include" / "soadyn_scenes" / "scenes.hpp").is_file(),
            "the built-in scenes beside the core (libsoadyn_scenes.a, soadyn_scenes/scenes.hpp)")

    # One version: the package's is pyproject.toml's.
    version = re.search(r'set\(PACKAGE_VERSION "([^"]+)"\)', (config_dir / "soadynConfigVersion.cmake").read_text())
    require(version is not None, "PACKAGE_VERSION in soadynConfigVersion.cmake")
    require(version.group(1) == pyproject_version(source),
            f"the C++ package's version {version.group(1)} equal to pyproject.toml's {pyproject_version(source)}")

    # soadyn::core links Eigen only (and, where the C library has it, glibc's
    # vector math library, as a part of the C library like libm: the joint
    # angles' sines, cpp/src/sweeps/joint_angles.cpp), and its archive calls no
    # socket, thread or scheduling function.
    targets = (config_dir / "soadynTargets.cmake").read_text()
    core = re.search(r"set_target_properties\(soadyn::core PROPERTIES(.*?)\n\)", targets, re.DOTALL)
    require(core is not None, "soadyn::core in soadynTargets.cmake")
    links = re.search(r'INTERFACE_LINK_LIBRARIES "([^"]*)"', core.group(1))
    require(links is not None and links.group(1) in ("Eigen3::Eigen", "Eigen3::Eigen;mvec"),
            f"soadyn::core linking Eigen3::Eigen (and libmvec) only (it links {links.group(1) if links else 'nothing'})")
    undefined = run(["nm", "-u", "--format=just-symbols", str(libraries / "libsoadyn.a")], show_output=False)
    forbidden = {"socket", "bind", "connect", "sendto", "recvfrom", "setsockopt", "pthread_create",
                 "pthread_setschedparam", "sched_setscheduler", "mlockall", "clock_nanosleep"}
    used = sorted(forbidden & {line.strip() for line in undefined.splitlines()})
    require(not used, f"no socket, thread or scheduling call in libsoadyn.a (it calls {', '.join(used)})")
    realtime = run(["nm", "-u", "--format=just-symbols", str(libraries / "libsoadyn_realtime.a")], show_output=False)
    require("socket" in {line.strip() for line in realtime.splitlines()},
            "the socket calls in libsoadyn_realtime.a (the symbol check above sees what it looks for)")
    defined = run(["nm", "--defined-only", "--format=just-symbols", "-C", str(libraries / "libsoadyn.a")],
                  show_output=False)
    scenes = sorted({line.strip() for line in defined.splitlines() if "cassini_model" in line})
    require(not scenes, f"no scene in libsoadyn.a (soadyn::core defines {', '.join(scenes[:3])})")
    print(f"installed soadyn {version.group(1)} into {prefix}: soadyn::core needs Eigen only")


def eigen_found_by_config(build: Path) -> str:
    cache = (build / "CMakeCache.txt").read_text()
    match = re.search(r"^Eigen3_DIR:PATH=(.*)$", cache, re.MULTILINE)
    require(match is not None and Path(match.group(1), "Eigen3Config.cmake").is_file(),
            "Eigen found by soadynConfig.cmake")
    return match.group(1)


def example(source: Path, scratch: Path) -> None:
    cmake = find_tool("cmake", "cmake", "CMAKE_BIN_DIR")
    build = scratch / "example"
    run([cmake, "-S", str(source / "examples" / "cpp"), "-B", str(build), *configure_args(),
         f"-DCMAKE_PREFIX_PATH={prefix_of(scratch)}"])
    print(f"Eigen: {eigen_found_by_config(build)}")
    run([cmake, "--build", str(build), "-j2"])
    output = run([str(build / "cassini_realtime")])
    require(re.search(r"^cassini: 10000 steps of 1.0 ms \(RK4\), simulated 10.000 s, energy lost to the lock "
                      r"\d+\.\d+ J$", output, re.MULTILINE) is not None, "10^4 steps of cassini, 10 s simulated")
    require(re.search(r"^step time us: p50 \S+ +p99 \S+ +p99.9 \S+ +max \S+$", output, re.MULTILINE) is not None,
            "the step-time summary")
    paced = re.search(r"^paced on CLOCK_MONOTONIC: wall (\S+) s, \d+ of 10000 steps ended after their deadline "
                      r"\(worst by \S+ us\)$", output, re.MULTILINE)
    require(paced is not None, "the pacing summary")
    # Sleeping to absolute deadlines, the run cannot end before its last deadline (no speed is judged).
    require(float(paced.group(1)) >= 10.0, f"a paced run: wall time {paced.group(1)} s not below the simulated 10 s")
    output = run([str(build / "four_bar_realtime")])
    torque = re.search(r"^four-bar: 4000 steps of 1.0 ms \(RK4\), simulated 4.000 s, crank torque while driven "
                       r"(\S+) \.\. (\S+) N m$", output, re.MULTILINE)
    require(torque is not None and float(torque.group(1)) < 0 < float(torque.group(2)),
            "4000 steps of the four-bar, its crank driven both ways")
    closure = re.search(r"^loop drift before projection: max (\S+) m, (\S+) m/s; closure at the end (\S+) m, "
                        r"(\S+) m/s$", output, re.MULTILINE)
    require(closure is not None and max(float(closure.group(3)), float(closure.group(4))) <= 1e-12,
            "the four-bar closed to 1e-12 at the end")
    require(re.search(r"^paced on CLOCK_MONOTONIC: wall (\S+) s, \d+ of 4000 steps", output, re.MULTILINE) is not None,
            "the four-bar's pacing summary")


def readme_blocks(source: Path) -> dict:
    """The fenced code blocks of the manual's C++ guide (docs/guides/cpp.md), by language."""
    page = source / "docs" / "guides" / "cpp.md"
    require(page.is_file(), "the manual's C++ guide, docs/guides/cpp.md")
    blocks: dict = {}
    for language, body in re.findall(r"^```(\w+)\n(.*?)^```$", page.read_text(), re.MULTILINE | re.DOTALL):
        blocks.setdefault(language, []).append(body)
    return blocks


def readme(source: Path, scratch: Path) -> None:
    blocks = readme_blocks(source)
    require(len(blocks.get("cpp", [])) == 1 and len(blocks.get("cmake", [])) == 1 and len(blocks.get("sh", [])) == 2,
            "in the C++ guide: one cpp block, one cmake block and two sh blocks (install, then build)")
    install_commands, build_commands = blocks["sh"]
    require('--prefix "$HOME/.local"' in install_commands and 'CMAKE_PREFIX_PATH="$HOME/.local"' in build_commands,
            'the C++ guide installing into "$HOME/.local" and building the program against it')
    project = scratch / "pendulum"
    project.mkdir(parents=True, exist_ok=True)
    (project / "main.cpp").write_text(blocks["cpp"][0])
    (project / "CMakeLists.txt").write_text(blocks["cmake"][0])
    # The guide's commands as written, with $HOME the scratch home that holds the installed package and the
    # cmake of the test extra first on PATH.
    env = dict(os.environ, HOME=str(scratch / "home"))
    env["PATH"] = os.pathsep.join([str(Path(find_tool("cmake", "cmake", "CMAKE_BIN_DIR")).parent), env["PATH"]])
    env.pop("CMAKE_PREFIX_PATH", None)
    output = run(build_commands, cwd=scratch, env=env, shell=True)
    print(f"Eigen: {eigen_found_by_config(project / 'build')}")

    # The closed form: a link of mass m on a hinge about x, its centre of mass at distance l along y, at angle q;
    # gravity g along -z. Inertia about the hinge I = Ixx + m l^2; gravity's torque -m g l cos q.
    m, length, ixx, q, g = 2.0, 0.5, 0.02, 0.3, 9.81
    hinge_inertia, gravity_torque = ixx + m * length ** 2, -m * g * length * math.cos(q)
    regular = re.search(r"^regular hinge: torque (\S+) N m -> acceleration (\S+) rad/s\^2$", output, re.MULTILINE)
    prescribed = re.search(r"^prescribed hinge: acceleration (\S+) rad/s\^2 -> torque (\S+) N m$", output,
                           re.MULTILINE)
    require(regular is not None and prescribed is not None, "the regular and prescribed results")
    torque, acceleration = float(regular.group(1)), float(regular.group(2))
    expected = (torque + gravity_torque) / hinge_inertia
    require(math.isclose(acceleration, expected, rel_tol=1e-9, abs_tol=1e-12),
            f"acceleration {acceleration} equal to the closed form {expected}")
    acceleration, torque = float(prescribed.group(1)), float(prescribed.group(2))
    expected = hinge_inertia * acceleration - gravity_torque
    require(math.isclose(torque, expected, rel_tol=1e-9, abs_tol=1e-12),
            f"torque {torque} equal to the closed form {expected}")
    print("the C++ guide's program: both results equal the closed-form pendulum")


def c_api(source: Path, scratch: Path) -> None:
    """The C API guide's program (docs/guides/c-api.md), its C and CMake blocks as written, built against the
    installed package and run on examples/models/double_pendulum.json: the locked double pendulum's
    acceleration equals the closed form of one 1 m, 2 kg rod."""
    page = source / "docs" / "guides" / "c-api.md"
    require(page.is_file(), "the manual's C API guide, docs/guides/c-api.md")
    blocks: dict = {}
    for language, body in re.findall(r"^```(\w+)\n(.*?)^```$", page.read_text(), re.MULTILINE | re.DOTALL):
        blocks.setdefault(language, []).append(body)
    require(len(blocks.get("c", [])) == 1 and len(blocks.get("cmake", [])) == 1,
            "in the C API guide: one c block and one cmake block")
    project = scratch / "pendulum_c"
    project.mkdir(parents=True, exist_ok=True)
    (project / "main.c").write_text(blocks["c"][0])
    (project / "CMakeLists.txt").write_text(blocks["cmake"][0])
    cmake = find_tool("cmake", "cmake", "CMAKE_BIN_DIR")
    run([cmake, "-S", str(project), "-B", str(project / "build"), *configure_args(),
         f"-DCMAKE_PREFIX_PATH={prefix_of(scratch)}"])
    run([cmake, "--build", str(project / "build")])
    output = run([str(project / "build" / "pendulum"), str(source / "examples" / "models" / "double_pendulum.json")])
    found = re.search(r"^elbow locked at 0.3 rad: shoulder acceleration (\S+) rad/s\^2$", output, re.MULTILINE)
    require(found is not None, "the shoulder's acceleration")
    expected = -9.81 * math.sin(0.3) / (2.0 / 3.0)
    require(math.isclose(float(found.group(1)), expected, rel_tol=1e-9),
            f"acceleration {found.group(1)} equal to the closed form {expected}")
    require(re.search(r"^after 1 s: shoulder \S+ rad, elbow 0.000000 rad$", output, re.MULTILINE) is not None,
            "the locked elbow held at 0")
    print("the C API guide's program: the locked pendulum's acceleration equals the closed form")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build-dir", type=Path, required=True)
    parser.add_argument("--source-dir", type=Path, required=True)
    parser.add_argument("--scratch", type=Path, required=True)
    parser.add_argument("step", choices=["install", "example", "readme", "c_api"])
    args = parser.parse_args()
    try:
        if args.step == "install":
            install(args.build_dir, args.source_dir, args.scratch)
        elif args.step == "example":
            example(args.source_dir, args.scratch)
        elif args.step == "c_api":
            c_api(args.source_dir, args.scratch)
        else:
            readme(args.source_dir, args.scratch)
    except CheckFailed as failed:
        print(f"installed package ({args.step}): expected {failed}", file=sys.stderr)
        return 1
    except subprocess.TimeoutExpired as expired:
        print(f"installed package ({args.step}): timed out: {expired.cmd}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
