#!/usr/bin/env bash
# Compares two builds of mb2co-lab byte for byte: every scenario of
# `mb2co-lab --help` with seeds 1 and 7 (and the variants a change to the
# simulator's scheduling can move: --firmware fast, --ring, --worst), with
# --events, every file of --out. For a change that must not move any figure
# (docs/performance.md, "Line simulator"). Usage:
#   tests/sim/lab_compare.sh BASE_LAB NEW_LAB [WORK_DIR]
# e.g. a build of main: git worktree add /tmp/m main && cmake ... && cmake --build /tmp/m/build --target mb2co-lab
set -uo pipefail
base=${1:?usage: lab_compare.sh BASE_LAB NEW_LAB [WORK_DIR]}
new=${2:?usage: lab_compare.sh BASE_LAB NEW_LAB [WORK_DIR]}
work=${3:-$(mktemp -d)}
mkdir -p "$work"
runs=(
  "--scenario run" "--scenario run --firmware fast" "--scenario run --ring --stations 5"
  "--scenario stop2" "--scenario latency --presses 300" "--scenario latency --worst"
  "--scenario faults" "--scenario sync-roundtrip" "--scenario sync-latency" "--scenario sync-processing"
  "--scenario alternative" "--scenario default" "--firmware fast --presses 200"
)
differ=0
n=0
for seed in 1 7; do
  for args in "${runs[@]}"; do
    n=$((n + 1))
    for side in base new; do
      lab=$base
      [ "$side" = new ] && lab=$new
      rm -rf "${work:?}/$side"
      # shellcheck disable=SC2086
      "$lab" $args --seed "$seed" --quiet --events --out "$work/$side" >"$work/$side.stdout" 2>&1
      echo "exit $?" >>"$work/$side.stdout"
      sed -i "s#$work/$side#OUT#g" "$work/$side.stdout" "$work/$side"/*.txt 2>/dev/null
    done
    if ! cmp -s "$work/base.stdout" "$work/new.stdout" || ! diff -r -q "$work/base" "$work/new" >/dev/null; then
      echo "DIFFERS: $args --seed $seed"
      diff -r -q "$work/base" "$work/new" | head -5
      differ=$((differ + 1))
    else
      echo "same: $args --seed $seed ($(find "$work/new" -type f | wc -l) files, $(tail -1 "$work/new.stdout"))"
    fi
  done
done
echo "$n runs, $differ differ"
exit $((differ > 0))
