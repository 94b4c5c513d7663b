# lptn_unity_build(TARGET...): each target's sources compiled in batches of five files to a
# translation unit (CMake's unity build).
#
# Why: a build of what the demo runs is bound by the compiler's work on two cores (388 s of it in
# 201 s of wall on a fresh clone, 2026-11-27), and most of a file's time is the optimizer working
# through templates that every file of a library instantiates again (nlohmann::json's, the
# model's): `lptn`'s ten command files took 87 s apart and 31 s as two batches.
# A name that two files of a target both define at file scope (an anonymous namespace, `static`)
# then fails to compile, loudly: the files of these targets keep their file-local names distinct.
function(lptn_unity_build)
  foreach(target IN LISTS ARGN)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 5)
  endforeach()
endfunction()
