# Shared build helpers: one place for warnings, sanitizers and test registration.

# gport_set_warnings(<target> [STRICT]): the project's warning set, clean on
# g++ and clang. STRICT adds the integer conversion warnings, used for the pure
# code that handles wire bytes.
function(gport_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow
                                           -Wnon-virtual-dtor -Wcast-align)
  if("STRICT" IN_LIST ARGN)
    target_compile_options(${target} PRIVATE -Wconversion -Wsign-conversion -Wold-style-cast)
  endif()
  if(GPORT_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# gport_add_library(<name> <alias> [STRICT] SOURCES ... [PUBLIC_LIBS ...] [PRIVATE_LIBS ...])
# Declares a static library with include/ as its public include directory and
# an alias gport::<alias>.
function(gport_add_library name alias)
  cmake_parse_arguments(ARG "STRICT" "" "SOURCES;PUBLIC_LIBS;PRIVATE_LIBS" ${ARGN})
  add_library(${name} STATIC ${ARG_SOURCES})
  add_library(gport::${alias} ALIAS ${name})
  target_include_directories(${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_compile_features(${name} PUBLIC cxx_std_20)
  target_link_libraries(${name} PUBLIC ${ARG_PUBLIC_LIBS} PRIVATE ${ARG_PRIVATE_LIBS})
  if(ARG_STRICT)
    gport_set_warnings(${name} STRICT)
  else()
    gport_set_warnings(${name})
  endif()
endfunction()

# gport_add_test(<name> SOURCES ... [LIBS ...] [LABELS ...] [TIMEOUT s])
# Builds a GoogleTest executable and registers each of its tests with CTest.
function(gport_add_test name)
  cmake_parse_arguments(ARG "" "TIMEOUT" "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gmock GTest::gtest_main)
  gport_set_warnings(${name})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 120)
  endif()
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60
                       PROPERTIES LABELS "${ARG_LABELS}" TIMEOUT ${ARG_TIMEOUT})
endfunction()
