#!/usr/bin/env bash
# Replay and convert throughput per CAN log format, beside python-can's reader of the same file.
# The demo's nine cycles (seed 1, 11.3 h of driving, 1,340,487 frames) as candump, Vector ASC and
# Vector BLF logs (`lptn convert`), calibrated as the demo does (LM, seed 1). For each format:
#   - one log, the demo's cycle_09_hilly (173,420 frames, 1.46 h): `lptn replay` (parse, estimate,
#     write the CSV; one thread) and `lptn convert` log -> CSV, each the whole process (start-up,
#     calibration, the nameplate check included), best of RUNS; python-can's reader (Debian's
#     python3-can: can.CanutilsLogReader, can.ASCReader, can.BLFReader) iterating every message of
#     the same file, timed around the loop alone (no interpreter start, no import), best of RUNS;
#   - the nine logs as a directory: `lptn replay --log DIR` on one thread (--threads 1) and on every
#     core, against python-can reading the nine files one after the other (one run each).
# Wall and CPU seconds of each; frames/s per CPU second (one core's rate: on a machine where other
# work runs, the wall time says more about the other work) and lptn's as a multiple of python-can's.
# The directory rows' gain from more threads is in their wall time, on a machine otherwise idle.
#
#   tools/bench-replay.sh                            builds lptn (host preset), work in build/bench-replay
#   LPTN=build/ci/tools/cli/lptn tools/bench-replay.sh   an lptn already built
#   RUNS=5 ...                                       best of 5 (default 3)
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ -n ${LPTN:-} ]]; then
  lptn=$(realpath "$LPTN")
else
  cmake --preset host >/dev/null
  cmake --build --preset host -j"$(nproc)" --target lptn >/dev/null
  lptn=$PWD/build/host/tools/cli/lptn
fi
runs=${RUNS:-3}
work=${WORK:-build/bench-replay}
mkdir -p "$work"
one=cycle_09_hilly

if [[ ! -f $work/fleet/truth.json ]]; then
  "$lptn" generate --out "$work/fleet" --cycles 9 --seed 1 --force >/dev/null 2>&1
fi
if [[ ! -f $work/calibration.json ]]; then
  status=0
  "$lptn" calibrate --data "$work/fleet" --motor "$work/fleet/motor.toml" --method lm --seed 1 \
    --out "$work/calibration.json" --force >/dev/null 2>&1 || status=$?
  ((status == 0 || status == 3)) || { echo "bench-replay: calibration failed ($status)" >&2; exit 1; }
fi
declare -A ext=([candump]=log [asc]=asc [blf]=blf)
declare -A reader=([candump]=CanutilsLogReader [asc]=ASCReader [blf]=BLFReader)
for format in candump asc blf; do
  [[ -d $work/logs-$format ]] ||
    "$lptn" convert --in "$work/fleet" --out "$work/logs-$format" --format "$format" --force >/dev/null 2>&1
done

# "WALL CPU": seconds of a command (its output thrown away), the best of $runs for each; CPU is
# user + system time of the process and its threads (os.wait4's rusage), which another program
# running beside it changes far less than the wall time.
best_of() {
  /usr/bin/python3 - "$runs" "$@" <<'PY'
import os, subprocess, sys, time
runs, cmd = int(sys.argv[1]), sys.argv[2:]
wall = cpu = None
for _ in range(runs):
    start = time.perf_counter()
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(p.pid, 0)
    w = time.perf_counter() - start
    if status != 0:
        sys.exit("bench-replay: failed: " + " ".join(cmd))
    c = usage.ru_utime + usage.ru_stime
    wall = w if wall is None else min(wall, w)
    cpu = c if cpu is None else min(cpu, c)
print(wall, cpu)
PY
}

# python-can: "FRAMES WALL CPU" of reading the files (the loop alone), the best of $runs for each.
python_can() {
  /usr/bin/python3 - "$runs" "$@" <<'PY'
import sys, time
import can
runs, name, paths = int(sys.argv[1]), sys.argv[2], sys.argv[3:]
reader = getattr(can, name)
wall = cpu = None
for _ in range(runs):
    w0, c0 = time.perf_counter(), time.process_time()
    n = 0
    for path in paths:
        for _ in reader(path):
            n += 1
    w, c = time.perf_counter() - w0, time.process_time() - c0
    wall = w if wall is None else min(wall, w)
    cpu = c if cpu is None else min(cpu, c)
print(n, wall, cpu)
PY
}

frames_of() {  # frames in a candump log: its non-empty lines
  grep -c . "$@" | awk -F: '{n += $NF} END {print n}'
}

threads=$(nproc)
directories=0
"$lptn" replay --help | grep -q -- --threads && directories=1  # an lptn from before directories: one log only
printf '| format | what | frames | lptn wall | lptn CPU | lptn frames/s (CPU) | python-can wall | python-can CPU | python-can frames/s (CPU) | lptn / python-can (CPU) |\n'
printf '|---|---|---|---|---|---|---|---|---|---|\n'
row() {  # format what frames lptn_wall lptn_cpu python_wall python_cpu
  awk -v f="$1" -v w="$2" -v n="$3" -v a="$4" -v c="$5" -v b="$6" -v d="$7" 'BEGIN {
    printf "| %s | %s | %d | %.3f s | %.3f s | %.0f | %.3f s | %.3f s | %.0f | %.1fx |\n", f, w, n, a, c, n / c, b, d, n / d, d / c }'
}
for format in candump asc blf; do
  dir=$work/logs-$format
  log=$dir/$one.${ext[$format]}
  frames=$(frames_of "$work/logs-candump/$one.log")
  read -r py_frames py_wall py_cpu < <(python_can "${reader[$format]}" "$log")
  ((py_frames == frames)) || echo "bench-replay: python-can read $py_frames frames of $log, lptn $frames" >&2
  read -r wall cpu < <(best_of "$lptn" replay --quiet --log "$log" --calibration "$work/calibration.json" \
    --out "$work/one.csv" --force)
  row "$format" "replay $one" "$frames" "$wall" "$cpu" "$py_wall" "$py_cpu"
  read -r wall cpu < <(best_of "$lptn" convert --in "$log" --out "$work/one-converted.csv" --force)
  row "$format" "convert $one to CSV" "$frames" "$wall" "$cpu" "$py_wall" "$py_cpu"
  ((directories)) || continue

  all_frames=$(frames_of "$work"/logs-candump/*.log)
  read -r py_frames py_wall py_cpu < <(runs=1 python_can "${reader[$format]}" "$dir"/*)
  ((py_frames == all_frames)) || echo "bench-replay: python-can read $py_frames frames of $dir, lptn $all_frames" >&2
  for t in 1 "$threads"; do
    read -r wall cpu < <(runs=1 best_of "$lptn" replay --quiet --log "$dir" --threads "$t" \
      --calibration "$work/calibration.json" --out "$work/out-$format" --force)
    row "$format" "replay 9 logs, $t thread(s)" "$all_frames" "$wall" "$cpu" "$py_wall" "$py_cpu"
  done
done
