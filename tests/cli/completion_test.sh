#!/bin/bash
# ctest cli.completion: scripts/completion/mb2co.bash offers what the built
# programs' option tables hold (mb2co-timing and mb2co-lab), as bash would
# ask it at a TAB. Usage: completion_test.sh SOURCE_DIR TIMING_DIR LAB_DIR
set -euo pipefail
src=$1
PATH=$2:$3:$PATH
# shellcheck disable=SC1091  # the checkout given as $1
source "$src/scripts/completion/mb2co.bash"
# shellcheck disable=SC1091  # the same checkout
source "$src/scripts/completion/expect_completion.bash"

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
