#!/usr/bin/env bash
# The bash and zsh completions of gport-web load, are registered for
# gport-web, and offer every long option gport-web --help prints (drift).
# Usage: completion_test.sh BASH_COMPLETION ZSH_COMPLETION GPORT_WEB
set -euo pipefail
bash_script=$1
zsh_script=$2
gport_web=$3

fail() {
    echo "FAIL: $*" >&2
    exit 1
}
complete_line() {  # words...: the completions of the last word
    bash -c 'source "$0"; COMP_WORDS=("${@}"); COMP_CWORD=$(($# - 1)); _gport_web; echo "${COMPREPLY[*]}"' \
        "$bash_script" "$@"
}
expect() {  # what got
    [ "$1" = "$2" ] || fail "expected '$1', got '$2'"
}

expect "complete -F _gport_web gport-web" "$(bash -c 'source "$0"; complete -p gport-web' "$bash_script")"
expect "--listen" "$(complete_line gport-web --li)"
expect "127.0.0.1:8790" "$(complete_line gport-web --listen 127)"
expect "--token-file" "$(complete_line gport-web --to)"

# Every long option of --help is offered by both.
options=$("$gport_web" --help | grep -o -- '--[a-z][a-z0-9-]*' | sort -u)
[ -n "$options" ] || fail "no options in gport-web --help"
offered=$(complete_line gport-web -- | tr ' ' '\n')
count=0
for option in $options; do
    grep -qx -- "$option" <<<"$offered" || fail "bash completion lacks $option"
    grep -qE -- "(^|[^a-z-])${option}[=[]" "$zsh_script" || fail "zsh completion lacks $option"
    count=$((count + 1))
done
echo "ok: both completions offer the $count options of gport-web --help"
