# bash completion for sunmc: commands, each command's options and config keys,
# all read from the binary's own --help (so they never fall out of step).
# Installed by `make install` as PREFIX/share/bash-completion/completions/sunmc;
# or `source scripts/sunmc-completion.bash` in a shell.
_sunmc_keys() {
    local bin=$1 fam
    for fam in $("$bin" --help 2>/dev/null | sed -n 's/.*--family \([a-z|]*\)$/\1/p' | head -1 | tr '|' ' '); do
        "$bin" --help --family "$fam" 2>/dev/null | sed -n 's/^    \([a-z_]*\.[A-Za-z0-9_]*\) = .*/\1/p'
    done | sort -u
}

_sunmc() {
    local bin=${COMP_WORDS[0]} cur=${COMP_WORDS[COMP_CWORD]} prev=
    (( COMP_CWORD > 0 )) && prev=${COMP_WORDS[COMP_CWORD - 1]}
    [[ $bin == */* || -n $(type -P "$bin") ]] || bin=sunmc
    COMPREPLY=()
    if (( COMP_CWORD == 1 )); then
        local cmds
        cmds=$("$bin" --help 2>/dev/null | sed -n '/^usage:/,/^$/p' | awk 'NR > 1 && NF { print $1 }')
        COMPREPLY=($(compgen -W "$cmds --help --version" -- "$cur"))
        return
    fi
    case $prev in
    --set | --only | --vary)
        compopt -o nospace 2>/dev/null
        COMPREPLY=($(compgen -S = -W "$(_sunmc_keys "$bin")" -- "$cur"))
        return ;;
    --family | --sensor)
        local fams
        fams=$("$bin" --help 2>/dev/null | sed -n 's/.*--family \([a-z|]*\)$/\1/p' | head -1 | tr '|' ' ')
        COMPREPLY=($(compgen -W "$fams" -- "$cur"))
        return ;;
    --out)
        COMPREPLY=($(compgen -d -- "$cur"))
        return ;;
    --format)
        COMPREPLY=($(compgen -W "tsv hdf5" -- "$cur"))
        return ;;
    esac
    if [[ $cur == -* ]]; then
        local opts
        opts=$("$bin" "${COMP_WORDS[1]}" --help 2>/dev/null | grep -o -- '--[a-z][a-z-]*' | sort -u)
        COMPREPLY=($(compgen -W "$opts --help" -- "$cur"))
        return
    fi
    COMPREPLY=($(compgen -f -- "$cur"))
}
complete -o filenames -F _sunmc sunmc
