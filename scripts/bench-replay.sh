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
#     core, best of RUNS, against python-can reading the nine files one after the other (one run:
#     it takes 2-4 s a format).
# Wall and CPU seconds of each, lptn's and python-can's runs interleaved; frames/s per CPU second
# (one core's rate: on a machine where other work runs, the wall time says more about the other
# work) and lptn's as a multiple of python-can's.
# The directory rows' gain from more threads is in their wall time, on a machine otherwise idle.
#
#   scripts/bench-replay.sh                            builds lptn (host preset), work in build/bench-replay
#   LPTN=build/ci/programs/cli/lptn scripts/bench-replay.sh   an lptn already built
#   RUNS=5 ...                                       best of 5 (default 3)
#   BEFORE=path/to/old/lptn ...                      rows "BEFORE" of that lptn on the same log and
#                                                    directory (one thread), its runs interleaved too
#                                                    (and its CSVs compared)
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ -n ${LPTN:-} ]]; then
  lptn=$(realpath "$LPTN")
else
  cmake --preset host >/dev/null
  cmake --build --preset host -j"$(nproc)" --target lptn >/dev/null
  lptn=$PWD/build/host/programs/cli/lptn
fi
runs=${RUNS:-3}
before=${BEFORE:+$(realpath "$BEFORE")}  # another lptn (an earlier build) measured beside it, one log
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

# One comparison, its runs interleaved so that other work on the machine weighs on each alike:
#   measure READER FILE... -- COMMAND... [-- COMMAND...]
# RUNS times: each COMMAND (a process, its output thrown away), then python-can's READER over
# the FILEs (the loop alone, in this process: no interpreter start, no import; in the first
# READER_RUNS runs only, default all). Prints the frames python-can read and its "WALL CPU", then
# "WALL CPU" of each COMMAND: the best of the runs for each. CPU is user + system time (a
# command's process and its threads, from os.wait4), which other work beside it changes far less
# than the wall time.
measure() {
  /usr/bin/python3 - "$runs" "${reader_runs:-$runs}" "$@" <<'PY'
import os, subprocess, sys, time
import can
args = sys.argv[3:]
runs, reader_runs, reader = int(sys.argv[1]), int(sys.argv[2]), getattr(can, args[0])
parts, cur = [], []
for a in args[1:]:
    if a == "--":
        parts.append(cur)
        cur = []
    else:
        cur.append(a)
parts.append(cur)
files, commands = parts[0], parts[1:]
best = [[None, None] for _ in range(len(commands) + 1)]
def keep(i, w, c):
    b = best[i]
    b[0] = w if b[0] is None else min(b[0], w)
    b[1] = c if b[1] is None else min(b[1], c)
frames = 0
for run in range(runs):
    for i, cmd in enumerate(commands):
        start = time.perf_counter()
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _, status, usage = os.wait4(p.pid, 0)
        if status != 0:
            sys.exit("bench-replay: failed: " + " ".join(cmd))
        keep(i + 1, time.perf_counter() - start, usage.ru_utime + usage.ru_stime)
    if run >= reader_runs:
        continue
    w0, c0 = time.perf_counter(), time.process_time()
    frames = 0
    for path in files:
        for _ in reader(path):
            frames += 1
    keep(0, time.perf_counter() - w0, time.process_time() - c0)
print(frames, *(f"{w} {c}" for w, c in best))
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
  before_cmds=()
  [[ -z $before ]] || before_cmds=(-- "$before" replay --quiet --log "$log" --calibration "$work/calibration.json" \
    --out "$work/one-before.csv" --force -- "$before" convert --in "$log" --out "$work/one-converted-before.csv" --force)
  read -r py_frames py_wall py_cpu replay_wall replay_cpu convert_wall convert_cpu b_replay_wall b_replay_cpu \
    b_convert_wall b_convert_cpu < <(measure "${reader[$format]}" "$log" \
    -- "$lptn" replay --quiet --log "$log" --calibration "$work/calibration.json" --out "$work/one.csv" --force \
    -- "$lptn" convert --in "$log" --out "$work/one-converted.csv" --force "${before_cmds[@]}")
  ((py_frames == frames)) || echo "bench-replay: python-can read $py_frames frames of $log, lptn $frames" >&2
  row "$format" "replay $one" "$frames" "$replay_wall" "$replay_cpu" "$py_wall" "$py_cpu"
  [[ -z $before ]] || row "$format" "replay $one, BEFORE" "$frames" "$b_replay_wall" "$b_replay_cpu" "$py_wall" "$py_cpu"
  [[ -z $before ]] || cmp -s "$work/one.csv" "$work/one-before.csv" || echo "bench-replay: $log: the CSVs differ" >&2
  row "$format" "convert $one to CSV" "$frames" "$convert_wall" "$convert_cpu" "$py_wall" "$py_cpu"
  [[ -z $before ]] || row "$format" "convert $one to CSV, BEFORE" "$frames" "$b_convert_wall" "$b_convert_cpu" "$py_wall" "$py_cpu"
  ((directories)) || continue

  all_frames=$(frames_of "$work"/logs-candump/*.log)
  before_cmds=()
  [[ -z $before ]] || ! "$before" replay --help | grep -q -- --threads || before_cmds=(-- "$before" replay --quiet \
    --log "$dir" --threads 1 --calibration "$work/calibration.json" --out "$work/out-before-$format" --force)
  read -r py_frames py_wall py_cpu one_wall one_cpu all_wall all_cpu b_one_wall b_one_cpu < <(reader_runs=1 measure \
    "${reader[$format]}" "$dir"/* \
    -- "$lptn" replay --quiet --log "$dir" --threads 1 --calibration "$work/calibration.json" --out "$work/out-$format" --force \
    -- "$lptn" replay --quiet --log "$dir" --threads "$threads" --calibration "$work/calibration.json" --out "$work/out-$format" \
    --force "${before_cmds[@]}")
  ((py_frames == all_frames)) || echo "bench-replay: python-can read $py_frames frames of $dir, lptn $all_frames" >&2
  row "$format" "replay 9 logs, 1 thread" "$all_frames" "$one_wall" "$one_cpu" "$py_wall" "$py_cpu"
  ((${#before_cmds[@]} == 0)) || row "$format" "replay 9 logs, 1 thread, BEFORE" "$all_frames" "$b_one_wall" "$b_one_cpu" "$py_wall" "$py_cpu"
  ((${#before_cmds[@]} == 0)) || diff -rq "$work/out-$format" "$work/out-before-$format" >/dev/null ||
    echo "bench-replay: $dir: the CSVs differ" >&2
  row "$format" "replay 9 logs, $threads threads" "$all_frames" "$all_wall" "$all_cpu" "$py_wall" "$py_cpu"
done
