#!/bin/bash
# The steps of the systemd end-to-end test. scripts/systemd-e2e.sh boots a
# fresh Debian 12 root with systemd-nspawn and runs this there as a unit of
# the container's systemd, as root, with the package and this script in
# /mnt. Each check prints PASS or FAIL and what it checked; a failure also
# prints the journal of gportd and of the simulated gimbals. At the end,
# `systemctl exit` hands the result to nspawn (0: every check passed).
set -u
export DEBIAN_FRONTEND=noninteractive LC_ALL=C.UTF-8 PATH=/usr/sbin:/usr/bin:/sbin:/bin
export SYSTEMD_COLORS=0 SYSTEMD_PAGER=
cd /mnt || exit 2
deb=$(ls /mnt/gportd_*.deb | head -n 1)
socket=/run/gportd.sock
t0=$(date +%s)
passes=0
failures=0

finish() {
    local rc=0
    [ "$failures" -eq 0 ] || rc=1
    if [ "$failures" -gt 0 ]; then
        echo "---- journal of gportd*, gimbal* and systemd about them (last 80 entries)"
        journalctl --no-pager -q -n 80 -o short-monotonic -u 'gportd*' -u 'gimbal*' | sed 's/^/      | /'
    fi
    echo "== $passes checks passed, $failures failed, in $(($(date +%s) - t0)) s inside the container"
    systemctl exit "$rc"
}
trap finish EXIT

step() { echo "---- $*"; }
pass() {
    echo "PASS  $*"
    passes=$((passes + 1))
}
# fail WHAT [DETAIL]: the journal follows at the end.
fail() {
    echo "FAIL  $1"
    [ -n "${2:-}" ] && printf '%s\n' "$2" | tail -n 20 | sed 's/^/      | /'
    failures=$((failures + 1))
}
# check WHAT COMMAND...: PASS when COMMAND succeeds, else FAIL with its output.
check() {
    local what=$1 out
    shift
    if out=$("$@" 2>&1); then
        pass "$what"
    else
        fail "$what" "$out"
    fi
}
# eventually SECONDS COMMAND...: polls COMMAND every 0.2 s until it succeeds.
eventually() {
    local tries=$(($1 * 5))
    shift
    for _ in $(seq "$tries"); do
        "$@" >/dev/null 2>&1 && return 0
        sleep 0.2
    done
    "$@"
}
# A background child that exited but was not reaped yet still answers kill -0.
gone() { [ ! -e "/proc/$1" ] || [ "$(cut -d' ' -f3 "/proc/$1/stat")" = Z ]; }
# The journal's current end, for --after-cursor.
journal_mark() { journalctl -q -n 1 --show-cursor -o cat | sed -n 's/^-- cursor: //p'; }
main_pid() { systemctl show -p MainPID --value "${1:-gportd.service}"; }
active() { [ "$(systemctl is-active "$1")" = active ]; }
inactive() { [ "$(systemctl is-active "$1")" != active ]; }
as_user() {
    local user=$1
    shift
    setpriv --reuid="$user" --regid="$user" --init-groups -- "$@"
}
link_up() { gportctl --socket "${1:-$socket}" status | grep -q '^link: *up'; }
# Trace lines of a simulated gimbal (a transient unit; its stdout is the journal).
sim_trace() { journalctl --no-pager -q -o cat -u "$1"; }
sim_traced() { sim_trace "$1" | grep -q -- "$2"; }
last_speed() { sim_trace "$1" | grep '"mode":"speed"' | tail -n 1; }

# start_sim UNIT LINK: gport-sim on a pty linked at LINK, the pty root:dialout
# 0660 as udev makes a real adapter (docs/operations.md, "The installed
# service on gport-sim").
start_sim() {
    systemd-run --quiet --unit="$1" /usr/bin/gport-sim --link "$2" --trace --group dialout --mode 0660 ||
        { fail "gport-sim $1 on $2 did not start"; return 1; }
    eventually 10 test -L "$2" || { fail "gport-sim $1 made no link $2"; return 1; }
}

# This machine's /dev/null is 0644 and nspawn copies its mode; make it 0666
# as on any Debian system, or the daemon's sandbox probes would fail on it.
chmod 0666 /dev/null

