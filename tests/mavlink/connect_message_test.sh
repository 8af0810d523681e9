#!/usr/bin/env bash
# gport-mavlink says once why it cannot reach gportd: "cannot connect to
# PATH: ..." with the path named once (issue 26, item 16).
# Usage: connect_message_test.sh GPORT_MAVLINK
set -euo pipefail
mavlink=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
socket=$dir/absent.sock

# udpout: no port of ours is bound, so that parallel tests do not collide.
timeout -s TERM 3 "$mavlink" --socket "$socket" --mavlink udpout:127.0.0.1:9 \
    >"$dir/out" 2>&1 || true
line=$(grep -m1 "cannot connect" "$dir/out") || {
    echo "FAIL: no 'cannot connect' line:" >&2
    cat "$dir/out" >&2
    exit 1
}
count=$(grep -o "cannot connect to $socket" <<<"$line" | wc -l)
if [ "$count" -ne 1 ]; then
    echo "FAIL: the socket is named $count times: $line" >&2
    exit 1
fi
grep -q "No such file or directory" <<<"$line" || {
    echo "FAIL: the reason is missing: $line" >&2
    exit 1
}
echo "ok: $line"
