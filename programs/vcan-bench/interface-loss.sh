#!/usr/bin/env bash
# interface-loss.sh --lptn LPTN --daemon DAEMON [--cache DIR] — lptn-daemon on vcan0 in the bench
# guest (run-guest.sh) when its interface goes away under it, in one boot:
#   1. the link down for 2 s and up again (`ip link set vcan0 down/up`, as a converter's CAN
#      controller is restarted): the daemon reads on, idle while the link is down (not spinning:
#      less than half a core), and its record holds every frame of both plays; exit 0 on SIGTERM;
#   2. the interface removed (`ip link delete vcan0`, a USB adapter unplugged, a driver reset): the
#      daemon stops by itself within 5 s with exit status 1 and one line naming the interface, and
#      its record holds every frame it received until then (the daemon used to spin a core with
#      nothing said, and a read error threw the record away).
# The log: the first 3000 frames of a generated cycle (LPTN generate and convert), ten times faster.
# Exit 0 when every check holds; 1, with what failed, when one does not.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
cache=$here/../../build/vcan-bench/cache lptn='' daemon=''
usage() { echo "usage: interface-loss.sh --lptn LPTN --daemon DAEMON [--cache DIR]" >&2; exit 2; }
while (($#)); do
  case $1 in
    --lptn) lptn=${2:-}; shift 2 || usage ;;
    --daemon) daemon=${2:-}; shift 2 || usage ;;
    --cache) cache=${2:-}; shift 2 || usage ;;
    *) usage ;;
  esac
done
[ -x "$lptn" ] && [ -x "$daemon" ] || usage

work=$(mktemp -d)
share=$work/share
mkdir -p "$share"
"$lptn" generate --out "$work/fleet" --cycles 1 --seed 1 --force >/dev/null
"$lptn" convert --in "$work/fleet/cycle_01_suburban.csv" --out "$work/cycle.log" --force >/dev/null
head -n 3000 "$work/cycle.log" >"$work/head.log"
"$here/scale-log.py" "$work/head.log" "$share/play.log" 10
"$here/copy-with-libs.sh" "$daemon" "$share"
frames=$(grep -c . "$share/play.log")

cat >"$share/run.sh" <<'EOF'
listening() {  # until the daemon's kernel filters show on vcan0 (at most 10 s)
  n=0; until grep -q '^ *vcan0 ' /proc/net/can/rcvlist_fil || [ $n -ge 200 ]; do sleep 0.05; n=$((n+1)); done
}
cpu() { cut -d' ' -f14,15 /proc/$1/stat | awk '{print $1 + $2}'; }  # user + system, in 1/100 s

lptn-daemon --interface vcan0 --time-scale 10 --record /tmp/bounce.log 2>bounce.err &
d=$!
listening
canplayer -I play.log vcan0=can0
ip link set vcan0 down
before=$(cpu $d)
sleep 2
echo $(($(cpu $d) - before)) >bounce.down-cpu
ip link set vcan0 up
canplayer -I play.log vcan0=can0
sleep 0.5
kill -TERM $d
wait $d
echo $? >bounce.status
cp /tmp/bounce.log bounce.log

lptn-daemon --interface vcan0 --time-scale 10 --record /tmp/removed.log 2>removed.err &
d=$!
listening
canplayer -I play.log vcan0=can0
sleep 0.5
ip link delete vcan0
n=0; while kill -0 $d 2>/dev/null && [ $n -lt 100 ]; do sleep 0.05; n=$((n+1)); done
if kill -0 $d 2>/dev/null; then echo yes >removed.alive; kill -TERM $d; fi
wait $d
echo $? >removed.status
cp /tmp/removed.log removed.log 2>/dev/null || true
EOF

"$here/run-guest.sh" --cache "$cache" --share "$share" --timeout 240 || {
  echo "interface-loss: FAILED, the guest's run failed; payload and console kept in $share" >&2
  exit 1
}

failed=0
fail() { echo "interface-loss: FAILED: $*" >&2; failed=1; }
rx() { [ -f "$1" ] && awk '$2 == "rx"' "$1" | wc -l || echo 0; }
s=$share
[ "$(cat "$s/bounce.status")" = 0 ] || fail "link down and up: exit status $(cat "$s/bounce.status") after SIGTERM (0 expected); $(tail -n 2 "$s/bounce.err")"
(($(cat "$s/bounce.down-cpu") < 100)) || fail "link down: the daemon used $(cat "$s/bounce.down-cpu")/100 s of CPU in 2 s (spinning)"
(($(rx "$s/bounce.log") == 2 * frames)) || fail "link down and up: $(rx "$s/bounce.log") frames recorded of the two plays' $((2 * frames))"
[ ! -f "$s/removed.alive" ] || fail "interface removed: the daemon was still running 5 s later"
[ "$(cat "$s/removed.status")" = 1 ] || fail "interface removed: exit status $(cat "$s/removed.status") (1 expected)"
grep -q '^lptn-daemon: error: vcan0: No such device' "$s/removed.err" ||
  fail "interface removed: no line naming vcan0 and the error; stderr: $(tail -n 2 "$s/removed.err")"
(($(rx "$s/removed.log") == frames)) || fail "interface removed: $(rx "$s/removed.log") frames recorded of the $frames received"
if ((failed)); then
  echo "interface-loss: payload, record and console kept in $share" >&2
  exit 1
fi
echo "interface-loss: link down 2 s and up: $((2 * frames)) frames recorded, $(cat "$s/bounce.down-cpu")/100 s of CPU while down, exit 0;" \
  "interface removed: stopped by itself, exit 1 ($(grep -m1 '^lptn-daemon: error' "$s/removed.err")), $frames frames recorded"
rm -rf "$work"
