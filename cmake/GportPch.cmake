# GPORT_PCH: one precompiled header of the heavy third-party headers
# (GoogleTest, Boost.Asio, nlohmann-json, spdlog, fmt and the standard
# library's), built once and reused by every C++ target of the build that
# has a few sources. For clang only: scripts/test.sh's sanitizer build
# (clang-14, -O0), where the front end is about half of a unit's time and
# clang loads a precompiled header lazily. Measured there: tests/daemon's
# unit 35.0 s of CPU without it, 25.6 s with it; the header costs 9.4 s
# once. GCC loads the whole header for every unit: with g++ it saved
# nothing (docs/operations.md, "How CI spends its time"), so it is refused.
#
# What cannot share it is left out: the libraries instrumented for the
# fuzzers and the fuzzers (-O1 and the coverage flags), the shared library
# and the code compiled into it (-fPIC), all of which clang checks against
# the header's flags, and targets of one or two sources (loading the
# header costs about what it saves there). The header's macros (those of
# spdlog, fmt, GoogleTest and Asio) are then defined in every unit that
# uses it: each only selects how its library is linked or configured, the
# same for every target of this project.
option(GPORT_PCH "Share one precompiled header of the third-party headers (clang only)" OFF)

# The targets defined in DIR and below, into OUT.
function(gport_targets_below dir out)
  get_property(targets DIRECTORY "${dir}" PROPERTY BUILDSYSTEM_TARGETS)
  get_property(subdirs DIRECTORY "${dir}" PROPERTY SUBDIRECTORIES)
  foreach(sub IN LISTS subdirs)
    gport_targets_below("${sub}" more)
    list(APPEND targets ${more})
  endforeach()
  set(${out} ${targets} PARENT_SCOPE)
endfunction()

# Called once, at the end of the top-level CMakeLists.txt, when every
# target is defined.
function(gport_share_pch)
  if(NOT GPORT_PCH)
    return()
  endif()
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "GPORT_PCH=ON is for clang (g++ gains nothing from it); "
                        "the compiler is ${CMAKE_CXX_COMPILER_ID}")
  endif()
  gport_targets_below("${CMAKE_SOURCE_DIR}" targets)
  add_library(gport_pch STATIC "${CMAKE_SOURCE_DIR}/cmake/pch.cpp")
  target_compile_features(gport_pch PRIVATE cxx_std_20)
  target_link_libraries(gport_pch PRIVATE gport::asio nlohmann_json::nlohmann_json
                                          spdlog::spdlog fmt::fmt)
  if(TARGET GTest::gmock)
    target_link_libraries(gport_pch PRIVATE GTest::gmock)
    set(gtest_headers <gmock/gmock.h> <gtest/gtest.h>)
  endif()
  target_precompile_headers(gport_pch PRIVATE
    ${gtest_headers} <boost/asio.hpp> <nlohmann/json.hpp> <spdlog/spdlog.h>
    <fmt/format.h> <chrono> <functional> <map> <memory> <optional> <string> <vector>)
  foreach(target IN LISTS targets)
    get_target_property(type ${target} TYPE)
    get_target_property(fuzzing ${target} GPORT_FUZZ_INSTRUMENTED)
    get_target_property(pic ${target} POSITION_INDEPENDENT_CODE)
    get_target_property(options ${target} COMPILE_OPTIONS)
    get_target_property(sources ${target} SOURCES)
    list(FILTER sources INCLUDE REGEX "\\.cpp$")
    list(LENGTH sources count)
    if(NOT type MATCHES "^(STATIC_LIBRARY|EXECUTABLE)$" OR pic OR fuzzing
       OR "${options}" MATCHES "fuzzer" OR count LESS 3)
      continue()
    endif()
    target_precompile_headers(${target} REUSE_FROM gport_pch)
  endforeach()
endfunction()
