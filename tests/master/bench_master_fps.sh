#!/bin/bash
# mb2co-master's speed on vcan0 (issue 25 item 6), measured in one boot of
# the vcan sandbox against the bus's own ceiling:
#
#   hil/uml/run-with-vcan.sh --timeout 1800 -- tests/master/bench_master_fps.sh [BUILD_DIR]
#
# Per round (BENCH_ROUNDS, default 3), back to back:
#   cangen     `cangen -g 0 -n BENCH_CANGEN_FRAMES -I 7E5 -L 8 vcan0` alone
#              (an id no one consumes): frames per second the kernel sent
#              (/proc/net/can/stats TXF) over cangen's wall time;
#   block      `mb2co-master upload 5 1F50 1 FILE --block` of BENCH_SIZE bytes
#              from mb2co-node: frames the kernel sent meanwhile over the
#              master's own transfer time ("in S s"), and that rate as a
#              share of the cangen round's;
#   segmented  the same object `--segmented`: the master's CPU time (user +
#              sys, GNU time) per segment (BENCH_SIZE / 7 segments).
# Every upload is compared byte for byte with what was downloaded first.
# Then, once, deterministic counts of a segmented upload: system calls of
# the master per segment (strace -c) and user-mode instructions per segment
# (valgrind --tool=callgrind: the difference between uploads of 64 KiB and
# 32 KiB over the difference in segments, so the start-up cancels out).
# BENCH_COUNTS=0 leaves them out. BENCH_BEFORE=DIR (another build, e.g. of
# main in a worktree): its mb2co-master and BUILD_DIR's take turns on the
# segmented upload, BENCH_ROUNDS times each, in the same boot against the
# same node: the fairest before/after of the CPU per segment.
#
# BUILD_DIR (default build) holds mb2co-master and mb2co-node.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
size=${BENCH_SIZE:-262144}
rounds=${BENCH_ROUNDS:-3}
cangen_frames=${BENCH_CANGEN_FRAMES:-50000}
with_counts=${BENCH_COUNTS:-1}
before=${BENCH_BEFORE:-}
node_id=5

# shellcheck source=tests/master/bench_node.sh
. "$here/bench_node.sh"
bench_start bench_master_fps "$build" "$node_id"

now_s() { date +%s.%N; }
content() {
  python3 -c "import sys; sys.stdout.buffer.write(bytes((i * 7 + (i >> 8) + 13) & 0xFF for i in range($1)))"
}
# upload MODE FILE [MASTER]: runs the master under GNU time; "frames seconds cpu_s".
upload() {
  rm -f "$2"
  local f0 f1 secs user sys
  f0=$(tx_frames)
  /usr/bin/time -f '%e %U %S' -o "$work/time.txt" \
    "${3:-$master}" -i vcan0 -t 5000 upload "$node_id" 1F50 1 "$2" "--$1" >"$work/up.out" 2>"$work/up.err" ||
    { echo "bench_master_fps: $1 upload failed" >&2; cat "$work/up.out" "$work/up.err" >&2; exit 1; }
  f1=$(tx_frames)
  cmp -s "$work/in.bin" "$2" || { echo "bench_master_fps: $1 upload differs from the download" >&2; exit 1; }
  secs=$(sed -n 's/.* in \([0-9.]*\) s .*/\1/p' "$work/up.out")
  read -r _ user sys <<<"$(tail -n 1 "$work/time.txt")"
  echo "$((f1 - f0)) $secs $(awk -v u="$user" -v s="$sys" 'BEGIN { printf "%.2f", u + s }')"
}

