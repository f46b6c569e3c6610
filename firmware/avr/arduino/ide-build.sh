#!/usr/bin/env bash
# Builds the sketch folders the way the Arduino IDE does — with
# arduino-builder, the IDE's build engine (Debian package arduino-builder),
# Debian's Arduino core and the mb2co library of install-library.sh — using
# exactly the board settings README.md tells IDE users to put into
# platform.local.txt. Checks that each sketch builds, fits the Uno, and comes
# out within 1 % of the CMake image of the same name (same sources, same
# options; LTO partitions the code a little differently, a few bytes apart.
# The size options alone are worth 13 % on the gateway: a bigger difference
# means README.md's settings or the library went out of step with
# firmware/avr/CMakeLists.txt).
# Usage: firmware/avr/arduino/ide-build.sh [sketch-name...]
#        (default: every sketches/*/ folder with a .ino)
# MB2CO_AVR_BUILD_DIR: the CMake build to compare with (default build/avr).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
cmake_build=$root/${MB2CO_AVR_BUILD_DIR:-build/avr}
hardware=/usr/share/arduino/hardware
command -v arduino-builder >/dev/null || { echo "ide-build: arduino-builder not found (apt-get install arduino-builder)" >&2; exit 1; }
[[ -f $hardware/arduino/avr/platform.txt ]] || { echo "ide-build: no Arduino core in $hardware (apt-get install arduino-core-avr)" >&2; exit 1; }

# The settings of README.md ("Arduino IDE"), one place for both.
size_flags="-mcall-prologues -mrelax -fno-inline-small-functions -mstrict-X -fno-move-loop-invariants -fno-tree-dominator-opts -fno-early-inlining"
cpp_extra="-std=gnu++14 -DDECIMAL_DIG=__DECIMAL_DIG__ $size_flags"
elf_extra="$size_flags"

sketches=("$@")
if ((${#sketches[@]} == 0)); then
  for ino in "$root"/firmware/avr/sketches/*/*.ino; do sketches+=("$(basename "$(dirname "$ino")")"); done
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$here/install-library.sh" "$work/sketchbook" >/dev/null

failed=0
kUnoFlash=32256
for sketch in "${sketches[@]}"; do
  ino=$root/firmware/avr/sketches/$sketch/$sketch.ino
  if [[ ! -f $ino ]]; then
    echo "ide-build: no sketch $ino" >&2
    failed=1
    continue
  fi
  out=$work/build-$sketch
  mkdir -p "$out"
  if ! arduino-builder -compile -hardware "$hardware" -hardware /usr/share/arduino-builder -tools /usr/bin \
      -libraries "$work/sketchbook/libraries" -fqbn arduino:avr:uno -build-path "$out" \
      -prefs "runtime.ide.version=10819" -prefs "compiler.cpp.extra_flags=$cpp_extra" \
      -prefs "compiler.c.elf.extra_flags=$elf_extra" "$ino" >"$work/$sketch.log" 2>&1; then
    echo "ide-build: $sketch does not build with arduino-builder:" >&2
    tail -n 20 "$work/$sketch.log" >&2
    failed=1
    continue
  fi
  read -r text data _ < <(avr-size --format=berkeley "$out/$sketch.ino.elf" | tail -n 1)
  ide=$((text + data))
  line="ide-build: $sketch with arduino-builder: $ide B flash"
  if ((ide > kUnoFlash)); then
    echo "$line: does not fit the Uno ($kUnoFlash B next to the bootloader)" >&2
    failed=1
    continue
  fi
  if [[ -f $cmake_build/$sketch.elf ]]; then
    read -r text data _ < <(avr-size --format=berkeley "$cmake_build/$sketch.elf" | tail -n 1)
    cmake_flash=$((text + data))
    diff=$((ide > cmake_flash ? ide - cmake_flash : cmake_flash - ide))
    if ((diff * 100 > cmake_flash)); then
      echo "$line, the CMake image $cmake_flash B: more than 1 % apart, README.md's IDE settings or the library are out of step with firmware/avr/CMakeLists.txt" >&2
      failed=1
      continue
    fi
    line="$line (CMake image: $cmake_flash B)"
  fi
  echo "$line"
done
exit "$failed"
