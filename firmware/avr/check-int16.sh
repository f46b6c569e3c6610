#!/usr/bin/env bash
# On the AVR an int is 16 bits: `uint16_t ms * 1000u` is computed in 16 bits
# and wraps before it is widened, where the host (32-bit int) is right, so no
# host test sees it (a 100 ms TPDO event timer fired every 34.5 ms on the Uno
# this way). This checks every source built for the AVR with clang-tidy for
# the AVR target (int = 16 bits there too): a multiplication widened after
# it was computed in int (bugprone-implicit-widening-of-multiplication-result),
# a widening cast applied to such a result (bugprone-misplaced-widening-cast),
# and clang's own warnings (shifts past 16 bits, constants that overflow int).
# Not covered: a sum of two 16-bit values that exceeds 65535, a shift by a
# variable count; write those with a 32-bit operand where it can happen.
# Run from anywhere; scripts/test.sh calls it. Exit 1 on any finding.
set -euo pipefail
cd "$(dirname "$0")/../.."
command -v clang-tidy >/dev/null || { echo "check-int16: clang-tidy not found (apt-get install clang-tidy)" >&2; exit 1; }
arduino=/usr/share/arduino/hardware/arduino/avr
sources=(shared/canopen/*.cpp shared/modbus/*.cpp shared/gateway/*.cpp shared/ionode/*.cpp
         firmware/mcp2515/*.cpp firmware/avr/port/*.cpp firmware/avr/sketches/*/*.cpp)
flags=(--target=avr -mmcu=atmega328p -std=gnu++14 -fno-exceptions -fno-rtti -Wall -Wextra
       -Ishared -Ifirmware/mcp2515 -Ifirmware/avr -I"$arduino/cores/arduino" -I"$arduino/variants/standard"
       -isystem /usr/lib/avr/include -D__AVR_ATmega328P__ -DF_CPU=16000000L -DARDUINO=10819)
checks='-*,bugprone-implicit-widening-of-multiplication-result,bugprone-misplaced-widening-cast'
report=$(printf '%s\n' "${sources[@]}" |
  xargs -P "$(nproc)" -I{} clang-tidy -quiet -checks="$checks" {} -- "${flags[@]}" 2>&1 |
  grep -E '(warning|error):' | sort -u || true)
if [[ -n $report ]]; then
  echo "$report"
  echo "check-int16: $(wc -l <<<"$report") finding(s) in code built for the AVR (16-bit int): widen an operand before the operation" >&2
  exit 1
fi
echo "check-int16: ${#sources[@]} AVR sources, no 16-bit int hazards"
