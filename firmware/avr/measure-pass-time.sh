#!/usr/bin/env bash
# Pass times of the gateway core on the ATmega328P at 16 MHz: builds the
# measurement image gateway-passtime (firmware/avr/sketches/gateway-passtime)
# with the firmware's own options and runs it under simavr, which executes
# every instruction with the ATmega328P's cycle counts. Prints one line per
# kind of pass: "<what> <µs> [<response bytes> <function code>]".
# MB2CO_AVR_BUILD_DIR: build directory (default build/avr), as for
# build-and-check.sh.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
build=${MB2CO_AVR_BUILD_DIR:-build/avr}
command -v simavr >/dev/null || { echo "measure-pass-time: simavr not found (apt-get install simavr)" >&2; exit 1; }
cmake -S firmware/avr -B "$build" -G Ninja \
  -DCMAKE_TOOLCHAIN_FILE="$root/cmake/avr-toolchain.cmake" -DCMAKE_BUILD_TYPE=MinSizeRel >/dev/null
cmake --build "$build" --target gateway-passtime >/dev/null
# simavr prints the UART's lines with a trailing '.' and colour codes.
out=$(timeout 120 simavr -m atmega328p -f 16000000 "$build/gateway-passtime.elf" 2>&1 |
  sed -e 's/\x1b\[[0-9;]*m//g' -e 's/\.$//')
if ! grep -q '^end$' <<<"$out"; then
  echo "measure-pass-time: the image did not finish under simavr:" >&2
  echo "$out" >&2
  exit 1
fi
grep -v -e '^end$' -e '^Loaded' -e 'simavr' <<<"$out" | sed '/^$/d'
