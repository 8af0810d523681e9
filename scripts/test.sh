#!/usr/bin/env bash
# Runs the README's demo, checks the layering, installs what is missing, then
# builds and runs every test:
#   D. scripts/demo.sh, the README's first command, on the clean checkout as a
#      newcomer runs it (its own packages, its plain build, no warning);
#   0. scripts/check-layering.sh: every include and CMake link is on its folder's
#      allow-list (docs/architecture.md, "Layout"; seconds);
#   1. Release build (warnings are errors): first, alone, the
#      interoperability suites (ArduCopter and PX4 SITL, node-mavlink,
#      Python, chromium) and the benchmarks; then the end-to-end, packaging
#      and source-check tests (the in-process suites run in stage 2); then the
#      systemd end-to-end test on its .deb: a real systemd booted in a
#      container (scripts/systemd-e2e.sh; GPORT_SYSTEMD_E2E=skip leaves it
#      out, =require fails if this machine cannot run it);
#   2. ASan+UBSan build with clang-14, the libFuzzer targets in it; every
#      test (but the source checks and the browser test of stage 1);
#   3. each fuzzer for $GPORT_FUZZ_SECONDS (12) on its corpus, one per core
#      at a time;
#   4. ARM (scripts/test-arm.sh): armhf cross build, the suites of the code
#      a 32-bit ABI changes under qemu-user and its .deb; arm64 cross build
#      of its base and protocol suites, run under qemu-user (no arm64 .deb:
#      GPORT_ARM_DEB=armhf below; GPORT_ARM=skip leaves both out).
# The builds of stages 2 and 4 run in the background at idle priority from
# the end of stage 1's interoperability tests, while the tests of the stages
# before theirs run (see "the later builds" below).
# What waits on the network rather than the CPU runs beside the demo's build
# (once it is configured) and the Release build, each with its log in
# build/ci-logs: what the Release build compiles with (apt), the rest of the
# packages (apt; then chromium for gport-web's browser test), the ARM
# sysroots, the e2e stage's Debian root and the npm installs of the tests
# (npm ci: node-mavlink, playwright-core).
# docs/operations.md, "How CI spends its time", has the figures behind these
# choices.
# Used word for word by .ci/run. The builds are unity builds (each target's
# sources compiled as one unit), which halves the compile time on a 2-core
# machine, but for the Release build's production code (shared with the
# demo's plain build through ccache) and the sanitizer build's tests: every
# source compiles on its own in one of the two (GPORT_PLAIN_PRODUCTION,
# GPORT_PLAIN_TESTS; cmake/GportPlainProduction.cmake).
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
# Each stage's name and start; the table of their times is printed at the
# end, and on failure up to the stage that failed.
stage_names=()
stage_starts=()
stage() {
  echo
  echo "== $* ($(($(date +%s) - start)) s)"
  stage_names+=("$*")
  stage_starts+=("$(date +%s)")
}
stage_table() {
  local status=$? now i next
  now=$(date +%s)
  echo
  echo "== Stage times (exit $status)"
  for i in "${!stage_names[@]}"; do
    next=${stage_starts[$((i + 1))]:-$now}
    printf '%6d s  %s\n' "$((next - stage_starts[i]))" "${stage_names[$i]%% (*}"
  done
  printf '%6d s  total\n' "$((now - start))"
  # Whatever still runs beside (after a failure) goes with us.
  jobs -p | xargs -r kill 2>/dev/null || true
}
trap stage_table EXIT

logs=build/ci-logs
mkdir -p "$logs"

source scripts/deps.sh
arm_arches=()
# armhf first: it runs more tests, so its build is awaited first.
[ "${GPORT_ARM:-}" = skip ] || arm_arches=(armhf arm64)
mapfile -t cross_packages < <(gport_cross_packages "${arm_arches[@]}")
# Only armhf's programs are built and packaged: the arm64 .deb's build was
# 4.5 minutes of the critical path for what armhf's checks (scripts/test-arm.sh).
export GPORT_ARM_DEB=armhf

jobs=$(nproc)
fuzz_seconds=${GPORT_FUZZ_SECONDS:-12}