# ---- 0 -----------------------------------------------------------------------
step "0. a root with nothing of ours"
check "no gportd user, no gport group, no /etc/gportd, no gportd units, no /run/gportd.sock" \
    sh -c "! getent passwd gportd && ! getent group gport && [ ! -e /etc/gportd ] \
           && ! systemctl cat gportd.service >/dev/null 2>&1 && [ ! -e $socket ]"
check "systemd $(systemctl --version | head -n 1 | cut -d' ' -f2) is PID 1 and the system is up" \
    sh -c '[ "$(ps -o comm= -p 1)" = systemd ] && systemctl is-system-running --wait | grep -Eq "running|degraded"'

# ---- 1 -----------------------------------------------------------------------
step "1. apt-get install ./$(basename "$deb")"
before=$(dpkg-query -W -f '${Package}\n' | sort)
if out=$(apt-get install -y -q --no-install-recommends "$deb" 2>&1); then
    added=$(comm -13 <(echo "$before") <(dpkg-query -W -f '${Package}\n' | sort) | grep -vx gportd | tr '\n' ' ')
    pass "apt-get installed gportd and resolved its dependencies from Debian: ${added:-none needed}"
else
    fail "apt-get install $deb" "$out"
fi
check "gportd is configured, so its Depends are met ($(dpkg-deb -f "$deb" Depends)); apt-get check is clean" \
    sh -c "[ \"\$(dpkg-query -W -f '\${Status}' gportd)\" = 'install ok installed' ] && apt-get check -q"
check "user gportd (groups: $(id -nG gportd 2>/dev/null)) is in dialout; group gport exists" \
    sh -c 'id -nG gportd | grep -qw dialout && getent group gport'
check "gportd.socket and gportd.service are enabled, the socket is listening" \
    sh -c 'systemctl is-enabled gportd.socket gportd.service && systemctl is-active gportd.socket'
check "/etc/gportd/gportd.json is a conffile: $(dpkg-query -W -f '${Conffiles}' gportd | xargs)" \
    sh -c "dpkg-query -W -f '\${Conffiles}' gportd | grep -q '/etc/gportd/gportd.json' && test -f /etc/gportd/gportd.json"

# ---- 4 (the gimbal first, so that the daemon has one to serve) ----------------
step "4. a simulated gimbal on /dev/gimbal"
start_sim gimbal-sim /dev/gimbal
check "gport-sim on /dev/gimbal -> $(readlink /dev/gimbal), root:dialout 0660 as udev makes an adapter" \
    sh -c '[ "$(stat -L -c "%U:%G %a" /dev/gimbal)" = "root:dialout 660" ]'

# ---- 2 -----------------------------------------------------------------------
step "2. socket activation"
systemctl stop gportd.service 2>/dev/null  # postinst started it; the socket stays
check "gportd.service stopped, gportd.socket listening on $socket ($(stat -c '%U:%G %a' $socket 2>/dev/null))" \
    sh -c "! systemctl is-active gportd.service && systemctl is-active gportd.socket \
           && [ \"\$(stat -c '%U:%G %a' $socket)\" = 'root:gport 660' ]"
mark=$(journal_mark)
check "the first client (gportctl status) started the daemon and was answered" \
    sh -c "{ gportctl status >/dev/null; rc=\$?; [ \$rc -eq 0 ] || [ \$rc -eq 75 ]; } && systemctl is-active gportd.service"
pid=$(main_pid)
# READY=1 only once it serves: the daemon's "serving clients" entry comes
# before systemd's "Started" one, and the service was "activating" till then.
ready_order() {
    journalctl --no-pager -q -o cat --after-cursor="$mark" -u gportd.service |
        grep -E 'serving clients on the socket passed by systemd|Started gportd.service' |
        head -n 2 | tr '\n' '|' | grep -q '^serving clients.*|Started gportd.service'
}
check "READY only once it serves: 'serving clients' logged before systemd's 'Started' (Type=notify)" \
    eventually 5 ready_order
