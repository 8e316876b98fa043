#!/usr/bin/env bash
# Every benchmark that needs no earlier build and no valgrind, one after the
# other, then bench/results/SUMMARY.md. Run from the venv made by the README's
# test command (it has cmake, ninja, pin, dartpy and example-robot-data):
#   bash bench/run_all.sh            (about 15 minutes on 2 cores)
# Pinocchio's C++ timings come from ../shared/tools/peer_bench (built on first
# use, bench/peers.py). The protocol, and the benchmarks run by hand:
# bench/README.md.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
cd "$repo"
bash bench/run_core.sh                                   # core.json, skips.json (also configures build/bench)
cmake --build build/bench --target bench_work_precision bench_step_spread bench_events -j2
python bench/bench_work_precision.py build/bench/bench/bench_work_precision   # work_precision.json, .png
python bench/run_cpp_bench.py step_spread build/bench/bench/bench_step_spread 10000
python bench/run_cpp_bench.py events build/bench/bench/bench_events 20000
python bench/bench_scaling.py                            # scaling.json, .png
python bench/bench_robots.py                             # robots.json
python bench/bench_derivatives.py                        # derivatives.json
python bench/bench_loops.py                              # loops.json
python bench/bench_batch.py                              # batch.json
python bench/bench_sensitivity.py                        # sensitivity.json
python bench/bench_python_calls.py                       # python_calls.json
python bench/bench_hil.py                                # hil_cassini.json, .png
python bench/summary.py                                  # SUMMARY.md
