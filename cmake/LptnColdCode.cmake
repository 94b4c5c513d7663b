# lptn_cold_code(TARGET... [SOURCES file...]): a Release build compiles these at -O1 instead of -O3.
#
# For code that parses arguments and files (CLI11's, nlohmann::json's, toml++'s templates), writes
# reports or generates code at build time: run once per command, never in a loop over samples or
# frames, and most of a fresh build's compiler time (`lptn`'s command batches took 18.2 s at -O3
# and 10.8 s at -O1, 2026-12-02). The numerics stay at -O3 in their own libraries (the model,
# integrator and observer are headers, instantiated where the hot loops are: simulate, lm,
# calibrate, diagnose, firmware, canlog), and a file whose templates run a cycle's steps is not
# given here.
# The results are the same at any level: no -ffast-math, and no contraction into fused
# multiply-adds (-ffp-contract=off, the top CMakeLists.txt), so every floating-point operation is
# the one the source says.
function(lptn_cold_code)
  cmake_parse_arguments(PARSE_ARGV 0 arg "" "" "SOURCES")
  set(cold $<$<CONFIG:Release>:-O1>)
  foreach(target IN LISTS arg_UNPARSED_ARGUMENTS)
    target_compile_options(${target} PRIVATE ${cold})
  endforeach()
  if(arg_SOURCES)
    set_property(SOURCE ${arg_SOURCES} APPEND PROPERTY COMPILE_OPTIONS ${cold})
  endif()
endfunction()