check "the link comes up with gport-sim" eventually 15 link_up
status_text() { systemctl show -p StatusText --value gportd.service | grep -q 'link up'; }
eventually 10 status_text
check "systemctl status shows the STATUS text: $(systemctl status gportd.service | grep -m1 'Status:' | xargs)" \
    sh -c "systemctl status gportd.service | grep -q 'Status: \"/dev/gimbal: link up'"

# ---- 3 -----------------------------------------------------------------------
step "3. the sandbox is in force"
check "the daemon (pid $pid) runs as $(ps -o user= -p "$pid"):$(ps -o group= -p "$pid") with no capabilities" \
    sh -c "[ \"\$(ps -o user= -p $pid)\" = gportd ] && grep -q '^CapEff:[[:space:]]*0*$' /proc/$pid/status"
check "in its mount namespace even root cannot write /etc, /usr, /var, /run (read-only file system)" \
    sh -c "for d in /etc /usr /var /run; do
               if nsenter -t $pid -m -r -w -- sh -c \": >\$d/.e2e-probe\" 2>/dev/null; then echo \"wrote \$d\"; exit 1; fi
           done"
# The same properties as the unit, read from the installed unit file, on a
# transient service: what the daemon could write or open.
mapfile -t properties < <(systemctl cat gportd.service | sed -n '/^User=/,/^\[Install\]/p' | grep -E '^[A-Za-z]+=')
sandbox_args=()
for p in "${properties[@]}"; do sandbox_args+=(-p "$p"); done
in_sandbox() { systemd-run --quiet --wait --pipe --collect "${sandbox_args[@]}" -- "$@"; }
writable=$(in_sandbox sh -c 'find / \( -path /proc -o -path /sys \) -prune -o -type d -writable -print 2>/dev/null' 2>&1 |
    grep -Evx '/tmp|/var/tmp')
if [ -z "$writable" ]; then
    pass "as gportd with the unit's ${#properties[@]} sandbox properties (systemd-run), no directory is writable but the private /tmp and /var/tmp"
else
    fail "as gportd with the unit's sandbox properties, directories beyond the private /tmp and /var/tmp are writable" "$writable"
fi
other_device=
for d in /dev/net/tun /dev/fuse; do [ -c "$d" ] && other_device=$d && break; done
if [ -n "$other_device" ]; then
    chmod 0666 "$other_device"  # so that only the sandbox, not the file mode, can refuse it
    check "gportd outside the sandbox opens $other_device (the control)" \
        as_user gportd sh -c "exec 3<>$other_device"
    opened=$(in_sandbox sh -c "exec 3<>$other_device && echo opened" 2>&1)
    if [ "$opened" != opened ] && printf '%s' "$opened" | grep -q 'Operation not permitted'; then
        pass "inside the sandbox, $other_device (not a serial device) is refused: $(printf '%s' "$opened" | tail -n 1)"
    else
        fail "inside the sandbox, $other_device must be refused (DevicePolicy=closed)" "$opened"
    fi
else
    fail "no non-serial device to try (/dev/net/tun, /dev/fuse) in this container"
fi
check "inside the sandbox, /dev/null still opens (DevicePolicy=closed keeps the pseudo devices)" \
    in_sandbox sh -c 'exec 3<>/dev/null'
score=$(systemd-analyze security gportd.service 2>&1 | sed -n 's/.*Overall exposure level for gportd.service: *\([0-9.]*\).*/\1/p')
if [ -n "$score" ] && awk -v s="$score" 'BEGIN { exit !(s <= 1.0) }'; then
    pass "systemd-analyze security gportd.service (online): exposure $score <= 1.0"
else
    fail "systemd-analyze security gportd.service (online): exposure ${score:-unknown} > 1.0" \
        "$(systemd-analyze security gportd.service 2>&1 | grep -v '^  ✓')"
fi

# ---- 4 -----------------------------------------------------------------------
step "4. commands: a user in group gport moves the gimbal, others are refused"
useradd --no-create-home --groups gport alice
useradd --no-create-home bob
check "alice (in gport): gportctl speed --yaw 12 --for 1s is accepted" \
    as_user alice gportctl speed --yaw 12 --for 1s
check "gport-sim received alice's speed (0x85, yaw 1200 = 12 deg/s)" \
    eventually 5 sim_traced gimbal-sim '"mode":"speed","speed":\[0,0,1200\]'
