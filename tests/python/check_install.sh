#!/bin/sh
# Installs the build tree twice and checks that the Python package `gport`
# lands where the system's Python finds it:
#   - DESTDIR + prefix /usr (the .deb's layout): in the interpreter's
#     system directory (/usr/lib/python3/dist-packages on Debian);
#   - prefix <tmp>: under <tmp>/lib/python3.X/{dist,site}-packages;
# each time importable from there, with py.typed beside it.
#
# usage: check_install.sh BUILD_DIR PYTHON3
set -eu

fail() {
    echo "FAIL: $*" >&2
    exit 1
}

[ $# -eq 2 ] || fail "usage: $0 BUILD_DIR PYTHON3"
build=$1
python=$2
work=$(mktemp -d /tmp/gport-pyinstall-XXXXXX)
trap 'rm -rf "$work"' EXIT

# Imports gport from directory $1 only (not from the source tree) and prints its file.
import_from() {
    (cd "$work" && PYTHONPATH=$1 PYTHONDONTWRITEBYTECODE=1 "$python" -I -c "
import sys; sys.path.insert(0, '$1')
import gport
assert gport.Client and gport.AsyncClient
print(gport.__file__)") || fail "gport does not import from $1"
}

check_dir() {
    [ -f "$1/gport/__init__.py" ] || fail "no gport/__init__.py in $1; installed: $(cd "$2" && find . -name '*.py')"
    [ -f "$1/gport/py.typed" ] || fail "no gport/py.typed in $1"
    file=$(import_from "$1")
    case $file in
        "$1"/gport/__init__.py) ;;
        *) fail "gport was imported from $file, not from $1" ;;
    esac
}

# The .deb's layout.
system=$("$python" -c 'import sysconfig
scheme = "deb_system" if "deb_system" in sysconfig.get_scheme_names() else "posix_prefix"
print(sysconfig.get_path("purelib", scheme, vars={"base": "/usr", "platbase": "/usr"}))')
DESTDIR=$work/root "${CMAKE:-cmake}" --install "$build" --prefix /usr >"$work/install.log" 2>&1 \
    || { cat "$work/install.log" >&2; fail "cmake --install (DESTDIR, prefix /usr) failed"; }
check_dir "$work/root$system" "$work/root"
echo "prefix /usr: $system"

# A private prefix.
"${CMAKE:-cmake}" --install "$build" --prefix "$work/prefix" >"$work/install2.log" 2>&1 \
    || { cat "$work/install2.log" >&2; fail "cmake --install --prefix $work/prefix failed"; }
dir=$(cd "$work/prefix" && find . -path '*/python3*/*-packages/gport/__init__.py' | head -n 1)
[ -n "$dir" ] || fail "no gport package under $work/prefix/lib/python3.X/*-packages"
dir=$work/prefix/$(dirname "$(dirname "${dir#./}")")
check_dir "$dir" "$work/prefix"
echo "prefix $work/prefix: ${dir#"$work/prefix/"}"
echo "PASS"
