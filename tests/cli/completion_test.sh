#!/usr/bin/env bash
# The bash completion of gportctl loads, is registered for gportctl, completes
# commands, options and arguments, and knows every command of `gportctl --help`.
# Usage: completion_test.sh COMPLETION_SCRIPT GPORTCTL
set -euo pipefail
script=$1
gportctl=$2

complete_line() {  # words...: the completions of the last word
    bash -c 'source "$0"; COMP_WORDS=("${@}"); COMP_CWORD=$(($# - 1)); _gportctl; echo "${COMPREPLY[*]}"' \
        "$script" "$@"
}
expect() {  # what got
    if [ "$1" != "$2" ]; then
        echo "FAIL: expected '$1', got '$2'" >&2
        exit 1
    fi
}

expect "complete -F _gportctl gportctl" "$(bash -c 'source "$0"; complete -p gportctl' "$script")"
expect "speed" "$(complete_line gportctl sp)"
expect "status stop" "$(complete_line gportctl st | tr ' ' '\n' | sort | xargs)"
expect "--clamp" "$(complete_line gportctl speed --yaw 5 --cl)"
expect "--wait" "$(complete_line gportctl --socket /tmp/s center --w)"
expect "attitude link motion" "$(complete_line gportctl watch "")"
expect "--shared-memory" "$(complete_line gportctl watch --sh)"
expect "on" "$(complete_line gportctl record o | tr ' ' '\n' | grep -x on)"
expect "yes" "$(complete_line gportctl settings --inverted y)"
expect "" "$(complete_line gportctl speed --yaw "")"
expect "limits" "$(complete_line gportctl call lim)"
expect "" "$(complete_line gportctl call limits "")"
expect "--raw" "$(complete_line gportctl call --r)"
expect "--timestamps" "$(complete_line gportctl watch --ti)"

# Every command gportctl --help lists is completed.
listed=$("$gportctl" --help | sed -n '/^Subcommands:/,/^$/p' | awk 'NR > 1 && NF { print $1 }')
[ -n "$listed" ] || { echo "FAIL: no commands in gportctl --help" >&2; exit 1; }
for command in $listed; do
    expect "$command" "$(complete_line gportctl "$command" | tr ' ' '\n' | grep -x "$command" || true)"
done
echo "completion: ok ($(echo $listed | wc -w) commands)"