# beside NAME CMD...: runs CMD in the background, its output in
# build/ci-logs/NAME.log; await NAME waits for it and fails, printing the log,
# if it failed.
declare -A beside_pids=()
beside() {
  local name=$1
  shift
  "$@" >"$logs/$name.log" 2>&1 &
  beside_pids[$name]=$!
}
await() {
  local name=$1 status=0
  wait "${beside_pids[$name]}" || status=$?
  if [ "$status" -ne 0 ] && [ "$status" -ne "${2:-0}" ]; then
    cat "$logs/$name.log"
    echo "error: $name failed (exit $status; log $logs/$name.log)" >&2
    exit 1
  fi
  return "$status"
}
# The node-mavlink install of the peer tests in BUILD (the folder
# tests/mavlink/peer/CMakeLists.txt names; a test would otherwise run it).
npm_install() { tests/mavlink/peer/run.sh "$1/tests/mavlink/peer/mavlink-peer" --install-only; }
# playwright-core for gport-web's browser test (tests/web/browser; the
# Release stage only runs it).
npm_install_browser() { tests/web/browser/run.sh "$1/tests/web/browser/web-browser" --install-only; }
# What waits on the network, beside the demo's build and the Release build:
# what the Release build compiles with (apt; then the marker
# installed-release-build), the rest of the packages (apt), then at once
# chromium (apt), the ARM sysroots, the e2e stage's Debian root
# (debootstrap) and the npm installs.
prepare_rest() {
  gport_install_deps release-build
  touch "$logs/installed-release-build"
  gport_install_deps all "${cross_packages[@]}"
  beside browser gport_install_deps browser
  for arch in "${arm_arches[@]}"; do
    beside "sysroot-$arch" scripts/cross-sysroot.sh "$arch" "${GPORT_SYSROOTS:-/var/cache/gport}/sysroot-$arch"
  done
  beside e2e-root scripts/systemd-e2e.sh --root-only
  beside npm-release npm_install build/release
  beside npm-browser npm_install_browser build/release
  local name
  for name in "${!beside_pids[@]}"; do
    # a skip (77) of the e2e root is reported by the e2e stage itself
    await "$name" 77 || true
  done
}

# ---- the README's first command, first, as a newcomer runs it --------------
# scripts/demo.sh on the clean checkout, before anything else is installed:
# its own package set (gport_install_deps build), its plain build (every
# source of gportd, gportctl and gport-sim compiled on its own), the daemon
# on its simulated gimbal, and an output with no warning in it. The one
# thing added is ccache, through CMake's CMAKE_CXX_COMPILER_LAUNCHER
# environment variable: the Release build below compiles the programs' sources
# file by file too, with the same commands (GPORT_PLAIN_PRODUCTION), and gets
# the demo's objects from the cache instead of compiling them again. The
# cache is this run's own (build/ccache), so nothing from another run counts.
# Once the demo compiles (its packages installed, its build configured:
# nothing installed after that changes what it found), what waits on the
# network starts beside it (prepare_rest).
stage "README demo (scripts/demo.sh: its own packages, its plain build)"
rm -f "$logs"/installed-*
command -v ccache >/dev/null || {
  DEBIAN_FRONTEND=noninteractive apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends ccache
}
export CCACHE_DIR=$PWD/build/ccache CCACHE_BASEDIR=$PWD CCACHE_NOHASHDIR=1 CCACHE_MAXSIZE=4G
: >"$logs/demo.log"
(
  set -o pipefail
  CMAKE_CXX_COMPILER_LAUNCHER=ccache scripts/demo.sh 2>&1 | tee "$logs/demo.log"
) &
demo_pid=$!
until grep -q "^== building" "$logs/demo.log" || ! kill -0 "$demo_pid" 2>/dev/null; do
  sleep 1
done
beside prepare prepare_rest
wait "$demo_pid" || { echo "error: the README's demo failed (log $logs/demo.log)" >&2; exit 1; }
if grep -nE "CMake (Warning|Deprecation)|: warning:" "$logs/demo.log"; then
  echo "error: the README's demo printed the warnings above (log $logs/demo.log)" >&2
  exit 1
fi
echo "(the demo's build: $(ccache --show-stats 2>/dev/null | grep -iE "^ *(cache )?(misses|hits)" | tr -s ' ' | paste -sd';' -))"

stage "Layering"
scripts/check-layering.sh

# The Release build runs what tests the programs as they ship: the suites
# that drive gportd, gport-sim, gportctl, gport-web and the client library
# end to end (integration, client, web; the RSS budgets, which mean nothing
# under ASan, among them), the interoperability suites (ArduCopter and PX4
# SITL, node-mavlink, Python, chromium), the benchmarks, the packaging and
# the source checks. The in-process suites (base, protocol, config, daemon,
# ipc, cli, mavlink, ...) run in the ASan+UBSan stage, and the unit ones
# again on armhf: in the Release build they would only repeat the check.
release_suites='integration_tests;client_tests;client_hostile_tests;web_tests'

