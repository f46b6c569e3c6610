# Bash completion for the mb2co programs (docs/cli.md). The words come from
# the programs themselves: `PROGRAM --list-options` prints the subcommands,
# `PROGRAM SUB --list-options` the options of SUB, one per line as
# "--name KIND [WORD...]" (KIND: flag, value, file, dir, choice), made from the
# same option tables as the parser and --help. Nothing here to regenerate.
# Load: source scripts/completion/mb2co.bash (cmake --install puts it where
# bash-completion finds it).

# Completes the word under the cursor for the mb2co program in COMP_WORDS[0].
_mb2co_complete() {
  local cur=${COMP_WORDS[COMP_CWORD]} prev="" program=${COMP_WORDS[0]} sub="" commands line name kind words
  ((COMP_CWORD > 0)) && prev=${COMP_WORDS[COMP_CWORD - 1]}
  COMPREPLY=()
  commands=$("$program" --list-options 2>/dev/null | grep -v '^-') || true
  # The subcommand: the first word after the program that is one.
  local w
  for w in "${COMP_WORDS[@]:1:COMP_CWORD-1}"; do
    if [[ -n $commands ]] && grep -qx -- "$w" <<<"$commands"; then
      sub=$w
      break
    fi
  done
  local listing
  listing=$("$program" ${sub:+"$sub"} --list-options 2>/dev/null | grep '^-') || true
  # The value of the option before the cursor.
  while read -r name kind words; do
    [[ $name == "$prev" ]] || continue
    case $kind in
      file) mapfile -t COMPREPLY < <(compgen -f -- "$cur") ;;
      dir) mapfile -t COMPREPLY < <(compgen -d -- "$cur") ;;
      choice | value) [[ -z $words ]] || mapfile -t COMPREPLY < <(compgen -W "$words" -- "$cur") ;;
      *) continue ;;
    esac
    return 0
  done <<<"$listing"
  if [[ -z $sub && -n $commands && $cur != -* ]]; then
    mapfile -t COMPREPLY < <(compgen -W "$commands" -- "$cur")
    return 0
  fi
  line=$(cut -d' ' -f1 <<<"$listing" | tr '\n' ' ')
  mapfile -t COMPREPLY < <(compgen -W "$line" -- "$cur")
}

complete -F _mb2co_complete mb2co-timing mb2co-lab mb2co-od mb2co-uno mb2co-plant mb2co-master mb2co-node mb2co-bridge mb2co-demo
