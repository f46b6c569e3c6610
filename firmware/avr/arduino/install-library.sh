#!/usr/bin/env bash
# Makes the mb2co sources an Arduino library, so that the sketch folders
# firmware/avr/sketches/mb2co-* open and build in the Arduino IDE:
#   firmware/avr/arduino/install-library.sh [sketchbook]   (default ~/Arduino)
# creates <sketchbook>/libraries/mb2co/ with library.properties and src/ made
# of symlinks into this checkout (edits here show up in the IDE at once):
#   src/canopen src/modbus src/gateway src/ionode   -> shared/<area>
#   src/platform (the port contract)                -> shared/platform
#   src/port                                        -> firmware/avr/port
#   src/pins.h src/mb2co.h                          -> firmware/avr/
#   src/mcp2515.* bit_timing.h filter_plan.* ...    -> firmware/mcp2515/
# The IDE compiles C++ as gnu++11; the sources need gnu++14 (README.md).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
sketchbook=${1:-$HOME/Arduino}
lib="$sketchbook/libraries/mb2co"

if [[ -e "$lib" && ! -f "$lib/.mb2co-generated" ]]; then
  echo "install-library.sh: $lib exists and was not made by this script; not touching it" >&2
  exit 1
fi
rm -rf "$lib"
mkdir -p "$lib/src"
touch "$lib/.mb2co-generated"
cp "$here/library.properties" "$lib/"
for area in canopen modbus gateway ionode platform; do ln -s "$root/shared/$area" "$lib/src/$area"; done
ln -s "$root/firmware/avr/port" "$lib/src/port"
ln -s "$root/firmware/avr/pins.h" "$lib/src/pins.h"
ln -s "$root/firmware/avr/mb2co.h" "$lib/src/mb2co.h"
for f in "$root"/firmware/mcp2515/*.h "$root"/firmware/mcp2515/*.cpp; do ln -s "$f" "$lib/src/$(basename "$f")"; done
echo "mb2co library: $lib"
echo "Open firmware/avr/sketches/mb2co-ionode/mb2co-ionode.ino (or mb2co-gateway) in the IDE."
