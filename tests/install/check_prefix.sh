#!/bin/sh
# Installs the build tree to a temporary prefix and checks that it is
# self-contained and starts from there:
#   - nothing is written outside the prefix (every line of the install
#     manifest is under it), the config goes to <prefix>/etc/gportd;
#   - every program in <prefix>/bin runs `--version` as an unprivileged user
#     (uid 65534) with an empty environment (env -i), also after the tree is
#     moved (the RUNPATH is relative to the program);
#   - the installed gportd reads <prefix>/etc/gportd/gportd.json by default;
#   - the non-root quick start (README.md): as that user, gportd cannot bind
#     /run/gportd.sock, exits 1 and says what to do; with --socket in a
#     directory of its own it serves gportctl;
#   - installed to /usr (DESTDIR, the .deb's layout) the programs carry no
#     RUNPATH and the config is /etc/gportd/gportd.json.
#   - from a build tree it cannot write (mounted read-only), the install
#     succeeds and its manifest goes to <prefix>/share/gportd.
# The install itself runs as root (when the tests do): the unprivileged part
# is running what it installed.
#
# usage: check_prefix.sh BUILD_DIR
set -eu

fail() {
    echo "FAIL: $*" >&2
    exit 1
}

[ $# -eq 1 ] || fail "usage: $0 BUILD_DIR"
build=$1
cmake=${CMAKE:-cmake}
work=$(mktemp -d /tmp/gport-prefix-XXXXXX)
daemon_pid=
cleanup() {
    [ -z "$daemon_pid" ] || kill "$daemon_pid" 2>/dev/null || true
    rm -rf "$work"
}
trap cleanup EXIT
chmod 755 "$work"

# As uid/gid 65534 with no supplementary groups when we are root (CI);
# as ourselves otherwise.
# (A command word, not a function: `as_user ... &` must give the daemon's own
# pid in $!, which a function run in a background subshell would not.)
if [ "$(id -u)" -eq 0 ]; then
    as_user="setpriv --reuid=65534 --regid=65534 --clear-groups --"
else
    as_user=
fi

# A cross build's programs run under qemu-user (binfmt_misc), which finds the
# target's loader and libc through QEMU_LD_PREFIX (scripts/test-arm.sh): the
# one variable the "empty" environment keeps.
keep=
[ -z "${QEMU_LD_PREFIX:-}" ] || keep="QEMU_LD_PREFIX=$QEMU_LD_PREFIX"

prefix=$work/prefix
"$cmake" --install "$build" --prefix "$prefix" >"$work/install.log" 2>&1 \
    || { cat "$work/install.log" >&2; fail "cmake --install --prefix $prefix failed"; }
outside=$(grep -v "^$prefix/" "$build/install_manifest.txt" || true)
[ -z "$outside" ] || fail "cmake --install --prefix $prefix wrote outside the prefix:
$outside"
[ -f "$prefix/etc/gportd/gportd.json" ] || fail "no $prefix/etc/gportd/gportd.json"
echo "installed $(wc -l <"$build/install_manifest.txt") files, all under the prefix"

# Each program's --version, unprivileged, with an empty environment, from $1/bin.
run_all() {
    found=
    for program in "$1"/bin/*; do
        name=$(basename "$program")
        out=$($as_user env -i $keep "$program" --version 2>&1) \
            || fail "$program --version failed (exit $?): $out"
        case $out in
            "$name "[0-9]*) ;;
            *) fail "$program --version printed \"$out\"" ;;
        esac
        found="$found $name"
    done
    for name in gportd gportctl gport-sim gport-mavlink; do
        case " $found " in *" $name "*) ;; *) fail "no $name in $1/bin (has:$found)" ;; esac
    done
    echo "$1/bin:$found: --version runs (uid $($as_user id -u), env -i)"
}
chown -R 65534:65534 "$prefix" 2>/dev/null || true
run_all "$prefix"
moved=$work/moved
mv "$prefix" "$moved"
run_all "$moved"

# The default config is the prefix's own.
help=$($as_user env -i $keep "$moved/bin/gportd" --help)
printf '%s\n' "$help" | grep -q "default $moved/etc/gportd/gportd.json" \
    || fail "gportd --help does not name $moved/etc/gportd/gportd.json as the default:
$help"
echo "gportd's default config: $moved/etc/gportd/gportd.json"

# The non-root quick start. As a user, /run is not writable.
if [ "$($as_user id -u)" -ne 0 ]; then
    status=0
    # With XDG_RUNTIME_DIR the hint names it; without (env -i, as after su -)
    # it names $HOME and says why.
    for runtime_dir in set unset; do
        env_runtime=
        hint='--socket "$HOME/gportd.sock" (XDG_RUNTIME_DIR is not set'
        if [ "$runtime_dir" = set ]; then
            env_runtime=XDG_RUNTIME_DIR=/run/user/65534
            hint='--socket "$XDG_RUNTIME_DIR/gportd.sock"'
        fi
        status=0
        # shellcheck disable=SC2086 # $keep and $env_runtime: words, or none
        out=$($as_user env -i $keep $env_runtime "$moved/bin/gportd" --simulate \
            --socket /run/gportd-prefix-test.sock 2>&1) || status=$?
        [ "$status" -eq 1 ] || fail "gportd on an unwritable socket path: exit $status, not 1: $out"
        for piece in "cannot bind: Permission denied" "$hint" "gport group"; do
            printf '%s\n' "$out" | grep -qF -- "$piece" || fail "gportd does not say \"$piece\": $out"
        done
    done
    echo "as a user, /run: exit 1 with the hint (XDG_RUNTIME_DIR set, and not)"
fi
runtime=$work/runtime
mkdir -m 700 "$runtime"
chown 65534:65534 "$runtime" 2>/dev/null || true
$as_user env -i $keep XDG_RUNTIME_DIR="$runtime" "$moved/bin/gportd" --simulate \
    --socket "$runtime/gportd.sock" >"$work/gportd.log" 2>&1 &
daemon_pid=$!
tries=0
until $as_user env -i $keep "$moved/bin/gportctl" --socket "$runtime/gportd.sock" status \
    >"$work/status.txt" 2>&1; do
    tries=$((tries + 1))
    kill -0 "$daemon_pid" 2>/dev/null || fail "gportd exited: $(cat "$work/gportd.log")"
    [ "$tries" -lt 100 ] || fail "gportctl status never succeeded: $(cat "$work/status.txt")"
    sleep 0.2
done
kill "$daemon_pid"
wait "$daemon_pid" 2>/dev/null || true
daemon_pid=
echo "as a user, --socket \$XDG_RUNTIME_DIR/gportd.sock: gportctl status works"

# The .deb's layout: prefix /usr, no RUNPATH, config in /etc.
root=$work/root
DESTDIR=$root "$cmake" --install "$build" --prefix /usr >"$work/install-usr.log" 2>&1 \
    || { cat "$work/install-usr.log" >&2; fail "cmake --install --prefix /usr (DESTDIR) failed"; }
[ -f "$root/etc/gportd/gportd.json" ] || fail "prefix /usr: no /etc/gportd/gportd.json"
for program in "$root"/usr/bin/*; do
    if readelf -d "$program" | grep -E 'RPATH|RUNPATH'; then
        fail "prefix /usr: $program carries an RPATH"
    fi
done
echo "prefix /usr: no RUNPATH, config /etc/gportd/gportd.json"

# Installing writes nothing into the build tree: an installer who cannot
# write it (a user installing a tree root built) gets a whole install, the
# manifest beside it (cmake/GportInstallManifest.cmake). The build tree is
# mounted read-only in a mount namespace of the install's own, which even
# root cannot write through; where no mount namespace can be made (an
# unprivileged container), this part is skipped, saying so.
readonly_prefix=$work/readonly-prefix
if unshare --mount true 2>/dev/null; then
    status=0
    unshare --mount sh -c '
        mount --bind "$1" "$1" && mount -o remount,bind,ro "$1" || exit 90
        exec "$2" --install "$1" --prefix "$3"' sh "$build" "$cmake" "$readonly_prefix" \
        >"$work/install-readonly.log" 2>&1 || status=$?
    [ "$status" -ne 90 ] || fail "could not mount $build read-only: $(cat "$work/install-readonly.log")"
    [ "$status" -eq 0 ] || { cat "$work/install-readonly.log" >&2;
        fail "cmake --install from a build tree it cannot write: exit $status"; }
    manifest=$readonly_prefix/share/gportd/install_manifest.txt
    [ -s "$manifest" ] || fail "no install manifest at $manifest"
    grep -q "/gportd.service$" "$manifest" || fail "the units are not in $manifest"
    outside=$(grep -v "^$readonly_prefix/" "$manifest" || true)
    [ -z "$outside" ] || fail "the read-only build tree's install wrote outside the prefix:
$outside"
    grep -qF "the install manifest is $manifest" "$work/install-readonly.log" \
        || fail "the install does not say where its manifest went: $(cat "$work/install-readonly.log")"
    echo "build tree read-only: installed $(wc -l <"$manifest") files, the manifest in the prefix"
else
    echo "SKIPPED the read-only build tree's install: no mount namespace here (unshare --mount)"
fi
echo "PASS"
