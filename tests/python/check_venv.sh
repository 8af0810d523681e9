#!/bin/sh
# pip installs the Python client (client/python/pyproject.toml) into a fresh
# virtualenv, offline (--no-index --no-build-isolation), and the package works
# from there: it imports from the venv (not from the source tree or the
# system), its metadata carries the project's version, and it reads status
# from a real `gportd --simulate`.
#
# The venv is made with --system-site-packages: Debian's setuptools 66 needs
# the `wheel` package to build, and a venv gets only pip and setuptools
# (python3-venv); with the system's site-packages it also sees python3-wheel.
# gport itself needs nothing but the standard library.
#
# usage: check_venv.sh SOURCE_DIR PYTHON3 PROJECT_VERSION GPORTD
set -eu

fail() {
    echo "FAIL: $*" >&2
    exit 1
}

[ $# -eq 4 ] || fail "usage: $0 SOURCE_DIR PYTHON3 PROJECT_VERSION GPORTD"
source_dir=$1
python=$2
version=$3
gportd=$4
work=$(mktemp -d /tmp/gport-venv-XXXXXX)
daemon_pid=
cleanup() {
    [ -z "$daemon_pid" ] || kill "$daemon_pid" 2>/dev/null || true
    rm -rf "$work"
}
trap cleanup EXIT

"$python" -m venv --system-site-packages "$work/venv" >"$work/venv.log" 2>&1 \
    || fail "python3 -m venv failed (Debian: apt-get install python3-venv): $(cat "$work/venv.log")"
# A copy, so that setuptools' build/ and gport.egg-info stay out of the sources.
cp -R "$source_dir/client/python" "$work/src"
rm -rf "$work/src/build" "$work/src"/*.egg-info
PIP_CONFIG_FILE=/dev/null PIP_FIND_LINKS='' "$work/venv/bin/python" -m pip install --no-index \
    --no-build-isolation --no-cache-dir "$work/src" >"$work/pip.log" 2>&1 \
    || fail "pip install --no-index --no-build-isolation ./client/python failed: $(cat "$work/pip.log")"
echo "pip: $(tail -n 1 "$work/pip.log")"

"$gportd" --simulate --socket "$work/gportd.sock" >"$work/gportd.log" 2>&1 &
daemon_pid=$!

cd "$work"
env -u PYTHONPATH "$work/venv/bin/python" - "$work/venv" "$version" "$work/gportd.sock" <<'PY' \
    || fail "the installed gport does not work: $(cat "$work/gportd.log")"
import importlib.metadata
import os
import sys
import time

venv, version, socket = sys.argv[1:]
import gport

assert gport.__file__.startswith(venv + "/"), f"gport imported from {gport.__file__}, not {venv}"
installed = importlib.metadata.version("gport")
assert installed == version, f"pip installed gport {installed}, the project is {version}"
assert gport.__version__ == version, f"gport.__version__ {gport.__version__} != {version}"
typed = [f for f in importlib.metadata.files("gport") if f.name == "py.typed"]
assert typed, "py.typed was not installed"
requires = importlib.metadata.requires("gport")
assert not requires, f"gport has runtime dependencies: {requires}"

deadline = time.monotonic() + 30
while True:
    try:
        with gport.Client(socket) as client:
            status = client.status()
        break
    except (gport.GportError, OSError) as error:
        if time.monotonic() > deadline:
            raise SystemExit(f"cannot reach gportd --simulate at {socket}: {error}")
        time.sleep(0.2)
print(f"gport {installed} from {os.path.dirname(gport.__file__)}: link {status.link.state}")
PY
echo "PASS"
