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

# gport_test_code(<target> [UBSAN]): code that only tests is built at -O1 in a
# Release build and at -O0 in the sanitizer (RelWithDebInfo) build, while the
# code under test, in its libraries and programs, keeps the build's level.
# The suites' unity units are the largest of the build: tests/cli's took
# 104 s at -O3, 69 s at -O1. Under ASan+UBSan clang-14 takes three times as
# long at -O1 as at -O0 (tests/ipc's unit: 107 s against 34 s), and there
# the suites' speed matters less than anywhere. -O0 in Release saved a
# quarter of the compile (45 s against 34 s) but not its cost: the tests
# that generate their own load (a flood of 300,000 notifications, random
# frames) ran up to six times as long under qemu (the armhf suites: 463 s
# against 173 s).
# (A precompiled header for GoogleTest, Asio, nlohmann-json and spdlog saved
# 4.5 s of a 77 s unit and costs 24 s and 200 MB per build: not used.)
# In the sanitizer build (GPORT_SANITIZE), code that only tests keeps
# AddressSanitizer but not UBSan's checks, unless UBSAN is given: UBSan's
# instrumentation is a quarter to a third of a test unit's compile at -O0
# (tests/cli's run_test.cpp: 13.4 s of CPU with it, 10.2 s without; about
# 200 CPU-s of the build), and what it checks there is the tests' own
# arithmetic. The code under test keeps every check: the libraries and
# programs are compiled with both sanitizers, and the end-to-end suites drive
# the programs so built. The suites that call header code on wire bytes, disk
# records and numbers (protocol, base, capture, config, the MAVLink codec and
# signing, the client's codec, which compiles its sources itself) pass UBSAN,
# so that the inline code they instantiate is checked too. The executables
# still link UBSan's runtime (add_link_options in CMakeLists.txt).
function(gport_test_code target)
  target_compile_options(${target} PRIVATE $<$<CONFIG:Release>:-O1> $<$<CONFIG:RelWithDebInfo>:-O0>)
  if(GPORT_SANITIZE AND NOT "UBSAN" IN_LIST ARGN)
    target_compile_options(${target} PRIVATE -fno-sanitize=undefined)
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

# The GoogleTest executables built and registered: `all`, or a list of their
# names (the others are still defined, so their folders configure, but not
# built). scripts/test.sh's Release stage lists the suites that drive the
# programs end to end; every suite runs in its ASan+UBSan stage.
set(GPORT_GTEST_SUITES "all" CACHE STRING
    "The GoogleTest executables to build and register: all, or a list of names")
# How CTest runs a GoogleTest executable's tests. 0 (the default): each test
# is a CTest test of its own, one process per test (gtest_discover_tests), as
# a developer wants them: ctest -R one test, its own timeout and output. N:
# the executable is N CTest tests, <name>/<i> of N, each a process that runs
# every Nth of its tests (GoogleTest's sharding), so that all run once. CI
# sets it for the sanitizer and ARM builds, where a process costs ~0.1 s of
# CPU before its first test (ASan's and LSan's set-up and exit; qemu-user
# translating the loader): over their 2,100 tests, minutes of CPU on two
# cores. docs/operations.md, "How CI spends its time".
set(GPORT_TEST_SHARDS 0 CACHE STRING
    "0: one CTest test per GoogleTest test; N: each GoogleTest executable as N CTest tests")

# gport_add_test(<name> [UBSAN] SOURCES ... [LIBS ...] [LABELS ...] [TIMEOUT s])
# Builds a GoogleTest executable and registers each of its tests with CTest
# (when GPORT_GTEST_SUITES names it). UBSAN: see gport_test_code.
function(gport_add_test name)
  cmake_parse_arguments(ARG "UBSAN" "TIMEOUT" "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gmock GTest::gtest_main)
  gport_set_warnings(${name})
  if(ARG_UBSAN)
    gport_test_code(${name} UBSAN)
  else()
    gport_test_code(${name})
  endif()
  if(NOT GPORT_GTEST_SUITES STREQUAL "all" AND NOT "${name}" IN_LIST GPORT_GTEST_SUITES)
    set_target_properties(${name} PROPERTIES EXCLUDE_FROM_ALL ON)
    return()
  endif()
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 120)
  endif()
  if(GPORT_TEST_SHARDS GREATER 0)
    gport_add_test_shards(${name} "${ARG_LABELS}" ${ARG_TIMEOUT})
  else()
    gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60
                         PROPERTIES LABELS "${ARG_LABELS}" TIMEOUT ${ARG_TIMEOUT})
  endif()
endfunction()

# The executable `name` as GPORT_TEST_SHARDS CTest tests (see above). A shard
# runs many tests, so it may take as long as several of them: its timeout is
# ten times a test's. A test GoogleTest skips is counted in the shard's
# output, not as a skipped CTest test; a failing one fails its shard, whose
# output (--output-on-failure) names it.
function(gport_add_test_shards name labels timeout)
  math(EXPR last "${GPORT_TEST_SHARDS} - 1")
  math(EXPR shard_timeout "${timeout} * 10")
  foreach(index RANGE ${last})
    set(test "${name}/${index}")
    add_test(NAME ${test} COMMAND ${name})
    set_tests_properties(${test} PROPERTIES
      LABELS "${labels}" TIMEOUT ${shard_timeout}
      ENVIRONMENT "GTEST_TOTAL_SHARDS=${GPORT_TEST_SHARDS};GTEST_SHARD_INDEX=${index}")
  endforeach()
endfunction()

# gport_install_program(<target>): installs a program to ${CMAKE_INSTALL_BINDIR}
# so that it starts from any prefix (cmake --install --prefix ~/.local/gportd, or a
# tree moved elsewhere afterwards): its RUNPATH names the library directory
# relative to the program ($ORIGIN/../lib/<multiarch>), where libgport-client
# is installed beside it. Under prefix /usr (the .deb) the RUNPATH is removed
# at install time: the dynamic loader searches /usr/lib/<multiarch> anyway,
# and Debian policy (10.2) asks packages not to carry one. docs/operations.md,
# "Installing from source", explains it.
function(gport_install_program target)
  if(IS_ABSOLUTE "${CMAKE_INSTALL_LIBDIR}")
    set(libdir "${CMAKE_INSTALL_LIBDIR}")
  else()
    file(RELATIVE_PATH relative "/prefix/${CMAKE_INSTALL_BINDIR}"
         "/prefix/${CMAKE_INSTALL_LIBDIR}")
    set(libdir "$ORIGIN/${relative}")
  endif()
  set_target_properties(${target} PROPERTIES INSTALL_RPATH "${libdir}")
  install(TARGETS ${target} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  set(name "$<TARGET_FILE_NAME:${target}>")
  install(CODE "
    if(CMAKE_INSTALL_PREFIX STREQUAL \"/usr\")
      set(_program \"\$ENV{DESTDIR}/usr/${CMAKE_INSTALL_BINDIR}/${name}\")
      if(IS_ABSOLUTE \"${CMAKE_INSTALL_BINDIR}\")
        set(_program \"\$ENV{DESTDIR}${CMAKE_INSTALL_BINDIR}/${name}\")
      endif()
      file(RPATH_REMOVE FILE \"\${_program}\")
    endif()
  ")
endfunction()
