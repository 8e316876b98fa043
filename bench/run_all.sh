#!/usr/bin/env bash
# Every benchmark in one command; writes bench/results/ (markdown tables and
# PNG plots). Run from the venv made by the README's test command (it has
# cmake, ninja, pin, dartpy and example-robot-data):
#   bash bench/run_all.sh            (about 10 minutes on 2 cores)
# Pinocchio's C++ timings come from ../shared/tools/peer_bench (built on first
# use). Timings are never asserted anywhere; compare ratios measured in the
# same run.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
cd "$repo"
bash bench/run_core.sh                                   # results/core.md (also configures build/bench)
cmake --build build/bench --target bench_work_precision bench_step_spread -j2
python bench/bench_work_precision.py build/bench/bench/bench_work_precision   # results/work_precision.*
python bench/bench_scaling.py                            # results/scaling.*
python bench/bench_robots.py                             # results/robots.md
python bench/bench_batch.py                              # results/batch.md
soadyn hil --scene cassini --rate 1000 --duration 10 --integrator rk4 --no-progress --spin-us 900 --fifo-priority 80 --lock-memory \
  --report bench/results/hil_cassini.json --plot bench/results/hil_cassini.png | tee bench/results/hil_cassini.txt
{
  echo "# Step-time spread at 1 kHz"
  echo
  echo "- Date: $(date -u '+%Y-%m-%d %H:%M UTC'); source: $(git describe --always --dirty 2>/dev/null || echo unknown)"
  echo "- Command: \`build/bench/bench/bench_step_spread 10000\` (from \`bash bench/run_all.sh\`)"
  echo
  build/bench/bench/bench_step_spread 10000
  echo
  echo "Each workload runs once per millisecond, busy-waiting between periods like"
  echo "\`soadyn hil --spin-us\`, in turns of 500 periods so that the machine's speed"
  echo "phases hit all three; 10000 periods each. The identical dynamics repeat the"
  echo "same four hybrid_dynamics calls on one cassini state: any spread they show"
  echo "is the machine's, not the data's. The arithmetic touches no memory."
} | tee bench/results/step_spread.md
echo "bench/results/ updated"
