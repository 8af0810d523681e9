# bash completion for gport-web: its options, files for the ones that take
# a file, and the usual listen addresses. Installed as
# /usr/share/bash-completion/completions/gport-web; keep in step with
# gport-web --help (tests/web/completion_test.sh compares them).

_gport_web() {
    local cur=${COMP_WORDS[COMP_CWORD]}
    local prev=${COMP_WORDS[COMP_CWORD - 1]}
    local options="--socket --listen --token-file --allow-host --print-url --help --version"
    COMPREPLY=()

    case $prev in
        --socket | --token-file)
            COMPREPLY=($(compgen -f -- "$cur"))
            return
            ;;
        --listen)
            COMPREPLY=($(compgen -W "127.0.0.1:8790 [::1]:8790 0.0.0.0:8790" -- "$cur"))
            return
            ;;
        --allow-host)
            COMPREPLY=($(compgen -A hostname -- "$cur"))
            return
            ;;
    esac
    COMPREPLY=($(compgen -W "$options" -- "$cur"))
}

complete -F _gport_web gport-web
