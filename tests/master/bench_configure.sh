#!/bin/bash
# Benchmark of mb2co-master configure: N mb2co-node (node ids 1..N) on
# vcan0, configured from DCFs all at once, then one after the other
# (--one-at-a-time), wall time printed both ways. Each run has the same
# work: every node's DCF is a full dump (about 155 writable values read and
# compared) with 1017h and TPDO1's event timer and COB-ID changed (the PDO
# disable/re-enable sequence included), the two runs alternating values so
# both write.
#
# Usage (builds first: cmake --build build --target mb2co-master mb2co-node):
#   hil/uml/run-with-vcan.sh --timeout 900 -- tests/master/bench_configure.sh [BUILD_DIR] [N] [SDO_TIMEOUT_MS]
# N defaults to 32 (setup then takes minutes: a scan and 32 dumps). A node's line other than "configured: 3 written" is
# printed (it would make the comparison unfair). Results: docs/performance.md, "Master".
set -euo pipefail
build=${1:-build}
count=${2:-32}
# SDO timeout: generous, N node processes in user-mode Linux answer slowly.
timeout_ms=${3:-5000}
master=$build/pcapp/master/mb2co-master
node=$(find "$build" -name mb2co-node -type f -perm -u+x | head -1)
eds=$(cd "$(dirname "$0")/../.." && pwd)/docs/mb2co-gateway.eds
work=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$work"' EXIT

for id in $(seq 1 "$count"); do
  "$node" --can vcan0 --node-id "$id" --pty "$work/st$id" >/dev/null 2>&1 &
done
# Until every node answers SDO (scan waits one SDO timeout per pass).
for _ in $(seq 1 60); do
  found=$("$master" -i vcan0 -t "$timeout_ms" scan 1 "$count" 2>/dev/null | grep -c '^node ' || true)
  [ "$found" -eq "$count" ] && break
done
[ "$found" -eq "$count" ] || { echo "bench: only $found of $count nodes answer" >&2; exit 1; }

# Each node's own values (station ring, heartbeat consumers differ per
# node id), dumped one after the other (not timed).
# A late answer to an earlier run's request (a loaded UML) makes a dump
# fail with 06040043h: tried again.
for id in $(seq 1 "$count"); do
  for try in 1 2 3; do
    "$master" -i vcan0 -t "$timeout_ms" --eds "$eds" dump "$id" "$work/base$id.dcf" >/dev/null && break
    [ "$try" -lt 3 ] || exit 1
  done
done
# Sets ParameterValue=VALUE in section [SECTION] of the DCF on stdin.
set_value() {
  awk -v sec="[$1]" -v val="$2" '
    /^\[/ { in_sec = ($0 == sec) }
    in_sec && /^ParameterValue=/ { $0 = "ParameterValue=" val }
    { print }'
}
make_net() {  # make_net NAME HEARTBEAT EVENT_TIMER COB_BASE
  for id in $(seq 1 "$count"); do
    set_value 1017 "$2" <"$work/base$id.dcf" | set_value 1800sub5 "$3" |
      set_value 1800sub1 "\$NODEID+$4" >"$work/$1-$id.dcf"
  done
  {
    echo "[Topology]"
    echo "Nodes=$count"
    for id in $(seq 1 "$count"); do
      echo "Node${id}Present=1"
      echo "Node${id}DCFName=$1-$id.dcf"
    done
  } >"$work/$1.cpj"
}
make_net a 250 500 0x1C0
make_net b 300 600 0x180

run() {  # run LABEL NET [OPTIONS]
  local label=$1 net=$2
  shift 2
  local start end out
  start=$(date +%s.%N)
  out=$("$master" -i vcan0 -t "$timeout_ms" configure "$work/$net.cpj" --no-start "$@" || true)
  end=$(date +%s.%N)
  grep -v ': configured: 3 written' <<<"$out" >&2 || true
  local ok
  ok=$(grep -c ': configured: 3 written' <<<"$out" || true)
  printf '%-26s %2d nodes, %2d configured with 3 writes each: %6.2f s\n' "$label" "$count" "$ok" \
    "$(echo "$end - $start" | bc)"
}
run "concurrent" a
run "one at a time" b --one-at-a-time
