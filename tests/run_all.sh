#!/usr/bin/env bash
# Every test, on a fresh machine, from the venv it should install into:
#   python3 -m venv .venv && . .venv/bin/activate && bash tests/run_all.sh
# 1. pip installs the package with its test extra, building the library, the
#    Python module and the C++ tests once, in pip's build tree
#    build/<cache tag> (pyproject.toml: build-dir);
# 2. CTest runs the C++ tests from that tree (tests/cpp/CMakeLists.txt);
# 3. pytest runs the Python suite.
# The exit code is CTest's if it failed, else pytest's (5: no tests collected).
set -uo pipefail
cd "$(dirname "$0")/.."

SOADYN_BUILD_TESTS=ON pip install ".[test]" || exit $?
build_dir="build/$(python -c 'import sys; print(sys.implementation.cache_tag)')"
ctest --test-dir "$build_dir" --output-on-failure --no-tests=error
ctest_rc=$?
python -m pytest -q tests
pytest_rc=$?
if [ "$ctest_rc" -ne 0 ]; then
  echo "C++ tests (ctest --test-dir $build_dir) failed" >&2
  exit "$ctest_rc"
fi
exit "$pytest_rc"
