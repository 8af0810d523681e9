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

# shellcheck source=../../support/npm_ci.sh
source "$here/../../support/npm_ci.sh"
npm_ci_need_node "the MAVLink cross-check"
npm_ci "$here" "$work" node-mavlink
if [[ $script == --install-only ]]; then
  exit 0
fi
NODE_PATH="$work/node_modules" node "$here/$script" "$@"