content "$size" >"$work/in.bin"
"$master" -i vcan0 -t 5000 download "$node_id" 1F50 1 "$work/in.bin" --block >&2
segments=$(((size + 6) / 7))
printf '%-5s %10s %10s %10s %7s %12s %14s\n' round cangen_fps block_fps block_s share seg_cpu_s seg_cpu_us/seg
for ((r = 1; r <= rounds; ++r)); do
  f0=$(tx_frames)
  t0=$(now_s)
  cangen -g 0 -n "$cangen_frames" -I 7E5 -L 8 vcan0
  t1=$(now_s)
  f1=$(tx_frames)
  cangen_fps=$(awk -v f=$((f1 - f0)) -v a="$t0" -v b="$t1" 'BEGIN { printf "%.0f", f / (b - a) }')
  read -r bf bs _ <<<"$(upload block "$work/up.bin")"
  read -r _ _ scpu <<<"$(upload segmented "$work/up.bin")"
  awk -v r="$r" -v c="$cangen_fps" -v f="$bf" -v s="$bs" -v cpu="$scpu" -v n="$segments" 'BEGIN {
    printf "%-5s %10d %10.0f %10.3f %6.0f%% %12.2f %14.1f\n", r, c, f / s, s, 100 * f / s / c, cpu, cpu * 1e6 / n }'
done

if [ -n "$before" ]; then
  [ -x "$before/pcapp/master/mb2co-master" ] || { echo "bench_master_fps: $before/pcapp/master/mb2co-master missing" >&2; exit 2; }
  echo "segmented upload, master CPU per segment, the two builds taking turns:"
  for ((r = 1; r <= rounds; ++r)); do
    for who in before after; do
      prog=$master
      [ "$who" = before ] && prog=$before/pcapp/master/mb2co-master
      read -r _ _ scpu <<<"$(upload segmented "$work/up.bin" "$prog")"
      awk -v w="$who" -v cpu="$scpu" -v n="$segments" 'BEGIN { printf "  %-6s %6.2f s %8.1f us/segment\n", w, cpu, cpu * 1e6 / n }'
    done
  done
fi

[ "$with_counts" = 1 ] || exit 0
# Deterministic counts of a segmented upload (not timed).
for kib in 32 64; do
  content $((kib * 1024)) >"$work/in.bin"
  "$master" -i vcan0 -t 5000 download "$node_id" 1F50 1 "$work/in.bin" --block >/dev/null
  strace -c -o "$work/strace$kib.txt" "$master" -i vcan0 -t 5000 upload "$node_id" 1F50 1 "$work/up.bin" --segmented >/dev/null
  cmp -s "$work/in.bin" "$work/up.bin" || { echo "bench_master_fps: segmented upload under strace differs" >&2; exit 1; }
  valgrind --tool=callgrind --callgrind-out-file="$work/cg$kib.out" \
    "$master" -i vcan0 -t 20000 upload "$node_id" 1F50 1 "$work/up.bin" --segmented >/dev/null 2>"$work/cg$kib.err"
  cmp -s "$work/in.bin" "$work/up.bin" || { echo "bench_master_fps: segmented upload under callgrind differs" >&2; exit 1; }
done
# strace -c columns: % time, seconds, usecs/call, calls, [errors], syscall.
calls() { awk '$NF == "total" { print $4 }' "$1"; }
instr() { sed -n 's/^summary: \([0-9]*\).*/\1/p' "$1"; }
seg32=$(((32 * 1024 + 6) / 7))
seg64=$(((64 * 1024 + 6) / 7))
echo "segmented upload of 64 KiB ($seg64 segments), mb2co-master's most frequent system calls (strace -c):"
awk -v n="$seg64" '$4 ~ /^[0-9]+$/ && $NF != "total" { printf "  %-16s %7d  %5.2f per segment\n", $NF, $4, $4 / n }' \
  "$work/strace64.txt" | sort -k2 -n -r | head -6
awk -v a="$(calls "$work/strace32.txt")" -v b="$(calls "$work/strace64.txt")" -v s=$((seg64 - seg32)) \
  'BEGIN { printf "system calls per segment (64 KiB - 32 KiB): %.2f\n", (b - a) / s }'
awk -v a="$(instr "$work/cg32.out")" -v b="$(instr "$work/cg64.out")" -v s=$((seg64 - seg32)) \
  'BEGIN { printf "instructions per segment (callgrind, 64 KiB - 32 KiB): %.0f\n", (b - a) / s }'
