# bash completion for gportctl: commands, their options and arguments (watch
# topics, record on/off, settings --inverted yes/no, call METHOD, help COMMAND).
# Installed as /usr/share/bash-completion/completions/gportctl; keep in step
# with cli/src/options.cpp (tests/cli/completion_test.sh compares them).

_gportctl() {
    local cur=${COMP_WORDS[COMP_CWORD]}
    local prev=${COMP_WORDS[COMP_CWORD - 1]}
    local commands="status attitude watch speed stop angle center lock photo record settings monitor call captures geotag wait limits help"
    local global="--socket --json --help --version"
    COMPREPLY=()

    case $prev in
        --socket)
            COMPREPLY=($(compgen -f -- "$cur"))
            return
            ;;
        --inverted)
            COMPREPLY=($(compgen -W "yes no" -- "$cur"))
            return
            ;;
        --color)
            COMPREPLY=($(compgen -W "auto always never" -- "$cur"))
            return
            ;;
        --roll | --pitch | --yaw | --for | --lease | --rate | -n | --count | --dead-zone | --follow-speed | --since | --limit | --timeout | --lat | --lon | --alt | --meta)
            return # a number or a duration
            ;;
    esac

    # The command is the first word that is neither an option nor --socket's value.
    # After it, `positionals` counts the arguments before the current word.
    local command="" positionals=0 i
    for ((i = 1; i < COMP_CWORD; i++)); do
        case ${COMP_WORDS[i]} in
            --socket) ((i++)) ;;
            -*) ;;
            *)
                if [ -z "$command" ]; then
                    command=${COMP_WORDS[i]}
                else
                    ((positionals++))
                fi
                ;;
        esac
    done

    local options="" arguments=""
    case $command in
        "") arguments=$commands ;;
        watch)
            options="--rate --shared-memory -n --count --for --timestamps"
            arguments="attitude link motion"
            ;;
        speed) options="--roll --pitch --yaw --for --lease --clamp" ;;
        angle) options="--roll --pitch --yaw --clamp --wait" ;;
        center) options="--wait" ;;
        photo) options="--lat --lon --alt --meta" ;;
        record)
            options="--force --lat --lon --alt --meta"
            arguments="on off"
            ;;
        settings) options="--dead-zone --follow-speed --inverted" ;;
        monitor) options="--control --for --color --ascii" ;;
        captures) options="--since --limit --follow --csv" ;;
        geotag)
            options="--captures --since --tolerance --clock-offset --in-order --write --force --geo-txt"
            ((positionals == 0)) && compopt -o dirnames 2>/dev/null
            ;;
        wait)
            options="--timeout"
            ((positionals == 0)) && arguments="link"
            ;;
        call)
            options="--raw"
            # The methods of docs/api.md; the params (JSON) are not completed.
            if ((positionals == 0)); then
                arguments="status attitude subscribe unsubscribe attitude_channel speed stop angle
                    center lock photo record captures acquire release get_settings set_settings limits"
            fi
            ;;
        help) arguments=$commands ;;
    esac
    if [[ $cur == -* ]]; then
        COMPREPLY=($(compgen -W "$options $global" -- "$cur"))
    else
        COMPREPLY=($(compgen -W "$arguments" -- "$cur"))
    fi
}

complete -F _gportctl gportctl
