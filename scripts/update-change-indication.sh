#!/usr/bin/env bash
# Regenerates the change-indication test's expected outputs (tests/change_indication/expected/)
# by running the test: it runs lptn replay (closed loop and --open-loop) and lptn calibrate
# --method lm over the committed inputs and, where a number differs from the committed one,
# writes its fresh output over it (the commands and what is kept of their outputs are the test's
# alone). Run it when a numerical change is intended, then commit the diff: the reviewer sees it.
#
#   scripts/update-change-indication.sh [--inputs] [BUILD_DIR]
#     BUILD_DIR  a configured build tree (default build/ci); its lptn and the test are built first
#     --inputs   first regenerate the committed inputs (log and fleet dump) with lptn generate and
#                lptn convert. Rarely wanted: new inputs make every expected number change at once.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
inputs=0
build=$root/build/ci
for arg in "$@"; do
  case $arg in
    --inputs) inputs=1 ;;
    -h | --help) sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "update-change-indication.sh: unknown option $arg (see --help)" >&2; exit 2 ;;
    *) build=$(cd "$arg" && pwd) ;;
  esac
done
[[ -f $build/CMakeCache.txt ]] || { echo "update-change-indication.sh: $build is not a configured build tree (cmake --preset ci)" >&2; exit 2; }
cmake --build "$build" --target lptn lptn_change_indication_tests >/dev/null
lptn=$build/programs/cli/lptn
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

# The test writes every expected file that differs; it fails then, which is why it runs here.
"$build/tests/change_indication/lptn_change_indication_tests" --gtest_filter='ChangeIndication.*' >"$work/test.log" 2>&1 ||
  grep -E "mismatch|missing" "$work/test.log" || true
# The written files must now pass: anything else is a failure of the commands themselves.
"$build/tests/change_indication/lptn_change_indication_tests" --gtest_filter='ChangeIndication.*' >"$work/test.log" 2>&1 || {
  cat "$work/test.log" >&2
  echo "update-change-indication.sh: the test still fails on the outputs it wrote" >&2
  exit 1
}
(cd "$root" && git status --short -- tests/change_indication) || true
echo "expected outputs rewritten in tests/change_indication/expected/; review the diff (git diff --stat) and commit it"
