#!/usr/bin/env bash
# README.md quotes what the demo prints; this holds it to that. It runs scripts/demo.sh itself (the
# same commands and seeds, so they stand in one place) with the lptn under test and without TD3's
# step (80 s), then builds each figure README quotes from the demo's output, formatted as README
# writes it, and fails with one line per figure README no longer matches.
#   check_readme_figures.sh LPTN README.md WORK_DIR
set -euo pipefail
lptn=$(realpath "$1") readme=$2 work=$3
demo=$(dirname "$(realpath "$0")")/../../scripts/demo.sh
rm -rf "$work"
mkdir -p "$work"
log=$work/demo.txt
LPTN=$lptn TD3_ROUNDS=0 "$demo" "$work/demo-out" >"$log" 2>&1 || { echo "scripts/demo.sh failed, see $log"; tail -n 20 "$log"; exit 1; }

failures=0
# quote WHAT TEXT: README.md must contain TEXT, made from the demo's output; TEXT empty means the
# demo no longer printed the line it is made from.
quote() {
  local what=$1 text=$2
  if [[ -z $text ]]; then
    echo "README.md: $what: the demo no longer prints the line this figure comes from (see $log)"
    failures=$((failures + 1))
  elif ! grep -qF -- "$text" "$readme"; then
    echo "README.md: $what: the demo now prints '$text', which README.md does not say (see $log)"
    failures=$((failures + 1))
  fi
}
# The first line of the log after the line matching START that matches PATTERN.
after() { awk -v start="$1" -v pat="$2" '$0 ~ start {on = 1} on && $0 ~ pat {print; exit}' "$log"; }

line=$(after "^== 3\\. simulate" "^all cycles")
quote "the motor file's guess against the sensors" "$([[ -n $line ]] && awk '{printf "%.1f K RMSE", $3}' <<<"$line")"
line=$(after "^== 4\\. calibrate" "^test ")
quote "LM on the test cycles" "$([[ -n $line ]] && sed -E 's/.*stator rmse ([0-9.]+) K.*rotor rmse ([0-9.]+) K.*/\1 \2/' <<<"$line" |
  awk '{printf "%.2f K stator and %.2f K rotor", $1, $2}')"
line=$(after "^== 7\\. on board" "stator winding estimate vs its sensor")
quote "replay, the stator" "$([[ -n $line ]] && awk '{printf "%.2f K RMS from its sensor", $(NF - 1)}' <<<"$line")"
line=$(after "^== 7\\. on board" "rotor winding estimate vs rotor telemetry")
quote "replay, the rotor" "$([[ -n $line ]] && awk '{printf "%.2f K RMS from the rotor telemetry", $(NF - 1)}' <<<"$line")"
line=$(after "^-- 8b\\. diagnose" "^  stator:")
quote "the loop's paper model" "$([[ -n $line ]] && sed -E 's/.*= ([0-9.]+)x its noise.*/the stator \1× its sensor'"'"'s noise/' <<<"$line")"
line=$(after "^-- 8b\\. diagnose" "^best:")
quote "the discovered term" "$([[ -n $line ]] && grep -oE 'k = [0-9.]+, [0-9.]+ k?W at the rated point' <<<"$line")"
quote "the held-out error after adding it" \
  "$([[ -n $line ]] && sed -nE 's/.*held-out ([0-9.]+) -> ([0-9.]+) K.*/from \1 to \2 K on the held-out/p' <<<"$line")"
line=$(after "^== 9\\. a fleet" "OUTLIER:")
quote "the fleet's outlier" "$([[ -n $line ]] && grep -oE "cools [0-9]+ % worse than the fleet's median" <<<"$line")"
line=$(after "^== 10\\. on board" "^motor_01: cooling factor")
quote "the weak motor's on-board cooling factor" \
  "$([[ -n $line ]] && sed -nE 's/.*at the end ([0-9.]+) \+- ([0-9.]+).*/(\1 ± \2)/p' <<<"$line")"

((failures == 0)) || exit 1
echo "every figure README.md quotes from the demo is what the demo printed ($log)"
