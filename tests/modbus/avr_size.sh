#!/bin/sh
# Compiles shared/modbus (and the CRC it uses, shared/crc) for the ATmega328P with Debian's avr-g++ (fails on
# any warning) and prints flash/RAM: per object file, and linked into a
# minimal slave firmware (avr_size_main.cpp, -flto --gc-sections).
# Usage: avr_size.sh SHARED_DIR OUT_DIR
set -eu
shared=$1
out=$2
here=$(dirname "$0")
mkdir -p "$out"
flags="-std=gnu++14 -mmcu=atmega328p -Os -fno-exceptions -fno-rtti -fno-threadsafe-statics
  -ffunction-sections -fdata-sections -Wall -Wextra -Wconversion -Wsign-conversion -Wshadow
  -Werror -I$shared/profiles/station -I$shared"
objects=""
for src in "$shared"/crc/*.cpp "$shared"/modbus/*.cpp; do
  obj="$out/$(basename "${src%.cpp}").o"
  avr-g++ $flags -c "$src" -o "$obj"
  objects="$objects $obj"
done
echo "== shared/crc, shared/modbus object files (avr-g++ -Os)"
avr-size $objects
slave_sources="rtu_framer rtu_timing slave slave_data slave_diagnostics"
sources="$shared/crc/crc16.cpp"
for s in $slave_sources; do sources="$sources $shared/modbus/$s.cpp"; done
avr-g++ $flags -flto -Wl,--gc-sections "$here/avr_size_main.cpp" $sources -o "$out/slave.elf"
echo "== minimal slave firmware (slave + tiny bank, -flto, --gc-sections)"
avr-size "$out/slave.elf"