# The programs and their libraries are compiled file by file
# (GPORT_PLAIN_PRODUCTION; the tests in unity units), with the demo's compile
# commands: ccache gives back the demo's objects. So that those commands are
# the demo's, -Werror is not among them; a warning fails the stage all the
# same (a cached object's warnings are printed again).
stage "Release build"
# What it compiles with, installed beside the demo (prepare_rest).
until [ -e "$logs/installed-release-build" ]; do
  kill -0 "${beside_pids[prepare]}" 2>/dev/null || { await prepare; break; }
  sleep 1
done
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER_LAUNCHER=ccache \
  -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=16 -DGPORT_PLAIN_PRODUCTION=ON \
  -DGPORT_GTEST_SUITES="$release_suites"
cmake --build build/release -j "$jobs" 2>&1 | tee "$logs/release-build.log"
if grep -n ": warning:" "$logs/release-build.log" | grep -v "^[0-9]*:ninja: "; then
  echo "error: the Release build has the warnings above (log $logs/release-build.log)" >&2
  exit 1
fi
echo "(ccache, demo and Release builds: $(ccache --show-stats 2>/dev/null | grep -iE "^ *(cache )?(misses|hits)" | tr -s ' ' | paste -sd';' -))"
# The tests that talk to another implementation at its own pace (ArduCopter
# and PX4 SITL, node-mavlink, the Python client, chromium) and the
# benchmarks run alone: with a build beside them (even a niced one) SITL and
# the peer tests failed on timing. Everything after them runs with the later
# builds in the background (below).
interop_labels='^(sitl|node|python|browser|bench)$'
stage "Release tests: interoperability and benchmarks, alone"
await prepare
ctest --test-dir build/release --output-on-failure -j "$jobs" -L "$interop_labels"

# ---- the later builds, in the background at idle priority ---------------------
# The ASan+UBSan build, then armhf's and arm64's, one after another under
# SCHED_IDLE (chrt --idle) and the idle I/O class: they get only the CPU no
# test wants, which is most of it while the suites wait on timers and
# sockets, and each stage below starts when its own build is done
# (await_built). One clang-14 build serves the sanitizers and the fuzzers:
# the libraries the fuzzers link are instrumented for both. It is -O0 (a
# third of -O1's compile time; the suites wait on timers, not on the CPU)
# but for the code the fuzzers run, which fuzz/CMakeLists.txt keeps at -O1;
# its targets share one precompiled header of the third-party headers
# (GPORT_PCH, cmake/GportPch.cmake: at -O0 the front end is half of a unit).
# Code that only tests keeps ASan but not UBSan's checks, but for the suites
# on wire bytes, records and numbers (gport_test_code, cmake/GportHelpers.cmake):
# the libraries and programs under test keep both.
# Its tests, benchmarks and fuzzers are compiled file by file
# (GPORT_PLAIN_TESTS), the production code in unity units: with the Release
# build's plain production code, every source compiles on its own somewhere
# (the shared header holds only third-party and standard headers, so a
# missing include of the project's own still fails). Each GoogleTest
# executable runs as 8 processes, not one per test (GPORT_TEST_SHARDS,
# cmake/GportHelpers.cmake): a process under ASan and LSan costs ~0.1 s of
# CPU before its first test.
asan_build() {
  CC=clang-14 CXX=clang++-14 cmake -S . -B build/asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DGPORT_SANITIZE=ON -DGPORT_BUILD_FUZZ=ON -DGPORT_BUILD_BENCH=OFF -DGPORT_WERROR=ON \
    -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=16 -DGPORT_PLAIN_TESTS=ON \
    -DGPORT_SITL_TESTS=OFF -DGPORT_PCH=ON -DGPORT_TEST_SHARDS=8 \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O0 -g1"
  # node-mavlink: the Release tree's install, copied (the same lock file), so
  # npm_install finds it done. npm ci again revalidated its cache with the
  # registry: two minutes at the head of this build in a fresh root.
  local peer=tests/mavlink/peer/mavlink-peer
  mkdir -p "build/asan/$peer"
  cp -a "build/release/$peer/." "build/asan/$peer/" 2>/dev/null || true
  npm_install build/asan
  cmake --build build/asan -j "$jobs"
}
later_builds() {
  chrt --idle --pid 0 "$BASHPID" || echo "warning: the later builds run at normal priority (chrt --idle failed)"
  ionice -c 3 -p "$BASHPID" || true  # where the I/O scheduler has classes
  echo "== ASan+UBSan build (clang-14), the fuzzers with it"
  asan_build
  touch "$logs/built-asan"
  local arch
  for arch in "${arm_arches[@]}"; do
    echo "== $arch build"
    scripts/test-arm.sh --build "$arch"
    touch "$logs/built-$arch"
  done
}
# await_built NAME: waits until the background builds have finished NAME's;
# fails, printing their log, if they stopped without it.
await_built() {
  local marker=$logs/built-$1
  while [ ! -e "$marker" ]; do
    if ! kill -0 "${beside_pids[later-builds]}" 2>/dev/null; then
      [ -e "$marker" ] && return 0
      await later-builds
      echo "error: the background builds ended without $1's (log $logs/later-builds.log)" >&2
      exit 1
    fi
    sleep 2
  done
  echo "($1's build done, in the background: $logs/later-builds.log)"
}
rm -f "$logs"/built-*
beside later-builds later_builds

