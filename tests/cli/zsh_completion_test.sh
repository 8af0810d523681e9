#!/usr/bin/env bash
# The zsh completion of gportctl loads in a bare zsh (zsh -f) with compinit,
# is registered for gportctl by its #compdef line, offers every command of
# `gportctl --help`, and for each command every long option of its --help
# and the values it takes. Skipped (exit 77) where zsh is not installed.
# Usage: zsh_completion_test.sh COMPLETION_DIR GPORTCTL
set -euo pipefail
dir=$1
gportctl=$2

if ! command -v zsh >/dev/null; then
    echo "SKIP: zsh is not installed (Debian package zsh; scripts/deps.sh)"
    exit 77
fi
fail() {
    echo "FAIL: $*" >&2
    exit 1
}
home=$(mktemp -d)
trap 'rm -rf "$home"' EXIT

# Runs zsh code with the completion system loaded and _gportctl sourced;
# _describe and _arguments are replaced by stand-ins that print what they
# were given (the first _arguments call, with -C, picks the argument state).
in_zsh() {
    HOME=$home zsh -f -c '
        fpath=("$1" $fpath)
        autoload -U compinit && compinit -u -d "$HOME/zcompdump"
        source "$1/_gportctl" || exit 1
        _describe() { print -rl -- ${(P)${@[-1]}} }
        _arguments() {
            if [[ $1 == -C ]]; then state=argument; return 1; fi
            print -rl -- "$@"
        }
        eval "$2"' zsh "$dir" "$1"
}

# Loaded and registered for gportctl (compinit reads #compdef).
[ "$(in_zsh 'print -r -- $_comps[gportctl]')" = _gportctl ] \
    || fail "_gportctl is not registered for gportctl"
# It runs as an autoloaded function too, as zsh loads it from fpath.
HOME=$home zsh -f -c 'fpath=("$1" $fpath); autoload -U compinit && compinit -u -d "$HOME/zcompdump";
    autoload -U +X _gportctl && [[ $(whence -w _gportctl) == "_gportctl: function" ]]' zsh "$dir" \
    || fail "_gportctl does not autoload"

offered=$(in_zsh '_gportctl_commands' | cut -d: -f1 | sort)
listed=$("$gportctl" --help | sed -n '/^Subcommands:/,/^$/p' | awk 'NR > 1 && NF { print $1 }' | sort)
[ -n "$listed" ] || fail "no commands in gportctl --help"
[ "$offered" = "$listed" ] || fail "commands differ: completion '$(echo $offered)', --help '$(echo $listed)'"

options=0
for command in $listed; do
    specs=$(in_zsh "words=($command); _gportctl")
    while read -r option; do
        [ "$option" = --help ] && continue
        grep -qF -- "$option[" <<<"$specs" || grep -qF -- "$option=" <<<"$specs" \
            || fail "$command: $option is not completed"
        options=$((options + 1))
    done < <("$gportctl" "$command" --help | grep -oE -- '--[a-z][a-z-]*' | sort -u)
done

# The values of a few options and arguments.
expect_in() {  # command value
    in_zsh "words=($1); _gportctl" | grep -qF -- "$2" || fail "$1: $2 is not offered"
}
expect_in watch "(attitude link motion)"
expect_in record "(on off)"
expect_in settings "(yes no)"
expect_in monitor "(auto always never)"
expect_in call "limits"
expect_in --socket "_files"
echo "zsh completion: ok ($(echo $listed | wc -w) commands, $options options)"
