#!/usr/bin/env bash
# The ctest web_browser: installs playwright-core (pinned by
# package-lock.json) with `npm ci` into WORKDIR, a folder of the build tree,
# and runs web.js with ARGS: gport-web's page in Debian's chromium, headless,
# against gport-web, gportd and gport-sim (docs/web.md, "Tested in a
# browser"). The source tree is never written. Fails, never skips, when
# node, npm or chromium is missing: CI installs them (scripts/deps.sh:
# nodejs and npm in the build set, chromium in the browser set).
#
#   run.sh WORKDIR ARGS...          # node web.js ARGS...
#   run.sh WORKDIR --install-only   # only the npm ci (scripts/test.sh can run
#                                   # it beside the build, off the tests' time)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
work=$1
shift
chromium=${GPORT_CHROMIUM:-/usr/bin/chromium}

# shellcheck source=../../support/npm_ci.sh
source "$here/../../support/npm_ci.sh"
npm_ci_need_node "the browser test"
npm_ci "$here" "$work" playwright-core
if [[ ${1:-} == --install-only ]]; then
  exit 0
fi

if [[ ! -x $chromium ]]; then
  echo "error: no chromium at $chromium; the browser test drives Debian's chromium" \
       "(apt-get install chromium; scripts/deps.sh: gport_install_deps browser), or set GPORT_CHROMIUM" >&2
  exit 1
fi
GPORT_CHROMIUM=$chromium NODE_PATH="$work/node_modules" node "$here/web.js" "$@"
