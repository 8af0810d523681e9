# Sourced by the tests that run a JavaScript peer (tests/mavlink/peer/run.sh,
# tests/web/browser/run.sh): Node.js 18+ checked, and `npm ci` of a
# package-lock.json into a folder of the build tree, never the sources.
#
#   npm_ci_need_node WHAT        # fails (exit 1) naming WHAT when node or npm is missing or old
#   npm_ci SOURCE WORK PACKAGE   # npm ci of SOURCE/package{,-lock}.json into WORK, once
#                                # per lock (WORK/node_modules/PACKAGE shows it is done)

npm_ci_need_node() {
  local cmd major
  for cmd in node npm; do
    if ! command -v "$cmd" >/dev/null 2>&1; then
      echo "error: '$cmd' is not installed; $1 needs Node.js 18+ and npm" \
           "(Debian: apt-get install nodejs npm; scripts/deps.sh installs them)" >&2
      exit 1
    fi
  done
  major=$(node -p 'process.versions.node.split(".")[0]')
  if ((major < 18)); then
    echo "error: node $(node --version) is too old; $1 needs Node.js 18+ (Debian 12's)" >&2
    exit 1
  fi
}

npm_ci() {
  local source=$1 work=$2 package=$3 ci
  mkdir -p "$work"
  # One npm ci at a time in WORK: ctest runs the tests that share it in
  # parallel, and scripts/test.sh runs it beside the build (--install-only).
  exec 9>"$work/.npm-ci.lock"
  flock 9
  # Again only when the lock changed or the install is incomplete.
  if ! cmp -s "$source/package-lock.json" "$work/package-lock.json" ||
     [[ ! -f $work/node_modules/$package/package.json ]]; then
    cp "$source/package.json" "$source/package-lock.json" "$work/"
    rm -rf "$work/node_modules"
    echo "== npm ci (node $(node --version), npm $(npm --version)) in $work"
    # --ignore-scripts: nothing runs at install, and nothing downloads (no
    # browser: the browser test uses the system's chromium).
    ci=(npm ci --no-audit --no-fund --ignore-scripts --omit=optional --loglevel=error)
    if ! (cd "$work" && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 "${ci[@]}") 2>"$work/npm-ci.err"; then
      # A registry reached through an intercepting proxy whose CA this
      # machine lacks (a fresh CI root): TLS cannot vouch for the bytes, but
      # package-lock.json pins every package by its sha512 integrity, which
      # npm checks on every tarball either way. Retry without TLS
      # verification then, and only then; any other failure fails the test.
      if grep -qE 'SELF_SIGNED_CERT|UNABLE_TO_GET_ISSUER_CERT|UNABLE_TO_VERIFY_LEAF_SIGNATURE|CERT_UNTRUSTED' \
           "$work/npm-ci.err"; then
        echo "note: npm could not verify the registry's TLS certificate ($(grep -m1 -oE '[A-Z_]*CERT[A-Z_]*' "$work/npm-ci.err"));" \
             "retrying with --strict-ssl=false: every package is still checked against its sha512 in package-lock.json" >&2
        (cd "$work" && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 "${ci[@]}" --strict-ssl=false)
      else
        cat "$work/npm-ci.err" >&2
        exit 1
      fi
    fi
  fi
  exec 9>&-
}
