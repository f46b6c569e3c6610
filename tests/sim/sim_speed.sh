#!/usr/bin/env bash
# The simulator's speed, as docs/performance.md ("Line simulator") gives it:
# instructions (callgrind: exact for the same binary and input) of 30 s of a
# 4-station line, and the default run's speed figure three times (wall clock:
# run it on an idle core). Usage: tests/sim/sim_speed.sh [BUILD_DIR]
set -euo pipefail
lab=${1:-build}/hil/lab/mb2co-lab
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
valgrind --tool=callgrind --callgrind-out-file="$out/run.cg" "$lab" --seed 1 --scenario run --stations 4 \
  --quiet --out "$out/run" 2>&1 | grep -E "I +refs" | sed 's/^==[0-9]*== /run scenario, 30 s, 4 stations: /'
for i in 1 2 3; do "$lab" --out "$out/default" 2>&1 >/dev/null | tail -1; done
