#!/usr/bin/env bash
# Builds the libFuzzer targets (clang) into build-fuzz/ and runs each for
# SECONDS on a copy of its corpus (tests/fuzz/corpus/<target>/, checked in):
#   tests/fuzz/run.sh 600 register_bank     one target, 10 min, a random seed
#   tests/fuzz/run.sh runs=10000000 eds     one target, 10 M executions, a random seed
#   MB2CO_FUZZ_MERGE=1 tests/fuzz/run.sh 600 ...   and merge what it found into the corpus
#   MB2CO_FUZZ_FLAGS=-max_len=512 tests/fuzz/run.sh ...   more libFuzzer options (long runs; they come last)
#   tests/fuzz/run.sh ci                    every target, seed 1, a fixed number of
#                                           executions (scripts/test.sh)
# "ci" runs the same inputs on every machine: a landing is never refused by
# what a random seed happened to find that day. Long random runs are by hand;
# what they find goes into the corpus, and from there into every ci run.
# A crash or an invariant violation fails the run (exit 1) and leaves the
# input in build-fuzz/artifacts/. Prints each target's executions.
set -euo pipefail
cd "$(dirname "$0")/../.."
seconds=${1:?usage: tests/fuzz/run.sh SECONDS|runs=N|ci [TARGET...]}
if [[ ! "$seconds" =~ ^(ci|[0-9]+|runs=[0-9]+)$ ]]; then
  echo "fuzz: '$seconds' is not SECONDS, runs=N or ci (usage: tests/fuzz/run.sh SECONDS|runs=N|ci [TARGET...])" >&2
  exit 2
fi
shift
# Executions per target in "ci" mode: about 10 s each on one busy core.
declare -A ci_runs=([node_frames]=60000 [gateway_modbus]=20000 [register_bank]=40000
                    [timing_csv]=300000 [plant_config]=300000 [eds]=10000
                    [sdo_transfer]=100000 [gateway_net]=300000 [param_image]=20000
                    [gateway_ascii]=25000)
targets=("$@")
((${#targets[@]})) || targets=(node_frames gateway_modbus register_bank timing_csv plant_config eds sdo_transfer gateway_net param_image
                               gateway_ascii)
build=${MB2CO_FUZZ_BUILD_DIR:-build-fuzz}
mkdir -p "$build"
if ! { cmake -S tests/fuzz -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ &&
       cmake --build "$build" --target "${targets[@]/#/mb2co_fuzz_}"; } >"$build/build.log" 2>&1; then
  echo "fuzz: the targets do not build (log $build/build.log):" >&2
  grep -E "error|FAILED" "$build/build.log" | head -10 >&2
  exit 1
fi
mkdir -p "$build/artifacts"
status=0
for t in "${targets[@]}"; do
  corpus=tests/fuzz/corpus/$t
  work=$(mktemp -d)
  [ -d "$corpus" ] && cp -r "$corpus/." "$work/"
  log=$build/$t.log
  if [ "$seconds" = ci ]; then
    limit=(-seed=1 -runs="${ci_runs[$t]}")
    span="seed 1"
  elif [[ "$seconds" == runs=* ]]; then
    limit=(-runs="${seconds#runs=}")
    span="${seconds#runs=} runs"
  else
    limit=(-max_total_time="$seconds")
    span="${seconds} s"
  fi
  # shellcheck disable=SC2086 # MB2CO_FUZZ_FLAGS: options, split on spaces
  # MB2CO_FUZZ_FLAGS last: a long run by hand may raise -timeout (wall clock:
  # a busy host's pause is not a hang).
  if "$build/mb2co_fuzz_$t" "${limit[@]}" -timeout=10 -rss_limit_mb=2048 \
      -artifact_prefix="$build/artifacts/$t-" -print_final_stats=1 ${MB2CO_FUZZ_FLAGS:-} "$work" >"$log" 2>&1; then
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    echo "fuzz $t: ${execs:-?} executions ($span), no failure"
    if [ "${MB2CO_FUZZ_MERGE:-0}" = 1 ]; then
      mkdir -p "$corpus"
      "$build/mb2co_fuzz_$t" -merge=1 "$corpus" "$work" >/dev/null 2>&1
    fi
  else
    echo "fuzz $t: FAILED (log $log, input in $build/artifacts/)" >&2
    grep -E "invariant violated|ERROR: |SUMMARY" "$log" | head -5 >&2 || true
    status=1
  fi
  rm -rf "$work"
done
exit $status