stage "Release tests: the rest"
ctest --test-dir build/release --output-on-failure -j "$jobs" -LE "$interop_labels"

stage "systemd end-to-end (the Release build's .deb on a real systemd, in a container)"
e2e_status=0
scripts/systemd-e2e.sh build/release || e2e_status=$?
if [ "$e2e_status" -eq 77 ]; then
  echo "systemd end-to-end: SKIPPED (the reason is above)"
elif [ "$e2e_status" -ne 0 ]; then
  echo "systemd end-to-end: FAILED" >&2
  exit "$e2e_status"
fi

stage "ASan+UBSan tests (clang-14; built in the background)"
await_built asan
# The checks of the sources themselves (layering, man pages, mypy: label
# typecheck) and of what is installed and packaged (label install: the
# .deb, the install tree, a consumer of the installed client library, the
# Python package in a venv) ran in the Release stage: they do not depend on
# how the code was built. So did the browser test: a chromium beside an
# instrumented gport-web on two cores measures the machine, not the page;
# gport-web's own suites (every request and WebSocket path, the attacks) run
# here under the sanitizers. So did the Python suites (label python): their
# code is Python, not instrumented, and gportd under them is driven here by
# the C++ client's suites (35 s of the stage's tests for nothing new).
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build/asan --output-on-failure -j "$jobs" -LE '^(layering|man|typecheck|install|browser|python)$'

# One fuzzer per corpus folder: fuzz/corpus/<name>/ seeds <name>_fuzz.
fuzzers=()
for corpus in fuzz/corpus/*/; do
  fuzzers+=("$(basename "$corpus")_fuzz")
done
# Each fuzzer runs for its full time; $jobs of them at once (they are
# single-threaded), each log printed when it ends.
fuzz_one() {
  local name=$1 work log
  work=$(mktemp -d)
  log=$(mktemp)
  cp -r "fuzz/corpus/$name/". "$work/"
  if ! "build/asan/fuzz/${name}_fuzz" -max_total_time="$fuzz_seconds" -print_final_stats=1 \
      "$work" >"$log" 2>&1; then
    echo "== ${name}_fuzz FAILED"
    tail -n 60 "$log"
    rm -rf "$work" "$log"
    return 1
  fi
  echo "== ${name}_fuzz: ${fuzz_seconds} s"
  grep -E "^#[0-9]+.*(DONE|pulse)|stat::number_of_executed_units|stat::peak_rss_mb" "$log" |
    tail -n 3 || true
  rm -rf "$work" "$log"
}
stage "Fuzzing ${#fuzzers[@]} fuzzers for ${fuzz_seconds} s each, $jobs at a time"
pids=()
failed=0
for corpus in fuzz/corpus/*/; do
  if [ ${#pids[@]} -ge "$jobs" ]; then
    wait "${pids[0]}" || failed=1
    pids=("${pids[@]:1}")
  fi
  fuzz_one "$(basename "$corpus")" &
  pids+=($!)
done
for pid in "${pids[@]}"; do
  wait "$pid" || failed=1
done
[ "$failed" -eq 0 ] || { echo "a fuzzer failed (above)" >&2; exit 1; }

if [ "${GPORT_ARM:-}" = skip ]; then
  stage "ARM stages: SKIPPED (GPORT_ARM=skip)"
else
  for arch in "${arm_arches[@]}"; do
    stage "$arch tests under qemu (scripts/test-arm.sh; built in the background)"
    await_built "$arch"
    scripts/test-arm.sh --test "$arch"
  done
fi
await later-builds

stage "All tests passed"
