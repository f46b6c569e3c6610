#!/usr/bin/env bash
# How many SDO requests the station image misses beside a neighbour: the
# gateway image (node 1, mb2co-uno: the real image in simavr, its MCP2515
# modelled with its two receive buffers) and one mb2co-node (node 2, its
# heartbeat and TPDO1 every 100 ms, which node 1's filters admit) on vcan0;
# mb2co-master reads node 1's 1008h (a segmented upload: three requests)
# READS times, one after the other. Prints the reads that ended in the SDO
# timeout (mb2co-master starts a transfer over once when node 1's heartbeat
# says it serves SDO: these are reads lost twice) and the Uno's `bus?` line
# (overflowed=: frames lost to full receive buffers, requests among them).
# Runs itself inside hil/uml/run-with-vcan.sh.
#
# Usage: firmware/avr/measure-sdo-loss.sh [READS]   (default 300)
# Needs the host build (scripts/test.sh or cmake --build build): build/ of
# this checkout, or MB2CO_BUILD_DIR.
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
build=${MB2CO_BUILD_DIR:-$here/build}
reads=${1:-300}
[[ $reads =~ ^[1-9][0-9]*$ ]] || { echo "measure-sdo-loss: READS must be a positive number, got '$reads'" >&2; exit 2; }
for p in hil/uno/mb2co-uno firmware/linux/node/mb2co-node pcapp/master/mb2co-master; do
  [[ -x $build/$p ]] || { echo "measure-sdo-loss: $build/$p not built (cmake --build build)" >&2; exit 1; }
done
if [[ ${MB2CO_IN_VCAN:-} != 1 ]]; then
  exec env MB2CO_IN_VCAN=1 MB2CO_BUILD_DIR="$build" "$here/hil/uml/run-with-vcan.sh" --timeout 900 -- "$0" "$reads"
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
coproc UNO { "$build/hil/uno/mb2co-uno" --can vcan0 --pty "$work/uno.pty" 2>&1; }
# The ready line: the image has booted and its Modbus slave listens.
while read -r line <&"${UNO[0]}"; do [[ $line == ready* ]] && break; done
"$build/firmware/linux/node/mb2co-node" --can vcan0 --node-id 2 --pty "$work/st2" >"$work/node.out" 2>&1 &
node_pid=$!
# Its ready line, looked for every 0.1 s for up to 20 s (its stdout goes on
# to the file: a pipe nobody reads would stop it once full).
for ((k = 0; k < 200; ++k)); do
  grep -q '^ready' "$work/node.out" && break
  sleep 0.1
done
grep -q '^ready' "$work/node.out" || { echo "measure-sdo-loss: mb2co-node did not start" >&2; exit 1; }
master() { "$build/pcapp/master/mb2co-master" -i vcan0 "$@"; }
# Node 2 is heard (its heartbeat is what node 1 admits) before the count starts.
master read 2 1008 0 vs >/dev/null

failed=0
for ((i = 0; i < reads; ++i)); do
  master read 1 1008 0 vs >/dev/null 2>>"$work/master.err" || failed=$((failed + 1))
done
echo "bus?" >&"${UNO[1]}"
while read -r line <&"${UNO[0]}"; do [[ $line == bus* ]] && break; done
echo "reads $reads, timed out $failed (of $((3 * reads)) requests to node 1)"
echo "uno: $line"
sort "$work/master.err" | uniq -c | sed 's/^/  /'
echo quit >&"${UNO[1]}"
kill "$node_pid" 2>/dev/null || true
wait 2>/dev/null || true
