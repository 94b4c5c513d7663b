# Cortex-M7 bare metal (the drive controller's MCU): arm-none-eabi with newlib-nano, hard float
# on the FPv5 double-precision unit. Needs: scripts/setup.sh cross.
# The memory map is the board's: firmware/baremetal/m7.ld.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
# Without an OS CMake cannot link a test executable before the linker script is known.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(LPTN_M7_FLAGS "-mcpu=cortex-m7 -mfpu=fpv5-d16 -mfloat-abi=hard -mthumb -ffunction-sections -fdata-sections")
# NDEBUG in every build type: Eigen's and the library's asserts pull in printf and malloc.
set(CMAKE_C_FLAGS_INIT "${LPTN_M7_FLAGS} -DNDEBUG")
set(CMAKE_CXX_FLAGS_INIT "${LPTN_M7_FLAGS} -DNDEBUG -fno-exceptions -fno-rtti")
# nano: the small newlib; nosys: stub system calls (no OS); gc-sections drops what nothing uses.
set(CMAKE_EXE_LINKER_FLAGS_INIT "--specs=nano.specs --specs=nosys.specs -Wl,--gc-sections")

# Libraries and headers only from newlib's tree; package configs from anywhere, for header-only
# ones such as Eigen's.
set(CMAKE_FIND_ROOT_PATH /usr/lib/arm-none-eabi)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
