#!/usr/bin/env bash
# The ctests mavlink_node_crosscheck and mavlink_peer_gimbal_manager: installs
# node-mavlink (pinned by package-lock.json) with `npm ci` into WORKDIR, a
# folder of the build tree, and runs SCRIPT (crosscheck.js against
# mavlink_peer_tool, or gimbal_manager.js against the programs) with ARGS.
# The source tree is never written. Fails, never skips, when node or npm is missing: CI installs
# Debian's nodejs and npm (scripts/deps.sh).
#
#   run.sh WORKDIR SCRIPT ARGS...
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
work=$1
script=$2
shift 2

for cmd in node npm; do
  if ! command -v "$cmd" >/dev/null 2>&1; then
    echo "error: '$cmd' is not installed; the MAVLink cross-check needs Node.js 18+ and npm" \
         "(Debian: apt-get install nodejs npm; scripts/deps.sh installs them)" >&2
    exit 1
  fi
done
major=$(node -p 'process.versions.node.split(".")[0]')
if ((major < 18)); then
  echo "error: node $(node --version) is too old; the cross-check needs Node.js 18+ (Debian 12's)" >&2
  exit 1
fi

mkdir -p "$work"
# npm ci again only when the lock changed or the install is incomplete.
if ! cmp -s "$here/package-lock.json" "$work/package-lock.json" ||
   [[ ! -f $work/node_modules/node-mavlink/package.json ]]; then
  cp "$here/package.json" "$here/package-lock.json" "$work/"
  echo "== npm ci (node $(node --version), npm $(npm --version)) in $work"
  (cd "$work" && npm ci --no-audit --no-fund --ignore-scripts --omit=optional --loglevel=error)
fi
NODE_PATH="$work/node_modules" node "$here/$script" "$@"
