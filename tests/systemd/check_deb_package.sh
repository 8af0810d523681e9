#!/bin/sh
# Builds the Debian package with `cpack -G DEB` (into a temporary directory)
# and checks what it holds: the programs, units, sysusers.d file, udev rule,
# default config (as a conffile), libgport-client with its headers, pkg-config
# and CMake files, the Python client module gport (Debian's dist-packages, no
# bytecode), the maintainer scripts, and dependencies
# computed by dpkg-shlibdeps (package dpkg-dev).
#
# usage: check_deb_package.sh BUILD_DIR
set -eu

fail() {
    echo "FAIL: $*" >&2
    exit 1
}

[ $# -eq 1 ] || fail "usage: $0 BUILD_DIR"
build=$1
cpack=${CPACK:-cpack}
for tool in "$cpack" dpkg-deb dpkg-shlibdeps; do
    command -v "$tool" >/dev/null || fail "$tool not found (Debian packages: cmake, dpkg-dev)"
done

work=$(mktemp -d /tmp/gport-deb-XXXXXX)
trap 'rm -rf "$work"' EXIT

"$cpack" -G DEB --config "$build/CPackConfig.cmake" -B "$work" >"$work/cpack.log" 2>&1 \
    || { cat "$work/cpack.log" >&2; fail "cpack -G DEB failed"; }
deb=$(find "$work" -maxdepth 1 -name '*.deb' | head -n 1)
[ -n "$deb" ] || fail "cpack made no .deb: $(cat "$work/cpack.log")"
echo "built: $(basename "$deb")"

contents=$(dpkg-deb -c "$deb" | awk '{ print $6 }')
for pattern in '^\./usr/bin/gportd$' '^\./usr/bin/gportctl$' '^\./usr/bin/gport-sim$' \
               '/systemd/system/gportd\.service$' '/systemd/system/gportd\.socket$' \
               '/systemd/system/gportd@\.service$' '/systemd/system/gportd@\.socket$' \
               '/sysusers\.d/gportd\.conf$' '/udev/rules\.d/60-gportd\.rules$' \
               '^\./usr/bin/gport-mavlink$' '/systemd/system/gport-mavlink\.service$' \
               '/systemd/system/gport-mavlink@\.service$' '/sysusers\.d/gport-mavlink\.conf$' \
               '^\./usr/bin/gport-web$' '/systemd/system/gport-web\.service$' \
               '/sysusers\.d/gport-web\.conf$' '^\./usr/share/doc/gportd/web\.md$' \
               '^\./usr/share/bash-completion/completions/gport-web$' \
               '^\./usr/share/zsh/vendor-completions/_gport-web$' \
               '^\./etc/gportd/gportd\.json$' '^\./usr/share/doc/gportd/operations\.md$' \
               '^\./usr/share/doc/gportd/examples/mavlink\.json$' \
               '^\./usr/share/bash-completion/completions/gportctl$' \
               '^\./usr/share/zsh/vendor-completions/_gportctl$' \
               '/libgport-client\.so\.1$' '/libgport-client\.so$' \
               '/pkgconfig/gport-client\.pc$' '/cmake/gport-client/gport-clientConfig\.cmake$' \
               '^\./usr/include/gport/client/client\.hpp$' \
               '^\./usr/include/gport/contract/errors\.hpp$' \
               '^\./usr/include/gport/contract/counters\.hpp$' \
               '^\./usr/lib/python3/dist-packages/gport/__init__\.py$' \
               '^\./usr/lib/python3/dist-packages/gport/client\.py$' \
               '^\./usr/lib/python3/dist-packages/gport/aio\.py$' \
               '^\./usr/lib/python3/dist-packages/gport/py\.typed$'; do
    printf '%s\n' "$contents" | grep -q -- "$pattern" \
        || fail "the package lacks a file matching $pattern; it holds:
$contents"
done

# The man pages (when built): gzipped under /usr/share/man, and `man NAME`
# finds and renders them from the unpacked package.
if grep -q '^GPORT_BUILD_MAN:BOOL=ON' "$build/CMakeCache.txt"; then
    root=$work/root
    dpkg-deb -x "$deb" "$root"
    for page in man8/gportd.8 man1/gportctl.1 man1/gport-sim.1 man1/gport-mavlink.1 man1/gport-web.1 \
                man5/gportd.json.5; do
        [ -f "$root/usr/share/man/$page.gz" ] || fail "the package lacks /usr/share/man/$page.gz"
        name=$(basename "$page")
        text=$(MANPATH="$root/usr/share/man" MANWIDTH=80 man "${name##*.}" "${name%.*}" 2>&1 | col -b)
        printf "%s\n" "$text" | grep -qx SYNOPSIS || fail "man ${name%.*} from the package does not render:
$text"
    done
    echo "man pages: packaged and rendered by man"
fi

# No RPATH in the package's programs (Debian policy 10.2): the RUNPATH that
# makes a prefix install start (cmake/GportHelpers.cmake) is removed for /usr.
programs=$work/programs
dpkg-deb -x "$deb" "$programs"
for program in "$programs"/usr/bin/*; do
    if readelf -d "$program" | grep -E 'RPATH|RUNPATH'; then
        fail "/usr/bin/$(basename "$program") in the package carries an RPATH"
    fi
done
echo "programs: no RPATH"

control=$work/control
dpkg-deb -e "$deb" "$control"
for script in postinst prerm postrm; do
    [ -x "$control/$script" ] || fail "the package lacks an executable $script"
done
grep -qx /etc/gportd/gportd.json "$control/conffiles" \
    || fail "/etc/gportd/gportd.json is not a conffile"

depends=$(dpkg-deb -f "$deb" Depends)
echo "Depends: $depends"
for dependency in libc6 'libsystemd0' systemd udev init-system-helpers; do
    printf '%s\n' "$depends" | grep -q "$dependency" \
        || fail "Depends lacks $dependency (dpkg-shlibdeps adds the libraries)"
done

# The Architecture field names the machine the programs were built for (read
# from gportd's ELF header, e_machine), not the machine that packaged them.
arch=$(dpkg-deb -f "$deb" Architecture)
machine=$(dpkg-deb --fsys-tarfile "$deb" | tar -xOf - ./usr/bin/gportd | od -An -tu2 -j18 -N2 | tr -d ' ')
case "$machine" in
    62) expected=amd64 triple=x86_64-linux-gnu ;;
    183) expected=arm64 triple=aarch64-linux-gnu ;;
    40) expected=armhf triple=arm-linux-gnueabihf ;;
    3) expected=i386 triple=i386-linux-gnu ;;
    *) fail "gportd is built for ELF machine $machine, which this check does not know" ;;
esac
[ "$arch" = "$expected" ] || fail "Architecture: $arch, but gportd is built for $expected"
echo "Architecture: $arch (gportd's ELF machine $machine)"
# The library in Debian's multiarch directory of that architecture.
printf '%s\n' "$contents" | grep -qx "\./usr/lib/$triple/libgport-client\.so\.1" \
    || fail "libgport-client.so.1 is not in /usr/lib/$triple"

printf '%s\n' "$contents" | grep -q '__pycache__' && fail "the package holds Python bytecode"
printf '%s\n' "$(dpkg-deb -f "$deb" Suggests)" | grep -q python3 \
    || fail "Suggests lacks python3 (the gport module)"

unit=$(printf '%s\n' "$contents" | grep '/systemd/system/gportd\.service$')
dpkg-deb --fsys-tarfile "$deb" | tar -xOf - "$unit" | grep -qx "ExecStart=/usr/bin/gportd" \
    || fail "the packaged gportd.service does not start /usr/bin/gportd"
echo "PASS"
