#!/usr/bin/env bash
# Soak test (minutes; not part of CI): gport-sim with every fault mode on,
# gportd on it, and 100 clients subscribing, commanding and disconnecting at
# random while the device vanishes and returns every few seconds. Alongside
# run the attacks of bench/e2e/soak_attacks.hpp: bursts of 96 speeds and a
# stop in one write, get_settings floods while the gimbal is silent, batch
# clients that never read, hoarded idle connections, and SIGHUP every 3 s;
# and the MAVLink-rogue attack on gport-mavlink (its own block below).
# The attitude channel's attacks (bench/e2e/soak_channel.hpp, issue 22): two
# peer processes with 500 threads each parked on their wake words, one of
# them disconnected; clients asking for the channel in batches of 32 that
# never read; a prober that must get both descriptors every 2 s.
# The line-rate attacks (bench/e2e/soak_line_rate.hpp, issue 30): the
# simulator drains the line at 115200 baud (gport-sim --baud) as the real
# UART does, and in turn, 4 s each with 2 s between, 8 connections flood
# `photo` with 1 KiB metas, 32 read-only peers (uid 65534 when run as root)
# flood `captures` (limit 1000), and one read-only peer sends batches of 32
# `captures` (limit 800), each reconnecting when gportd closes it.
#
#   scripts/soak.sh [SECONDS] [BUILD_DIR]        (defaults: 600, ./build)
#
# Checks: gportd never crashes and exits 0 on SIGTERM; its resident memory
# stays under 32 MiB and bounded (the largest VmRSS of the second half is
# within a small margin of the first half's); every speed motion whose owner
# left ends within 1 s (the deadman, seen as `motion` notifications); the
# status counters only grow and agree with each other; no burst's stop is
# refused, and each reaches the wire after its burst (gport-sim's trace);
# at most 4 settings requests per client and 64 in all are outstanding; no
# idle connection outlives twice the idle timeout; a well-behaved attitude
# subscriber never waits over 500 ms unless the link changed; every stop
# gportd counted as sent is in the trace, and no other. Prints the figures
# and PASS or FAIL; exits 0 on PASS. Environment: SOAK_WRITE_MODE
# (merge, the default, or split) chooses how the simulator chunks its
# output; SOAK_BAUD (default 115200; 0: a pty that drains at once, as
# before issue 30) the line rate; SOAK_KEEP=1 keeps the work directory
# (trace, logs, JSON).
set -euo pipefail

seconds=${1:-600}
build_dir=${2:-build}
sim="$build_dir/sim/gport-sim"
daemon="$build_dir/app/gportd"
driver="$build_dir/bench/e2e/gport_soak"
for binary in "$sim" "$daemon" "$driver"; do
    if [[ ! -x $binary ]]; then
        echo "soak.sh: $binary not found; build it first:" >&2
        echo "  ninja -C $build_dir gport-sim gportd gport_soak" >&2
        exit 66
    fi
done

# ---- The MAVLink-rogue attack (issue 22, gport-mavlink's side) ---------------
# gport-mavlink runs on the soak's gportd with its defaults (udpin on
# loopback, on a free port; vehicle system 1, ground station 255), and
# gport_soak_mavlink floods it for the whole soak: a rogue system 99 (every
# eighth frame another random id) sending an autopilot heartbeat and
# broadcast-targeted SET_ATTITUDE (a marker angle, a marker rate, NEUTRAL) and
# IMAGE_START_CAPTURE, 200 frames/s; one-byte datagrams from four more ports,
# 400/s; the vehicle's heartbeat (system 1, its own socket) at 1 Hz. Checks:
# the marker angle and rate never reach the gimbal's trace; no rogue socket
# gets a datagram back while the vehicle gets attitude status; gport-mavlink
# exits 0 on SIGTERM with its peak RSS under 32 MiB; its lines about the
# attack (ignored senders, peers, adoption) stay at most 16 + 1 + 1 and its
# other lines, beside gportd's link changes (one each, the gimbal's doing),
# at most 40, whatever the soak's length.
mavlink_bridge="$build_dir/mavlink/bridge/gport-mavlink"
mavlink_rogue="$build_dir/bench/e2e/gport_soak_mavlink"
mavlink_pid=""
mavlink_rogue_pid=""
mavlink_ok=no
for binary in "$mavlink_bridge" "$mavlink_rogue"; do
    if [[ ! -x $binary ]]; then
        echo "soak.sh: $binary not found; build it first:" >&2
        echo "  ninja -C $build_dir gport-mavlink gport_soak_mavlink" >&2
        exit 66
    fi
