#!/usr/bin/env bash
# Runs mb2co-lab's faults scenario (frame loss, bus-off, a gateway reboot, a
# serial unplug) over a sweep of seeds and line shapes; each run must pass
# every check, among them "STOP2 counted once everywhere": every press counted
# exactly once by its gateway, its own PC and the next station's PC (issue 16
# item 8: a rebooted gateway's not-yet-heard counter made a phantom event).
# Usage: lab_faults_sweep.sh LAB OUT_DIR [SEEDS]   (SEEDS default 20)
set -uo pipefail
lab=$1
out=$2
seeds=${3:-20}
shapes=("" "--ring" "--stations 6" "--firmware fast")
failed=0
runs=0
for shape in "${shapes[@]}"; do
  for ((seed = 1; seed <= seeds; ++seed)); do
    # shellcheck disable=SC2086  # a shape is several words on purpose
    report=$("$lab" --scenario faults --seed "$seed" $shape --quiet --out "$out" 2>&1)
    status=$?
    runs=$((runs + 1))
    if ((status != 0)); then
      failed=$((failed + 1))
      echo "FAIL: --seed $seed ${shape:-(chain of 4)}: exit $status"
      grep -A1 -F '[FAIL]' <<<"$report"
    fi
  done
done
echo "faults scenario: $((runs - failed)) of $runs runs passed"
((failed == 0))
