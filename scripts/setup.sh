#!/usr/bin/env bash
# Installs, on Debian 12, the packages that lptn's build, tests and demo need. Idempotent: it asks
# apt only for what is missing, so a second run costs a second.
#
#   scripts/setup.sh [GROUP...]   no group: host build, tests and demo
#     cross   aarch64 Linux and Cortex-M7 cross toolchains (+ qemu-user to run aarch64 tests); 530 MB
#     bench   the vcan bench: a qemu guest with SocketCAN, can-utils, python-can
#     report  chromium, for lptn report's headless browser test
#     fuzz    clang-14 with libFuzzer and the sanitizers' runtimes, for scripts/run-fuzz.sh
# The cross toolchains are big, so only the steps that need them ask for them.
set -euo pipefail

HOST=(
  build-essential cmake ninja-build pkg-config python3  # toolchain; python3 for the project's scripts
  libeigen3-dev libceres-dev                            # model on the host, Levenberg-Marquardt
  libtorch-dev libopenblas0-pthread                     # TD3; OpenBLAS, or torch runs on reference BLAS (16x slower)
  libgtest-dev libgmock-dev googletest libbenchmark-dev # tests and benchmarks; googletest's sources are built for aarch64
  libcli11-dev libtomlplusplus-dev nlohmann-json3-dev   # command line, motor files and bus maps, JSON
  libgmp-dev                                            # the DBC reader's exact range arithmetic (can/dbc; the CAN generators)
  libjs-dygraphs                                        # lptn report's charts, embedded at build time
  time                                                  # GNU time: scripts/bench-scale.sh's peak memory
  zlib1g-dev libdeflate-dev                             # Vector BLF logs' containers, MDF4's DZ blocks: deflated, inflated
  python3-can                                           # tests: ASC and BLF logs written and read by another implementation
  libopenmpi-dev openmpi-bin                            # mpirun -np N lptn calibrate: one calibration over N processes
)
CROSS=(
  g++-aarch64-linux-gnu qemu-user-static                # aarch64 Linux; tests run under qemu-aarch64-static
  gcc-arm-none-eabi libstdc++-arm-none-eabi-newlib libnewlib-arm-none-eabi  # Cortex-M7 bare metal
  qemu-system-arm                                       # the Cortex-M7 replay image on mps2-an500
)
BENCH=(
  python3-can can-utils                                 # CAN logs and the bench's tools
  qemu-system-x86 busybox-static cpio xz-utils kmod     # the vcan guest: kernel boot, initramfs, depmod
)
REPORT=(
  chromium                                              # the report's headless browser test
)
FUZZ=(
  clang libclang-rt-14-dev                              # clang-14; libFuzzer, ASan and UBSan runtimes
  cmake ninja-build python3                             # the fuzz preset's build; python3 for the project's scripts
  libgmp-dev                                            # the CAN generators' DBC reader (exact range arithmetic)
  libtomlplusplus-dev nlohmann-json3-dev                # the fuzzed trainer/ libraries (no libtorch, no Ceres)
  zlib1g-dev libdeflate-dev pkg-config                  # the fuzzed CAN log readers (BLF, MDF4)
)

PACKAGES=()
if (($# == 0)); then set -- host; fi
for group in "$@"; do
  case $group in
    host) PACKAGES+=("${HOST[@]}") ;;
    cross) PACKAGES+=("${CROSS[@]}") ;;
    bench) PACKAGES+=("${BENCH[@]}") ;;
    report) PACKAGES+=("${REPORT[@]}") ;;
    fuzz) PACKAGES+=("${FUZZ[@]}") ;;
    *) echo "setup: unknown group '$group' (host, cross, bench, report, fuzz)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "setup ($*): all ${#PACKAGES[@]} packages present"
  exit 0
fi
SUDO=()
if [ "$(id -u)" -ne 0 ]; then SUDO=(sudo); fi
echo "setup ($*): installing ${missing[*]}"
"${SUDO[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup ($*): done"
