# GoogleTest for cross builds. Debian's libgtest-dev is built for the host architecture only, but
# the `googletest` package ships its sources: build them with the cross compiler and let
# find_package(GTest) resolve to these targets. Host builds use the packaged library (no-op here).
# Included from the top-level CMakeLists.txt before tests/ is added.
if(NOT CMAKE_CROSSCOMPILING)
  return()
endif()

set(INSTALL_GTEST OFF CACHE BOOL "GoogleTest built from source for a cross build is not installed")
# SYSTEM: GoogleTest's headers reach the tests as system headers, as the packaged ones do, so the
# project's -Werror does not apply to them. GoogleTest's build names its targets GTest::gtest,
# GTest::gtest_main, GTest::gmock as the packaged GTestConfig.cmake does.
add_subdirectory(/usr/src/googletest "${CMAKE_BINARY_DIR}/googletest" EXCLUDE_FROM_ALL SYSTEM)
# GCC 12 at -O3 warns of an overlapping memcpy inside libstdc++'s char_traits in gtest-all.cc: a
# known false positive (GCC bug 105329), not worth a screenful in every CI log.
target_compile_options(gtest PRIVATE -Wno-restrict)
# find_package() reads this directory before any other, even in module mode (CMake >= 3.24).
file(WRITE "${CMAKE_FIND_PACKAGE_REDIRECTS_DIR}/gtest-config.cmake"
     "# GTest::* are built from /usr/src/googletest by toolchains/gtest-from-source.cmake\n")
