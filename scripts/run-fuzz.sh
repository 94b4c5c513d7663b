#!/usr/bin/env bash
# Fuzz smoke run: builds the libFuzzer targets (tests/fuzz, preset fuzz: clang, ASan, UBSan) and
# runs each one, from its seeds, for a bounded time. Fails on any crash, leak, timeout, memory
# blow-up or sanitizer report; prints one line per target with the executions it reached.
#
#   scripts/run-fuzz.sh [SECONDS_PER_TARGET]   default 60
#
# The seeds (tests/fuzz/corpus/TARGET) are copied into build/fuzz/run/TARGET/corpus, where the
# fuzzer adds what it finds, so the repository is never written. A failing input is saved there
# too (crash-*, leak-*, timeout-*, oom-*); rerun it with build/fuzz/tests/fuzz/TARGET FILE.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-60}
if ! [[ $seconds =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: scripts/run-fuzz.sh [SECONDS_PER_TARGET]" >&2
  exit 2
fi
start=$SECONDS

scripts/setup.sh fuzz
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j"$(nproc)"

# Longest input per target: a CAN payload and a double; a log line; a short log file (MDF4: its blocks
# and a few data records), CSV or motor file;
# 340 frames for the estimator.
declare -A MAX_LEN=(
  [fuzz_can_codecs]=16
  [fuzz_candump_line]=256
  [fuzz_can_log]=8192
  [fuzz_mdf4]=16384
  [fuzz_cycle_csv]=4096
  [fuzz_data_map]=4096
  [fuzz_motor_toml]=4096
  [fuzz_motor_json]=4096
  [fuzz_estimator_frames]=4093
)
TARGETS=(fuzz_can_codecs fuzz_candump_line fuzz_can_log fuzz_mdf4 fuzz_cycle_csv fuzz_data_map fuzz_motor_toml fuzz_motor_json fuzz_estimator_frames)

# UBSan aborts on the first report anyway (-fno-sanitize-recover); the stack says where.
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export ASAN_OPTIONS=detect_leaks=1

# One target: its log, corpus and status under build/fuzz/run/TARGET.
run_target() {
  local target=$1 work=build/fuzz/run/$1 status=0
  rm -rf "$work"
  mkdir -p "$work/corpus"
  cp tests/fuzz/corpus/"$target"/* "$work/corpus/"
  # -timeout: one input taking this long is a hang (the slowest seeds take well under a second).
  build/fuzz/tests/fuzz/"$target" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=30 \
    -max_len="${MAX_LEN[$target]}" -detect_leaks=1 -print_final_stats=1 -artifact_prefix="$work/" \
    "$work/corpus" >"$work/log" 2>&1 || status=$?
  echo "$status" >"$work/status"
}

# As many targets at once as there are cores: each still runs for its own $seconds.
for target in "${TARGETS[@]}"; do
  while (($(jobs -rp | wc -l) >= $(nproc))); do wait -n || true; done
  run_target "$target" &
done
wait

failed=()
summary=()
for target in "${TARGETS[@]}"; do
  work=build/fuzz/run/$target
  status=$(cat "$work/status" 2>/dev/null || echo 1)
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$work/log" | tail -n 1)
  inputs=$(find "$work/corpus" -type f | wc -l)
  # Belt and braces: a sanitizer report is a failure even if the exit status missed it.
  if ((status != 0)) || grep -qE 'ERROR: (AddressSanitizer|LeakSanitizer|UndefinedBehaviorSanitizer|libFuzzer)|runtime error:|fuzz check failed' "$work/log"; then
    failed+=("$target")
    artifact=$(find "$work" -maxdepth 1 -type f \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \) | head -n 1)
    summary+=("$(printf '%-22s FAILED (exit %d) after %s executions; log %s%s' "$target" "$status" "${runs:-?}" \
      "$work/log" "${artifact:+, input $artifact}")")
    echo "---- $target: last lines of $work/log" >&2
    tail -n 40 "$work/log" >&2
  else
    summary+=("$(printf '%-22s ok  %10s executions in %s s, corpus %s inputs' "$target" "${runs:-?}" "$seconds" "$inputs")")
  fi
done

echo "fuzz, $seconds s per target ($((SECONDS - start)) s in all, with the build):"
printf '  %s\n' "${summary[@]}"
echo "fuzz: $((${#TARGETS[@]} - ${#failed[@]})) passed, ${#failed[@]} failed"
((${#failed[@]} == 0))
