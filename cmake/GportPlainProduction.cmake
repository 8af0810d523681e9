# GPORT_PLAIN_PRODUCTION: in a unity build (CMAKE_UNITY_BUILD), the programs
# and their libraries are still compiled file by file; only the code under
# tests/, bench/ and fuzz/ is merged into unity units.
#
# Why (docs/operations.md, "How CI spends its time"): a unity build hides a
# source that does not include what it uses when another file of its batch
# does, and the README's first command (scripts/demo.sh) and a build by hand
# are plain builds: a missing include once broke the demo for days under a
# green CI. scripts/test.sh runs the demo first, then its Release build with
# this option: every production source is compiled on its own there, with
# the demo's very compile commands, so ccache hands the Release build the
# demo's objects instead of compiling them twice. The sanitizer build
# compiles the tests' sources on its own (GPORT_PLAIN_TESTS), so every
# source of the project compiles alone somewhere in CI.
option(GPORT_PLAIN_PRODUCTION
       "In a unity build, compile everything but tests/, bench/ and fuzz/ file by file" OFF)
option(GPORT_PLAIN_TESTS "In a unity build, compile tests/, bench/ and fuzz/ file by file" OFF)

# Called once, at the end of the top-level CMakeLists.txt.
function(gport_plain_builds)
  if(NOT CMAKE_UNITY_BUILD OR NOT (GPORT_PLAIN_PRODUCTION OR GPORT_PLAIN_TESTS))
    return()
  endif()
  gport_targets_below("${CMAKE_SOURCE_DIR}" targets)  # cmake/GportPch.cmake
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    if(type STREQUAL "INTERFACE_LIBRARY" OR type STREQUAL "UTILITY")
      continue()
    endif()
    get_target_property(dir ${target} SOURCE_DIR)
    file(RELATIVE_PATH where "${CMAKE_SOURCE_DIR}" "${dir}")
    if(where MATCHES "^(tests|bench|fuzz)(/|$)")
      set(plain ${GPORT_PLAIN_TESTS})
    else()
      set(plain ${GPORT_PLAIN_PRODUCTION})
    endif()
    if(plain)
      set_target_properties(${target} PROPERTIES UNITY_BUILD OFF)
    endif()
  endforeach()
endfunction()