check "alice reads attitude through the shared-memory channel under the unit's sandbox (memfd, SCM_RIGHTS, futex)" \
    timeout 10 setpriv --reuid=alice --regid=alice --init-groups -- gportctl watch attitude --shared-memory --count 5
check "alice (in gport): gportctl photo prints its capture index" \
    sh -c "setpriv --reuid=alice --regid=alice --init-groups -- gportctl photo | grep -q 'capture [0-9]'"
check "the capture log is gportd:gport, directory 750 and file 640 ($(stat -c '%U:%G %a' /var/lib/gportd /var/lib/gportd/captures.jsonl 2>&1 | xargs))" \
    sh -c "[ \"\$(stat -c '%U:%G %a' /var/lib/gportd /var/lib/gportd/captures.jsonl | xargs)\" = 'gportd:gport 750 gportd:gport 640' ]"
check "alice (in gport) reads the capture log's file; bob (not in gport) cannot" \
    sh -c "as_user() { u=\$1; shift; setpriv --reuid=\$u --regid=\$u --init-groups -- \"\$@\"; }
           as_user alice grep -q '\"kind\":\"photo\"' /var/lib/gportd/captures.jsonl &&
           ! as_user bob cat /var/lib/gportd/captures.jsonl >/dev/null 2>&1"
out=$(as_user bob gportctl status 2>&1)
rc=$?
if [ "$rc" -eq 69 ] && printf '%s' "$out" | grep -qi 'permission denied'; then
    pass "bob (not in gport) is refused by the socket's mode: exit $rc, $(printf '%s' "$out" | head -n 1)"
else
    fail "bob (not in gport) must be refused by the socket's mode (got exit $rc)" "$out"
fi

# ---- 5 -----------------------------------------------------------------------
step "5. watchdog and restarts"
check "WatchdogSec is $(systemctl show -p WatchdogUSec --value gportd.service) and the daemon logged its pings" \
    sh -c "[ \"\$(systemctl show -p WatchdogUSec --value gportd.service)\" = 10s ] \
           && journalctl -q -o cat -u gportd.service _PID=$pid | grep -q 'watchdog enabled'"
restarted_from() { local p; p=$(main_pid); [ "$p" != 0 ] && [ "$p" != "$1" ] && active gportd.service; }
old=$(main_pid)
kill -STOP "$old"
watchdog_fired() { journalctl -q -o cat -u gportd.service | grep -q 'Watchdog timeout'; }
if eventually 40 restarted_from "$old" && eventually 5 watchdog_fired; then
    pass "frozen (SIGSTOP) pid $old: systemd's watchdog killed it and restarted it as pid $(main_pid) \
($(journalctl -q -o cat -u gportd.service | grep -m1 -o 'Watchdog timeout[^!]*'))"
else
    fail "frozen (SIGSTOP) pid $old was not restarted by the watchdog within 40 s"
fi
check "the restarted daemon serves the same socket and gets the link back" eventually 15 link_up
old=$(main_pid)
kill -KILL "$old"
if eventually 20 restarted_from "$old"; then
    pass "killed (SIGKILL) pid $old: restarted as pid $(main_pid)"
else
    fail "killed (SIGKILL) pid $old was not restarted within 20 s"
fi
check "after kill -9 the new daemon reopens /dev/gimbal and the link is up (gport-sim: $(sim_trace gimbal-sim | grep -o '"event":"\(exclusive_cleared\|pty_replaced\)"' | sort | uniq -c | xargs))" \
    eventually 15 link_up

# ---- 6 -----------------------------------------------------------------------
step "6. journald fields"
journal_json() { journalctl --no-pager -q -o json -u gportd.service; }
check "entries carry PRIORITY, GPORT_DEVICE=/dev/gimbal and GPORT_LINK" \
    sh -c "journalctl --no-pager -q -o json -u gportd.service | grep '\"PRIORITY\":\"[0-9]\"' \
           | grep '\"GPORT_DEVICE\":\"/dev/gimbal\"' | grep -q '\"GPORT_LINK\":\"[a-z]*\"'"
