#!/usr/bin/env bash
# The systemd end-to-end test: boots a real systemd (a minimal Debian 12 root
# in a systemd-nspawn container) and runs the life of the service there with
# the .deb packed from BUILD_DIR: install, socket activation, the sandbox, a
# simulated gimbal, watchdog, journal fields, reload, stop, two instances,
# upgrade, remove and purge. The steps are tests/systemd/e2e_steps.sh; each
# prints PASS or FAIL with what it checked (docs/operations.md, "End-to-end
# test on a real systemd").
#
#   scripts/systemd-e2e.sh [BUILD_DIR]      # default build/release, built
#   GPORT_E2E_DEB=path/gportd_X_amd64.deb scripts/systemd-e2e.sh   # a given .deb
#   scripts/systemd-e2e.sh --root-only      # only make (or check) the cached
#       Debian root: scripts/test.sh runs it beside the build
#   GPORT_E2E_ARCH=arm64 scripts/systemd-e2e.sh build/arm64   # an arm64 root,
#       run under qemu-user through binfmt_misc (docs/operations.md, "Building
#       for ARM": what qemu-user cannot do for systemd there)
#
# Needs root (debootstrap, nspawn) and the network to Debian's mirror (the
# container's apt resolves the package's dependencies). The Debian root is
# made once with debootstrap in build/systemd-e2e/root and kept (rebuilt when
# older than 7 days, or with GPORT_E2E_NEW_ROOT=1); each run boots a fresh
# copy of it, so the package always meets a root with nothing of ours.
#
# Exit status: 0 every step passed; 1 a step failed (the journal is printed);
# 2 the test could not be set up; 77 skipped because this machine cannot run
# it (the reason is printed; GPORT_SYSTEMD_E2E=require turns that into a
# failure, GPORT_SYSTEMD_E2E=skip skips on purpose).
set -euo pipefail
cd "$(dirname "$0")/.."
project=$(pwd)
root_only=no
if [ "${1:-}" = --root-only ]; then
    root_only=yes
    shift
fi
build=${1:-build/release}
work=$project/build/systemd-e2e
arch=${GPORT_E2E_ARCH:-$(dpkg --print-architecture)}
native=$([ "$arch" = "$(dpkg --print-architecture)" ] && echo yes || echo no)
root=$work/root        # pristine debootstrap root, reused between runs
[ "$native" = yes ] || root=$work/root-$arch
run=$work/run          # the copy one run boots (kept until the next run)
stage=$work/mnt        # bound read-only at /mnt in the container: the .deb, the steps
archives=$work/apt-archives  # apt's download cache, shared by the runs
# What the root holds beyond debootstrap's minbase; a change rebuilds it.
root_packages=systemd,dbus,procps
root_recipe="bookworm minbase $root_packages v1"
[ "$native" = yes ] || root_recipe="$root_recipe $arch"
boot_timeout=${GPORT_E2E_TIMEOUT:-600}
start=$(date +%s)

say() { echo "e2e: $*"; }
skip() {
    say "SKIPPED: $*"
    if [ "${GPORT_SYSTEMD_E2E:-}" = require ]; then
        say "GPORT_SYSTEMD_E2E=require: a skip is a failure"
        exit 1
    fi
    exit 77
}
die() {
    say "error: $*" >&2
    exit 2
}

[ "${GPORT_SYSTEMD_E2E:-}" = skip ] && skip "GPORT_SYSTEMD_E2E=skip"
[ "$(uname -s)" = Linux ] || skip "needs Linux (systemd-nspawn)"
[ "$(id -u)" -eq 0 ] || skip "needs root: debootstrap and systemd-nspawn (run it with sudo)"
[ -d /sys/fs/cgroup ] || skip "no /sys/fs/cgroup: systemd cannot boot in a container here"

# What this script needs; scripts/deps.sh (gport_install_deps) lists them too.
need() {
    command -v "$1" >/dev/null && return 0
    say "installing $2"
    { apt-get update -qq && apt-get install -y -qq --no-install-recommends "$2" >/dev/null; } ||
        die "cannot install $2"
}

