#!/usr/bin/env bash
# The ARM stages of scripts/test.sh: gportd cross-built on this (amd64) machine
# for the companion computers it is deployed on, its tests run under qemu-user
# (docs/operations.md, "Building for ARM"):
#   arm64 (Raspberry Pi 4/5, Jetson): Release build (-O1, below), warnings
#         are errors, the base and protocol suites under qemu-aarch64, and
#         its .deb checked (unless GPORT_ARM_DEB leaves arm64 out: then
#         only those suites are built);
#   armhf (32-bit Raspberry Pi OS): Release build (-O1), warnings are
#         errors, the suites of the code a 32-bit ABI changes under
#         qemu-arm (below), and its .deb checked.
#   scripts/test-arm.sh [--build|--test] [arm64] [armhf]   # both, build and test
# (--build only builds, --test only runs the tests of a finished build:
# scripts/test.sh builds in the background while other stages test.)
# The target's libraries come from a sysroot (scripts/cross-sysroot.sh, in
# $GPORT_SYSROOTS, default /var/cache/gport: readable by every user, as the
# tests that run gportd as another uid need its loader), never from this
# machine's dpkg. Needs root (the cross
# compilers, qemu-user-static and its binfmt_misc entries).
# The unit suites run through the emulator CMake names (CMAKE_CROSSCOMPILING_
# EMULATOR); the .deb's check starts the target's programs by path, which
# needs binfmt_misc: where it cannot be set up (an unprivileged container)
# that check is reported SKIPPED (GPORT_ARM=require makes that a failure).
# Why arm64 runs fewer suites than armhf: what an emulated arm64 can tell
# beyond amd64 (LP64 and little-endian both) and armhf is ARM's unsigned
# char and the aarch64 ABI, and on armhf the unit suites also meet a 32-bit
# size_t, a 64-bit time_t on a 32-bit ABI and the soft alignment of ARM:
# arm64 builds everything with warnings as errors, makes and checks its
# .deb and runs the base and protocol suites (the wire bytes); the
# end-to-end suites run on amd64, natively and under ASan. Until 2026-11-28
# arm64 ran every suite under qemu as well (1217 tests, 290 s, and 270 s of
# building them); what that found was about tests under emulation (timing,
# qemu-user's own limits: git log --grep=qemu), not about the code on arm64.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/deps.sh

steps=(build test)
case "${1:-}" in
  --build) steps=(build); shift ;;
  --test) steps=(test); shift ;;