alice=$(id -u alice)
check "alice's motion is logged with GPORT_CLIENT_PID, GPORT_CLIENT_UID=$alice and GPORT_CLIENT_ID" \
    sh -c "journalctl --no-pager -q -o json -u gportd.service | grep '\"MESSAGE\":\"motion ' \
           | grep '\"GPORT_CLIENT_UID\":\"$alice\"' | grep '\"GPORT_CLIENT_PID\":\"[0-9]*\"' \
           | grep -q '\"GPORT_CLIENT_ID\":\"[0-9]*\"'"

# ---- 7 -----------------------------------------------------------------------
step "7. reload, stop, two instances"
as_user alice gportctl watch attitude --rate 5 >/tmp/watch.out 2>&1 &
watcher=$!
eventually 5 test -s /tmp/watch.out
pid=$(main_pid)
mark=$(journal_mark)
check "systemctl reload (SIGHUP) reloads the configuration" systemctl reload gportd.service
lines=$(wc -l </tmp/watch.out)
grew() { [ "$(wc -l </tmp/watch.out)" -gt "$1" ]; }
reloaded() {
    [ "$(main_pid)" = "$pid" ] && ! gone "$watcher" &&
        journalctl -q -o cat --after-cursor="$mark" -u gportd.service | grep -q 'reloaded configuration'
}
check "after the reload: same pid $pid, the watching client still connected, 'reloaded configuration' logged" \
    eventually 5 reloaded
check "the watching client still receives attitude after the reload" eventually 5 grew "$lines"
kill "$watcher" 2>/dev/null
wait "$watcher" 2>/dev/null

as_user alice gportctl speed --yaw 15 --for 60s >/dev/null 2>&1 &
mover=$!
check "alice's 60 s motion reached the gimbal (yaw 1500)" \
    eventually 5 sim_traced gimbal-sim '"speed":\[0,0,1500\]'
systemctl stop gportd.service
check "systemctl stop: the last speed the gimbal got is zero ($(last_speed gimbal-sim))" \
    sh -c "journalctl -q -o cat -u gimbal-sim | grep '\"mode\":\"speed\"' | tail -n 1 | grep -q '\"speed\":\[0,0,0\]'"
check "the daemon exited cleanly (Result=$(systemctl show -p Result --value gportd.service)); gportd.socket and $socket stay" \
    sh -c "[ \"\$(systemctl show -p Result --value gportd.service)\" = success ] \
           && systemctl is-active gportd.socket && [ -S $socket ]"
kill "$mover" 2>/dev/null
wait "$mover" 2>/dev/null

start_sim gimbal0-sim /dev/gimbal0
start_sim gimbal1-sim /dev/gimbal1
systemctl start gportd@gimbal0.socket gportd@gimbal1.socket
check "gportd@gimbal0 and gportd@gimbal1 both bring their link up, on /run/gportd-gimbal0.sock and -gimbal1.sock" \
    sh -c "for i in 0 1; do
               for _ in \$(seq 75); do
                   gportctl --socket /run/gportd-gimbal\$i.sock status 2>/dev/null | grep -q '^link: *up' && break
                   sleep 0.2
               done
               gportctl --socket /run/gportd-gimbal\$i.sock status | grep -q '^link: *up' || exit 1
           done"
check "two daemons (pids $(main_pid gportd@gimbal0.service) and $(main_pid gportd@gimbal1.service)), each on its own device" \
    sh -c "[ \"\$(systemctl show -p MainPID --value gportd@gimbal0.service)\" != \
             \"\$(systemctl show -p MainPID --value gportd@gimbal1.service)\" ] \
           && journalctl -q -o json -u gportd@gimbal1.service | grep -q '\"GPORT_DEVICE\":\"/dev/gimbal1\"' \
           && journalctl -q -o json -u gportd@gimbal0.service | grep -q '\"GPORT_DEVICE\":\"/dev/gimbal0\"'"
check "alice moves gimbal1 through its own socket" \
    sh -c "setpriv --reuid=alice --regid=alice --init-groups -- gportctl --socket /run/gportd-gimbal1.sock speed --pitch 5 --for 1s"
check "only gimbal1's simulator got that speed" \
    sh -c "journalctl -q -o cat -u gimbal1-sim | grep -q '\"speed\":\[0,500,0\]' \
           && ! journalctl -q -o cat -u gimbal0-sim | grep -q '\"speed\":\[0,500,0\]'"