# ---- the Debian root (cached), made once ---------------------------------------
mirror() {
    local m
    m=$(awk '/^URIs:/ { print $2; exit }' /etc/apt/sources.list.d/debian.sources 2>/dev/null || true)
    [ -n "$m" ] || m=$(awk '/^deb / { print $2; exit }' /etc/apt/sources.list 2>/dev/null || true)
    echo "${m:-http://deb.debian.org/debian}"
}

root_is_fresh() {
    [ "${GPORT_E2E_NEW_ROOT:-0}" != 1 ] && [ -x "$root/lib/systemd/systemd" ] &&
        [ "$(cat "$root/.gport-e2e-recipe" 2>/dev/null)" = "$root_recipe" ] &&
        [ -z "$(find "$root/.gport-e2e-recipe" -mtime +7)" ]
}

make_root() {
    root_is_fresh && return 0
    say "building the Debian 12 root in $root (debootstrap, once; about a minute)"
    rm -rf "$root" "$root.tmp"
    debootstrap --arch="$arch" --variant=minbase --include="$root_packages" bookworm "$root.tmp" "$(mirror)" \
        >"$work/debootstrap.log" 2>&1 ||
        { tail -n 20 "$work/debootstrap.log"; die "debootstrap failed (log: $work/debootstrap.log)"; }
    echo "$root_recipe" >"$root.tmp/.gport-e2e-recipe"
    mv "$root.tmp" "$root"
}

if [ "$root_only" = yes ]; then
    [ "$native" = yes ] || die "--root-only makes this machine's own architecture's root"
    need debootstrap debootstrap
    mkdir -p "$work"
    make_root
    say "root ready: $root ($(($(date +%s) - start)) s)"
    exit 0
fi

# nspawn first turns "/" into a slave mount (mount MS_REC|MS_SLAVE on "/"),
# which fails with EINVAL when "/" is not a mount point: in a plain chroot,
# such as the fresh-machine CI root. There, run again from a private mount
# namespace, chrooted into a recursive bind of "/" (which is a mount point);
# the bind goes away with the namespace.
if ! mountpoint -q / && [ -z "${GPORT_E2E_REBOUND:-}" ]; then
    say "/ is not a mount point (a chroot?), which systemd-nspawn needs: running again" \
        "in a private mount namespace, chrooted into a bind of /"
    unshare --mount --propagation unchanged true 2>/dev/null ||
        skip "/ is not a mount point (a chroot?), which systemd-nspawn needs, and no mount namespace can be made here"
    mkdir -p "$work/rebound"
    exec unshare --mount --propagation unchanged -- env GPORT_E2E_REBOUND=1 bash -c '
        view=$1 project=$2
        shift 2
        if ! mount --rbind / "$view"; then
            echo "e2e: SKIPPED: / is not a mount point (a chroot?), and it cannot be bound onto one here"
            exit 77
        fi
        if grep -q " $view .*shared:" /proc/self/mountinfo; then
            # The bind would show on the host too: undo it and give up.
            umount -l "$view"
            echo "e2e: SKIPPED: / is not a mount point and its mount is shared: cannot bind it privately"
            exit 77
        fi
        exec chroot "$view" /bin/bash -c "cd \"\$0\" && exec bash scripts/systemd-e2e.sh \"\$@\"" "$project" "$@"
    ' _ "$work/rebound" "$project" "$@"
fi

need debootstrap debootstrap
need systemd-nspawn systemd-container
if [ "$native" = no ]; then
    source scripts/deps.sh
    gport_register_binfmt "$(gport_qemu_arch "$arch")" ||
        skip "a $arch root needs qemu-user through binfmt_misc, which cannot be set up here"
fi

# ---- the package -------------------------------------------------------------
rm -rf "$stage"
mkdir -p "$stage" "$archives"
if [ -n "${GPORT_E2E_DEB:-}" ]; then
    deb=$GPORT_E2E_DEB  # a package built elsewhere
    [ -f "$deb" ] || die "GPORT_E2E_DEB=$deb: no such file"
else
    [ -f "$build/CPackConfig.cmake" ] || die "$build is not a configured build (no CPackConfig.cmake)"
    [ -x "$build/app/gportd" ] || die "$build has no gportd: build it first (scripts/test.sh does)"
    say "packing the .deb from $build (cpack -G DEB)"
    rm -rf "$work/cpack"
    cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work/cpack" >"$work/cpack.log" 2>&1 ||
        { cat "$work/cpack.log"; die "cpack -G DEB failed"; }
    deb=$(find "$work/cpack" -maxdepth 1 -name 'gportd_*.deb' | head -n 1)
    [ -n "$deb" ] || die "cpack made no gportd_*.deb (see $work/cpack.log)"
