#!/usr/bin/env bash
# The main job, end to end, on the built-in demo: set up, build, generate a demo fleet dump with a
# known truth, check it, and compare the model (as the motor file guesses it) with the sensors.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
cmake --preset host >/dev/null
cmake --build --preset host -j"$(nproc)" --target lptn
lptn=build/host/tools/cli/lptn
out=${1:-demo-out}
mkdir -p "$out"

echo "== 1. generate: 9 driving cycles from the synthetic plant (seed 1)"
"$lptn" generate --out "$out/fleet" --cycles 9 --seed 1 --force
echo "== 2. inspect: rates, coverage, gaps and warnings per cycle"
"$lptn" inspect --data "$out/fleet" --motor "$out/fleet/motor.toml" > "$out/inspect.txt"
tail -n 3 "$out/inspect.txt"
echo "== 3. simulate and compare: the paper's model with the motor file's initial guesses"
"$lptn" simulate --data "$out/fleet" --motor "$out/fleet/motor.toml" --out "$out/simulation" --force
echo
echo "demo output in $out/: fleet/ (cycle CSVs, motor.toml, truth.json, truth/), inspect.txt, simulation/ (traces, metrics.json)"
