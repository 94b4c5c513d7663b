#!/usr/bin/env bash
# The calibration benchmark (docs/benchmarks.md): Levenberg-Marquardt and the TD3 formulations on
# the same nine generated cycles, six train and three test, every TD3 formulation over seeds.
# Each run's calibration.json stays in OUT_DIR and a run whose output exists is not repeated, so
# the benchmark resumes where it stopped; scripts/bench-calibration-summary.py prints the table.
#   scripts/bench-calibration.sh [OUT_DIR]              every method over SEEDS, then the table
#   scripts/bench-calibration.sh scheduled [OUT_DIR]    the paper's actor scheduling on data whose physics
#       depends on the operating point (hidden rotor_speed_convection and windage): scheduled, its
#       constant set and LM, on the test cycles
#   scripts/bench-calibration.sh discovered [OUT_DIR]   the retrain after the loop: the demo's second fleet (an
#       eddy-current loss no library effect describes), its model carrying the term diagnose discovers
#       there (heat_stator_winding_i2f: more parameters, the same TD3 budget); LM and td3 over SEEDS
#   scripts/bench-calibration.sh transfer [OUT_DIR]     a retrain on a second dump of the motor type, its
#       conductances shifted by +-15 %: td3 from scratch and --warm-start from the first dump's td3-N
#       agent; the time until the best set's test RMSE is within 1.1x LM's
#     METHODS  (default "lm td3 td3-paper td3-episode random-search cma-es")   SEEDS (default "1 2 3 4 5")
#     LPTN: an lptn already built (default: build the host preset's)
#     TD3_PAPER_EPISODES / TD3_EPISODE_EPISODES: budgets of the paper's formulations (default 100 / 500,
#       about 5 and 4 minutes a seed here); SCHEDULED_EPISODES: td3-paper's in the scheduled mode (200)
set -euo pipefail
cd "$(dirname "$0")/.."
mode=all
[[ ${1:-} == scheduled || ${1:-} == transfer || ${1:-} == discovered ]] && { mode=$1; shift; }
if [[ -z ${LPTN:-} ]]; then  # LPTN=path/to/lptn uses a binary already built
  cmake --preset host >/dev/null
  cmake --build --preset host --target lptn >/dev/null
fi
lptn=$(realpath "${LPTN:-build/host/programs/cli/lptn}")
out=$(realpath -m "${1:-bench-out}")
methods=${METHODS:-lm td3 td3-paper td3-episode random-search cma-es}
seeds=${SEEDS:-1 2 3 4 5}
mkdir -p "$out"
[[ -f $out/fleet/motor.toml ]] || "$lptn" generate --out "$out/fleet" --cycles 9 --seed 1 --force >/dev/null

# One calibration into $dir/$name.json unless it exists: calibrate DIR NAME ARGS...
calibrate() {
  local dir=$1 name=$2
  shift 2
  [[ -f $dir/$name.json ]] && return 0
  local start end
  start=$(date +%s.%N)
  "$lptn" calibrate --data "$dir/fleet" --motor "$dir/fleet/motor.toml" --out "$dir/$name.json" \
    --checkpoint-dir "$dir/$name.checkpoints" --force --quiet "$@" > "$dir/$name.txt"
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f\n", b - a }' > "$dir/$name.wall"
  echo "$name: $(cat "$dir/$name.wall") s"
}

if [[ $mode == scheduled ]]; then
  dir=$out/scheduled
  mkdir -p "$dir"
  [[ -f $dir/fleet/motor.toml ]] ||
    "$lptn" generate --out "$dir/fleet" --cycles 9 --seed 1 --hidden rotor_speed_convection,windage --force >/dev/null
  calibrate "$dir" lm --method lm
  calibrate "$dir" td3-paper --method td3-paper --seed 1 --episodes "${SCHEDULED_EPISODES:-200}"
  PYTHONPATH=scripts python3 - "$dir" <<'PY'
import json, sys
from pooled_rmse import combined
d = sys.argv[1]
lm = json.load(open(d + "/lm.json"))["metrics"]["test"]
td3 = json.load(open(d + "/td3-paper.json"))
s = td3["method"]["details"]["scheduled_actor"]
print("hidden rotor_speed_convection and windage; test cycles, stator and rotor pooled:")
print(f"| LM (constant set) | {combined(lm):.3f} K | {lm['rmse_stator_k']:.3f} / {lm['rmse_rotor_k']:.3f} K |")
t = td3["metrics"]["test"]
print(f"| td3-paper, its constant set | {s['constant_set_test_rmse_k']:.3f} K | {t['rmse_stator_k']:.3f} / {t['rmse_rotor_k']:.3f} K |")
print(f"| td3-paper, the actor scheduling | {s['test_rmse_k']:.3f} K | {s['test_rmse_stator_k']:.3f} / {s['test_rmse_rotor_k']:.3f} K |")
print("the actor wins over its constant set:", s["actor_wins"], "; over LM:", s["test_rmse_k"] < combined(lm))
PY
  exit 0