done
mavlink_start() {
    local port
    port=$(python3 -c 'import socket; s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
    "$mavlink_bridge" --socket "$work/gportd.sock" --mavlink "udpin:127.0.0.1:$port" \
        >"$work/gport-mavlink.log" 2>&1 &
    mavlink_pid=$!
    "$mavlink_rogue" --port "$port" --seconds "$seconds" --json "$work/mavlink.json" \
        >"$work/gport-soak-mavlink.log" 2>&1 &
    mavlink_rogue_pid=$!
    echo "soak.sh: gport-mavlink pid $mavlink_pid on udpin:127.0.0.1:$port, rogue pid $mavlink_rogue_pid"
}
mavlink_finish() {  # after gport-sim stopped: its trace is complete
    local rogue_status=0 bridge_status=none hwm_kib=0 attack_lines other_lines trace_ok=no
    wait "$mavlink_rogue_pid" || rogue_status=$?
    mavlink_rogue_pid=""
    if kill -0 "$mavlink_pid" 2>/dev/null; then
        hwm_kib=$(awk '/^VmHWM:/ {print $2}' "/proc/$mavlink_pid/status")
        kill -TERM "$mavlink_pid"
        bridge_status=0
        wait "$mavlink_pid" || bridge_status=$?
    fi
    mavlink_pid=""
    "$mavlink_rogue" --check-trace "$work/trace.jsonl" && trace_ok=yes
    attack_lines=$(grep -c 'ignoring system\|untrusted senders\|replying to\|adopted system' \
        "$work/gport-mavlink.log" || true)
    other_lines=$(grep -vc 'ignoring system\|untrusted senders\|replying to\|adopted system\|gportd: link \|gportd: connected\|gportd: connection lost' \
        "$work/gport-mavlink.log" || true)
    cat "$work/gport-soak-mavlink.log"
    echo "soak.sh: gport-mavlink: exit status after SIGTERM $bridge_status, peak RSS $((hwm_kib / 1024)) MiB," \
        "$(wc -l <"$work/gport-mavlink.log") lines: $attack_lines about the attack (at most 18)," \
        "$other_lines others beside gportd's link changes (at most 40)"
    if [[ $rogue_status == 0 && $trace_ok == yes && $bridge_status == 0 && $hwm_kib -lt 32768 &&
          $attack_lines -le 18 && $other_lines -le 40 ]]; then
        mavlink_ok=yes
    fi
    echo "soak.sh: MAVLink rogue attack: $([[ $mavlink_ok == yes ]] && echo PASS || echo FAIL)"
}

work=$(mktemp -d /tmp/gport-soak-XXXXXX)
chmod 755 "$work"  # the read-only floods' uid reaches the socket inside
sim_pid=""
daemon_pid=""
cleanup() {
    [[ -n $mavlink_rogue_pid ]] && kill "$mavlink_rogue_pid" 2>/dev/null || true
    [[ -n $mavlink_pid ]] && kill "$mavlink_pid" 2>/dev/null || true
    [[ -n $daemon_pid ]] && kill "$daemon_pid" 2>/dev/null || true
    [[ -n $sim_pid ]] && kill "$sim_pid" 2>/dev/null || true
    wait 2>/dev/null || true
    if [[ ${SOAK_KEEP:-0} == 1 ]]; then
        echo "soak.sh: work directory kept: $work"
    else
        rm -rf "$work"
    fi
}
trap cleanup EXIT

case ${SOAK_WRITE_MODE:-merge} in
    merge) chunking=(--merge 3) ;;
    split) chunking=(--split) ;;
    *) echo "soak.sh: SOAK_WRITE_MODE must be merge or split" >&2; exit 64 ;;
esac

baud=${SOAK_BAUD:-115200}
if [[ ! $baud =~ ^[0-9]+$ ]]; then
    echo "soak.sh: SOAK_BAUD must be a number (0: off)" >&2
    exit 64
fi
# Read-only peers need another uid: root can switch to nobody's.
reader_uid=0
access=''
if [[ $(id -u) == 0 ]]; then
    reader_uid=65534
    access='"access": {"control_uids": [0]},  // uid 65534 is read-only'
