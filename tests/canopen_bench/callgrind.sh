#!/usr/bin/env bash
# Instructions per operation of the CANopen core, counted by callgrind.
# Usage: tests/canopen_bench/callgrind.sh [BUILD_DIR]   (default build)
set -euo pipefail
build=${1:-build}
driver=$build/tests/canopen_bench/mb2co_callgrind_canopen
out=$(mktemp -d)
for fn in run_od_lookup run_sdo_upload run_sync_4_tpdos; do
  valgrind --tool=callgrind --callgrind-out-file="$out/$fn" --toggle-collect="*$fn*" "$driver" >/dev/null 2>"$out/$fn.log"
  total=$(sed -n 's/^==[0-9]*== Collected : //p' "$out/$fn.log")
  echo "$fn: $((total / 10000)) instructions per operation ($total for 10000)"
done
rm -rf "$out"
