#!/usr/bin/env bash
# The ARM stages of scripts/test.sh: gportd cross-built on this (amd64) machine
# for the companion computers it is deployed on, its tests run under qemu-user
# (docs/operations.md, "Building for ARM"):
#   arm64 (Raspberry Pi 4/5, Jetson): Release build, warnings are errors, and
#         every test of the suite under qemu-aarch64 (the .deb's among them)
#         but the source checks and the interoperability suites (below);
#   armhf (32-bit Raspberry Pi OS): Release build, warnings are errors, the
#         unit suites under qemu-arm, and its .deb checked.
#   scripts/test-arm.sh [arm64] [armhf]        # both by default
# The target's libraries come from a sysroot (scripts/cross-sysroot.sh, in
# $GPORT_SYSROOTS, default /var/cache/gport: readable by every user, as the
# tests that run gportd as another uid need its loader), never from this
# machine's dpkg. Needs root (the cross
# compilers, qemu-user-static and its binfmt_misc entries).
# The tests that start the target's programs by path (gportd, gport-sim,
# gport-mavlink: integration, python, mavlink, systemd) need binfmt_misc; where
# it cannot be set up (an unprivileged container) only the unit suites run,
# through the emulator CMake names, and the rest is reported SKIPPED
# (GPORT_ARM=require makes that a failure).
# What emulation cannot tell: timing, and ARM's memory ordering (qemu-user on
# x86 keeps x86's); benchmarks belong on a real board (docs/operations.md).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/deps.sh

arches=("$@")
[ ${#arches[@]} -gt 0 ] || arches=(arm64 armhf)
jobs=$(nproc)
sysroots=${GPORT_SYSROOTS:-/var/cache/gport}
mkdir -p "$sysroots"
chmod 755 "$sysroots"
start=$(date +%s)
stage() { echo; echo "== $* ($(($(date +%s) - start)) s)"; }

# The suites a 32-bit build runs: everything but the programs' end-to-end
# tests (integration, python, mavlink, systemd), which arm64 runs.
unit_labels='^(base|protocol|config|daemon|ipc|sim|client|cli|app)$'
unit_parts='base;protocol;sim;config;daemon;ipc;systemd;app;client;cli'
# What arm64 leaves to the Release stage: the checks of the sources
# (layering, man pages) and the interoperability suites, where another
# implementation talks to our programs (node-mavlink: node; the Python
# client: python; chromium: browser). What they check is the protocol between
# programs, not how the code runs on ARM: the same parsing and codecs run
# here in the unit suites (mavlink, client, web) and gportd and gport-web end
# to end in integration, web and systemd.
interop_labels='^(layering|man|node|python|browser)$'

stage "ARM: cross compilers and qemu-user for ${arches[*]}"
gport_install_cross_deps "${arches[@]}"
declare -A by_path=()
for arch in "${arches[@]}"; do
  by_path[$arch]=yes
  gport_register_binfmt "$(gport_qemu_arch "$arch")" || by_path[$arch]=no
  if [ "${by_path[$arch]}" = no ] && [ "${GPORT_ARM:-}" = require ]; then
    echo "error: binfmt_misc is needed for the $arch end-to-end tests (GPORT_ARM=require)" >&2
    exit 1
  fi
done

for arch in "${arches[@]}"; do
  triple=$(gport_cross_triple "$arch")
  sysroot=$sysroots/sysroot-$arch
  build=build/$arch

  stage "$arch: sysroot"
  scripts/cross-sysroot.sh "$arch" "$sysroot"

  stage "$arch: Release build ($triple)"
  # armhf builds only the test folders it runs (the unit suites, and
  # systemd/ for the .deb's check); arm64 builds them all.
  parts=()
  [ "$arch" = armhf ] && parts=(-DGPORT_TEST_PARTS="$unit_parts")
  cmake -S . -B "$build" -G Ninja -DCMAKE_TOOLCHAIN_FILE="cmake/toolchains/$triple.cmake" \
    -DGPORT_SYSROOT="$sysroot" -DCMAKE_BUILD_TYPE=Release -DGPORT_WERROR=ON \
    -DGPORT_BUILD_BENCH=OFF -DGPORT_SITL_TESTS=OFF -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=16 \
    "${parts[@]}"
  cmake --build "$build" -j "$jobs"

  # The target's loader and glibc for everything qemu runs, the programs the
  # tests start by path (through binfmt_misc) included.
  export QEMU_LD_PREFIX=$sysroot
  if [ "${by_path[$arch]}" = no ]; then
    stage "$arch: the unit suites under qemu (end-to-end tests SKIPPED: no binfmt_misc, above)"
    ctest --test-dir "$build" --output-on-failure -j "$jobs" -L "$unit_labels"
  elif [ "$arch" = arm64 ]; then
    stage "$arch: every test but the interoperability suites, under qemu"
    ctest --test-dir "$build" --output-on-failure -j "$jobs" -LE "$interop_labels"
  else
    stage "$arch: the unit suites under qemu, and the .deb"
    ctest --test-dir "$build" --output-on-failure -j "$jobs" -L "$unit_labels"
    ctest --test-dir "$build" --output-on-failure -R '^systemd_deb_package$'
  fi
  unset QEMU_LD_PREFIX
done

stage "ARM stages passed"
