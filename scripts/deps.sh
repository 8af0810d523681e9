#!/usr/bin/env bash
# Installs the Debian 12 packages gportd needs, when any is missing:
# `gport_install_deps build` what building and running the programs need
# (scripts/demo.sh), `release-build` that and what compiling the tests and
# benchmarks needs, `gport_install_deps` (or `all`) that and what running the
# tests, fuzzers and packaging needs (scripts/test.sh). Sourced; needs root
# for apt.
set -euo pipefail

# Building and running gportd, gportctl, gport-sim, gport-mavlink and the
# client library (cmake -DGPORT_BUILD_TESTS=OFF -DGPORT_BUILD_BENCH=OFF
# -DGPORT_BUILD_MAN=OFF).
GPORT_BUILD_PACKAGES=(
  cmake ninja-build g++ pkg-config
  libboost-dev nlohmann-json3-dev libspdlog-dev libfmt-dev libsystemd-dev libcli11-dev
  # OpenSSL 3's libcrypto (SHA-256, EVP) for MAVLink 2 message signing in
  # gport-mavlink (mavlink/src/signing.cpp): a well-kept library rather than
  # our own SHA-256; its runtime, libssl3, is on every Debian system.
  libssl-dev
)

# What a Release build with its tests, benchmarks and man pages needs to
# compile, on top of the above: scripts/test.sh installs this set first,
# starts the build and installs the rest beside it. python3 and systemd are
# looked up when CMake configures (the Python package's directory, the
# units'); the man pages are built with scdoc.
GPORT_RELEASE_BUILD_PACKAGES=(
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 systemd dpkg-dev scdoc
)

# What the tests, fuzzers and packages run with, on top of the above.
GPORT_TEST_PACKAGES=(
  clang-14 libclang-rt-14-dev
  # Tools the tests call that a minimal Debian 12 (debootstrap --variant=minbase)
  # lacks: `file` (CPackDeb, in the systemd_deb_package test) and procps
  # (/bin/kill, the units' ExecReload, which systemd_units verifies).
  file procps
  # The Python client's tests: pytest and mypy --strict (client/python).
  python3-pytest mypy
  # pip install ./client/python into a fresh venv, offline (tests/python/
  # check_venv.sh): python3-venv (venv, with pip and setuptools), and
  # python3-wheel, which Debian's setuptools needs to build a wheel.
  python3-venv python3-setuptools python3-wheel
  # libfaketime: gportd with the companion's clock wrong and stepped
  # (tests/python/test_true_time.py; skipped without it).
  faketime
  # Node.js and npm for the MAVLink cross-check against node-mavlink
  # (tests/mavlink/peer; Debian 12: nodejs 18, npm 9).
  nodejs npm
  # The systemd end-to-end stage (scripts/systemd-e2e.sh): a Debian root made
  # with debootstrap, booted with systemd-nspawn (package systemd-container).
  debootstrap systemd-container
  # gportctl monitor's test runs it in tmux; the man pages' tests render them
  # with man -l (man-db) and col (bsdextrautils).
  tmux man-db bsdextrautils
  # zsh: the test of gportctl's zsh completion loads it in `zsh -f`
  # (tests/cli/zsh_completion_test.sh; skipped without it).
  zsh
  # gpsd, for bench_vs_gpsd (the side-by-side benchmark, docs/performance.md).
  # The benchmark starts its own `gpsd -N -n -b -S PORT` on a pty; the
  # package's gpsd.socket (port 2947, only where systemd runs) starts nothing
  # until something connects to it, and we never do. Its udev rule would
  # hand USB serial adapters it takes for GPS receivers (CP210x 10c4:ea60,
  # PL2303 067b:2303: adapters a G-Port may sit behind) to that gpsd; when
  # this script installs gpsd it turns that off (USBAUTO="false" in
  # /etc/default/gpsd, read by gpsdctl@.service; nothing is masked).
  gpsd
  # exiftool: gportctl geotag's tests write and read tags in JPEGs they make
  # (tests/integration/geotag_test.cpp); users install it to use the command.
  libimage-exiftool-perl
)

# gport-web's browser test: Debian's chromium, driven headless by
# playwright-core (npm, pinned by tests/web/browser/package-lock.json): the
# system browser, no browser download. A set of its own (`gport_install_deps
# browser`): scripts/test.sh installs it beside the Release build, off the
# critical path (about 300 MB unpacked); apt leaves out recommended
# packages, so a font for the page's text (and the screenshots) is named.
GPORT_BROWSER_PACKAGES=(chromium fonts-dejavu-core)

# Packages that count as present when their command is, whoever installed it
# (e.g. a NodeSource nodejs, which bundles npm and conflicts with Debian's).
declare -gA GPORT_PACKAGE_COMMANDS=([nodejs]=node [npm]=npm)

