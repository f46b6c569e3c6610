#!/usr/bin/env bash
# Flash and static RAM of the Uno's two gateway images side by side: the
# station (profile "station", mb2co-gateway.elf) and the network gateway
# (profile "network": the station plus FC 2Bh / MEI 0Dh, without node/life
# guarding, FC 08, 0020h-0023h and 1011h; mb2co-gateway-network.elf), and what the
# part has left next to Optiboot. Budgets: size-budgets.txt; which image for
# what: docs/gateway-network.md.
# Usage: firmware/avr/size-with-network.sh   (build dir: build/avr, or MB2CO_AVR_BUILD_DIR)
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
build=${MB2CO_AVR_BUILD_DIR:-build/avr}

cmake -S firmware/avr -B "$build" -G Ninja -DCMAKE_TOOLCHAIN_FILE="$root/cmake/avr-toolchain.cmake" \
  -DCMAKE_BUILD_TYPE=MinSizeRel >/dev/null
cmake --build "$build" --target mb2co-gateway mb2co-gateway-network >/dev/null

kUnoFlash=32256
sizes() {  # flash (text + data) and RAM (data + bss) of an ELF
  avr-size --format=berkeley "$1" | tail -n 1 | awk '{ print $1 + $2, $2 + $3 }'
}
read -r off_flash off_ram < <(sizes "$build/mb2co-gateway.elf")
read -r on_flash on_ram < <(sizes "$build/mb2co-gateway-network.elf")
printf 'mb2co-gateway (station):         %6d B flash %5d B RAM\n' "$off_flash" "$off_ram"
printf 'mb2co-gateway-network (network): %6d B flash %5d B RAM (%+d B flash, %+d B RAM)\n' \
  "$on_flash" "$on_ram" $((on_flash - off_flash)) $((on_ram - off_ram))
printf 'the part holds %d B next to Optiboot: station %+d B, network %+d B\n' "$kUnoFlash" \
  $((kUnoFlash - off_flash)) $((kUnoFlash - on_flash))
