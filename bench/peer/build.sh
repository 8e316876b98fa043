#!/usr/bin/env bash
# Build bench/peer/pin_derivatives.cpp and pin_calls.cpp against the Pinocchio
# that ../shared/tools/peer_bench installs (run its build.sh first), with its flags.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
dir=${PEER_BENCH_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/peer_bench}
[ -f "$dir/prefix" ] || { echo "build ../shared/tools/peer_bench first" >&2; exit 2; }
pfx=$(cat "$dir/prefix")
for program in pin_derivatives pin_calls; do
  g++ -O3 -DNDEBUG -std=c++17 \
    -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS \
    -DBOOST_FUSION_INVOKE_MAX_ARITY=12 -DPINOCCHIO_WITH_URDFDOM -DPINOCCHIO_URDFDOM_HEADERS_MAJOR_VERSION=3 \
    -DPINOCCHIO_URDFDOM_HEADERS_MINOR_VERSION=0 -DPINOCCHIO_URDFDOM_HEADERS_PATCH_VERSION=0 \
    "$here/$program.cpp" -I"$pfx/include" -I"$pfx/include/eigen3" -L"$pfx/lib" \
    -lpinocchio_default -lpinocchio_parsers -lurdfdom_model -Wl,-rpath,"$pfx/lib" -o "$dir/$program"
  echo "built $dir/$program"
done
