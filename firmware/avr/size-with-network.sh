#!/usr/bin/env bash
# Flash and static RAM of the gateway image with FC 2Bh / MEI 0Dh built in
# (MB2CO_GATEWAY_NET=1, shared/modbus/net_switch.h), next to the shipped image
# without it. The Uno image leaves the function out until it fits the part
# with room to spare (docs/gateway-network.md, "Builds"); this measures the
# gap. Linked against a 64 KiB region so that an image too big for the part
# still links and can be measured (it gets no upload).
# Usage: firmware/avr/size-with-network.sh   (build dirs: build/avr, build/avr-net)
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
shipped=${MB2CO_AVR_BUILD_DIR:-build/avr}
net=${MB2CO_AVR_NET_BUILD_DIR:-build/avr-net}
toolchain=(-G Ninja -DCMAKE_TOOLCHAIN_FILE="$root/cmake/avr-toolchain.cmake" -DCMAKE_BUILD_TYPE=MinSizeRel)

cmake -S firmware/avr -B "$shipped" "${toolchain[@]}" >/dev/null
CXXFLAGS=-DMB2CO_GATEWAY_NET=1 LDFLAGS=-Wl,--defsym=__TEXT_REGION_LENGTH__=0x10000 \
  cmake -S firmware/avr -B "$net" "${toolchain[@]}" >/dev/null
cmake --build "$shipped" --target mb2co-gateway >/dev/null
cmake --build "$net" --target mb2co-gateway >/dev/null

kUnoFlash=32256
sizes() {  # flash (text + data) and RAM (data + bss) of an ELF
  avr-size --format=berkeley "$1" | tail -n 1 | awk '{ print $1 + $2, $2 + $3 }'
}
read -r off_flash off_ram < <(sizes "$shipped/mb2co-gateway.elf")
read -r on_flash on_ram < <(sizes "$net/mb2co-gateway.elf")
printf 'mb2co-gateway without FC 2Bh: %6d B flash %5d B RAM\n' "$off_flash" "$off_ram"
printf 'mb2co-gateway with FC 2Bh:    %6d B flash %5d B RAM (%+d B flash, %+d B RAM)\n' \
  "$on_flash" "$on_ram" $((on_flash - off_flash)) $((on_ram - off_ram))
printf 'the part holds %d B next to Optiboot: %+d B\n' "$kUnoFlash" $((kUnoFlash - on_flash))
