#!/usr/bin/env bash
# The calibration benchmark: Levenberg-Marquardt, TD3 (the paper's per-step formulation) and TD3
# (one action per episode) on the same nine generated cycles, six train and three test; prints
# each method's wall time and test RMSE as a Markdown table (the one in README.md).
#   tools/bench-calibration.sh [OUT_DIR]     TD3_EPISODES / TD3E_EPISODES set the TD3 budgets
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --preset host >/dev/null
cmake --build --preset host --target lptn >/dev/null
lptn=build/host/tools/cli/lptn
out=${1:-bench-out}
td3_episodes=${TD3_EPISODES:-200}
td3e_episodes=${TD3E_EPISODES:-1000}
mkdir -p "$out"
"$lptn" generate --out "$out/fleet" --cycles 9 --seed 1 --force >/dev/null

rows=()
for method in lm td3 td3-episode; do
  extra=()
  [[ $method == td3 ]] && extra=(--episodes "$td3_episodes")
  [[ $method == td3-episode ]] && extra=(--episodes "$td3e_episodes")
  start=$(date +%s.%N)
  "$lptn" calibrate --data "$out/fleet" --motor "$out/fleet/motor.toml" --method "$method" --seed 1 \
    --out "$out/$method.json" --checkpoint-dir "$out/$method.checkpoints" --force "${extra[@]}" | tee "$out/$method.txt"
  end=$(date +%s.%N)
  # "test   stator rmse 0.352 K  max ... | rotor rmse 0.415 K ..."
  stator=$(awk '/^test /{print $4}' "$out/$method.txt")
  rotor=$(awk '/^test /{for (i = 1; i <= NF; ++i) if ($i == "rotor") print $(i + 2)}' "$out/$method.txt")
  budget=${extra[1]:-}
  rows+=("| $method | ${budget:+$budget episodes} | $(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.0f", b - a }') s | $stator K | $rotor K |")
done
echo
echo "| method | budget | wall time | test RMSE stator | test RMSE rotor |"
echo "|---|---|---|---|---|"
printf '%s\n' "${rows[@]}"
