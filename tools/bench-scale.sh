#!/usr/bin/env bash
# Scale: fleet dumps of 50 and 200 hours of 10 Hz cycles (generated), each loaded (lptn inspect),
# calibrated (LM) and diagnosed, with wall time, CPU time and peak memory of each step (GNU time).
# Time should grow linearly with the hours, memory only by the resampled signals themselves
# (10 channels of 4-byte floats per 0.1 s step: 14.4 MB per hour), and CPU time should be about
# twice the wall time (work split over cycles on both cores).
#
#   tools/bench-scale.sh [HOURS...]    default: 50 200; work in build/bench-scale (about 1 GB per 100 h)
#   LPTN=build/ci/tools/cli/lptn tools/bench-scale.sh   an lptn already built (the ci preset has
#                                                       the host preset's Release flags)
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ -n ${LPTN:-} ]]; then
  lptn=$(realpath "$LPTN")
else
  tools/setup.sh >/dev/null
  cmake --preset host >/dev/null
  cmake --build --preset host -j"$(nproc)" --target lptn >/dev/null
  lptn=$PWD/build/host/tools/cli/lptn
fi
work=build/bench-scale
mkdir -p "$work"
(($# > 0)) || set -- 50 200

# Runs a step under GNU time; prints one table row: step, hours, wall s, CPU s, peak RSS MB.
measure() {
  local step=$1 hours=$2
  shift 2
  /usr/bin/time -f "%e %U %S %M" -o "$work/time.txt" "$@" > "$work/$step-$hours.log" 2>&1 || {
    echo "bench-scale: $step on $hours h failed, see $work/$step-$hours.log" >&2
    exit 1
  }
  awk -v step="$step" -v hours="$hours" '{
    printf "| %-9s | %5s h | %8.1f s | %8.1f s | %7.0f MB | %6.1f h/min |\n", step, hours, $1, $2 + $3, $4 / 1024, hours * 60 / $1
  }' "$work/time.txt"
}

echo "| step      | data    | wall       | CPU        | peak RSS   | data/time   |"
echo "|---|---|---|---|---|---|"
for hours in "$@"; do
  fleet="$work/fleet-$hours"
  # 75 minutes on average per cycle.
  if [ ! -f "$fleet/truth.json" ]; then
    "$lptn" generate --out "$fleet" --cycles $((hours * 60 / 75)) --seed 7 --minutes-min 60 --minutes-max 90 \
      --force > "$work/generate-$hours.log" 2>&1
  fi
  measure load "$hours" "$lptn" inspect --data "$fleet"
  measure calibrate "$hours" "$lptn" calibrate --data "$fleet" --motor "$fleet/motor.toml" --method lm --seed 1 \
    --out "$work/calibration-$hours.json" --force
  measure diagnose "$hours" "$lptn" diagnose --data "$fleet" --calibration "$work/calibration-$hours.json" --quiet
done
echo "signals in memory: 14.4 MB per hour of data (10 channels, float, 10 Hz); lptn's own baseline: about 80 MB (libtorch is lptn-td3's alone)"
