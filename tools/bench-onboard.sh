#!/usr/bin/env bash
# The on-board figures for README.md, in one run on this machine:
#  1. the estimator's step time and allocations per step (Google Benchmark: constant parameters
#     and actor-scheduled, double and float), build/host/firmware/bench/lptn_estimator_benchmark;
#  2. replay throughput in frames/s: `lptn replay` (candump parsing + the estimator + CSV output)
#     against python-can's candump log reader (Debian's python3-can, can.CanutilsLogReader) merely
#     reading the same logs (Debian's /usr/bin/python3, which has it): the demo's nine cycles (11 h of driving) as CAN logs.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh bench >/dev/null
cmake --preset host >/dev/null
cmake --build --preset host -j"$(nproc)" --target lptn lptn_estimator_benchmark >/dev/null
lptn=build/host/tools/cli/lptn
work=${1:-build/host/bench-onboard}
mkdir -p "$work"

echo "== estimator step (Google Benchmark)"
build/host/firmware/bench/lptn_estimator_benchmark --benchmark_min_time=2 2>/dev/null | grep -E "^(BM_|Benchmark)"

echo "== replay throughput: the demo's nine cycles as CAN logs"
"$lptn" generate --out "$work/fleet" --cycles 9 --seed 1 --force >/dev/null 2>&1
"$lptn" convert --in "$work/fleet" --out "$work/logs" --force >/dev/null 2>&1
"$lptn" calibrate --data "$work/fleet" --motor "$work/fleet/motor.toml" --method lm --seed 1 \
  --out "$work/calibration.json" --force >/dev/null 2>&1
frames=0 lptn_s=0
for log in "$work"/logs/*.log; do
  line=$("$lptn" replay --quiet --log "$log" --calibration "$work/calibration.json" --out "$work/estimates.csv" --force |
         awk '/frames\/s/ {print $1}')
  n=$(grep -c . "$log")
  frames=$((frames + n))
  lptn_s=$(awk -v a="$lptn_s" -v b="$line" 'BEGIN {print a + b}')
done
python_s=$(/usr/bin/python3 - "$work"/logs/*.log <<'PY'
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
awk -v f="$frames" -v a="$lptn_s" -v b="$python_s" 'BEGIN {
  printf "   %d frames\n", f
  printf "   lptn replay (parse + estimate + CSV)       %7.2f s  %10.0f frames/s\n", a, f / a
  printf "   python-can CanutilsLogReader (parse only)   %7.2f s  %10.0f frames/s\n", b, f / b
}'
du -sh "$work/logs" | awk '{print "   logs on disk: " $1}'
