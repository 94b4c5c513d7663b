# lptn_inline_jets(TARGET...): Eigen's small kernels always inlined in the target's sources.
#
# Why: Ceres' Jet<double, N> keeps its derivatives in an Eigen vector, and every Jet operation is an
# Eigen assignment that Eigen marks EIGEN_STRONG_INLINE, which is a plain `inline` for GCC. In the
# LM residuals (the model stepped in Jets over every cycle) GCC left the 10-wide product
# out of line: one call per Jet multiplication, 15 % of a 200 h diagnosis in that one function
# (perf). Always inlined, the same arithmetic in the same order: the 200 h diagnosis 101.9 s ->
# 82.9 s, its LM calibration 17.3 s -> 14.9 s, every output the same bytes (2026-11-28). For the
# targets that differentiate the model alone: elsewhere it only costs compile time.
function(lptn_inline_jets)
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    foreach(target IN LISTS ARGN)
      target_compile_definitions(${target} PRIVATE "EIGEN_STRONG_INLINE=inline __attribute__((always_inline))")
    endforeach()
  endif()
endfunction()
