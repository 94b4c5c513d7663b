# The CAN code generators for the build host, in a cross build: this project configured and built
# again with the host's compiler (no toolchain file) and LPTN_CODEGEN_ONLY, which builds the
# generators and what they are made of (can/dbc, can/bus, hostio), like LLVM's native tablegen.
# An ExternalProject: it builds at build time, before the codecs, and again whenever the build runs
# (BUILD_ALWAYS; a no-op unless a reader or generator changed, and then the headers regenerate).
#
# Sets LPTN_HOST_DBC_CODEGEN and LPTN_HOST_BUS_CODEGEN (the executables) and the target
# lptn_host_codegen. The host build needs the host's packages (scripts/setup.sh host: toml++, GMP).
include(ExternalProject)
set(host_dir "${CMAKE_BINARY_DIR}/host-codegen")
set(LPTN_HOST_DBC_CODEGEN "${host_dir}/can/codegen/lptn-dbc-codegen")
set(LPTN_HOST_BUS_CODEGEN "${host_dir}/can/codegen/lptn-bus-codegen")
ExternalProject_Add(lptn_host_codegen
  SOURCE_DIR "${PROJECT_SOURCE_DIR}"
  BINARY_DIR "${host_dir}"
  CMAKE_ARGS -DLPTN_CODEGEN_ONLY=ON -DLPTN_FIRMWARE_ONLY=ON -DBUILD_TESTING=OFF -DCMAKE_BUILD_TYPE=Release
             -DLPTN_WERROR=${LPTN_WERROR}
  BUILD_COMMAND ${CMAKE_COMMAND} --build <BINARY_DIR> --target lptn-dbc-codegen lptn-bus-codegen
  INSTALL_COMMAND ""
  BUILD_ALWAYS ON
  BUILD_BYPRODUCTS "${LPTN_HOST_DBC_CODEGEN}" "${LPTN_HOST_BUS_CODEGEN}"
  USES_TERMINAL_BUILD ON)
