#!/usr/bin/env bash
# Makes the mb2co sources an Arduino library, so that the sketch folders
# firmware/avr/sketches/mb2co-* open and build in the Arduino IDE:
#   firmware/avr/arduino/install-library.sh [sketchbook]   (default ~/Arduino)
# creates <sketchbook>/libraries/mb2co/ (and mb2co_network/, mb2co_ionode/:
# one per profile, below) with library.properties and src/ made of symlinks
# into this checkout (edits here show up in the IDE at once):
#   src/canopen src/modbus src/gateway src/ionode   -> shared/<area>
#   src/profiles, src/mb2co_profile.h               -> shared/profiles(/<profile>/...)
#   src/platform (the port contract)                -> shared/platform
#   src/port                                        -> firmware/avr/port
#   src/pins.h src/mb2co.h                          -> firmware/avr/
#   src/mcp2515.* bit_timing.h filter_plan.* ...    -> shared/mcp2515/
# The IDE compiles C++ as gnu++11; the sources need gnu++14 (README.md).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
sketchbook=${1:-$HOME/Arduino}

# One library per profile (shared/profiles/<profile>/mb2co_profile.h): the
# IDE compiles a library without the sketch's folder on the include path, so
# the profile is the library's: a sketch picks it by the header it includes
# (<mb2co.h> station, <mb2co_network.h> network, <mb2co_ionode.h> I/O node).
# The sources are the same symlinks in each.
make_library() {  # name profile
  local dir="$sketchbook/libraries/$1"
  if [[ -e "$dir" && ! -f "$dir/.mb2co-generated" ]]; then
    echo "install-library.sh: $dir exists and was not made by this script; not touching it" >&2
    exit 1
  fi
  rm -rf "$dir"
  mkdir -p "$dir/src"
  touch "$dir/.mb2co-generated"
  sed "s/^name=mb2co$/name=$1/" "$here/library.properties" >"$dir/library.properties"
  for area in canopen crc modbus gateway ionode platform profiles; do ln -s "$root/shared/$area" "$dir/src/$area"; done
  ln -s "$root/shared/profiles/$2/mb2co_profile.h" "$dir/src/mb2co_profile.h"
  ln -s "$root/firmware/avr/port" "$dir/src/port"
  ln -s "$root/firmware/avr/pins.h" "$dir/src/pins.h"
  ln -s "$root/firmware/avr/mb2co.h" "$dir/src/$1.h"
  for f in "$root"/shared/mcp2515/*.h "$root"/shared/mcp2515/*.cpp; do ln -s "$f" "$dir/src/$(basename "$f")"; done
  echo "$1 library (profile $2): $dir"
}
make_library mb2co station
make_library mb2co_network network
make_library mb2co_ionode ionode
echo "Open firmware/avr/sketches/mb2co-ionode/mb2co-ionode.ino (or mb2co-gateway, mb2co-gateway-network) in the IDE."
