#!/usr/bin/env bash
# The installed lptn, as a user gets it from `cmake --install`: installed into a temporary prefix,
# run from elsewhere through the demo's first steps (generate, inspect, calibrate with LM and with
# TD3 through lptn-td3, export, convert, replay, the daemon on the log), and a drive controller's
# program compiled against the installed headers and the exported calibration. Fails if an
# installed program names a path of the source or build tree (a Release build's: a sanitizer or
# debug build names its sources by design, in its debug information and UBSan's reports).
#   scripts/test-install.sh BUILD_DIR SOURCE_DIR [--sources-named-by-design]
set -euo pipefail
build=$(realpath "$1")
src=$(realpath "$2")
check_paths=${3:-}
prefix=$(mktemp -d /tmp/lptn-install.XXXXXX)
work=$(mktemp -d /tmp/lptn-install-run.XXXXXX)
trap 'rm -rf "$prefix" "$work"' EXIT
fail() { echo "test-install: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$prefix" >/dev/null
for f in bin/lptn bin/lptn-full bin/lptn-daemon include/lptn/model.hpp include/lptn/version.hpp include/lptn/firmware/estimator.hpp \
         include/lptn/can/lptn_frames.hpp include/lptn/bus/bus_glue.hpp include/lptn/bus/bus_glue_codecs.hpp; do
  [ -e "$prefix/$f" ] || fail "$f was not installed"
done
[ -e "$prefix/bin/lptn-vcan-bench" ] && fail "the bench was installed"
if [ "$check_paths" != "--sources-named-by-design" ]; then
  for f in "$prefix"/bin/*; do
    if grep -q -a -F "$src" "$f" || grep -q -a -F "$build" "$f"; then fail "$f names a path of the source or build tree"; fi
  done
fi

cd "$work"
lptn=$prefix/bin/lptn
"$lptn" --version | grep -q '^lptn [0-9]' || fail "lptn --version"
# 20-minute drives: on 8-minute ones the paper's conductances are not pinned and LM ends on a bound (status failed)
"$lptn" generate --out fleet --cycles 3 --seed 5 --minutes-min 20 --minutes-max 25 >/dev/null 2>&1
"$lptn" inspect --data fleet --motor fleet/motor.toml >/dev/null
"$lptn" calibrate --data fleet --motor fleet/motor.toml --method lm --out lm.json --quiet
"$lptn" export --calibration lm.json --out thermal_calibration.hpp >/dev/null
if [ -e "$prefix/bin/lptn-td3" ]; then  # built with TD3: lptn hands --method td3* over to it
  # Two episodes leave the model far from its sensors' noise: written with warnings (exit 3).
  "$lptn" calibrate --data fleet --motor fleet/motor.toml --method td3-episode --episodes 2 --out td3.json --quiet ||
    [ $? -eq 3 ] || fail "the TD3 calibration failed"
  grep -q '"name": "td3-episode"' td3.json || fail "the TD3 calibration was not written by lptn-td3"
fi
cycle=$(ls fleet/*.csv | head -n 1)
"$lptn" convert --in "$cycle" --out cycle.log >/dev/null
"$lptn" replay --log cycle.log --calibration lm.json --out estimates.csv --quiet
[ "$(wc -l < estimates.csv)" -gt 4000 ] || fail "the replay wrote $(wc -l < estimates.csv) lines"
"$prefix/bin/lptn-daemon" --replay cycle.log --csv daemon.csv 2>/dev/null
[ "$(wc -l < daemon.csv)" -gt 4000 ] || fail "the daemon wrote $(wc -l < daemon.csv) lines"

# A controller's program against the installed headers only (no source tree on the include path).
cat > controller.cpp <<'CPP'
#include "thermal_calibration.hpp"
#include <lptn/firmware/exported_calibration.hpp>
#include <lptn/firmware/estimator.hpp>
#include <lptn/version.hpp>
#include <cstdio>
int main() {
  lptn::fw::Estimator<float> estimator(lptn::fw::config_from_exported_header<float>());
  const auto& out = estimator.tick(100000);
  std::printf("%s: %d\n", lptn::kNameAndVersion, static_cast<int>(out.mode));
  return 0;
}
CPP
c++ -std=c++20 -fno-exceptions -fno-rtti -I"$prefix/include" -I. controller.cpp -o controller || fail "a program against the installed headers did not compile"
./controller >/dev/null || fail "the controller program failed"
echo "test-install: installed into $prefix and ran generate, inspect, calibrate, export, convert, replay, the daemon and a controller program"
