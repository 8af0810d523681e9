#!/usr/bin/env bash
# Makes a sysroot for cross-building and testing gportd on another Debian
# architecture (arm64, armhf), without adding that architecture to this
# machine's dpkg: apt resolves and downloads the target's -dev packages (and
# everything they need at run time) into a private apt state, and each .deb is
# unpacked with dpkg -x. The machine's own package state is never touched, so a
# foreign index that fails to download (Debian's armhf security list has been
# seen to fail its size check on every retry) costs only that index.
#
#   scripts/cross-sysroot.sh ARCH DIR
#
# DIR is made (or reused when it was made from the same package list) and holds
# usr/include, usr/lib/<triple>, lib/<triple> (the target's dynamic loader and
# glibc, from the same packages, for qemu-user's QEMU_LD_PREFIX), and
# var/lib/dpkg, a dpkg database of these packages (for dpkg-shlibdeps). Used by
# cmake/toolchains/*.cmake (GPORT_SYSROOT) and scripts/test.sh's ARM stages.
set -euo pipefail

arch=${1:?usage: cross-sysroot.sh ARCH DIR}
root=${2:?usage: cross-sysroot.sh ARCH DIR}

# What gportd's build needs from the target, and the tests at run time
# (bench/ is not built for the targets). nlohmann-json and CLI11 are
# architecture-independent, but CMake finds packages inside the sysroot only.
packages=(
  libc6-dev libstdc++-12-dev
  libboost-dev nlohmann-json3-dev libspdlog-dev libfmt-dev libsystemd-dev libcli11-dev
  libgtest-dev libgmock-dev libssl-dev
)

stamp="$root/.gport-sysroot"
want="3 $arch ${packages[*]}"  # 2: with var/lib/dpkg
if [[ -f $stamp && $(cat "$stamp") == "$want" ]]; then
  echo "== sysroot for $arch: $root (already made)"
  exit 0
fi

rm -rf "$root"
state=$(mktemp -d /tmp/gport-apt-$arch-XXXXXX)
trap 'rm -rf "$state"' EXIT
mkdir -p "$root" "$state"/{lists/partial,archives/partial,etc} "$state/dpkg"
touch "$state/dpkg/status"
apt_opts=(
  -o "APT::Architecture=$arch" -o "APT::Architectures::=$arch"
  -o "Dir::State=$state" -o "Dir::State::Lists=$state/lists"
  -o "Dir::State::status=$state/dpkg/status" -o "Dir::Cache=$state"
  -o "Dir::Cache::Archives=$state/archives"
  -o "Dir::Etc::Preferences=$state/etc/none" -o "Dir::Etc::PreferencesParts=$state/etc"
  -o "Debug::NoLocking=1" -o "APT::Sandbox::User=root"
)

echo "== sysroot for $arch: downloading ${#packages[@]} packages and their dependencies"
# An index that fails (a mirror mid-sync) is reported and ignored: the others
# still resolve everything from the release and its updates.
if ! apt-get "${apt_opts[@]}" update -qq 2>"$state/update.err"; then
  grep -E '^(E|W):' "$state/update.err" >&2 || true
  echo "note: some $arch package indices failed to download (above); going on with the rest" >&2
fi
apt-get "${apt_opts[@]}" install -qq -y --download-only --no-install-recommends \
  "${packages[@]}" >"$state/install.log" 2>&1 ||
  { cat "$state/install.log" >&2; echo "error: cannot resolve the $arch packages" >&2; exit 1; }

# Each package unpacked, and recorded in a dpkg database of the sysroot's own
# (var/lib/dpkg: status, file lists under the sysroot's paths, symbols and
# shlibs files) so that dpkg-shlibdeps, given DPKG_ADMINDIR, finds which
# package holds each library the .deb needs (cmake/GportPackaging.cmake).
admin="$root/var/lib/dpkg"
mkdir -p "$admin/info" "$admin/updates"
echo 1 >"$admin/info/format"  # multiarch names: <package>:<arch>.list
: >"$admin/status"
echo "$arch" >"$admin/arch"
count=0
for deb in "$state"/archives/*.deb; do
  dpkg -x "$deb" "$root"
  name=$(dpkg-deb -f "$deb" Package)
  entry=$name
  [ "$(dpkg-deb -f "$deb" Multi-Arch)" = same ] && entry="$name:$arch"
  { dpkg-deb -f "$deb"; echo "Status: install ok installed"; echo; } >>"$admin/status"
  dpkg-deb --fsys-tarfile "$deb" | tar -t | sed -e 's|^\./|/|' -e 's|/$||' -e '/^$/d' \
    | sed "s|^|$root|" >"$admin/info/$entry.list"
  control=$(mktemp -d "$state/control-XXXXXX")
  dpkg-deb -e "$deb" "$control"
  for file in symbols shlibs; do
    [ -f "$control/$file" ] && cp "$control/$file" "$admin/info/$entry.$file"
  done
  count=$((count + 1))
done
# Absolute symlinks inside the sysroot (e.g. usr/lib/<triple>/libfoo.so ->
# /lib/<triple>/libfoo.so.1) must point into it, not into this machine.
while IFS= read -r link; do
  target=$(readlink "$link")
  ln -sfn "$root$target" "$link"
done < <(find "$root" -type l -lname '/*')
echo "$want" >"$stamp"
echo "== sysroot for $arch: $count packages unpacked into $root"
