"""The C++ tests (tests/cpp): configure and build them once per session with
the cmake and ninja that `pip install .[test]` brought in, then run each
executable and check its exit code and summary line.

The build tree is build/cpp-tests in the repository (gitignored) and is
reused between sessions, so later runs rebuild only what changed.
"""
from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
BUILD_DIR = REPO / "build" / "cpp-tests"
BUILD_TIMEOUT = 3600  # seconds: a cold build of the library and tests on 2 cores takes ~1-2 min
RUN_TIMEOUT = 600


def find_tool(name: str, module: str, attribute: str) -> str:
    """The tool installed by the PyPI package `module` (next to this Python),
    else the one on PATH."""
    try:
        package = __import__(module)
        candidate = Path(getattr(package, attribute)) / name
        if candidate.is_file():
            return str(candidate)
    except (ImportError, AttributeError):
        pass
    found = shutil.which(name)
    if found is None:
        raise RuntimeError(f"{name} not found: install the test extra (pip install '.[test]')")
    return found


def cached_value(cache: Path, key: str) -> str | None:
    match = re.search(rf"^{key}:[A-Z]+=(.*)$", cache.read_text(), re.MULTILINE)
    return match.group(1) if match else None


def discard_foreign_build_tree() -> None:
    """A build tree configured from another checkout or with another generator
    cannot be reconfigured in place: start it afresh."""
    cache = BUILD_DIR / "CMakeCache.txt"
    if not cache.is_file():
        return
    home = cached_value(cache, "CMAKE_HOME_DIRECTORY")
    same_source = home is not None and Path(home).resolve() == REPO
    if not same_source or cached_value(cache, "CMAKE_GENERATOR") != "Ninja":
        shutil.rmtree(BUILD_DIR)


def run_checked(command: list[str], timeout: int) -> None:
    result = subprocess.run(command, cwd=REPO, capture_output=True, text=True, timeout=timeout)
    assert result.returncode == 0, (
        f"{' '.join(command)} failed ({result.returncode}):\n{result.stdout[-20000:]}\n{result.stderr[-20000:]}")


@pytest.fixture(scope="module")
def cpp_tests_dir() -> Path:
    """Configures and builds the C++ tests once; returns where the executables are."""
    cmake = find_tool("cmake", "cmake", "CMAKE_BIN_DIR")
    ninja = find_tool("ninja", "ninja", "BIN_DIR")
    discard_foreign_build_tree()
    run_checked([cmake, "-S", str(REPO), "-B", str(BUILD_DIR), "-G", "Ninja",
                 f"-DCMAKE_MAKE_PROGRAM={ninja}",
                 # The Python whose site-packages hold cmeel-eigen, whatever is on PATH.
                 f"-DPython3_EXECUTABLE={sys.executable}",
                 "-DSOADYN_BUILD_TESTS=ON", "-DCMAKE_BUILD_TYPE=Release"], BUILD_TIMEOUT)
    run_checked([cmake, "--build", str(BUILD_DIR), "-j2"], BUILD_TIMEOUT)
    return BUILD_DIR / "tests" / "cpp"


def run_test_executable(directory: Path, name: str) -> str:
    result = subprocess.run([str(directory / name)], capture_output=True, text=True, timeout=RUN_TIMEOUT)
    output = result.stdout + result.stderr
    assert result.returncode == 0, f"{name} exited with {result.returncode}:\n{output}"
    return output


def test_no_allocation_in_run_time_algorithms(cpp_tests_dir):
    output = run_test_executable(cpp_tests_dir, "test_no_allocation")
    # The counter proved it sees std::vector, aligned new and libc's malloc...
    assert re.search(r"^self-check: std::vector -> [1-9]\d* new", output, re.MULTILINE), output
    # ...and then saw nothing during 10^5 hybrid calls with flag changes, on a rigid tree and on the
    # same tree with flexible bodies.
    assert re.search(r"^tree with flexible bodies: \d+ bodies \([1-9]\d* flexible\)", output, re.MULTILINE), output
    assert len(re.findall(r"^calls: 100000 hybrid_dynamics, \d+ other, \d+ flag changes; failed statuses: 0$",
                          output, re.MULTILINE)) == 2, output
    assert len(re.findall(r"^allocations: 0 operator new, 0 malloc family; frees: 0$", output, re.MULTILINE)) == 2, output
    assert re.search(r"^test_no_allocation: PASS: 100000 hybrid_dynamics calls per model$", output, re.MULTILINE), output