fi

# Every fault at once: line noise, bad CRCs, odd chunking, silences long
# enough to make the link stale, and the device vanishing every few seconds,
# on a line drained at $baud baud.
"$sim" --link "$work/gimbal" --trace --rate 50 --form 24 --noise 300 --corrupt-crc 0.02 \
    --baud "$baud" "${chunking[@]}" --silence-every 4000 --silence-for 700 \
    --vanish-every 6000 --vanish-for 1500 --seed 7 >"$work/trace.jsonl" &
sim_pid=$!
for _ in $(seq 100); do
    [[ -L $work/gimbal ]] && break
    sleep 0.05
done

cat >"$work/gportd.json" <<CONFIG
// Soak configuration: room for the 100 clients, the watcher and the attacks
// (all under one uid but the read-only floods), and an idle timeout short
// enough to be seen at work.
{
    "socket": {"max_clients": 320, "max_clients_per_uid": 256, "idle_timeout_ms": 15000,
               "mode": "0666"},
    $access
    "log": {"level": "info"}
}
CONFIG
"$daemon" --config "$work/gportd.json" --device "$work/gimbal" --socket "$work/gportd.sock" \
    >"$work/gportd.log" 2>&1 &
daemon_pid=$!

echo "soak.sh: ${seconds}s, gport-sim pid $sim_pid, gportd pid $daemon_pid, work dir $work"
mavlink_start
echo "soak.sh: load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
driver_status=0
"$driver" --socket "$work/gportd.sock" --pid "$daemon_pid" --seconds "$seconds" \
    --json "$work/soak.json" --trace "$work/trace.jsonl" --idle-timeout-s 15 \
    --reader-uid "$reader_uid" || driver_status=$?

alive=no
kill -0 "$daemon_pid" 2>/dev/null && alive=yes
daemon_status=none
if [[ $alive == yes ]]; then
    kill -TERM "$daemon_pid"
    daemon_status=0
    wait "$daemon_pid" || daemon_status=$?
fi
daemon_pid=""
kill -TERM "$sim_pid" 2>/dev/null || true
wait "$sim_pid" 2>/dev/null || true
sim_pid=""
mavlink_finish

count() { grep -c -- "$1" "$work/trace.jsonl" || true; }
counter() { grep -o "\"$1\": [0-9]*" "$work/soak.json" 2>/dev/null | tail -n 1 | grep -o '[0-9]*$' || true; }
# Stops on the wire against gportd's stops_sent, which counts zero speeds
# written to the device (a stop waiting behind an unwritten stop coalesces
# with it and is written once). None invented (one more is allowed: a
# deadman stop after the last status sample, or an owed stop written again
# on reopen), and none lost but those written as the device vanished (at
# most two per vanish).
trace_stops=$(count '"mode":"speed","speed":\[0,0,0\]')
vanishes=$(count '"event":"vanish"')
stops_counted=$(counter stops_sent)
stops_counted=${stops_counted:-0}
stops_ok=yes
if (( trace_stops > stops_counted + 1 || trace_stops < stops_counted - 2 * vanishes )); then
    stops_ok=no
fi
echo "soak.sh: load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "soak.sh: simulator trace: $(count '"mode":"speed"') speed frames received," \
    "$trace_stops of them stops (gportd's stops_sent: $stops_counted; consistent: $stops_ok)," \
    "$vanishes vanishes," \
    "$(count '"event":"silence_start"') silences, $(count '"cmd":"0x15"') settings writes"
echo "soak.sh: gportd log: $(wc -l <"$work/gportd.log") lines," \
    "$(grep -c '\[error\]\|\[critical\]' "$work/gportd.log" || true) at error level or above," \
    "$(grep -c 'reloaded configuration from' "$work/gportd.log" || true) reloads (SIGHUP)"
echo "soak.sh: gportd alive at the end: $alive; exit status after SIGTERM: $daemon_status"
echo "soak.sh: driver verdict: $([[ $driver_status == 0 ]] && echo PASS || echo "FAIL ($driver_status)")"

if [[ $driver_status == 0 && $alive == yes && $daemon_status == 0 && $stops_ok == yes &&
      $mavlink_ok == yes ]]; then
    echo "SOAK PASS"
    exit 0
fi
echo "SOAK FAIL"
SOAK_KEEP=1
exit 1
