#!/usr/bin/env bash
# Regenerates the change-indication test's expected outputs (tests/change_indication/expected/)
# by running, over the committed inputs, exactly what tests/change_indication runs fresh:
#   lptn replay (closed loop and --open-loop) of input/cycle.log with the committed default
#   calibration, every 10th tick kept; lptn calibrate --method lm on input/fleet, its
#   deterministic part kept (parameters, correlations, split, iterations, final cost, initial
#   offsets, metrics: no timestamps, wall times, paths or hashes).
# Run it when a numerical change is intended, then commit the diff: the reviewer sees it there.
#
#   tools/update-change-indication.sh [--inputs] [LPTN]
#     LPTN      the lptn binary (default build/ci/tools/cli/lptn); build it first
#     --inputs  also regenerate the committed inputs (log and fleet dump) with lptn generate and
#               lptn convert. Rarely wanted: new inputs make every expected number change at once.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
inputs=0
lptn=$root/build/ci/tools/cli/lptn
for arg in "$@"; do
  case $arg in
    --inputs) inputs=1 ;;
    -h | --help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "update-change-indication.sh: unknown option $arg (see --help)" >&2; exit 2 ;;
    *) lptn=$arg ;;
  esac
done
[[ -x $lptn ]] || { echo "update-change-indication.sh: $lptn is not an executable (build: cmake --build --preset ci --target lptn)" >&2; exit 2; }
here=$root/tests/change_indication
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

if ((inputs)); then
  # One cycle of 5 minutes as the CAN log a converter would have sent, at its full rates.
  "$lptn" generate --out "$work/log-source" --cycles 1 --seed 21 --minutes-min 5 --minutes-max 5 >/dev/null
  "$lptn" convert --in "$work/log-source"/cycle_*.csv --out "$work/cycle.log" >/dev/null
  # Three cycles of 10-12 minutes and their motor file for LM; with --seed 1, two train, one test.
  # Shorter cycles do not pin the conductances down (seeds 22-26 at 2-5 minutes: LM stopped at its
  # 60 iterations with parameters on their bounds; a result that depends on the path, not a
  # minimum). Seed 61 converges in 4 iterations, nothing on a bound, no pair correlated past 0.95.
  "$lptn" generate --out "$work/fleet-source" --cycles 3 --seed 61 --minutes-min 10 --minutes-max 12 >/dev/null
  rm -rf "$here/input/fleet"
  mkdir -p "$here/input/fleet"
  # Thinned to keep the committed files small: every row with a slow channel (airflow, ambient,
  # stator, rotor: 1 Hz and 0.2 Hz, their samples untouched) and the 10 Hz electrical rows at most
  # 1 s apart (they fall on the 1 Hz rows too: 2 Hz in all). A fleet dump within the contract
  # (rows need not be evenly spaced; 1 s is within the 2 s the loader bridges) and a fifth of the size.
  for csv in "$work/fleet-source"/cycle_*.csv; do
    awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; print; next }
      { slow = 0
        if ($(col["airflow_m3s"]) != "" || $(col["ambient_c"]) != "" || $(col["stator_winding_c"]) != "" || $(col["rotor_c"]) != "") slow = 1
        t = $(col["time_s"]) + 0
        if (slow || NR == 2 || t >= last + 1.0) { print; last = t } }' "$csv" >"$here/input/fleet/$(basename "$csv")"
  done
  cp "$work/fleet-source/motor.toml" "$here/input/fleet/"
  mv "$work/cycle.log" "$here/input/cycle.log"
fi

# Every 10th tick (1 s apart) and the header; the test decimates its fresh CSV the same way.
decimate() { awk 'NR == 1 || (NR - 2) % 10 == 0' "$1"; }

cal=$root/firmware/calibration/default_calibration.json
"$lptn" replay --quiet --log "$here/input/cycle.log" --calibration "$cal" --out "$work/closed.csv"
"$lptn" replay --quiet --open-loop --log "$here/input/cycle.log" --calibration "$cal" --out "$work/open.csv"
decimate "$work/closed.csv" >"$work/replay_closed_loop.csv"
decimate "$work/open.csv" >"$work/replay_open_loop.csv"

"$lptn" calibrate --quiet --method lm --seed 1 --data "$here/input/fleet" --motor "$here/input/fleet/motor.toml" \
  --out "$work/calibration.json"
# The same selection as deterministic_part() in the test. Python's json writes every double in its
# shortest round-trip form, so nothing is lost and nothing is invented.
python3 - "$work/calibration.json" "$work/calibration_lm.json" <<'PY'
import json, sys
cal = json.load(open(sys.argv[1]))
d = cal["method"]["details"]
out = {
    "parameters": [{k: p[k] for k in ("name", "unit", "calibrated", "value", "std_error")} for p in cal["parameters"]],
    "correlated": cal["correlated"],
    "split": cal["data"]["split"],
    "method": {"name": cal["method"]["name"], **{k: d[k] for k in ("iterations", "converged", "final_cost_k2", "initial_offsets")}},
    "metrics": cal["metrics"],
}
with open(sys.argv[2], "w") as f:
    json.dump(out, f, indent=1)
    f.write("\n")
PY

mkdir -p "$here/expected"
for f in replay_closed_loop.csv replay_open_loop.csv calibration_lm.json; do
  mv "$work/$f" "$here/expected/$f"
done
(cd "$root" && git status --short -- tests/change_indication) || true
echo "expected outputs rewritten in tests/change_indication/expected/; review the diff (git diff --stat) and commit it"
