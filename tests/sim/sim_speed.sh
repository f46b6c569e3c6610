#!/usr/bin/env bash
# The simulator's speed, as docs/performance.md ("Line simulator") gives it:
# instructions (callgrind: exact for the same binary and input) of 30 s of a
# 4-station line, and the default run's speed figure three times (wall clock,
# one core, with the load average before and after: run it on an idle core).
# Usage: tests/sim/sim_speed.sh [BUILD_DIR]
set -euo pipefail
lab=${1:-build}/hil/lab/mb2co-lab
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
valgrind --tool=callgrind --callgrind-out-file="$out/run.cg" "$lab" --seed 1 --scenario run --stations 4 \
  --quiet --out "$out/run" 2>&1 | grep -E "I +refs" | sed 's/^==[0-9]*== /run scenario, 30 s, 4 stations: /'
# Wall clock moves with the machine's load: print it with the figures, and
# run on one core (taskset) as docs/performance.md measures.
pin=()
command -v taskset >/dev/null && pin=(taskset -c 0)
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
for _ in 1 2 3; do "${pin[@]}" "$lab" --out "$out/default" 2>&1 >/dev/null | tail -1; done
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"
