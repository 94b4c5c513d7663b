#!/usr/bin/env bash
# Scale: fleet dumps of 50 and 200 hours of 10 Hz cycles (generated), each loaded (lptn inspect),
# calibrated (LM) and diagnosed, with wall time, CPU time and peak memory of each step (GNU time).
# Time should grow linearly with the hours, memory only by the resampled signals themselves
# (10 channels of 4-byte floats per 0.1 s step: 14.4 MB per hour), and CPU time should be about
# twice the wall time (work split over cycles on both cores).
#
#   scripts/bench-scale.sh [HOURS...]    default: 50 200; work in build/bench-scale (about 1 GB per 100 h);
#                                      then a fleet of FLEET_MOTORS (default 20) motors, 3 cycles each
#                                      (FLEET_MOTORS=0: no fleet)
#   scripts/bench-scale.sh fleet         the fleet alone
#   scripts/bench-scale.sh mpi [HOURS]   the calibration of HOURS (default 200) alone and under
#                                      `mpirun -np 2` (Open MPI; lptn built with LPTN_WITH_MPI)
#   LPTN=build/ci/programs/cli/lptn scripts/bench-scale.sh   an lptn already built (the ci preset has
#                                                       the host preset's Release flags)
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ -n ${LPTN:-} ]]; then
  lptn=$(realpath "$LPTN")
else
  scripts/setup.sh >/dev/null
  cmake --preset host >/dev/null
  cmake --build --preset host -j"$(nproc)" --target lptn >/dev/null
  lptn=$PWD/build/host/programs/cli/lptn
fi
work=build/bench-scale
mkdir -p "$work"
(($# > 0)) || set -- 50 200
mpi=0
ratios=()
if [[ $1 == fleet ]]; then set --; fi  # the fleet's row alone
if [[ $1 == mpi ]]; then mpi=1; set -- "${2:-200}"; fi

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
  last_wall=$(awk '{ print $1 }' "$work/time.txt")
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
  if ((mpi)); then
    # One calibration alone, then over 2 processes (each simulating its own files on one core); the
    # peak RSS is the largest process's. As root Open MPI wants to be told.
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
    measure calibrate "$hours" "$lptn" calibrate --data "$fleet" --motor "$fleet/motor.toml" --method lm --seed 1 \
      --out "$work/calibration-$hours.json" --force
    measure calibrate-np2 "$hours" mpirun -np 2 "$lptn" calibrate --data "$fleet" --motor "$fleet/motor.toml" \
      --method lm --seed 1 --out "$work/calibration-$hours-np2.json" --force
    python3 -c 'import json, sys
for f in sys.argv[1:]:
    d = json.load(open(f))["method"]["details"]
    print("%s: %d ranks, %d iterations, %d evaluations, %d doubles joined each, %.3f s joining, %.3f s linear solver"
          % (f, d["mpi_ranks"], d["iterations"], d["evaluations"], d["joined_doubles"], d["join_seconds"],
             d["linear_solver_seconds"]))' "$work/calibration-$hours.json" "$work/calibration-$hours-np2.json"
    exit 0
  fi
  measure load "$hours" "$lptn" inspect --data "$fleet"
  measure calibrate "$hours" "$lptn" calibrate --data "$fleet" --motor "$fleet/motor.toml" --method lm --seed 1 \
    --out "$work/calibration-$hours.json" --force
  calibrate_wall=$last_wall
  measure diagnose "$hours" "$lptn" diagnose --data "$fleet" --calibration "$work/calibration-$hours.json" --quiet
  ratios+=("$(awk -v h="$hours" -v d="$last_wall" -v c="$calibrate_wall" \
    'BEGIN { printf "%s h: diagnose %.1f s = %.1fx the LM calibration of the same data (%.1f s)", h, d, d / c, c }')")
done
# Issue 28's measure: diagnose's wall time as a multiple of the calibration's, in the same run.
for r in "${ratios[@]}"; do echo "$r"; done
# A fleet of FLEET_MOTORS (default 20) motors, 3 cycles each (one motor weak): the type over all of them, each
# motor's cooling factor, the outliers (lptn calibrate --fleet). Its hours are counted from truth.json.
: "${FLEET_MOTORS:=20}"
[[ $FLEET_MOTORS != 0 ]] || exit 0  # any other value goes to generate --motors, which checks it
motors="$work/motors-$FLEET_MOTORS"
if [ ! -f "$motors/truth.json" ]; then
  "$lptn" generate --fleet --motors "$FLEET_MOTORS" --cycles 3 --seed 7 --minutes-min 60 --minutes-max 90 --out "$motors" \
    --force > "$work/generate-motors-$FLEET_MOTORS.log" 2>&1
fi
fleet_hours=$(python3 -c 'import json, sys
t = json.load(open(sys.argv[1]))
print(round(sum(c["duration_s"] for m in t["motors"] for c in json.load(open(sys.argv[2] + "/" + m + "/truth.json"))["cycles"]) / 3600))' \
  "$motors/truth.json" "$motors")
measure fleet "$fleet_hours" "$lptn" calibrate --fleet "$motors" --motor "$motors/motor.toml" --method lm --seed 1 \
  --out "$work/fleet-$FLEET_MOTORS.json" --force
echo "signals in memory: 14.4 MB per hour of data (10 channels, float, 10 Hz); lptn's own baseline: about 80 MB (libtorch is lptn-td3's alone)"