# ---- 7b ----------------------------------------------------------------------
step "7b. a bad configuration and a client retrying in a loop: no lock-out"
cp /etc/gportd/gportd.json /tmp/gportd.json.good
sed -i 's/"baud": 115200/"baud": 115201/' /etc/gportd/gportd.json
systemctl reset-failed gportd.service gportd.socket 2>/dev/null
restarts() { systemctl show -p NRestarts --value gportd.service; }
before=$(restarts)
for _ in $(seq 30); do
    gportctl status >/tmp/bad-config.out 2>&1
    sleep 0.1
done
check "30 clients in 3 s each get the error naming the key ($(head -c 160 /tmp/bad-config.out | tr '\n' ' '))" \
    grep -q 'serial.baud' /tmp/bad-config.out
check "the daemon stayed up: one start, $(($(restarts) - before)) restarts, gportd.socket $(systemctl is-active gportd.socket)" \
    sh -c "[ \"\$(systemctl show -p NRestarts --value gportd.service)\" = $before ] \
           && systemctl is-active gportd.service && systemctl is-active gportd.socket"
check "systemctl status says why: $(systemctl status gportd.service | grep -m1 'Status:' | xargs)" \
    sh -c "systemctl status gportd.service | grep -Eq 'Status: \"?configuration error'"
check "the error is in the journal once, at priority err" \
    sh -c "[ \"\$(journalctl -q -o cat -p err -u gportd.service | grep -c 'configuration error: .*serial.baud')\" = 1 ]"
cp /tmp/gportd.json.good /etc/gportd/gportd.json
check "with the file fixed, systemctl restart brings it back: the link comes up" \
    sh -c "systemctl restart gportd.service && for _ in \$(seq 75); do
               gportctl status 2>/dev/null | grep -q '^link: *up' && exit 0; sleep 0.2; done; exit 1"
sed -i 's/"baud": 115200/"baud": 115201/' /etc/gportd/gportd.json
systemctl restart gportd.service
eventually 5 sh -c "gportctl status 2>&1 | grep -q serial.baud"
cp /tmp/gportd.json.good /etc/gportd/gportd.json
check "or systemctl reload: the fixed file makes it exit 75 and systemd starts it again; the link comes up" \
    sh -c "systemctl reload gportd.service; for _ in \$(seq 100); do
               gportctl status 2>/dev/null | grep -q '^link: *up' && exit 0; sleep 0.2; done; exit 1"

# ---- 8 -----------------------------------------------------------------------
step "8. upgrade with a client connected, remove, purge"
check "the daemon is back by socket activation with the link up" eventually 15 link_up
as_user alice gportctl watch link >/tmp/watch-upgrade.out 2>&1 &
watcher=$!
sleep 0.5
old=$(main_pid)
if out=$(apt-get install -y -q --reinstall "$deb" 2>&1); then
    pass "apt-get install --reinstall $(basename "$deb") with a client connected"
else
    fail "apt-get install --reinstall $(basename "$deb")" "$out"
fi
restarted_cleanly() {
    restarted_from "$old" && journalctl -q -o cat -u gportd.service _PID="$old" | grep -q 'gportd stopped'
}
check "postinst restarted the daemon (pid $old -> $(main_pid)); the old one stopped cleanly" \
    eventually 5 restarted_cleanly
check "the connected client was let go (the old daemon closed it)" eventually 5 gone "$watcher"
check "the new daemon serves the same socket and the link is up" eventually 15 link_up
check "the instances were restarted too and serve again" \
    eventually 15 link_up /run/gportd-gimbal1.sock

if out=$(apt-get remove -y -q gportd 2>&1); then
    pass "apt-get remove gportd"
else
    fail "apt-get remove gportd" "$out"
