#!/usr/bin/env bash
# The man pages built from docs/man: each renders with man -l, and each
# program's --help names no long option that its man page lacks (drift).
#
#   check_man_pages.sh render  MAN_DIR
#   check_man_pages.sh options MAN_DIR GPORTD GPORTCTL GPORT_SIM GPORT_MAVLINK GPORT_WEB
set -euo pipefail

fail() {
    echo "FAIL: $*" >&2
    exit 1
}

for tool in man col; do
    command -v "$tool" >/dev/null \
        || fail "$tool not found (Debian packages: man-db, bsdextrautils; scripts/deps.sh)"
done

mode=$1
man_dir=$2

# The page as a person reads it at 80 columns, without overstrikes.
render() {
    MANWIDTH=80 LC_ALL=C.UTF-8 man -l "$man_dir/$1.gz" 2>&1 | col -b
}

check_render() {
    local page text heading count=0
    for page in gportd.8 gportctl.1 gport-sim.1 gport-mavlink.1 gport-web.1 gportd.json.5; do
        [ -f "$man_dir/$page.gz" ] || fail "$man_dir/$page.gz was not built"
        text=$(render "$page")
        [ -n "$text" ] || fail "$page renders empty"
        for heading in NAME SYNOPSIS DESCRIPTION "SEE ALSO"; do
            grep -qx "$heading" <<<"$text" || fail "$page has no $heading section:
$text"
        done
        if grep -qi "warning\|error" <<<"$(MANWIDTH=80 man -l "$man_dir/$page.gz" 2>&1 >/dev/null)"; then
            fail "$page: man reports problems"
        fi
        echo "ok: $page ($(wc -l <<<"$text") lines)"
        count=$((count + 1))
    done
    echo "$count passed, 0 failed"
}

# Long options in a help text.
long_options() {
    grep -o -- '--[a-z][a-z0-9-]*' | sort -u
}

# Every long option of `help` appears in the page.
check_page_has() {
    local page=$1 help=$2 text option missing=()
    text=$(render "$page")
    while read -r option; do
        [ -n "$option" ] || continue
        grep -qF -- "$option" <<<"$text" || missing+=("$option")
    done < <(long_options <<<"$help")
    [ ${#missing[@]} -eq 0 ] || fail "$page lacks options its program's --help prints: ${missing[*]}"
    echo "ok: $page has every option of --help ($(long_options <<<"$help" | wc -l) options)"
}

check_options() {
    local gportd=$1 gportctl=$2 gport_sim=$3 gport_mavlink=$4 gport_web=$5 help command commands page
    check_page_has gportd.8 "$("$gportd" --help)"
    check_page_has gport-sim.1 "$("$gport_sim" --help)"
    check_page_has gport-mavlink.1 "$("$gport_mavlink" --help)"
    check_page_has gport-web.1 "$("$gport_web" --help)"
    # gportctl: the overview and each command's help (commands are the
    # words indented by two spaces in the overview).
    help=$("$gportctl" --help)
    commands=$(grep -oE '^  [a-z][a-z-]*' <<<"$help" | tr -d ' ' | sort -u)
    [ -n "$commands" ] || fail "no commands found in gportctl --help"
    page=$(render gportctl.1)
    for command in $commands; do
        help+=$'\n'$("$gportctl" "$command" --help)
        grep -qE "^ +$command( |$)" <<<"$page" \
            || fail "gportctl.1 does not describe the command $command"
    done
    check_page_has gportctl.1 "$help"
    echo "5 passed, 0 failed"
}

case $mode in
    render) check_render ;;
    options) check_options "$3" "$4" "$5" "$6" "$7" ;;
    *) fail "unknown mode $mode; use render or options" ;;
esac
