#!/bin/bash
# The Modbus round trip of mb2co-node on its RTU pty and on Modbus/TCP, the
# same node, the same request (FC 03, one register), one after the other:
# docs/performance.md "Modbus/TCP round trip". No CAN (--can none).
#
# Usage (after cmake --build build --target mb2co-node mb2co_node_bench_round_trip):
#   tests/node/bench_round_trip.sh [BUILD_DIR] [COUNT]
set -euo pipefail
build=${1:-build}
count=${2:-2000}
node=$build/firmware/linux/node/mb2co-node
bench=$build/tests/node/mb2co_node_bench_round_trip
work=$(mktemp -d)
fifo=$work/out
mkfifo "$fifo"
"$node" --can none --pty "$work/tty" --tcp 127.0.0.1:0 </dev/null >"$fifo" &
pid=$!
trap 'kill $pid 2>/dev/null || true; wait $pid 2>/dev/null || true; rm -rf "$work"' EXIT
exec 3<"$fifo"
ready=
while read -r -t 10 line <&3; do
  if [[ $line == ready\ * ]]; then
    ready=$line
    break
  fi
done
[ -n "$ready" ] || { echo "bench_round_trip: no ready line from mb2co-node" >&2; exit 1; }
# The node's later lines (state changes) must not fill the pipe.
cat <&3 >/dev/null &
tcp=${ready##*tcp=}
"$bench" --rtu "$work/tty" "$count"
"$bench" --tcp "$tcp" "$count"
