#!/bin/bash
# The bridge end to end (issue 13's must-show), run inside hil/uml/run-with-vcan.sh:
# three serial I/O nodes on one segment (ptys joined by mb2co-serial-hub), the
# bridge to vcan0 with offset 0x20; candump must see their boot-ups and
# heartbeats at CAN node ids 21h-23h, and an SDO upload of 1018h sub 2 sent
# with cansend to CAN node 22h must be answered by serial node 2 through the
# bridge. The bridge is mb2co-bridge (linux) or the Uno image mb2co-bridge.elf
# in simavr (uno: mb2co-uno with its USART0 pty joined to the hub; the
# image's segment settings are built in: poll, as below).
# linux_echo: mb2co-bridge --echo on a hub port that echoes its bytes back
# (an RS-485 adapter), which must be taken out.
# Usage: bridge_vcan_test.sh HUB NODE poll|token linux|linux_echo MB2CO_BRIDGE
#        bridge_vcan_test.sh HUB NODE poll uno MB2CO_UNO BRIDGE_ELF
set -u
usage="usage: bridge_vcan_test.sh HUB NODE poll|token linux|linux_echo|uno BRIDGE_PROGRAM [ELF]"
hub=${1:?$usage} node=${2:?$usage} access=${3:?$usage} kind=${4:?$usage} bridge=${5:?$usage} elf=${6:-}
dir=$(mktemp -d)
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  wait 2>/dev/null
  rm -rf "$dir"
}
trap cleanup EXIT
fail() {
  echo "FAIL ($kind $access): $*" >&2
  # The bridge's counters (mb2co-bridge --verbose prints them when it ends).
  [[ -n ${bridge_pid:-} ]] && kill "$bridge_pid" && wait "$bridge_pid" 2>/dev/null
  echo "--- candump (last 40 lines)" >&2
  tail -n 40 "$dir/can.log" >&2
  for f in "$dir"/*.err; do [[ -s $f ]] && { echo "--- $f" >&2; cat "$f" >&2; }; done
  exit 1
}
# Waits up to $1 s for `grep -E $2` to find $3 lines (default 1) in the candump log.
wait_for() {
  local pattern=$2 want=${3:-1} end=$((SECONDS + $1))
  while ((SECONDS < end)); do
    (($(grep -cE "$pattern" "$dir/can.log") >= want)) && return 0
    sleep 0.05
  done
  return 1
}

seg=(--bits 8 --access "$access" --nodes 1-3 --window-us 20000 --guard-us 5000)
if [[ $kind == uno ]]; then
  # The simulated Uno makes its own pty for USART0: the hub joins it.
  "$bridge" --elf "$elf" --can vcan0 --pty "$dir/uno" >"$dir/bridge.out" 2>"$dir/bridge.err" &
  pids+=($!)
  for ((i = 0; i < 200; i++)); do [[ -e $dir/uno ]] && break; sleep 0.05; done
  [[ -e $dir/uno ]] || fail "mb2co-uno made no pty"
  member=@$dir/uno
elif [[ $kind == linux_echo ]]; then
  member=+$dir/br
else
  member=$dir/br
fi
"$hub" "$dir/n1" "$dir/n2" "$dir/n3" "$member" >"$dir/hub.out" 2>"$dir/hub.err" &
pids+=($!)
for ((i = 0; i < 200; i++)); do grep -q ready "$dir/hub.out" && break; sleep 0.05; done
grep -q ready "$dir/hub.out" || fail "the hub did not start"

candump -L vcan0 >"$dir/can.log" 2>"$dir/candump.err" &
pids+=($!)
# candump is listening once it logs a probe frame.
for ((i = 0; i < 100; i++)); do
  cansend vcan0 7FF#A5
  grep -q ' 7FF#A5' "$dir/can.log" && break
  sleep 0.05
done
grep -q ' 7FF#A5' "$dir/can.log" || fail "candump did not start"

if [[ $kind == linux* ]]; then
  echo_opt=()
  [[ $kind == linux_echo ]] && echo_opt=(--echo)
  "$bridge" --serial "$dir/br" --can vcan0 --offset 32 --verbose "${echo_opt[@]}" "${seg[@]}" >"$dir/bridge.out" 2>"$dir/bridge.err" &
  bridge_pid=$!
  pids+=($!)
fi
for n in 1 2 3; do
  "$node" --serial "$dir/n$n" --node-id "$n" --heartbeat-ms 200 "${seg[@]}" >"$dir/node$n.out" 2>"$dir/node$n.err" &
  pids+=($!)
done

# Boot-up (00) then heartbeats in pre-operational (7F) at 720h + n.
for n in 1 2 3; do
  wait_for 15 " 72$n#00\$" || fail "no boot-up of serial node $n at CAN id 72${n}h"
  wait_for 15 " 72$n#7F\$" 3 || fail "fewer than 3 heartbeats of serial node $n at CAN id 72${n}h"
done
grep -qE ' 70[123]#' "$dir/can.log" && fail "a serial node's id reached CAN without its offset"
grep -qE ' 080#' "$dir/can.log" && fail "a poll SYNC of the segment reached CAN"

# SDO upload of 1018h sub 2 (product code 0401h) from CAN node 22h's server.
cansend vcan0 622#4018100200000000
wait_for 10 ' 5A2#4[23]18100201040000$' || fail "no SDO answer of serial node 2 at 5A2h"
# An upload of 1018h sub 1 from node 23h as well (a different node, same path).
cansend vcan0 623#4018100100000000
wait_for 10 ' 5A3#4[23]181001' || fail "no SDO answer of serial node 3 at 5A3h"

if [[ $kind == linux* ]]; then
  # The bridge's counters at exit: everything crossed, nothing was dropped,
  # and with an echoing adapter its own bytes were taken out.
  kill "$bridge_pid"
  wait "$bridge_pid" 2>/dev/null
  counters=$(grep -o 'to_can=.*' "$dir/bridge.err")
  [[ -n $counters ]] || fail "no counters from mb2co-bridge"
  grep -q ' overflow=0 ' <<<"$counters" || fail "frames dropped: $counters"
  if [[ $kind == linux_echo ]]; then
    grep -qE 'echo_dropped=[1-9]' <<<"$counters" || fail "no echo taken out: $counters"
  else
    grep -q 'echo_dropped=0' <<<"$counters" || fail "echo taken out without --echo: $counters"
  fi
fi
echo "PASS ($kind $access): $(grep -cE ' 72[123]#' "$dir/can.log") boot-ups/heartbeats at 721h-723h, SDO answered at 5A2h and 5A3h${counters:+; bridge: $counters}"
exit 0
