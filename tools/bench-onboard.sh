#!/usr/bin/env bash
# The on-board figures for README.md, in one run on this machine:
#  1. the estimator's step time and allocations per step (Google Benchmark: constant parameters
#     and actor-scheduled, double and float), build/host/firmware/bench/lptn_estimator_benchmark;
#  2. replay throughput in frames/s: `lptn replay` (log parsing + the estimator + CSV output) of
#     candump, Vector ASC and Vector BLF logs, against python-can's candump log reader (Debian's
#     python3-can, can.CanutilsLogReader) merely reading the same logs (Debian's /usr/bin/python3,
#     which has it): the demo's nine cycles (11 h of driving) as CAN logs.
#
#   tools/bench-onboard.sh [WORK_DIR]     LPTN=path/to/lptn: that lptn, and no step benchmark
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh bench >/dev/null
if [[ -z ${LPTN:-} ]]; then
  cmake --preset host >/dev/null
  cmake --build --preset host -j"$(nproc)" --target lptn lptn_estimator_benchmark >/dev/null
  echo "== estimator step (Google Benchmark)"
  build/host/firmware/bench/lptn_estimator_benchmark --benchmark_min_time=2 2>/dev/null | grep -E "^(BM_|Benchmark)"
fi
lptn=${LPTN:-build/host/tools/cli/lptn}
work=${1:-build/host/bench-onboard}
mkdir -p "$work"

echo "== replay throughput: the demo's nine cycles as CAN logs"
"$lptn" generate --out "$work/fleet" --cycles 9 --seed 1 --force >/dev/null 2>&1
"$lptn" calibrate --data "$work/fleet" --motor "$work/fleet/motor.toml" --method lm --seed 1 \
  --out "$work/calibration.json" --force >/dev/null 2>&1
# Seconds of `lptn replay` over every log in a directory (the replay's own wall time).
replay_seconds() {
  local total=0 line
  for log in "$1"/*; do
    line=$("$lptn" replay --quiet --log "$log" --calibration "$work/calibration.json" --out "$work/estimates.csv" --force |
           awk '/frames\/s/ {print $1}')
    total=$(awk -v a="$total" -v b="$line" 'BEGIN {print a + b}')
  done
  echo "$total"
}
declare -A seconds size
for format in candump asc blf; do
  "$lptn" convert --in "$work/fleet" --out "$work/logs-$format" --format "$format" --force >/dev/null 2>&1
  seconds[$format]=$(replay_seconds "$work/logs-$format")
  size[$format]=$(du -sh "$work/logs-$format" | awk '{print $1}')
done
frames=$(cat "$work"/logs-candump/*.log | grep -c .)
python_s=$(/usr/bin/python3 - "$work"/logs-candump/*.log <<'PY'
import sys, time
import can
start = time.perf_counter()
n = 0
for path in sys.argv[1:]:
    for _ in can.CanutilsLogReader(path):
        n += 1
print(time.perf_counter() - start)
PY
)
printf '   %d frames\n' "$frames"
for format in candump asc blf; do
  awk -v f="$frames" -v a="${seconds[$format]}" -v n="$format" -v d="${size[$format]}" 'BEGIN {
    printf "   lptn replay, %-8s (parse + estimate + CSV) %7.2f s  %10.0f frames/s  (%s on disk)\n", n, a, f / a, d }'
done
awk -v f="$frames" -v b="$python_s" 'BEGIN {
  printf "   python-can CanutilsLogReader (parse only)     %7.2f s  %10.0f frames/s\n", b, f / b }'
