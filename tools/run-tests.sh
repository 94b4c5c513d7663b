#!/usr/bin/env bash
# Builds and runs every test: the host build as CI runs it (warnings are errors) and the
# firmware-only build (no libtorch, no Ceres). Installs what is missing first.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
jobs=$(nproc)
cmake --preset ci >/dev/null
cmake --build --preset ci -j"$jobs"
ctest --preset ci -j"$jobs"
cmake --preset firmware -DLPTN_WERROR=ON >/dev/null
cmake --build --preset firmware -j"$jobs"
ctest --preset firmware -j"$jobs"