def test_float_agrees_with_double(cpp_tests_dir):
    output = run_test_executable(cpp_tests_dir, "test_float_vs_double")
    match = re.search(r"^test_float_vs_double: PASS: max relative error (\S+) rigid, (\S+) with flexible bodies "
                      r"\(tolerance 1e-04\), \d+ states per model, 0 failures$", output, re.MULTILINE)
    assert match, output
    assert max(float(match.group(1)), float(match.group(2))) <= 1e-4, output


def test_simulator_steps_allocate_nothing(cpp_tests_dir):
    """10^5 steps of each built-in scene, RK4 and semi-implicit Euler, with events firing; and the HIL loop,
    paced and as fast as possible, with real-time scheduling requested, and over the UDP link under hostile
    traffic with the clamp, reject and stop policies."""
    output = run_test_executable(cpp_tests_dir, "test_sim_no_allocation")
    rows = re.findall(r"^(\S+) \((rk4|euler)\): 100000 steps, 0 allocations, 0 frees, 0 failed statuses", output,
                      re.MULTILINE)
    assert len(rows) == 4, output
    hil = re.findall(r"^hil runner \((paced|as fast as possible)\): 20000 steps, 0 allocations, 0 frees, status ok;",
                     output, re.MULTILINE)
    assert sorted(hil) == ["as fast as possible", "paced"], output
    udp = re.findall(r"^hil runner over UDP \((clamp|reject)\): 20000 steps, 0 allocations, 0 frees, status ok;",
                     output, re.MULTILINE)
    assert sorted(udp) == ["clamp", "reject"], output
    assert re.search(r"^hil runner over UDP \(stop\): 0 allocations, 0 frees, stopped at step \d+ of 20000 by DOF 0$",
                     output, re.MULTILINE), output
    assert re.search(r"^test_sim_no_allocation: PASS$", output, re.MULTILINE), output


def cmeel_prefixes() -> list[str]:
    return [str(Path(p) / "cmeel.prefix") for p in sys.path if (Path(p) / "cmeel.prefix").is_dir()]


def test_embedded_example_links_the_installed_package(cpp_tests_dir, tmp_path):
    """`cmake --install` exports soadyn; examples/cpp finds it with find_package and steps cassini for 10 s."""
    cmake = find_tool("cmake", "cmake", "CMAKE_BIN_DIR")
    ninja = find_tool("ninja", "ninja", "BIN_DIR")
    prefix, build = tmp_path / "prefix", tmp_path / "example"
    run_checked([cmake, "--install", str(BUILD_DIR), "--prefix", str(prefix)], BUILD_TIMEOUT)
    assert (prefix / "lib" / "cmake" / "soadyn" / "soadynConfig.cmake").is_file() or \
        (prefix / "lib64" / "cmake" / "soadyn" / "soadynConfig.cmake").is_file()
    run_checked([cmake, "-S", str(REPO / "examples" / "cpp"), "-B", str(build), "-G", "Ninja",
                 f"-DCMAKE_MAKE_PROGRAM={ninja}", f"-DCMAKE_PREFIX_PATH={';'.join([str(prefix)] + cmeel_prefixes())}"],
                BUILD_TIMEOUT)
    run_checked([cmake, "--build", str(build), "-j2"], BUILD_TIMEOUT)
    output = run_test_executable(build, "cassini_realtime")
    assert re.search(r"^cassini: 10000 steps of 1.0 ms \(RK4\), simulated 10.000 s, energy lost to the lock "
                     r"\d+\.\d+ J$", output, re.MULTILINE), output
    assert re.search(r"^step time us: p50 \S+ +p99 \S+ +p99.9 \S+ +max \S+$", output, re.MULTILINE), output
