#!/bin/sh
# The table's cells are in backquotes, which the sed and grep patterns match.
# shellcheck disable=SC2016
# scripts/check-layering.sh against deliberate violations: each case copies
# the source tree (the layered folders, docs/, scripts/, the top-level
# CMakeLists.txt), breaks one rule, runs the script on the copy and expects
# exit 1 with a finding that names the file and the line (or, for the
# table, the table's line). The unbroken copy must pass.
#
# usage: check_layering_test.sh SOURCE_DIR
set -eu

fail() {
    echo "FAIL: $*" >&2
    exit 1
}

[ $# -eq 1 ] || fail "usage: $0 SOURCE_DIR"
source=$1
work=$(mktemp -d /tmp/gport-layering-XXXXXX)
trap 'rm -rf "$work"' EXIT

mkdir "$work/tree"
for part in base contract protocol config daemon sim ipc systemd app client cli examples mavlink \
    docs scripts cmake CMakeLists.txt; do
    [ -e "$source/$part" ] && cp -R "$source/$part" "$work/tree/"
done
rm -rf "$work/tree/build"
cases=0

# fresh: a new copy in $case for the caller to break.
fresh() {
    rm -rf "$work/case"
    cp -R "$work/tree" "$work/case"
    case=$work/case
}

# expect NAME TEXT...: the script fails on $case and says each TEXT.
expect() {
    name=$1
    shift
    if bash "$case/scripts/check-layering.sh" "$case" >"$work/out" 2>&1; then
        cat "$work/out" >&2
        fail "$name: check-layering passed"
    fi
    for text in "$@"; do
        grep -qF -- "$text" "$work/out" || {
            cat "$work/out" >&2
            fail "$name: the output does not say: $text"
        }
    done
    cases=$((cases + 1))
}

# append FILE TEXT: adds TEXT as the last line of FILE and sets $line to its number.
append() {
    printf '%s\n' "$2" >>"$1"
    line=$(wc -l <"$1" | tr -d ' ')
}

# 0. The tree as it is passes.
fresh
bash "$case/scripts/check-layering.sh" "$case" >"$work/out" 2>&1 \
    || { cat "$work/out" >&2; fail "the unbroken tree does not pass"; }

# 1. An upward include: gportctl reaching into the server.
fresh
append "$case/cli/src/options.cpp" '#include "gport/ipc/json_rpc.hpp"'
expect "upward include" \
    "cli/src/options.cpp:$line: includes \"gport/ipc/json_rpc.hpp\": cli/ may not use ipc/" \
    "(it may use: base contract client)"

# 1b. A private header of a folder it may use: ipc/ may use daemon/'s Api,
#     not the core's headers.
fresh
append "$case/ipc/src/server.cpp" '#include "gport/daemon/core/serial_port.hpp"'
expect "private header" \
    "ipc/src/server.cpp:$line: includes \"gport/daemon/core/serial_port.hpp\": gport/daemon/core/ is private to daemon/"

# 2. An upward link, by alias.
fresh
append "$case/cli/CMakeLists.txt" 'target_link_libraries(gportctl PRIVATE gport::ipc)'
expect "upward link" "cli/CMakeLists.txt:$line: links gport::ipc: cli/ may not use ipc/"

# 3. An upward link by the raw target name, inside a multi-line call.
fresh
printf 'target_link_libraries(gportctl\n  PRIVATE fmt::fmt\n  gport_core)\n' >>"$case/cli/CMakeLists.txt"
line=$(wc -l <"$case/cli/CMakeLists.txt" | tr -d ' ')
expect "raw target link" "cli/CMakeLists.txt:$line: links gport_core: cli/ may not use daemon/"

# 4. A folder below in the old total order but not on the list: the
#    allow-list, not an order, decides (sim/ may not use config/).
fresh
append "$case/sim/src/model.cpp" '#include "gport/config/config.hpp"'
expect "not on the list" "sim/src/model.cpp:$line: includes \"gport/config/config.hpp\": sim/ may not use config/"

# 5. A relative include into another folder.
fresh
append "$case/cli/src/output.cpp" '#include "../../ipc/src/methods.hpp"'
expect "relative include" "cli/src/output.cpp:$line: includes \"../../ipc/src/methods.hpp\": cli/ may not use ipc/"

# 6. A link to a target of tests/ (outside the table).
fresh
append "$case/client/CMakeLists.txt" 'target_link_libraries(gport_client PRIVATE gport::test_fakes)'
mkdir -p "$case/tests/support"
printf 'add_library(gport_test_fakes INTERFACE)\nadd_library(gport::test_fakes ALIAS gport_test_fakes)\n' \
    >"$case/tests/support/CMakeLists.txt"
expect "test target" "client/CMakeLists.txt:$line: links gport::test_fakes, declared in tests/, outside the layered folders"

# 7. A comment naming a target is not a link: still passes.
fresh
append "$case/cli/CMakeLists.txt" '# once linked gport::ipc; not any more'
bash "$case/scripts/check-layering.sh" "$case" >"$work/out" 2>&1 \
    || { cat "$work/out" >&2; fail "a comment was taken for a link"; }
cases=$((cases + 1))

# 8. The table: a cycle (base/ may use cli/, which may use base/).
fresh
sed -i 's/^| `base\/` | — |/| `base\/` | `cli` |/' "$case/docs/architecture.md"
row=$(grep -n '^| `base/` | `cli` |' "$case/docs/architecture.md" | cut -d: -f1)
[ -n "$row" ] || fail "could not edit the table's base row"
expect "cycle" "docs/architecture.md:" "the table has a cycle"

# 9. The table: a use that is not a row.
fresh
sed -i 's/^| `cli\/` | `base`, `contract`, `client` |/| `cli\/` | `base`, `contract`, `client`, `server` |/' \
    "$case/docs/architecture.md"
row=$(grep -n '^| `cli/` |' "$case/docs/architecture.md" | cut -d: -f1)
expect "unknown folder" "docs/architecture.md:$row: cli/ may use \"server\", which is not a row of the table"

# 10. No table at all.
fresh
sed -i 's/<!-- layers:/<!-- gone:/' "$case/docs/architecture.md"
expect "no table" "no \"<!-- layers:\" table in docs/architecture.md"

echo "PASS ($cases violations caught, the unbroken tree passes)"
