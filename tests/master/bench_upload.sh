#!/bin/bash
# SDO upload throughput on vcan0: mb2co-master (block with CRC, segmented)
# against npm's canopen client (tests/peers/canopen_peer.js) uploading the
# same object, mb2co-node's 1F50h/1, on the same bus in the same run.
# Not a ctest test (npm needs minutes for 1 MiB); runs inside the vcan
# sandbox:
#
#   hil/uml/run-with-vcan.sh --timeout 2400 -- tests/master/bench_upload.sh [BUILD_DIR]
#
# BUILD_DIR (default build) holds mb2co-master and mb2co-node. Environment:
#   BENCH_SIZES  sizes in bytes, each downloaded first then uploaded
#                (default "131072 1048576"; the node's 1F50h/1 takes <= 1 MiB)
#   BENCH_NPM=0  leaves npm's client out (its 1 MiB uploads take ~6 min each)
#
# Per row: bytes/s of the transfer (mb2co-master: its own "in S s", timed
# from its first request to the last answer; npm: the peer's time_s, the same
# span), wall seconds of the whole process (npm's includes Node.js's start),
# CPU (user+sys of the process, getrusage through GNU time), the CAN frames
# the kernel sent meanwhile, and CPU µs per frame. Every upload is compared
# byte for byte with the downloaded file.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
peer=$root/tests/peers/canopen_peer.js
sizes=${BENCH_SIZES:-131072 1048576}
with_npm=${BENCH_NPM:-1}
node_id=5

# shellcheck source=tests/master/bench_node.sh
. "$here/bench_node.sh"
bench_start bench_upload "$build" "$node_id"

failed() {
  echo "bench_upload: $1 failed:" >&2
  cat "$work/up.out" "$work/up.err" "$work/time.txt" >&2
  exit 1
}

rows=()
# row WHO MODE BYTES RATE WALL CPU FRAMES
row() {
  local cpu_us_per_frame
  cpu_us_per_frame=$(awk -v c="$6" -v f="$7" 'BEGIN { printf "%.1f", (f > 0 ? c * 1e6 / f : 0) }')
  rows+=("$(printf '%-13s %-10s %8s %12s %9s %8s %8s %10s' "$1" "$2" "$3" "$4" "$5" "$6" "$7" "$cpu_us_per_frame")")
  echo "${rows[-1]}" >&2
}

for size in $sizes; do
  # The content: not the node's start pattern (i mod 251), so the upload
  # proves the download.
  python3 -c "import sys; sys.stdout.buffer.write(bytes((i * 7 + (i >> 8) + 13) & 0xFF for i in range($size)))" >"$work/in.bin"
  "$master" -i vcan0 -t 5000 download "$node_id" 1F50 1 "$work/in.bin" --block >"$work/down.out"
  echo "bench_upload: $(cat "$work/down.out")" >&2

  for mode in block segmented; do
    rm -f "$work/up.bin"
    tx0=$(tx_frames)
    /usr/bin/time -f '%e %U %S' -o "$work/time.txt" \
      "$master" -i vcan0 -t 5000 upload "$node_id" 1F50 1 "$work/up.bin" "--$mode" >"$work/up.out" 2>"$work/up.err" ||
      failed "mb2co-master $mode upload"
    frames=$(($(tx_frames) - tx0))
    cmp -s "$work/in.bin" "$work/up.bin" || { echo "bench_upload: mb2co-master $mode upload differs" >&2; exit 1; }
    read -r wall user sys <<<"$(tail -n 1 "$work/time.txt")"
    secs=$(sed -n 's/.* in \([0-9.]*\) s .*/\1/p' "$work/up.out")
    rate=$(awk -v b="$size" -v s="$secs" 'BEGIN { printf "%.0f", b / s }')
    cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN { printf "%.2f", u + s }')
    row mb2co-master "$mode" "$size" "$rate" "$wall" "$cpu" "$frames"
  done

  if [ "$with_npm" = 1 ]; then
    for mode in block segmented; do
      rm -f "$work/up.bin"
      flag=()
      [ "$mode" = block ] && flag=(--block)
      # Who ends a transfer with an abort (80h): a witness, not a counter
      # (see tx_frames); Node.js's 1-3 s start gives it time to listen.
      candump -L "vcan0,$(printf '%X' $((0x600 + node_id))):7FF,$(printf '%X' $((0x580 + node_id))):7FF" \
        >"$work/npm_dump.txt" &
      dump_pid=$!
      tx0=$(tx_frames)
      status=0
      /usr/bin/time -f '%e %U %S' -o "$work/time.txt" \
        node "$peer" --can vcan0 client upload --node "$node_id" --index 0x1F50 --sub 1 "${flag[@]}" \
        --file "$work/up.bin" --timeout 5000 >"$work/up.out" 2>"$work/up.err" || status=$?
      frames=$(($(tx_frames) - tx0))
      kill -INT "$dump_pid"
      wait "$dump_pid" || true
      read -r wall user sys <<<"$(tail -n 1 "$work/time.txt")"
      cpu=$(awk -v u="$user" -v s="$sys" 'BEGIN { printf "%.2f", u + s }')
      if [ "$status" = 1 ]; then
        # An SDO abort: a row that says so (the code as the rate), and on.
        code=$(sed -n 's/.* code=\([0-9A-F]*\).*/\1/p' "$work/up.out")
        echo "bench_upload: npm $mode upload aborted: $(cat "$work/up.out")" >&2
        echo "bench_upload: abort frames on the bus (605h: npm's client, 585h: mb2co-node):" >&2
        grep -E '#80' "$work/npm_dump.txt" >&2 || echo "  (none seen)" >&2
        row "npm canopen" "$mode" "$size" "abort:$code" "$wall" "$cpu" "$frames"
        continue
      fi
      [ "$status" = 0 ] || failed "npm $mode upload"
      cmp -s "$work/in.bin" "$work/up.bin" || { echo "bench_upload: npm $mode upload differs" >&2; exit 1; }
      rate=$(sed -n 's/.* bytes_per_s=\([0-9]*\).*/\1/p' "$work/up.out")
      row "npm canopen" "$mode" "$size" "$rate" "$wall" "$cpu" "$frames"
    done
  fi
done

printf '%-13s %-10s %8s %12s %9s %8s %8s %10s\n' client mode bytes bytes/s wall_s cpu_s frames cpu_us/frm
printf '%s\n' "${rows[@]}"