fi
cp "$deb" "$stage/"
cp tests/systemd/e2e_steps.sh "$stage/"
say "package: $(basename "$deb")"

# ---- the Debian root (cached; made by make_root above) -----------------------
make_root

# A fresh copy for this run: nothing of ours, nothing left by an earlier run.
rm -rf "$run"
cp -a "$root" "$run"
echo "gport-e2e" >"$run/etc/hostname"
# The steps run as a unit of the container's systemd once it is up, with their
# output on the console (nspawn's stdout), then `systemctl exit` hands their
# status to nspawn.
cat >"$run/etc/systemd/system/gport-e2e.service" <<'EOF'
[Unit]
Description=gportd end-to-end steps
After=multi-user.target

[Service]
Type=simple
ExecStart=/bin/bash /mnt/e2e_steps.sh
StandardInput=null
StandardOutput=tty
StandardError=tty
TTYPath=/dev/console
EOF
# No login prompt on that console: its getty would hang the steps up.
ln -sf /dev/null "$run/etc/systemd/system/console-getty.service"
ln -sf /dev/null "$run/etc/systemd/system/getty@.service"
mkdir -p "$run/etc/systemd/system/multi-user.target.wants"
ln -sf /etc/systemd/system/gport-e2e.service "$run/etc/systemd/system/multi-user.target.wants/"

# Can nspawn run here at all? (Not, for instance, without cgroups or without
# the right to create namespaces.) If not, skip and say why.
# See "boot and run" for the flags.
export SYSTEMD_NSPAWN_UNIFIED_HIERARCHY=1
nspawn=(systemd-nspawn --quiet --register=no --keep-unit --system-call-filter=bpf -D "$run")
if ! probe=$("${nspawn[@]}" --console=pipe /bin/true 2>&1 </dev/null); then
    skip "systemd-nspawn cannot start a container on this machine: $probe"
fi

# ---- boot and run ------------------------------------------------------------
# --register=no: no systemd-machined on the host (often no systemd at all);
# --keep-unit: stay in the caller's cgroup instead of asking the host's
# systemd for a scope; --console=passive: the container's console (where the
# steps write) goes to our stdout without needing a terminal (with =pipe,
# services could not open /dev/console).
# SYSTEMD_NSPAWN_UNIFIED_HIERARCHY=1 and --system-call-filter=bpf: the
# container's systemd gets cgroup v2 and may load BPF programs, which is how
# it enforces DevicePolicy=/DeviceAllow=. On a host with the hybrid cgroup
# layout (these CI machines) nspawn would otherwise hand the container the v1
# devices controller read-only and filter out bpf(): the units' device list
# would silently not apply, and step 3 would (rightly) fail.
# The arguments after --boot go to the container's systemd: no boot status,
# its own messages to the journal only.
say "booting systemd in the container ($(($(date +%s) - start)) s so far)"
# The console is a pty: its lines end in CR LF.
set +e
timeout --kill-after=20 "$boot_timeout" "${nspawn[@]}" --console=passive \
    --bind-ro="$stage:/mnt" --bind="$archives:/var/cache/apt/archives" --resolv-conf=copy-host \
    --boot -- systemd.show_status=false systemd.log_target=journal systemd.log_color=false \
    </dev/null | tr -d '\r' | tee "$work/console.log"
rc=${PIPESTATUS[0]}
set -e
took=$(($(date +%s) - start))
# A container that powers off for another reason also exits 0: only the
# steps' own summary line says they ran to the end.
if [ "$rc" -eq 0 ] && ! grep -qE '^== [0-9]+ checks passed, 0 failed' "$work/console.log"; then
    say "FAIL: the container stopped (status 0) before the steps reported their result"
    rc=3
fi
case $rc in
    0) say "all steps passed in $took s" ;;
    124) say "FAIL: the container did not finish within $boot_timeout s; root kept in $run"
         rc=1 ;;
    *) say "FAIL: exit status $rc after $took s; root kept in $run (journal: journalctl -D $run/var/log/journal)"
       rc=1 ;;
esac
exit $rc