esac
arches=("$@")
[ ${#arches[@]} -gt 0 ] || arches=(arm64 armhf)
wants() { [[ " ${steps[*]} " == *" $1 "* ]]; }
jobs=$(nproc)
sysroots=${GPORT_SYSROOTS:-/var/cache/gport}
mkdir -p "$sysroots"
chmod 755 "$sysroots"
start=$(date +%s)
stage() { echo; echo "== $* ($(($(date +%s) - start)) s)"; }

# The optimisation of the programs and libraries: -O1 (the test code is
# -O1 anyway, cmake/GportHelpers.cmake). What these stages check does not
# depend on -O2: the target's ABI (32-bit size_t and time_t, unsigned char,
# alignment) under the unit suites, the cross toolchain's warnings and the
# .deb's contents; the amd64 Release build checks -O2's code. It saves a
# quarter of the ARM builds' compile (daemon's unity unit for arm64: 22.4 s
# of CPU at -O2, 17.2 s at -O1); they are about a third of CI's CPU. A package to
# install is built at -O2 (docs/operations.md, "Building for ARM");
# GPORT_ARM_RELEASE_FLAGS='-O2 -DNDEBUG' builds these so.
release_flags=${GPORT_ARM_RELEASE_FLAGS:--O1 -DNDEBUG}

# The architectures whose programs are built and whose .deb is made and
# checked (default: both). scripts/test.sh sets GPORT_ARM_DEB=armhf: the
# arm64 .deb's build was 4.5 minutes of a fresh CI run's critical path for
# what armhf's already checks (the same packaging, cross-built; warnings as
# errors with the stricter 32-bit ABI and ARM's alignment and unsigned char),
# so CI builds for arm64 only its suites. docs/operations.md, "How CI spends
# its time".
deb_arches=" ${GPORT_ARM_DEB-arm64 armhf} "
makes_deb() { [[ "$deb_arches" == *" $1 "* ]]; }

# The suites each runs, the test folders each builds for them and the
# GoogleTest executables built (the programs and libraries are always
# built, warnings as errors; systemd/ is there for the .deb's check, not its
# GoogleTest suite). armhf runs the suites of the code a 32-bit ABI changes:
# sizes, offsets, times and counters on the wire, on disk and in shared
# memory (base: the futex's time64 call, the token bucket; protocol; config's
# numbers; capture's records; ipc: the ring, its limits and the session's
# buffers), and the client library's decoding, its shared-memory reader and
# its bounds against a lying server (client_codec, client_channel,
# client_hostile). Left out, as the amd64 stages run them natively and under
# ASan: the motion policy and the core (daemon_tests), gportctl (cli_tests),
# the composition root (app_tests), the client's calls against a live
# gportd (client_tests), gport-sim's and gportctl monitor's drawing. What
# armhf ever found was in the kept suites (base's time64 futex) or in the
# build's warnings (git log --grep=armhf); the four left out took about 180
# s of the stage's CPU (100 s to build, 100 s of tests under qemu).
declare -A labels=(
  [armhf]='^(base|protocol|config|capture|ipc|client)$'
  [arm64]='^(base|protocol)$'
)
declare -A parts=(
  [armhf]='base;protocol;config;capture;ipc;systemd;client'
  [arm64]='base;protocol;systemd'
)
declare -A suites=(
  [armhf]='base_tests;protocol_tests;config_tests;capture_tests;ipc_tests;client_channel_tests;client_codec_tests;client_hostile_tests'
  [arm64]='base_tests;protocol_tests'
)

# Each GoogleTest executable runs under qemu as 8 processes, each a share
# of its tests, not one process per test (GPORT_TEST_SHARDS, cmake/
# GportHelpers.cmake): qemu-user spends ~0.1 s of CPU and ~0.2 s translating
# the loader and start-up of every process. GPORT_TEST_SHARDS=0 gives one
# per test again (ctest -R a single test).
shards=${GPORT_TEST_SHARDS:-8}

stage "ARM: cross compilers and qemu-user for ${arches[*]}"
gport_install_cross_deps "${arches[@]}"
declare -A by_path=()
if wants test; then
  for arch in "${arches[@]}"; do
    by_path[$arch]=yes
    gport_register_binfmt "$(gport_qemu_arch "$arch")" || by_path[$arch]=no
    if [ "${by_path[$arch]}" = no ] && [ "${GPORT_ARM:-}" = require ]; then
      echo "error: binfmt_misc is needed for the $arch .deb check (GPORT_ARM=require)" >&2
      exit 1
    fi
  done
fi

for arch in "${arches[@]}"; do
  triple=$(gport_cross_triple "$arch")
  sysroot=$sysroots/sysroot-$arch
  build=build/$arch

  if wants build; then
    stage "$arch: sysroot"
    scripts/cross-sysroot.sh "$arch" "$sysroot"

    stage "$arch: Release build ($triple)"
    cmake -S . -B "$build" -G Ninja -DCMAKE_TOOLCHAIN_FILE="cmake/toolchains/$triple.cmake" \
      -DGPORT_SYSROOT="$sysroot" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="$release_flags" \
      -DGPORT_WERROR=ON -DGPORT_TEST_SHARDS="$shards" \
      -DGPORT_BUILD_BENCH=OFF -DGPORT_SITL_TESTS=OFF -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=16 \
      -DGPORT_TEST_PARTS="${parts[$arch]}" -DGPORT_GTEST_SUITES="${suites[$arch]}"
    if makes_deb "$arch"; then
      cmake --build "$build" -j "$jobs"
    else
      # only the suites' executables (and what they link)
      cmake --build "$build" -j "$jobs" --target ${suites[$arch]//;/ }
    fi
  fi

  if wants test; then
    # The target's loader and glibc for everything qemu runs, the programs the
    # .deb's check starts by path (through binfmt_misc) included.
    export QEMU_LD_PREFIX=$sysroot
    stage "$arch: the suites ${labels[$arch]} under qemu"
    ctest --test-dir "$build" --output-on-failure -j "$jobs" -L "${labels[$arch]}"
    if ! makes_deb "$arch"; then
      stage "$arch: no .deb (GPORT_ARM_DEB=${GPORT_ARM_DEB-})"
    elif [ "${by_path[$arch]}" = no ]; then
      stage "$arch: the .deb's check SKIPPED (no binfmt_misc, above)"
    else
      stage "$arch: the .deb"
      ctest --test-dir "$build" --output-on-failure -R '^systemd_deb_package$'
    fi
    unset QEMU_LD_PREFIX
  fi
done

stage "ARM stages passed (${steps[*]})"