fi

if [[ $mode == discovered ]]; then
  dir=$out/discovered
  mkdir -p "$dir"
  # The demo's step 8 fleet and test cycles (scripts/demo.sh), and the term its diagnosis recommends.
  [[ -f $dir/fleet/motor.toml ]] ||
    "$lptn" generate --out "$dir/fleet" --cycles 8 --seed 3 --plant eddy_loss --minutes-min 20 --minutes-max 25 --force >/dev/null
  split=(--test-cycles cycle_07_regional,cycle_08_intercity --effect heat_stator_winding_i2f)
  calibrate "$dir" lm --method lm "${split[@]}"
  for seed in $seeds; do calibrate "$dir" "td3-$seed" --method td3 --seed "$seed" "${split[@]}"; done
  PYTHONPATH=scripts python3 - "$dir" $seeds <<'PY'
import json, statistics, sys
from pooled_rmse import combined
d, seeds = sys.argv[1], sys.argv[2:]
lm = json.load(open(d + "/lm.json"))
lm_test = combined(lm["metrics"]["test"])
free = sum(1 for p in lm["parameters"] if p["calibrated"])
print(f"eddy_loss fleet, the paper's model + heat_stator_winding_i2f ({free} parameters calibrated); "
      f"LM test {lm_test:.4f} K in {float(open(d + '/lm.wall').read()):.1f} s")
ratios, walls = [], []
for seed in seeds:
    j = json.load(open(f"{d}/td3-{seed}.json"))
    t = combined(j["metrics"]["test"])
    wall = float(open(f"{d}/td3-{seed}.wall").read())
    ratios.append(t / lm_test)
    walls.append(wall)
    print(f"| td3 seed {seed} | test {t:.4f} K | {t / lm_test:.3f}x LM | {wall:.0f} s |")
print(f"median {statistics.median(ratios):.3f}x LM (worst {max(ratios):.3f}x), within 1.1x on "
      f"{sum(r <= 1.1 for r in ratios)} of {len(ratios)}; wall median {statistics.median(walls):.0f} s (worst {max(walls):.0f} s)")
PY
  exit 0
fi

if [[ $mode == transfer ]]; then
  dir=$out/transfer
  mkdir -p "$dir"
  # The motor type's second motor: every conductance 15 % off the first's, alternately up and down.
  [[ -f $dir/fleet/motor.toml ]] ||
    "$lptn" generate --out "$dir/fleet" --cycles 9 --seed 2 --force --truth lambda_1s=27.6 --truth lambda_2s=55.25 \
      --truth lambda_12s=126.5 --truth lambda_1r=17.85 --truth lambda_2r=51.75 --truth lambda_12r=127.5 >/dev/null
  previous=$(grep -l '"agent_file"' "$out"/td3-[0-9]*.json 2>/dev/null | head -1 || true)
  if [[ -z $previous ]]; then  # the first dump's td3 run whose agent is kept
    calibrate "$out" td3-1 --method td3 --seed 1
    previous=$out/td3-1.json
  fi
  calibrate "$dir" lm --method lm
  calibrate "$dir" td3-scratch --method td3 --seed 1 --test-curve
  calibrate "$dir" td3-warm --method td3 --seed 1 --test-curve --warm-start "$previous"
  PYTHONPATH=scripts python3 - "$dir" "$previous" <<'PY'
import json, sys
from pooled_rmse import combined
d = sys.argv[1]
lm = combined(json.load(open(d + "/lm.json"))["metrics"]["test"])
print(f"second dump (conductances +-15 %), warm start from {sys.argv[2]}; LM test {lm:.4f} K, target 1.1x = {1.1 * lm:.4f} K")
for name in ("td3-scratch", "td3-warm"):
    j = json.load(open(f"{d}/{name}.json"))
    curve = j["method"]["details"]["test_curve"]
    hit = next((c for c in curve if c["test_rmse_k"] <= 1.1 * lm), None)
    when = f"{hit['seconds']:.0f} s (round {hit['round']})" if hit else "not reached"
    print(f"| {name} | to 1.1x LM: {when} | final test {combined(j['metrics']['test']):.4f} K ({combined(j['metrics']['test']) / lm:.3f}x) "
          f"| {j['method']['seconds']:.0f} s in all |")
PY
  exit 0
fi

for method in $methods; do
  extra=()
  [[ $method == td3-paper ]] && extra=(--episodes "${TD3_PAPER_EPISODES:-100}")
  [[ $method == td3-episode ]] && extra=(--episodes "${TD3_EPISODE_EPISODES:-500}")
  for seed in $([[ $method == lm ]] && echo 1 || echo "$seeds"); do
    calibrate "$out" "$method-$seed" --method "$method" --seed "$seed" "${extra[@]}"
  done
done
python3 scripts/bench-calibration-summary.py "$out"
