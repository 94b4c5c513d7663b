# aarch64 Linux (the traction converter's application processor): Debian's cross compiler, tests run
# under qemu user emulation. binfmt_misc is not mounted on the build machines, so ctest and
# gtest_discover_tests call qemu explicitly through CMAKE_CROSSCOMPILING_EMULATOR.
# Needs: scripts/setup.sh cross. GoogleTest comes from source: see gtest-from-source.cmake.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)

# Libraries and headers only from the aarch64 tree; CMake package configs from anywhere, so that
# header-only Eigen's config in /usr/share is found (its include path is architecture-neutral).
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)

find_program(LPTN_QEMU_AARCH64 qemu-aarch64-static REQUIRED)
set(CMAKE_CROSSCOMPILING_EMULATOR "${LPTN_QEMU_AARCH64};-L;/usr/aarch64-linux-gnu")
