#!/usr/bin/env bash
# Core benchmarks in one command: configure and build (Release, no
# -march=native) into build/bench, run bench_core and bench_skips, write
# bench/results/core.md and bench/results/skips.md.
# Needs cmake (and preferably ninja) and the Python with cmeel-eigen on PATH,
# e.g. the venv after `pip install '.[test]'`.
# Usage: bash bench/run_core.sh [repetitions]
set -euo pipefail

repo="$(cd "$(dirname "$0")/.." && pwd)"
build="$repo/build/bench"
results="$repo/bench/results/core.md"
skips="$repo/bench/results/skips.md"
repetitions="${1:-3000}"

command -v cmake >/dev/null || { echo "cmake not found: activate the venv with the test extra" >&2; exit 1; }
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
python="$(command -v python3 || command -v python)"

cmake -S "$repo" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DSOADYN_NATIVE=OFF \
  -DSOADYN_BUILD_BENCH=ON -DPython3_EXECUTABLE="$python" >/dev/null
cmake --build "$build" --target bench_core bench_skips -j2

cache_value() { sed -n "s/^$1:[A-Z]*=//p" "$build/CMakeCache.txt"; }
cxx="$(cache_value CMAKE_CXX_COMPILER)"
cpu="$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -n 1)"

# The provenance lines both result files start with.
header() {
  echo "- Date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "- Machine: $(uname -m), ${cpu:-unknown CPU}, $(nproc) logical cores"
  echo "- Source: $(git -C "$repo" describe --always --dirty 2>/dev/null || echo "not a git checkout")"
  echo "- Compiler: $("$cxx" --version | head -n 1)"
  echo "- Build: Release ($(cache_value CMAKE_CXX_FLAGS_RELEASE)), no -march=native"
  echo "- Command: \`bash bench/run_core.sh $repetitions\`"
  echo
}

table="$(mktemp)"
skips_table="$(mktemp)"
trap 'rm -f "$table" "$skips_table"' EXIT
"$build/bench/bench_core" "$repetitions" | tee "$table"

mkdir -p "$(dirname "$results")"
{
  echo "# Core benchmark"
  echo
  header
  cat "$table"
  echo
  echo "Times are medians per call over many short timed batches, the algorithms"
  echo "interleaved batch by batch and the models visited in rounds, on a shared"
  echo "and possibly noisy machine: compare ratios rather than absolute times."
  echo "ABA: forward_dynamics. RNEA: inverse_dynamics. CRBA: mass_matrix."
  echo "hybrid all-regular solves the ABA problem and hybrid all-prescribed the RNEA"
  echo "problem (the benchmark checks that the results agree); hybrid 50% mixed uses"
  echo "a random mask with about half the DOFs prescribed. In the flexible chain the"
  echo "modal DOFs are always regular: there 'all-prescribed' prescribes the hinges"
  echo "only, a harder problem than RNEA's, and CRBA is the composite-body algorithm with augmented bodies"
  echo "(it was nv Newton-Euler columns before 2026-11-24: 226 us, 21x ABA, in the run of 2026-11-23)."
} > "$results"
echo "wrote $results"

"$build/bench/bench_skips" "$repetitions" | tee "$skips_table"
{
  echo "# What each skip saves"
  echo
  header
  cat "$skips_table"
  echo
  echo "Each row solves one problem two ways, with the skip and without it, timed batch"
  echo "by batch in turn; the benchmark checks that both give the same accelerations and"
  echo "forces (except the gravity row, two different problems). 'Without' runs what the"
  echo "library would run if it did not know better: every joint through the general"
  echo "joint code, body frames instead of tree frames, the flexible-body code on a rigid"
  echo "model, an articulated inertia for every body, joint wrenches computed, the"
  echo "velocity terms of a model at rest. The last row is not a skip: it measures what a"
  echo "gravity-free special case could save, the reason there is none."
} > "$skips"
echo "wrote $skips"
