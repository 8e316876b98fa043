#!/usr/bin/env bash
# Every test, on a fresh machine, from the venv it should install into:
#   python3 -m venv .venv && . .venv/bin/activate && bash tests/run_all.sh
# 1. pip installs the package with its test extra, building the library, the
#    Python module, the C++ tests and the C++ benchmarks (compiled so that none
#    falls behind the library's interface; run by bench/) once, in pip's build tree
#    build/<cache tag> (pyproject.toml: build-dir) (before it, Debian's
#    Chromium for the browser test, if missing);
# 2. CTest runs the C++ tests from that tree (tests/cpp/CMakeLists.txt);
# 3. pytest runs the Python suite, one process per core (pytest-xdist: -n auto; --dist worksteal
#    lets an idle process take tests queued for a busy one): much of the suite waits on real-time
#    runs, subprocesses and sockets, so two processes take about half the time on two cores.
# The exit code is CTest's if it failed, else pytest's (5: no tests collected).
set -uo pipefail
cd "$(dirname "$0")/.."

# The viewer's browser test (tests/viz/test_viewer_browser.py) drives Debian's
# Chromium headless; installed here when missing and we may (root, apt-get).
if ! command -v chromium >/dev/null 2>&1 && [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null 2>&1; then
  { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium; } >/dev/null 2>&1 ||
    echo "could not install chromium: the browser test will fail and say so" >&2
fi

SOADYN_BUILD_TESTS=ON SOADYN_BUILD_BENCH=ON pip install ".[test]" || exit $?
build_dir="build/$(python -c 'import sys; print(sys.implementation.cache_tag)')"
ctest --test-dir "$build_dir" --output-on-failure --no-tests=error
ctest_rc=$?
python -m pytest -q -n auto --dist worksteal tests
pytest_rc=$?
if [ "$ctest_rc" -ne 0 ]; then
  echo "C++ tests (ctest --test-dir $build_dir) failed" >&2
  exit "$ctest_rc"
fi
exit "$pytest_rc"
