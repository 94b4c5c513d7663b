# lptn_module_headers(TARGET [HEADERS h...] [NO_INTERNAL])
#
# The build, not a comment, keeps a module's insides private. TARGET's consumers see its public
# headers only (by default the *.hpp directly in the calling directory; HEADERS names them where
# a directory holds more than one library), at their path from the repository root
# ("trainer/data/dataset.hpp"), through a directory of links in the build tree; TARGET's own
# sources see those and the module's internal/ headers (unless NO_INTERNAL). Nothing exports the
# repository root, so an include of a module the target does not link fails to compile, and
# scripts/check-layers.py (a test) holds the links themselves to the layers.
function(lptn_module_headers target)
  cmake_parse_arguments(PARSE_ARGV 1 ARG "NO_INTERNAL" "" "HEADERS")
  if(ARG_HEADERS)
    list(TRANSFORM ARG_HEADERS PREPEND "${CMAKE_CURRENT_SOURCE_DIR}/" OUTPUT_VARIABLE public)
  else()
    file(GLOB public CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/*.hpp")
  endif()
  set(internal)
  if(NOT ARG_NO_INTERNAL)
    file(GLOB_RECURSE internal CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/internal/*.hpp")
  endif()
  set(root "${CMAKE_BINARY_DIR}/modules/${target}")
  file(REMOVE_RECURSE "${root}")
  foreach(kind public internal)
    foreach(header IN LISTS ${kind})
      file(RELATIVE_PATH path "${PROJECT_SOURCE_DIR}" "${header}")
      get_filename_component(dir "${root}/${kind}/${path}" DIRECTORY)
      file(MAKE_DIRECTORY "${dir}")
      file(CREATE_LINK "${header}" "${root}/${kind}/${path}" SYMBOLIC)
    endforeach()
  endforeach()
  file(MAKE_DIRECTORY "${root}/public" "${root}/internal")
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "INTERFACE_LIBRARY")  # header-only: nothing of its own is compiled
    target_include_directories(${target} INTERFACE "${root}/public")
  else()
    target_include_directories(${target} PUBLIC "${root}/public" PRIVATE "${root}/internal")
  endif()
endfunction()

# lptn_module_internals(TEST_TARGET LIBRARY): a module's own tests may reach its internal headers.
function(lptn_module_internals test_target library)
  target_include_directories(${test_target} PRIVATE "${CMAKE_BINARY_DIR}/modules/${library}/internal")
endfunction()
