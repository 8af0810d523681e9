#!/usr/bin/env bash
# The ctests mavlink_node_crosscheck and mavlink_peer_gimbal_manager: installs
# node-mavlink (pinned by package-lock.json) with `npm ci` into WORKDIR, a
# folder of the build tree, and runs SCRIPT (crosscheck.js against
# mavlink_peer_tool, or gimbal_manager.js against the programs) with ARGS.
# The source tree is never written. Fails, never skips, when node or npm is missing: CI installs
# Debian's nodejs and npm (scripts/deps.sh).
#
#   run.sh WORKDIR SCRIPT ARGS...
#   run.sh WORKDIR --install-only     # only the npm ci (scripts/test.sh runs
#                                     # it beside the build, off the tests' time)
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
# Both ctests share WORKDIR and ctest runs them in parallel: one npm ci at a time.
exec 9>"$work/.npm-ci.lock"
flock 9
# npm ci again only when the lock changed or the install is incomplete.
if ! cmp -s "$here/package-lock.json" "$work/package-lock.json" ||
   [[ ! -f $work/node_modules/node-mavlink/package.json ]]; then
  cp "$here/package.json" "$here/package-lock.json" "$work/"
  rm -rf "$work/node_modules"
  echo "== npm ci (node $(node --version), npm $(npm --version)) in $work"
  ci=(npm ci --no-audit --no-fund --ignore-scripts --omit=optional --loglevel=error)
  if ! (cd "$work" && "${ci[@]}") 2>"$work/npm-ci.err"; then
    # A registry reached through an intercepting proxy whose CA this machine
    # lacks (a fresh CI root): TLS cannot vouch for the bytes, but
    # package-lock.json pins every package by its sha512 integrity, which
    # npm checks on every tarball either way. Retry without TLS verification
    # then, and only then; any other failure fails the test.
    if grep -qE 'SELF_SIGNED_CERT|UNABLE_TO_GET_ISSUER_CERT|UNABLE_TO_VERIFY_LEAF_SIGNATURE|CERT_UNTRUSTED' \
         "$work/npm-ci.err"; then
      echo "note: npm could not verify the registry's TLS certificate ($(grep -m1 -oE '[A-Z_]*CERT[A-Z_]*' "$work/npm-ci.err"));" \
           "retrying with --strict-ssl=false: every package is still checked against its sha512 in package-lock.json" >&2
      (cd "$work" && "${ci[@]}" --strict-ssl=false)
    else
      cat "$work/npm-ci.err" >&2
      exit 1
    fi
  fi
fi
exec 9>&-
if [[ $script == --install-only ]]; then
  exit 0
fi
NODE_PATH="$work/node_modules" node "$here/$script" "$@"
