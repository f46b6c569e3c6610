#!/bin/bash
# ctest cli.completion: scripts/completion/mb2co.bash offers what the built
# programs' option tables hold (mb2co-timing and mb2co-lab), as bash would
# ask it at a TAB. Usage: completion_test.sh SOURCE_DIR TIMING_DIR LAB_DIR
set -euo pipefail
src=$1
PATH=$2:$3:$PATH
# shellcheck disable=SC1091  # the checkout given as $1
source "$src/scripts/completion/mb2co.bash"
failed=0

# expect "WORD..." -- what COMPREPLY must hold (all of it, in order) after "LINE".
expect() {
  local want=$1
  shift
  COMP_WORDS=("$@")
  COMP_CWORD=$(($# - 1))
  _mb2co_complete
  if [[ "${COMPREPLY[*]}" != "$want" ]]; then
    echo "completion of '$*': got '${COMPREPLY[*]}', want '$want'" >&2
    failed=1
  fi
}

expect "frame load rta latency serial" mb2co-timing ""
expect "rta" mb2co-timing r
expect "--bitrate" mb2co-timing rta --b
expect "--check" mb2co-timing rta --ch
expect "" mb2co-timing rta --window
expect "--window-us" mb2co-timing load --window
expect "N E O none even odd" mb2co-timing latency --parity ""
expect "course davis" mb2co-timing frame --frame-bits ""
expect "run stop2 latency faults sync-roundtrip sync-latency sync-processing alternative default" mb2co-lab --scenario ""
expect "125k 250k 500k 1M" mb2co-lab --bitrates ""
expect "--scenario --stations --seed --syncs --sync-period-us" mb2co-lab --s

# Every option of the table, no more: the listing is the table.
mapfile -t options < <(mb2co-lab --list-options | cut -d' ' -f1)
expect "${options[*]}" mb2co-lab --
exit $failed
