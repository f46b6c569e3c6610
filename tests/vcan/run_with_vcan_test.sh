#!/bin/bash
# ctest vcan.run_with_vcan: what callers of hil/uml/run-with-vcan.sh rely on.
# Usage: run_with_vcan_test.sh PATH/TO/run-with-vcan.sh
set -u
run=${1:?usage: run_with_vcan_test.sh PATH/TO/run-with-vcan.sh}
work=$(mktemp -d)
trap 'rm -rf -- "$work"' EXIT
failures=0
check() { # description, then a test command
  local what=$1
  shift
  if "$@"; then echo "ok   $what"; else echo "FAIL $what"; failures=$((failures + 1)); fi
}

# Exit codes pass through: plain failure, a chosen code, death by signal.
"$run" -- false
check "'-- false' exits 1 (got $?)" test $? -eq 1
"$run" -- bash -c 'kill -TERM $$'
check "a command killed by SIGTERM gives 143 (got $?)" test $? -eq 143

# Interfaces, directory, environment, stdout and stderr kept apart.
cd "$work" || exit 1
# shellcheck disable=SC2016  # a literal $ on purpose
export MB2CO_PROBE_VAR='a b$c'
"$run" --ifaces vcan0,vcan1 -- bash -c '
  ip link show vcan0 && ip -details link show vcan1 | grep -q "vcan" || exit 90
  test "$(ip -brief link show vcan0 | cut -d" " -f1)" = vcan0 || exit 91
  echo "cwd=$PWD var=$MB2CO_PROBE_VAR"
  echo to-stderr >&2
  exit 7' >"$work/out" 2>"$work/err"
rc=$?
check "exit code 7 of the command (got $rc)" test $rc -eq 7
check "ip link show vcan0 works inside" grep -q '^[0-9]*: vcan0: .*UP' "$work/out"
check "working directory and environment preserved" grep -qxF "cwd=$work var=$MB2CO_PROBE_VAR" "$work/out"
check "stderr reaches stderr only" test "$(cat "$work/err")" = to-stderr
check "stdout carries no stderr" bash -c "! grep -q to-stderr '$work/out'"
cd - >/dev/null || exit 1

# Processes the command leaves behind die with it: neither the sandbox nor
# our pipe waits for them (the outer timeout would say 124).
out=$(timeout 120 "$run" -- bash -c 'sleep 1000 & setsid sleep 1000 & echo started')
check "background processes do not hold the run (got $?)" test "$out" = started

"$run" --timeout 1 -- sleep 100 2>"$work/err"
check "--timeout stops the command with 124 (got $?)" test $? -eq 124

# Usage errors and a sandbox that cannot boot: 125 and one line.
"$run" 2>"$work/err"
check "no command: exit 125 (got $?)" test $? -eq 125
check "no command: one line on stderr" test "$(wc -l <"$work/err")" -eq 1
MB2CO_UML_MEM=1M "$run" --mode uml -- true 2>"$work/err"
check "user-mode Linux that cannot boot: exit 125 (got $?)" test $? -eq 125
check "  ... and one error line: $(head -c 200 "$work/err")" \
  bash -c "test \$(wc -l <'$work/err') -eq 1 && grep -q '^run-with-vcan: user-mode Linux did not run the command' '$work/err'"

echo "$failures failure(s)"
test "$failures" -eq 0
