#!/usr/bin/env bash
# The calibration benchmark (README "Calibration"): Levenberg-Marquardt and the TD3 formulations on
# the same nine generated cycles, six train and three test, every TD3 formulation over seeds.
# Each run's calibration.json stays in OUT_DIR and a run whose output exists is not repeated, so
# the benchmark resumes where it stopped; tools/bench-calibration-summary.py prints the table.
#   tools/bench-calibration.sh [OUT_DIR]
#     METHODS  (default "lm td3 td3-paper td3-episode")   SEEDS (default "1 2 3 4 5")
#     LPTN: an lptn already built (default: build the host preset's)
#     TD3_PAPER_EPISODES / TD3_EPISODE_EPISODES: budgets of the paper's formulations (default 200 / 1000)
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ -z ${LPTN:-} ]]; then  # LPTN=path/to/lptn uses a binary already built
  cmake --preset host >/dev/null
  cmake --build --preset host --target lptn >/dev/null
fi
lptn=$(realpath "${LPTN:-build/host/tools/cli/lptn}")
out=$(realpath -m "${1:-bench-out}")
methods=${METHODS:-lm td3 td3-paper td3-episode}
seeds=${SEEDS:-1 2 3 4 5}
mkdir -p "$out"
[[ -f $out/fleet/motor.toml ]] || "$lptn" generate --out "$out/fleet" --cycles 9 --seed 1 --force >/dev/null

for method in $methods; do
  extra=()
  [[ $method == td3-paper ]] && extra=(--episodes "${TD3_PAPER_EPISODES:-200}")
  [[ $method == td3-episode ]] && extra=(--episodes "${TD3_EPISODE_EPISODES:-1000}")
  for seed in $([[ $method == lm ]] && echo 1 || echo "$seeds"); do
    run=$out/$method-$seed
    [[ -f $run.json ]] && continue
    start=$(date +%s.%N)
    "$lptn" calibrate --data "$out/fleet" --motor "$out/fleet/motor.toml" --method "$method" --seed "$seed" \
      --out "$run.json" --checkpoint-dir "$run.checkpoints" --force --quiet "${extra[@]}" > "$run.txt"
    end=$(date +%s.%N)
    awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f\n", b - a }' > "$run.wall"
    echo "$method seed $seed: $(cat "$run.wall") s"
  done
done
python3 tools/bench-calibration-summary.py "$out"
