#!/bin/bash
# ctest master.completion: scripts/completion/mb2co.bash offers mb2co-master's
# subcommands and, after one, its own options and the global ones, as bash
# would ask at a TAB (the words come from the program's tables).
# Usage: completion_test.sh SOURCE_DIR MASTER_DIR
set -euo pipefail
src=$1
PATH=$2:$PATH
# shellcheck disable=SC1091  # the checkout given as $1
source "$src/scripts/completion/mb2co.bash"
# shellcheck disable=SC1091  # the same checkout
source "$src/scripts/completion/expect_completion.bash"

expect "scan read write upload download nmt sync time watch dump configure serve" mb2co-master ""
expect "sync" mb2co-master sy
expect "--period --parity" mb2co-master sync --p
expect "--heartbeat --help" mb2co-master -i vcan0 watch --he
expect "--help" mb2co-master read --he
expect "--watchdog" mb2co-master --wat
expect "--block --baud" mb2co-master -t 300 upload --b
expect "N E O none even odd" mb2co-master --via-modbus /dev/ttyACM0 --parity ""
expect "--listen" mb2co-master serve --li
exit $failed
