#!/usr/bin/env bash
# Installs, on Debian 12, every package that lptn's build, tests and demo need. Idempotent: it
# asks apt only for what is missing, so a second run costs a second.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config          # toolchain
  libeigen3-dev libceres-dev                            # model on the host, Levenberg-Marquardt
  libtorch-dev libopenblas0-pthread                     # TD3; OpenBLAS, or torch runs on reference BLAS (16x slower)
  libgtest-dev libgmock-dev googletest libbenchmark-dev # tests and benchmarks
  libcli11-dev libtomlplusplus-dev nlohmann-json3-dev   # command line, motor files, JSON
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "setup: all ${#PACKAGES[@]} packages present"
  exit 0
fi
SUDO=()
if [ "$(id -u)" -ne 0 ]; then SUDO=(sudo); fi
echo "setup: installing ${missing[*]}"
"${SUDO[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
