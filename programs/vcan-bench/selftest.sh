#!/usr/bin/env bash
# selftest.sh [--cache DIR] — proves the vcan bench end to end without the daemon: a generated
# candump log (300 frames, ids 0x101 and 0x120, 30 s of made-up time) is sped up tenfold with
# scale-log.py, played onto vcan0 in the guest by canplayer while candump -L records the bus, and
# checked here: every frame back, in order, with the same data, over the scaled time span.
# DIR (default build/vcan-bench/cache) holds the guest's kernel between runs.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
cache=$here/../../build/vcan-bench/cache
if (($#)); then
  [ "$1" = --cache ] && [ -n "${2:-}" ] || { echo "usage: selftest.sh [--cache DIR]" >&2; exit 2; }
  cache=$2
fi

share=$(mktemp -d)
# 0x101 every 0.2 s with 8 changing bytes, 0x120 between them with 0 to 8 bytes (DLC edge cases).
awk 'BEGIN {
  for (k = 0; k < 150; ++k) {
    t = 1700000000 + k * 0.2
    d = ""; for (b = 0; b < 8; ++b) d = d sprintf("%02X", (k * 7 + b * 31) % 256)
    printf "(%.6f) can0 101#%s\n", t, d
    d = ""; for (b = 0; b < k % 9; ++b) d = d sprintf("%02X", (255 - k - b) % 256)
    printf "(%.6f) can0 120#%s\n", t + 0.1, d
  }
}' >"$share/recorded-on-train.log"
"$here/scale-log.py" "$share/recorded-on-train.log" "$share/played.log" 10

cat >"$share/run.sh" <<'EOF'
candump -L vcan0 >bus.log &
candump=$!
# Play only once candump's socket is listening on vcan0.
until grep -q '^ *vcan0 ' /proc/net/can/rcvlist_all; do sleep 0.05; done
canplayer -I played.log vcan0=can0
kill "$candump"
wait "$candump"
EOF

"$here/run-guest.sh" --cache "$cache" --share "$share" --timeout 120 || {
  echo "selftest: FAILED, payload and console kept in $share" >&2
  exit 1
}

# Same frames in the same order (interface and time stamps differ), and the log's pace kept: not
# faster than its time stamps, and well short of the unscaled 30 s.
sent=$(awk '{print $3}' "$share/played.log")
got=$(awk '{print $3}' "$share/bus.log")
span() { awk 'NR == 1 {gsub(/[()]/, "", $1); t0 = $1} END {gsub(/[()]/, "", $1); printf "%.2f", $1 - t0}' "$1"; }
if [ "$sent" != "$got" ]; then
  echo "selftest: FAILED, frames differ (sent $(wc -l <<<"$sent"), received $(wc -l <<<"$got")); first difference:" >&2
  diff <(echo "$sent") <(echo "$got") | head -5 >&2
  echo "selftest: logs kept in $share" >&2
  exit 1
fi
played=$(span "$share/played.log") took=$(span "$share/bus.log")
if ! awk -v p="$played" -v t="$took" 'BEGIN {exit !(t >= 0.95 * p && t < 3 * p)}'; then
  echo "selftest: FAILED, $played s of log took $took s on the bus; logs kept in $share" >&2
  exit 1
fi
echo "selftest: $(wc -l <<<"$got") frames came back in order and intact; $played s of log took $took s on vcan0"
rm -rf "$share"
