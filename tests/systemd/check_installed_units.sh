#!/bin/sh
# Installs the build tree to a temporary DESTDIR (prefix /usr, the layout the
# .deb has) and checks the installed units as CI and users will see them:
#   - `systemd-analyze verify` prints nothing for any unit (the template
#     pair checked through instance gimbal0);
#   - `systemd-analyze security --offline=yes` rates gportd.service (and
#     gportd@gimbal0.service) at 1.0 or lower;
#   - the sysusers.d file and the udev rule are in place.
# Fails, loudly, when gportd was not built: the check is meaningless without it.
#
# usage: check_installed_units.sh BUILD_DIR
set -eu

fail() {
    echo "FAIL: $*" >&2
    exit 1
}

[ $# -eq 1 ] || fail "usage: $0 BUILD_DIR"
build=$1
command -v systemd-analyze >/dev/null || fail "systemd-analyze not found (Debian package: systemd)"

work=$(mktemp -d /tmp/gport-units-XXXXXX)
trap 'rm -rf "$work"' EXIT
root=$work/root

DESTDIR=$root "${CMAKE:-cmake}" --install "$build" --prefix /usr >"$work/install.log" 2>&1 \
    || { cat "$work/install.log" >&2; fail "cmake --install failed"; }
[ -x "$root/usr/bin/gportd" ] \
    || fail "gportd is not installed: build it first (ninja -C $build gportd), and daemon/ must" \
            "install it: install(TARGETS gportd RUNTIME DESTINATION \${CMAKE_INSTALL_BINDIR})"

# Where the install put each file (the directories depend on the system).
installed() {
    found=$(cd "$root" && find . -path "*/$1" | head -n 1)
    [ -n "$found" ] || fail "$1 was not installed (install log: $(cat "$work/install.log"))"
    echo "${found#.}"
}
unit=$(installed systemd/system/gportd.service)
for file in systemd/system/gportd.service systemd/system/gportd.socket systemd/system/gportd@.service \
            systemd/system/gportd@.socket sysusers.d/gportd.conf udev/rules.d/60-gportd.rules \
            systemd/system/gport-mavlink.service systemd/system/gport-mavlink@.service \
            sysusers.d/gport-mavlink.conf systemd/system/gport-web.service sysusers.d/gport-web.conf; do
    echo "installed: $(installed "$file")"
done
grep -qx "ExecStart=/usr/bin/gportd" "$root$unit" || fail "$unit does not start /usr/bin/gportd"

# verify --root resolves everything inside the root: the units ours depend on
# (sysinit.target, sockets.target, ...), the template's /bin/sh and
# ExecReload's /bin/kill. Give it the host's, as an installed system has
# them, without touching our files.
host_units=$root/usr/local/lib/systemd/system
mkdir -p "$host_units" "$root/bin"
for dir in /lib/systemd/system /usr/lib/systemd/system; do
    [ -d "$dir" ] && tar -C "$dir" --exclude='gportd*' -cf - . | tar -C "$host_units" -xf -
done
[ -e "$root/bin/sh" ] || cp /bin/sh "$root/bin/sh"
[ -e "$root/bin/kill" ] || cp /bin/kill "$root/bin/kill"   # ExecReload=

units="gportd.service gportd.socket gportd@gimbal0.service gportd@gimbal0.socket
       gport-mavlink.service gport-mavlink@gimbal0.service gport-web.service"
echo "\$ systemd-analyze verify --root=ROOT $units"
# shellcheck disable=SC2086  # $units is a list
output=$(systemd-analyze verify --root="$root" $units 2>&1) || status=$?
if [ -n "$output" ] || [ "${status:-0}" -ne 0 ]; then
    fail "systemd-analyze verify (exit ${status:-0}) must print nothing, printed:
$output"
fi
echo "(no output)"

# gport-mavlink and gport-web need IP (MAVLink, the browsers): their bound is
# 2.0, not 1.0.
for service in gportd.service gportd@gimbal0.service gport-mavlink.service \
               gport-mavlink@gimbal0.service gport-web.service; do
    case $service in gport-mavlink* | gport-web*) bound=2.0 ;; *) bound=1.0 ;; esac
    report=$(systemd-analyze security --offline=yes --root="$root" "$service" 2>&1) || true
    line=$(printf '%s\n' "$report" | grep "Overall exposure level for $service:") \
        || fail "no exposure level for $service:
$report"
    echo "$line"
    level=$(printf '%s\n' "$line" | sed 's/.*: \([0-9][0-9.]*\).*/\1/')
    awk -v level="$level" -v bound="$bound" 'BEGIN { exit !(level <= bound) }' \
        || fail "$service exposure level $level is above $bound:
$report"
done
echo "PASS"
