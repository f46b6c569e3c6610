# shellcheck shell=bash
# Sourced by the master's benchmarks against mb2co-node on vcan0
# (bench_upload.sh, bench_master_fps.sh): `bench_start NAME BUILD NODE_ID`
# checks the programs and vcan0 (exit 2 with NAME's message otherwise),
# makes $work (removed at exit, with the processes in $pids) and starts
# mb2co-node; sets $master and $node_bin.

# Polls a file for a line matching a pattern (a benchmark, not a test:
# bounded by `tries` x 0.1 s).
wait_for() {
  local file=$1 pattern=$2 tries=${3:-600}
  for ((i = 0; i < tries; ++i)); do
    grep -q -- "$pattern" "$file" 2>/dev/null && return 0
    sleep 0.1
  done
  echo "$bench_name: no '$pattern' in $file" >&2
  cat "$file" >&2
  return 1
}

# Frames on the bus: the kernel's CAN transmit count (/proc/net/can/stats,
# TXF). candump is no counter here: under user-mode Linux it misses about
# half the frames of a block upload (no drop reported) while the kernel and
# both ends see them all. The sandbox's bus carries only the node and the
# client, so the count is the transfer's frames plus the node's heartbeats
# during it.
tx_frames() {
  awk '/transmitted frames/ { print $1; exit }' /proc/net/can/stats
}

bench_cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  rm -rf "$work"
}

bench_start() {
  bench_name=$1
  local build=$2 node_id=$3
  master=$build/pcapp/master/mb2co-master
  node_bin=$build/firmware/linux/node/mb2co-node
  for f in "$master" "$node_bin"; do
    [ -x "$f" ] || { echo "$bench_name: $f missing (cmake --build $build --target mb2co-master mb2co-node)" >&2; exit 2; }
  done
  ip link show vcan0 >/dev/null 2>&1 || { echo "$bench_name: no vcan0 (run it inside hil/uml/run-with-vcan.sh)" >&2; exit 2; }
  work=$(mktemp -d)
  pids=()
  trap bench_cleanup EXIT
  "$node_bin" --can vcan0 --node-id "$node_id" --pty "$work/pty" >"$work/node.out" 2>&1 </dev/null &
  pids+=($!)
  wait_for "$work/node.out" '^ready'
}
