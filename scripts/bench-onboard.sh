#!/usr/bin/env bash
# The on-board figures for docs/benchmarks.md, in one run on this machine:
#  1. the estimator's step time and allocations per step (Google Benchmark: constant parameters
#     and actor-scheduled, double and float), build/host/firmware/bench/lptn_estimator_benchmark;
#  2. replay and convert throughput in frames/s per log format (candump, Vector ASC, Vector BLF)
#     beside python-can's reader of the same file: scripts/bench-replay.sh, which says how.
#
#   scripts/bench-onboard.sh [WORK_DIR]     LPTN=path/to/lptn: that lptn, and no step benchmark
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh bench >/dev/null
if [[ -z ${LPTN:-} ]]; then
  cmake --preset host >/dev/null
  cmake --build --preset host -j"$(nproc)" --target lptn lptn_estimator_benchmark >/dev/null
  echo "== estimator step (Google Benchmark)"
  build/host/firmware/bench/lptn_estimator_benchmark --benchmark_min_time=2 2>/dev/null | grep -E "^(BM_|Benchmark)"
fi
lptn=${LPTN:-build/host/programs/cli/lptn}
work=${1:-build/host/bench-onboard}
mkdir -p "$work"

echo "== replay and convert throughput per log format, beside python-can's readers (scripts/bench-replay.sh)"
LPTN=$lptn WORK=$work/bench-replay scripts/bench-replay.sh