# gport_install_deps [build|release-build|all|browser] [PACKAGE...]: installs what is
# missing of that set (default all) and of the packages named after it, in one apt run
# (scripts/test.sh adds the ARM stages' cross compilers: gport_cross_packages).
gport_install_deps() {
  local set=${1:-all} missing=() wanted=() p
  case "$set" in
    build) wanted=("${GPORT_BUILD_PACKAGES[@]}") ;;
    release-build) wanted=("${GPORT_BUILD_PACKAGES[@]}" "${GPORT_RELEASE_BUILD_PACKAGES[@]}") ;;
    all) wanted=("${GPORT_BUILD_PACKAGES[@]}" "${GPORT_RELEASE_BUILD_PACKAGES[@]}" "${GPORT_TEST_PACKAGES[@]}") ;;
    browser) wanted=("${GPORT_BROWSER_PACKAGES[@]}") ;;
    *) echo "error: gport_install_deps: no package set '$set' (build, release-build, all or browser)" >&2; return 1 ;;
  esac
  [ $# -gt 0 ] && shift
  wanted+=("$@")
  for p in "${wanted[@]}"; do
    if [[ -n ${GPORT_PACKAGE_COMMANDS[$p]:-} ]] && command -v "${GPORT_PACKAGE_COMMANDS[$p]}" >/dev/null; then
      continue
    fi
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$p")
    fi
  done
  if [ ${#missing[@]} -eq 0 ]; then
    return 0
  fi
  echo "== installing: ${missing[*]}"
  if [ "$(id -u)" -ne 0 ]; then
    echo "error: packages missing (${missing[*]}) and not root; run as root or install them" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
  if [[ " ${missing[*]} " == *" gpsd "* ]] && [ -f /etc/default/gpsd ]; then
    sed -i 's/^USBAUTO=.*/USBAUTO="false"/' /etc/default/gpsd
    echo "== gpsd installed for bench_vs_gpsd only: USB hotplug turned off (/etc/default/gpsd USBAUTO)"
  fi
}

# ---- cross-building for ARM (scripts/test.sh's ARM stages; docs/operations.md,
# "Building for ARM") -------------------------------------------------------

# gport_cross_triple ARCH: the GNU triple of a Debian architecture.
gport_cross_triple() {
  case "$1" in
    arm64) echo aarch64-linux-gnu ;;
    armhf) echo arm-linux-gnueabihf ;;
    *) echo "error: no cross build for Debian architecture '$1' (arm64 or armhf)" >&2; return 1 ;;
  esac
}

# gport_install_cross_deps ARCH...: this machine's cross compiler and qemu-user
# for each architecture (amd64 packages: the target's own libraries go into a
# sysroot, scripts/cross-sysroot.sh, never into this machine's dpkg).
gport_install_cross_deps() {
  local missing=()
  mapfile -t missing < <(gport_cross_packages "$@")
  if [ ${#missing[@]} -gt 0 ]; then
    echo "== installing: ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends "${missing[@]}"
  fi
}

# gport_cross_packages ARCH...: the packages of gport_install_cross_deps that
# are missing, one per line.
gport_cross_packages() {
  local arch triple
  command -v qemu-aarch64-static >/dev/null || echo qemu-user-static
  for arch in "$@"; do
    triple=$(gport_cross_triple "$arch")
    command -v "$triple-g++" >/dev/null || echo "g++-$triple"
  done
}

# gport_qemu_arch ARCH: qemu-user's name of a Debian architecture.
gport_qemu_arch() {
  case "$1" in
    arm64) echo aarch64 ;;
    armhf) echo arm ;;
    *) echo "error: no qemu-user for Debian architecture '$1'" >&2; return 1 ;;
  esac
}

# gport_register_binfmt QEMU_ARCH: runs the target's ELF files through
# qemu-user-static, so that tests can start the target's programs by path (the
# entry Debian's package ships for systemd-binfmt, whose F flag opens the
# emulator now, so it also serves chroots and containers). Fails, saying why,
# where binfmt_misc cannot be mounted or written (an unprivileged container).
gport_register_binfmt() {
  local dir=/proc/sys/fs/binfmt_misc entry=qemu-$1
  if [ ! -e "$dir/register" ]; then
    mount -t binfmt_misc binfmt_misc "$dir" ||
      { echo "error: cannot mount binfmt_misc on $dir (the ARM tests need it)" >&2; return 1; }
  fi
  [ -e "$dir/$entry" ] && grep -qx enabled "$dir/$entry" && return 0
  [ -e "$dir/$entry" ] && { echo -1 >"$dir/$entry" || return 1; }
  [ -r "/usr/lib/binfmt.d/$entry.conf" ] ||
    { echo "error: /usr/lib/binfmt.d/$entry.conf is missing (package qemu-user-static)" >&2; return 1; }
  cat "/usr/lib/binfmt.d/$entry.conf" >"$dir/register" ||
    { echo "error: cannot register $entry with binfmt_misc" >&2; return 1; }
  echo "== binfmt_misc: $entry registered"
}
