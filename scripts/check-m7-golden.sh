#!/usr/bin/env bash
# check-m7-golden.sh — the Cortex-M7 replay image under qemu (scripts/run-m7.sh) against its host
# twin (tests/m7: the same float estimator and replay, built for this machine) on a generated
# 20-minute drive, closed and open loop: the same rows at the same times, every estimate and
# standard deviation within float rounding (TOLERANCE_K, default 1e-4 K; the rows print 1e-5 K).
# Needs the host build (preset ci: lptn and the twin) and scripts/setup.sh cross.
set -euo pipefail
cd "$(dirname "$0")/.."
tolerance=${TOLERANCE_K:-1e-4}
lptn=${LPTN:-build/ci/programs/cli/lptn}
twin=${LPTN_TWIN:-build/ci/tests/m7/lptn_host_float_replay}
work=build/cortex-m7/golden
rm -rf "$work"
mkdir -p "$work"
"$lptn" generate --out "$work/data" --cycles 1 --seed 11 --minutes-min 20 --minutes-max 20 >/dev/null 2>&1
"$lptn" convert --in "$work"/data/cycle_01_*.csv --out "$work/drive.log" >/dev/null
for mode in closed open; do
  flag=$([[ $mode == open ]] && echo --open-loop || true)
  "$twin" "$work/drive.log" "$work/host-$mode.csv" $flag >/dev/null
  scripts/run-m7.sh "$work/drive.log" "$work/m7-$mode.csv" $flag | sed "s/^/[$mode loop] /"
  python3 - "$work/host-$mode.csv" "$work/m7-$mode.csv" "$tolerance" "$mode" <<'PY'
import csv, sys
host, m7, tolerance, mode = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
a, b = list(csv.reader(open(host))), list(csv.reader(open(m7)))
if a[0] != b[0] or len(a) != len(b) or len(a) < 1000:
    sys.exit(f"m7 golden ({mode} loop): {len(b) - 1} rows against the host's {len(a) - 1}, or other columns")
worst = [0.0] * len(a[0])
for row_a, row_b in zip(a[1:], b[1:]):
    if row_a[0] != row_b[0]:
        sys.exit(f"m7 golden ({mode} loop): a row at {row_b[0]} s where the host has {row_a[0]} s")
    for i in range(1, len(row_a)):
        worst[i] = max(worst[i], abs(float(row_a[i]) - float(row_b[i])))
largest = max(worst[1:])
print(f"[{mode} loop] m7 against the host's float estimator: {len(a) - 1} rows, largest difference "
      f"{largest:.1e} K (allowed {tolerance:.0e} K)")
if largest > tolerance:
    sys.exit("m7 golden: " + ", ".join(f"{a[0][i]} {worst[i]:.1e}" for i in range(1, len(worst))))
PY
done