fi
check "remove stopped every unit and daemon, the sockets are gone, the config stays" \
    sh -c "for u in gportd.service gportd.socket gportd@gimbal0.service gportd@gimbal1.socket; do
               ! systemctl is-active \$u || { echo \"\$u still active\"; exit 1; }
           done
           ! pgrep -x gportd && [ ! -e $socket ] && [ ! -e /run/gportd-gimbal1.sock ] \
           && [ -f /etc/gportd/gportd.json ] && [ ! -e /usr/bin/gportd ]"
if out=$(apt-get purge -y -q gportd 2>&1); then
    pass "apt-get purge gportd"
else
    fail "apt-get purge gportd" "$out"
fi
check "purge removed /etc/gportd and the package's record; the gportd user stays (Debian policy)" \
    sh -c "[ ! -e /etc/gportd ] && ! dpkg -s gportd >/dev/null 2>&1 && getent passwd gportd >/dev/null"

# ---- 9 -----------------------------------------------------------------------
step "9. gport-mavlink: starts after gportd, stops with it"
# Step 8 purged the package; install it again for the bridge's unit. The
# MAVLink side itself (heartbeats, attitude, commands) is the ctest
# mavlink_peer_gimbal_manager's job; here: the unit's life beside gportd.
if out=$(apt-get install -y -q "$deb" 2>&1); then
    pass "apt-get install $(basename "$deb") again"
else
    fail "apt-get install $(basename "$deb") again" "$out"
fi
check "postinst made the gport-mavlink user, in groups gport and dialout" \
    sh -c "getent passwd gport-mavlink >/dev/null && id -nG gport-mavlink | grep -qw gport \
           && id -nG gport-mavlink | grep -qw dialout"
check "gport-mavlink.service is installed but not enabled (it needs its endpoint first)" \
    sh -c "[ \"\$(systemctl is-enabled gport-mavlink.service)\" = disabled ]"
systemctl stop gportd.service gportd.socket >/dev/null 2>&1
systemctl start gport-mavlink.service
check "starting gport-mavlink starts gportd (BindsTo) and runs as gport-mavlink" \
    sh -c "systemctl is-active -q gportd.service && sleep 1 && systemctl is-active -q gport-mavlink.service \
           && [ \"\$(ps -o user= -p \$(systemctl show -p MainPID --value gport-mavlink.service))\" = gport-mavlink ]"
started_after() {
    local daemon bridge
    daemon=$(systemctl show -p ActiveEnterTimestampMonotonic --value gportd.service)
    bridge=$(systemctl show -p ExecMainStartTimestampMonotonic --value gport-mavlink.service)
    [ "$daemon" -gt 0 ] && [ "$bridge" -ge "$daemon" ]
}
check "gport-mavlink started after gportd was ready" started_after
check "the bridge is a client of gportd (status counts it)" \
    eventually 10 sh -c "gportctl --json status | grep -Eq '\"clients\": ?[2-9]'"
check "the bridge listens on loopback only by default (udpin:127.0.0.1:14560)" \
    sh -c "grep -q ' 0100007F:38E0 ' /proc/net/udp && ! grep -q ' 00000000:38E0 ' /proc/net/udp"
check "its StateDirectory (signing timestamp) is /var/lib/gport-mavlink, the bridge's, mode 700" \
    sh -c "[ \"\$(stat -c '%U %a' /var/lib/gport-mavlink)\" = 'gport-mavlink 700' ]"
# A rogue HEARTBEAT from system 99 (a valid MAVLink 2 frame): ignored, and
# logged natively at priority 4, so `journalctl -p warning` finds it.
printf '\xfd\x09\x00\x00\x00\x63\x01\x00\x00\x00\x00\x00\x00\x00\x02\x03\x00\x04\x03\x75\x91' \
    >/dev/udp/127.0.0.1/14560
check "a rogue sender is a journal warning of its own (journalctl -p warning -u gport-mavlink)" \
    eventually 10 sh -c "journalctl -q -u gport-mavlink.service -p warning -o cat | grep -q 'ignoring system 99'"
check "gport-mavlink's entries are native (SYSLOG_IDENTIFIER=gport-mavlink, info at priority 6)" \
    sh -c "journalctl -q -u gport-mavlink.service -o verbose | grep -q 'SYSLOG_IDENTIFIER=gport-mavlink' \
           && journalctl -q -u gport-mavlink.service -p info -o cat | grep -q 'MAVLink on udpin:127.0.0.1:14560'"
systemctl stop gportd.service
check "stopping gportd stops gport-mavlink with it" \
    eventually 10 sh -c "! systemctl is-active -q gport-mavlink.service"
# ---- 10 ----------------------------------------------------------------------
step "10. gport-web: its own user, a token made on first start, a login on every path"
check "postinst made the gport-web user, in group gport and not dialout" \
    sh -c "getent passwd gport-web >/dev/null && id -nG gport-web | grep -qw gport \
           && ! id -nG gport-web | grep -qw dialout"
check "gport-web.service is installed but not enabled" \
    sh -c "[ \"\$(systemctl is-enabled gport-web.service)\" = disabled ]"
systemctl start gport-web.service
check "starting gport-web starts gportd (BindsTo) and runs as gport-web" \
    eventually 10 sh -c "systemctl is-active -q gportd.service && systemctl is-active -q gport-web.service \
           && [ \"\$(ps -o user= -p \$(systemctl show -p MainPID --value gport-web.service))\" = gport-web ]"
check "its token file was made on the first start: /var/lib/gport-web/token, gport-web's, mode 600" \
    eventually 10 sh -c "[ \"\$(stat -c '%U %a' /var/lib/gport-web/token)\" = 'gport-web 600' ]"
web_token=$(sed -n 's/^control://p; /^[A-Za-z0-9_-]\{16,\}$/p' /var/lib/gport-web/token 2>/dev/null | head -n 1)
check "the journal names the token file, never the token" \
    sh -c "[ -n '$web_token' ] && journalctl -q -u gport-web.service -o cat | grep -q /var/lib/gport-web/token \
           && ! journalctl -q -u gport-web.service -o cat | grep -qF '$web_token'"
check "it listens on loopback only (127.0.0.1:8790)" \
    eventually 10 sh -c "grep -q ' 0100007F:2256 ' /proc/net/tcp && ! grep -q ' 00000000:2256 ' /proc/net/tcp"
# http_get PATH [HEADER]: gport-web's answer to a GET (bash's /dev/tcp: the
# root has no curl).
http_get() {
    local answer
    exec 3<>/dev/tcp/127.0.0.1/8790 || return 1
    printf 'GET %s HTTP/1.1\r\nHost: 127.0.0.1:8790\r\n%sConnection: close\r\n\r\n' \
        "$1" "${2:+$2$'\r\n'}" >&3
    answer=$(timeout 10 cat <&3 | tr -d '\r')
    exec 3<&-
    printf '%s\n' "$answer"
}
answers() {  # STATUS TEXT PATH [HEADER]: the answer has that status and text
    local answer
    answer=$(http_get "$3" "${4:-}")
    printf '%s\n' "$answer" | head -n 1 | grep -q " $1 " && printf '%s\n' "$answer" | grep -qF -- "$2" \
        || { printf '%s\n' "$answer" | head -n 20; return 1; }
}
no_status() { ! http_get /api/status | grep -q daemon_version; }
check "without a login /api/status answers 401" answers 401 error /api/status
check "without a login no status is given" no_status
check "with the token from the file /api/status is gportd's status" \
    answers 200 daemon_version /api/status "Authorization: Bearer $web_token"
web_link=$(runuser -u gport-web -- gport-web --print-url --listen 127.0.0.1:8790 \
    --token-file /var/lib/gport-web/token 2>&1 | head -n 1)
link_works_once() {
    local target=${web_link#http://127.0.0.1:8790}
    [ "$target" != "$web_link" ] || { echo "no link: $web_link"; return 1; }
    answers 303 gport_session= "$target" && answers 401 error "$target"
}
check "gport-web --print-url, as gport-web, prints a one-time link that logs in once" link_works_once
check "the journal says how to get a login link, and holds no code" \
    sh -c "journalctl -q -u gport-web.service -o cat | grep -q 'gport-web --print-url' \
           && ! journalctl -q -u gport-web.service -o cat | grep -q 'code='"
systemctl stop gportd.service
check "stopping gportd stops gport-web with it" \
    eventually 10 sh -c "! systemctl is-active -q gport-web.service"
if out=$(apt-get purge -y -q gportd 2>&1); then
    pass "apt-get purge gportd (again)"
else
    fail "apt-get purge gportd (again)" "$out"
fi
