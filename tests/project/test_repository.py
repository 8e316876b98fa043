"""The repository holds sources only: no tracked file is a log, a cache or a build output, whether or not
.gitignore names it, so scratch a run leaves behind (MuJoCo's MUJOCO_LOG.TXT, say) can never be committed
again. (The suite itself leaves none in the tree: tests/conftest.py sends MuJoCo's log to a temporary folder.)"""
import re
import subprocess
from pathlib import Path, PurePosixPath

ROOT = Path(__file__).resolve().parents[2]

# Folders no source lives in: caches of Python and its tools, and build trees (CMake's among them).
SCRATCH_FOLDERS = {"__pycache__", ".pytest_cache", ".hypothesis", ".mypy_cache", ".ruff_cache", ".ipynb_checkpoints",
                   "CMakeFiles", "Testing", ".venv", "node_modules"}
TOP_SCRATCH_FOLDERS = {"build", "dist"}  # at the top: scikit-build-core's build-dir, wheels and sdists
# Files: logs of any tool (MuJoCo's MUJOCO_LOG.TXT, CTest's LastTest.log), bytecode, objects and libraries,
# editor and merge leftovers, core dumps, CMake's cache.
SCRATCH_NAME = re.compile(r"""(?ix)
    .*\.log | .*_log\.txt | \.ninja_(log|deps)
  | .*\.py[co] | .*\.(o|obj|a|so|dylib|dll|lib|exe)
  | .*\.(tmp|swp|swo|bak|orig|rej) | .*~ | \.DS_Store
  | core(\.\d+)? | CMakeCache\.txt | .*\.egg-info
""")


def scratch_files(paths: list[str]) -> list[str]:
    """The paths among `paths` (relative, '/'-separated) that are logs, caches or build outputs."""
    found = []
    for path in paths:
        parts = PurePosixPath(path).parts
        if (parts[0] in TOP_SCRATCH_FOLDERS or any(part in SCRATCH_FOLDERS or part.endswith(".egg-info")
                                                   for part in parts[:-1]) or SCRATCH_NAME.fullmatch(parts[-1])):
            found.append(path)
    return found


def git(*args: str) -> list[str]:
    return subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True, check=True).stdout.splitlines()


def test_no_tracked_file_is_one_gitignore_names():
    assert git("ls-files", "--cached", "--ignored", "--exclude-standard") == []


def test_no_tracked_file_is_a_log_a_cache_or_a_build_output():
    tracked = git("ls-files")
    assert "tests/conftest.py" in tracked
    assert scratch_files(tracked) == []


def test_scratch_is_told_from_sources():
    scratch = ["MUJOCO_LOG.TXT", "tests/MUJOCO_LOG.TXT", "bench/run.log", "Testing/Temporary/LastTest.log",
               "tests/__pycache__/conftest.cpython-311.pyc", "python/soadyn/__pycache__/model.cpython-311.pyc",
               "tests/.pytest_cache/v/cache/nodeids", ".hypothesis/examples/0a1b", "build/cpython-311/build.ninja",
               "dist/soadyn-1.0.tar.gz", "python/soadyn.egg-info/PKG-INFO", "python/soadyn/_soadyn.so",
               "cpp/src/model/model.o", "CMakeFiles/soadyn.dir/flags.make", "CMakeCache.txt", ".ninja_log",
               "examples/cpp/main.cpp~", "README.md.orig", "tests/core", "core.12345", "docs/.DS_Store",
               "tests/fuzz/model.pyc"]
    sources = ["CMakeLists.txt", "tests/cpp/CMakeLists.txt", "bench/results/hil_cassini.txt", "README.md",
               "python/soadyn/_soadyn.pyi", "python/soadyn/model.py", "tests/conftest.py", "cpp/src/model/model.cpp",
               "cpp/include/soadyn/core/status.hpp", "docs/notation.md", "bench/build_times.py", "tests/cpp/catalog.h",
               "examples/python/logistics.py", "bench/results/build.csv", "cpp/include/soadyn/sim/build_step.hpp",
               "tests/dynamics/test_build.py", "python/soadyn/core_api.py", "tests/support/logs.py"]
    assert scratch_files(scratch + sources) == scratch
