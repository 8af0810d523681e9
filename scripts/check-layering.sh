#!/usr/bin/env bash
# Fails when a folder includes a folder above it in the layering order
# (docs/architecture.md, "Layout"):
#
#   base  protocol  config  daemon  sim  ipc  systemd  app  client  cli  examples  mavlink
#
# mavlink/ is last: its codec needs only base/, and the gport-mavlink program
# (mavlink/bridge/) is a client of gportd built on the client library, so it
# sits above every part of the daemon and above client/.
#
# Each folder may include its own headers and those of the folders before
# it, never those after it. Checked: quoted or angled "gport/<part>/..."
# includes (<part> is the folder whose include/ holds it) and relative
# "../" includes, resolved against the including file. gport/version.hpp is
# generated (gport::version) and may be included anywhere. tests/, bench/
# and fuzz/ are outside the order and not checked. A folder that does not
# exist is skipped.
set -euo pipefail
cd "$(dirname "$0")/.."

order=(base protocol config daemon sim ipc systemd app client cli examples mavlink)

rank() {  # the folder's place in the order, or nothing
  local i
  for i in "${!order[@]}"; do
    if [[ ${order[$i]} == "$1" ]]; then
      echo "$i"
      return
    fi
  done
}

failures=0
fail() {
  echo "$1" >&2
  failures=$((failures + 1))
}

for folder in "${order[@]}"; do
  [[ -d $folder ]] || continue
  own=$(rank "$folder")
  while IFS= read -r hit; do
    file=${hit%%:*}
    rest=${hit#*:}
    line=${rest%%:*}
    text=${rest#*:}
    target=$(sed -E 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*["<]([^">]+)[">].*/\1/' <<<"$text")
    case $target in
      gport/version.hpp)
        continue
        ;;
      gport/*/*)
        part=${target#gport/}
        part=${part%%/*}
        ;;
      ../*)
        resolved=$(realpath -m --relative-to=. "$(dirname "$file")/$target")
        part=${resolved%%/*}
        [[ $part == "$folder" ]] && continue
        ;;
      *)
        continue
        ;;
    esac
    reached=$(rank "$part")
    if [[ -z $reached ]]; then
      fail "$file:$line: includes \"$target\", which reaches $part/, outside the layered folders"
    elif ((reached > own)); then
      fail "$file:$line: includes \"$target\": $folder/ reaches up to $part/ (the order is: ${order[*]})"
    fi
  done < <(grep -rnE '^[[:space:]]*#[[:space:]]*include[[:space:]]*["<](gport/|\.\./)' \
             --include='*.cpp' --include='*.hpp' --include='*.h' --include='*.cc' \
             --include='*.in' "$folder" || true)
done

if ((failures > 0)); then
  echo "check-layering: $failures upward include(s); see docs/architecture.md, \"Layout\"" >&2
  exit 1
fi
echo "check-layering: every include points down (${order[*]})"
