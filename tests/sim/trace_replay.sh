#!/bin/bash
# mb2co-lab --trace writes a candump -L log that can-utils read: canplayer
# replays it onto vcan0 and candump -L sees every frame, in order, with the
# same identifier and bytes. Runs inside hil/uml/run-with-vcan.sh.
# Usage: trace_replay.sh MB2CO_LAB WORK_DIR
set -euo pipefail
lab=${1:?usage: trace_replay.sh MB2CO_LAB WORK_DIR}
work=${2:?usage: trace_replay.sh MB2CO_LAB WORK_DIR}
rm -rf "$work" && mkdir -p "$work"
"$lab" --scenario stop2 --quiet --out "$work/out" --trace "$work/trace.log" >/dev/null
frames=$(wc -l <"$work/trace.log")
[ "$frames" -gt 100 ] || { echo "trace has only $frames frames" >&2; exit 1; }
# The log itself is candump -L: (seconds.micro) iface id#data, time moving forward.
if grep -vqE '^\([0-9]{10}\.[0-9]{6}\) can0 [0-9A-F]{3}#([0-9A-F]{2})*$' "$work/trace.log"; then
  echo "not candump -L: $(grep -vE '^\([0-9]{10}\.[0-9]{6}\) can0 [0-9A-F]{3}#([0-9A-F]{2})*$' "$work/trace.log" | head -1)" >&2
  exit 1
fi
awk '{ t = substr($1, 2, 17) + 0; if (t < last) { print "time goes back: " $0; bad = 1 }; last = t }
     END { exit bad }' "$work/trace.log"

candump -L -d -r 8388608 vcan0 >"$work/seen.log" &
dump=$!
trap 'kill $dump 2>/dev/null || true' EXIT
# candump is listening once its socket shows in /proc/net/can/rcvlist_all.
for _ in $(seq 1 500); do
  grep -qE '^ +vcan0 +[0-9A-F]+ ' /proc/net/can/rcvlist_all 2>/dev/null && break
  sleep 0.01  # polling the condition above, bounded by the loop
done
# -t: ignore the time stamps, -g 1: one frame per ms (a 1 s gap of the
# simulated runs would only make the test slower).
canplayer -t -g 1 -I "$work/trace.log" vcan0=can0
for _ in $(seq 1 1000); do
  [ "$(wc -l <"$work/seen.log")" -ge "$frames" ] && break
  sleep 0.01  # polling the condition above, bounded by the loop
done
kill $dump; wait $dump 2>/dev/null || true
trap - EXIT
cut -d' ' -f3 "$work/trace.log" >"$work/sent.txt"
cut -d' ' -f3 "$work/seen.log" >"$work/got.txt"
if ! diff "$work/sent.txt" "$work/got.txt" >"$work/diff.txt"; then
  echo "candump saw other frames than the trace holds:" >&2
  head -20 "$work/diff.txt" >&2
  exit 1
fi
echo "trace_replay: $frames frames replayed by canplayer and seen by candump, identical"
