#!/bin/sh
# Installs libgport-client from a build tree into a temporary prefix
# (components client and client-dev only) and builds a program outside the
# tree against it twice: with `pkg-config --cflags --libs gport-client`, and
# with CMake's find_package(gport-client); and a C program (the C interface,
# ring_read.h) with pkg-config. All must run.
#
# usage: check_install.sh BUILD_DIR CONSUMER_SOURCE_DIR
set -eu

fail() {
    echo "FAIL: $*" >&2
    exit 1
}

[ $# -eq 2 ] || fail "usage: $0 BUILD_DIR CONSUMER_SOURCE_DIR"
build=$1
source=$2
cmake=${CMAKE:-cmake}
cxx=${CXX:-c++}
command -v pkg-config >/dev/null || fail "pkg-config not found (Debian package: pkg-config)"

work=$(mktemp -d /tmp/gport-client-install-XXXXXX)
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix

for component in client client-dev; do
    "$cmake" --install "$build" --prefix "$prefix" --component "$component" >"$work/install.log" \
        || { cat "$work/install.log" >&2; fail "cmake --install --component $component failed"; }
done
pc=$(find "$prefix" -name gport-client.pc | head -n 1)
[ -n "$pc" ] || fail "no gport-client.pc installed under $prefix"
libdir=$(dirname "$(dirname "$pc")")
[ -e "$libdir/libgport-client.so.1" ] || fail "no libgport-client.so.1 in $libdir"
[ -e "$prefix/include/gport/client/client.hpp" ] || fail "no include/gport/client/client.hpp"
[ ! -e "$prefix/include/gport/client/connection.hpp" ] \
    || fail "the internal connection.hpp was installed"
# error.hpp, types.hpp and client.hpp include the wire contract's errors.hpp,
# counters.hpp and names.hpp.
for header in errors.hpp counters.hpp names.hpp; do
    [ -e "$prefix/include/gport/contract/$header" ] || fail "no include/gport/contract/$header"
done
soname=$(objdump -p "$libdir/libgport-client.so.1" | awk '$1 == "SONAME" { print $2 }')
[ "$soname" = "libgport-client.so.1" ] || fail "SONAME is '$soname'"

# 1. pkg-config (the .pc computes its paths from its own location).
flags=$(PKG_CONFIG_PATH="$libdir/pkgconfig" pkg-config --cflags --libs gport-client) \
    || fail "pkg-config does not know gport-client"
# The run path as docs/client-cpp.md ("Linking") tells pkg-config users of
# a prefix of their own to add it; the program runs without LD_LIBRARY_PATH.
pc_libdir=$(PKG_CONFIG_PATH="$libdir/pkgconfig" pkg-config --variable=libdir gport-client)
[ "$pc_libdir" -ef "$libdir" ] || fail "pkg-config --variable=libdir is '$pc_libdir', not $libdir"
# shellcheck disable=SC2086  # the flags are words
"$cxx" -std=c++17 ${CONSUMER_FLAGS:-} "$source/main.cpp" $flags -Wl,-rpath,"$pc_libdir" -o "$work/pc-consumer" \
    || fail "building with pkg-config flags ($flags) failed"
env -u LD_LIBRARY_PATH "$work/pc-consumer" "$work/no-gportd.sock" \
    || fail "the pkg-config program did not run"

# 1b. The C interface from C (ring_read.h is a standalone C99 header).
# shellcheck disable=SC2086  # the flags are words
"${CC:-cc}" -std=c99 -Wall -Wextra -Wpedantic -Werror ${CONSUMER_FLAGS:-} "$source/ring_reader.c" \
    $flags -Wl,-rpath,"$libdir" -o "$work/c-consumer" \
    || fail "building the C program against ring_read.h failed"
"$work/c-consumer" || fail "the C program did not run"

# 2. find_package.
"$cmake" -S "$source" -B "$work/cmake-build" -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_BUILD_RPATH="$libdir" -DCMAKE_CXX_FLAGS="${CONSUMER_FLAGS:-}" \
    -DCMAKE_EXE_LINKER_FLAGS="${CONSUMER_FLAGS:-}" >"$work/configure.log" 2>&1 \
    || { cat "$work/configure.log" >&2; fail "find_package(gport-client) failed"; }
"$cmake" --build "$work/cmake-build" >"$work/build.log" 2>&1 \
    || { cat "$work/build.log" >&2; fail "building with find_package failed"; }
"$work/cmake-build/consumer" "$work/no-gportd.sock" || fail "the CMake program did not run"
"$work/cmake-build/async_consumer" "$work/no-gportd.sock" \
    || fail "the CMake AsyncClient program did not run"
echo "PASS"
