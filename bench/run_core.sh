#!/usr/bin/env bash
# The C++ core benchmarks: configure and build (Release, no -march=native) into
# build/bench, run bench_core and bench_skips, and write their tables to
# bench/results/core.json and bench/results/skips.json (bench/run_cpp_bench.py).
# Needs cmake (and preferably ninja) and the Python with cmeel-eigen on PATH,
# e.g. the venv after `pip install '.[test]'`.
# Usage: bash bench/run_core.sh [batches]   (default 3000 timed batches per algorithm)
set -euo pipefail

repo="$(cd "$(dirname "$0")/.." && pwd)"
build="$repo/build/bench"
batches="${1:-3000}"

command -v cmake >/dev/null || { echo "cmake not found: activate the venv with the test extra" >&2; exit 1; }
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
python="$(command -v python3 || command -v python)"

cmake -S "$repo" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DSOADYN_NATIVE=OFF \
  -DSOADYN_BUILD_BENCH=ON -DPython3_EXECUTABLE="$python" >/dev/null
cmake --build "$build" --target bench_core bench_skips -j2

"$python" "$repo/bench/run_cpp_bench.py" core "$build/bench/bench_core" "$batches"
"$python" "$repo/bench/run_cpp_bench.py" skips "$build/bench/bench_skips" "$batches"
