#!/usr/bin/env bash
# run-m7.sh LOG OUT.csv [--open-loop] — a candump log through the Cortex-M7 replay image
# (firmware/baremetal/replay_main.cpp: the float estimator with the compiled-in calibration) on
# qemu's mps2-an500 (Cortex-M7), reading LOG and writing the estimates to OUT.csv through
# semihosting. Prints the image's counts, the estimator's instructions per tick and the stack's
# high-water mark.
#
# Instructions: qemu runs with -icount shift=0 (one instruction a virtual nanosecond), and the
# board's SysTick counts its 25 MHz clock: 40 instructions a count. The image counts SysTick around
# the estimator's own work (receiving frames, ticking), not around parsing and writing.
# Builds the image (preset cortex-m7) if it is missing; needs scripts/setup.sh cross.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
usage() { echo "usage: scripts/run-m7.sh LOG OUT.csv [--open-loop]" >&2; exit 2; }
(($# == 2 || $# == 3)) || usage
log=$1 out=$2 mode=${3:-}
[[ -z $mode || $mode == --open-loop ]] || usage
[[ -f $log ]] || { echo "run-m7: $log: no such file" >&2; exit 2; }
for path in "$log" "$out"; do
  # The image splits its semihosting command line at spaces.
  [[ $path != *" "* ]] || { echo "run-m7: $path: a path with a space cannot reach the image" >&2; exit 2; }
done
image=$root/build/cortex-m7/firmware/baremetal/lptn_m7_replay.elf
if [[ ! -f $image ]]; then
  (cd "$root" && cmake --preset cortex-m7 -DLPTN_WERROR=ON >/dev/null && cmake --build --preset cortex-m7 --target lptn_m7_replay >/dev/null)
fi
command -v qemu-system-arm >/dev/null || { echo "run-m7: qemu-system-arm missing: run scripts/setup.sh cross" >&2; exit 2; }
# qemu's option syntax doubles a comma inside a value.
arg() { printf ',arg=%s' "${1//,/,,}"; }
config="enable=on,target=native$(arg lptn_m7_replay.elf)$(arg "$log")$(arg "$out")${mode:+$(arg "$mode")}"
status=0
report=$(timeout 600 qemu-system-arm -M mps2-an500 -nographic -monitor none -serial none -icount shift=0 \
  -semihosting-config "$config" -kernel "$image") || status=$?
echo "$report"
cycles=$(sed -n 's/.* estimator cycles \([0-9]*\) in all, \([0-9]*\) per tick/\1 \2/p' <<<"$report")
if [[ -n $cycles ]]; then
  read -r total per_tick <<<"$cycles"
  echo "m7 replay: estimator instructions $((total * 40)) in all, about $((per_tick * 40)) per tick (qemu -icount, 40 a SysTick count)"
fi
exit "$status"
