#!/bin/bash
# Benchmark of mb2co-master serve: requests per second of
# "read 0x1017 0 u16" (1017h, the producer heartbeat time) to one node and
# to N nodes (mb2co-node, node ids 1..N on vcan0) through serve on a local
# socket, by bench_serve.py (Python's sockets): each request waiting for
# the answer before it (window 1), and pipelined (window W: that many
# sent and not yet answered; serve runs requests to different nodes at
# once and answers in order). The one-shot `mb2co-master read` is timed
# for comparison (a process, a socket and the bus set up per request).
#
# Usage (builds first: cmake --build build --target mb2co-master mb2co-node):
#   hil/uml/run-with-vcan.sh --timeout 900 -- tests/master/bench_serve.sh [BUILD_DIR] [N] [COUNT]
# N defaults to 32, COUNT (requests per run) to 2000. Results: docs/performance.md, "serve".
set -euo pipefail
build=${1:-build}
count=${2:-32}
requests=${3:-2000}
here=$(cd "$(dirname "$0")" && pwd)
master=$build/pcapp/master/mb2co-master
node=$(find "$build" -name mb2co-node -type f -perm -u+x | head -1)
work=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null || true; rm -rf "$work"' EXIT

for id in $(seq 1 "$count"); do
  "$node" --can vcan0 --node-id "$id" --pty "$work/st$id" >/dev/null 2>&1 &
done
"$master" -i vcan0 -t 5000 serve --listen "unix:$work/S" --max-clients 4 >"$work/serve.log" 2>&1 &
serve_pid=$!
for _ in $(seq 1 100); do
  grep -q "listening on" "$work/serve.log" 2>/dev/null && break
  sleep 0.1
done
# Until every node answers (each once, through serve).
for _ in $(seq 1 60); do
  /usr/bin/python3 "$here/bench_serve.py" "unix:$work/S" 1 "$count" "$count" "$count" >/dev/null 2>&1 && break
  sleep 1
done
/usr/bin/python3 "$here/bench_serve.py" "unix:$work/S" 1 "$count" "$count" "$count" >/dev/null
# The N node processes share user-mode Linux's one CPU: left as they start
# (TPDOs on their event timers, heartbeats every 100 ms: ~1,500 frames/s for
# 32, each received by every node) they keep that CPU busy and the figure
# measures them. Pre-operational (no PDOs) with 1 s heartbeats they are as
# idle as nodes on CPUs of their own.
/usr/bin/python3 "$here/bench_serve.py" "unix:$work/S" 1 "$count" "$count" "$count" "write 0x1017 0 u16 1000" >/dev/null
/usr/bin/python3 "$here/bench_serve.py" "unix:$work/S" 1 "$count" "$count" "$count" preop >/dev/null

# serve's own CPU (user + system, clock ticks) from /proc: what a request
# costs it, whatever the node processes beside it take.
serve_ticks() { awk '{print $14 + $15}' "/proc/$serve_pid/stat"; }
hz=$(getconf CLK_TCK)
run() {  # run LAST_NODE WINDOW
  local before after line
  before=$(serve_ticks)
  line=$(/usr/bin/python3 "$here/bench_serve.py" "unix:$work/S" 1 "$1" "$requests" "$2")
  after=$(serve_ticks)
  printf '%s serve_cpu_us_per_request=%.0f\n' "$line" "$(echo "($after - $before) * 1000000 / $hz / $requests" | bc -l)"
}
echo "# $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg), $count nodes on vcan0, $requests requests a run"
run 1 1
run 1 16
run "$count" 1
run "$count" "$count"
run "$count" $((2 * count))
# The one-shot command, 50 times to node 1 (a process start each: most of its time).
start=$(date +%s.%N)
for _ in $(seq 1 50); do "$master" -i vcan0 read 1 1017 0 u16 >/dev/null; done
end=$(date +%s.%N)
printf 'one-shot mb2co-master read, 50 runs: %.0f/s\n' "$(echo "50 / ($end - $start)" | bc -l)"
