#!/usr/bin/env bash
# Installs what is missing, builds, and shows gportd working against its
# simulated gimbal: gportctl reads status, watches attitude, shows the live
# monitor for 3 s, moves the gimbal, and changes a setting. Everything runs
# from build/demo; nothing is installed and the daemon is stopped at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/deps.sh
gport_install_deps build   # only what building needs: not the tests' toolchain

echo "== building (Release; the programs only, no tests, benchmarks or man pages)"
cmake -S . -B build/demo -G Ninja -DCMAKE_BUILD_TYPE=Release -DGPORT_BUILD_TESTS=OFF \
  -DGPORT_BUILD_BENCH=OFF -DGPORT_BUILD_MAN=OFF >/dev/null
cmake --build build/demo -j "$(nproc)" --target gportd gportctl gport-sim

workdir=$(mktemp -d)
socket="$workdir/gportd.sock"
gportd=build/demo/app/gportd
gportctl=build/demo/cli/gportctl
export GPORT_SOCKET="$socket"

echo "== starting: gportd --simulate --socket $socket"
"$gportd" --simulate --socket "$socket" 2>"$workdir/gportd.log" &
daemon=$!
cleanup() {
  kill "$daemon" 2>/dev/null && wait "$daemon" 2>/dev/null
  echo "== gportd's log:"
  cat "$workdir/gportd.log"
  rm -rf "$workdir"
}
trap cleanup EXIT
for _ in $(seq 100); do [ -S "$socket" ] && break; sleep 0.1; done

run() {
  echo
  echo "\$ gportctl $*"
  "$gportctl" "$@"
}

run wait link --timeout 10s   # status exits 75 until the link is up
run status
run settings
run settings --dead-zone 20
echo
echo "\$ gportctl watch attitude motion --rate 4 --for 3.5s   (while: gportctl speed --yaw +30 --for 2s)"
"$gportctl" watch attitude motion --rate 4 --for 3.5s &
watcher=$!
sleep 0.6
"$gportctl" speed --yaw +30 --for 2s
wait "$watcher"
echo
echo "\$ gportctl monitor --for 3s   (while: gportctl speed --yaw -20 --pitch 10 --for 2s)"
"$gportctl" speed --yaw -20 --pitch 10 --for 2s >/dev/null &
mover=$!
"$gportctl" monitor --for 3s
wait "$mover" || true
run angle --pitch -30 --yaw 45 --wait
run attitude
run center --wait
run --version
run photo
run status
echo
echo "The daemon is stopped now. Next: docs/api.md, docs/operations.md."
