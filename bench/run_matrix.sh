#!/usr/bin/env bash
# Runs the whole end-to-end benchmark matrix against the real gportd:
# 50, 200 and 500 attitude frames/s to 1, 10, 100 and 1000 subscribers, then
# keepalive timing idle, while 10 clients flood the socket with requests, and
# both at once under full load. Prints the table and writes bench-results.json.
#
#   bench/run_matrix.sh [BUILD_DIR] [SECONDS_PER_CELL] [OUTPUT_JSON]
#
# BUILD_DIR defaults to ./build (configure it Release: the figures are only
# meaningful from an optimised build); SECONDS_PER_CELL to 5; OUTPUT_JSON to
# ./bench-results.json. The whole matrix takes about four minutes with 5 s
# cells (keepalive cells run six times as long).
set -euo pipefail

build_dir=${1:-build}
seconds=${2:-5}
output=${3:-bench-results.json}
bench="$build_dir/bench/e2e/bench_e2e"
if [[ ! -x $bench ]]; then
    echo "run_matrix.sh: $bench not found; build it first:" >&2
    echo "  cmake -S . -B $build_dir -G Ninja -DCMAKE_BUILD_TYPE=Release" >&2
    echo "  ninja -C $build_dir bench_e2e gportd" >&2
    exit 66
fi

cells_dir=$(mktemp -d /tmp/gport-matrix-XXXXXX)
trap 'rm -rf "$cells_dir"' EXIT

# rate subscribers flooders seconds [extra option]
# Keepalive cells run longer: at 10 Hz, 30 s give 300 gaps, so that p99 is
# not simply the largest one. The --daemon-fifo cells run gportd SCHED_FIFO:
# what is left of a delay there is the daemon's own, not the CPU queue's.
keepalive_seconds=$(( seconds * 6 ))
cells=()
for rate in 50 200 500; do
    for subs in 1 10 100 1000; do
        cells+=("$rate $subs 0 $seconds")
    done
done
cells+=("50 0 0 $keepalive_seconds" "50 0 10 $keepalive_seconds" "500 100 10 $keepalive_seconds")
cells+=("500 100 0 $seconds --daemon-fifo" "50 0 10 $keepalive_seconds --daemon-fifo")

load_before=$(cut -d' ' -f1-3 /proc/loadavg)
"$bench" --help >/dev/null
first=1
failed=0
index=0
for cell in "${cells[@]}"; do
    read -r rate subs flood cell_seconds extra <<<"$cell"
    index=$((index + 1))
    header=--no-header
    if [[ $first == 1 ]]; then
        header=
        first=0
    fi
    # shellcheck disable=SC2086
    if ! "$bench" --rate "$rate" --subscribers "$subs" --flood "$flood" --seconds "$cell_seconds" \
        --json "$cells_dir/$(printf '%02d' "$index").json" $header $extra; then
        echo "run_matrix.sh: cell rate=$rate subscribers=$subs flood=$flood failed" >&2
        failed=1
    fi
done

{
    printf '{\n  "date": "%s",\n' "$(date -u +%Y-%m-%dT%H:%M:%SZ)"
    printf '  "host": {"cpus": %s, "kernel": "%s", "loadavg_before": "%s", "loadavg_after": "%s"},\n' \
        "$(nproc)" "$(uname -r)" "$load_before" "$(cut -d' ' -f1-3 /proc/loadavg)"
    printf '  "seconds_per_cell": %s,\n  "cells": [\n' "$seconds"
    sep=""
    for file in "$cells_dir"/*.json; do
        [[ -e $file ]] || continue
        printf '%s' "$sep"
        sed 's/^/    /' "$file"
        sep=$',\n'
    done
    printf '\n  ]\n}\n'
} >"$output"

echo
echo "columns: rate = 0x87 frames/s written; subs = attitude subscribers; flood = clients"
echo "sending status back to back; lines = attitude lines read; miss% = lines not delivered;"
echo "p50/p99/max = last byte written -> JSON line read (µs); cpu% = gportd utime+stime as %"
echo "of one core; RSS/HWM = gportd VmRSS/VmHWM (MiB) at the end; ka p99/max = keepalive gap"
echo "deviation from 100 ms (ms), n gaps; req/s = flood replies per second; 1st p99 = the"
echo "first subscriber's line per frame (no fan-out); (gportd FIFO) = gportd ran SCHED_FIFO."
echo "A failed cell is one where gportd did not exit 0 on SIGTERM (see exit_status in the JSON)."
echo "load before: $load_before; results: $output"
exit $failed
