#!/usr/bin/env bash
# Each extra compiler option alone on the Uno network gateway image
# (mb2co-gateway-network.elf, profile "network"): flash, text +
# data, next to the build without any (docs/gateway-network.md, "Why the Uno
# image does not have it yet"). One build per option into a scratch dir.
# Usage: firmware/avr/size-option-sweep.sh [OPTION...]   (default: the list below)
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
options=("$@")
((${#options[@]})) || options=(-finline-limit=20 -finline-limit=5 --param=max-inline-insns-auto=10
  --param=max-inline-insns-single=50 -fno-inline-functions-called-once -fno-ipa-icf -fipa-pta
  -fno-tree-switch-conversion -fno-optimize-sibling-calls -fno-tree-loop-optimize -fno-ipa-sra
  -fno-if-conversion -fno-tree-vrp -fno-reorder-blocks -fno-shrink-wrap -fno-ipa-cp -fno-jump-tables
  -fno-split-wide-types -fno-gcse)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
flash() {  # flash of mb2co-gateway-network built with extra option $1 (may be empty)
  rm -rf "$dir/b"
  CXXFLAGS="$1" CFLAGS="$1" LDFLAGS="-Wl,--defsym=__TEXT_REGION_LENGTH__=0x10000 $1" \
    cmake -S firmware/avr -B "$dir/b" -G Ninja -DCMAKE_TOOLCHAIN_FILE="$root/cmake/avr-toolchain.cmake" \
    -DCMAKE_BUILD_TYPE=MinSizeRel >/dev/null
  if cmake --build "$dir/b" --target mb2co-gateway-network >/dev/null 2>&1; then
    avr-size --format=berkeley "$dir/b/mb2co-gateway-network.elf" | tail -n 1 | awk '{ print $1 + $2 }'
  else
    echo "does not build"
  fi
}
base=$(flash "")
printf '%-40s %s B\n' "(none)" "$base"
for o in "${options[@]}"; do
  printf '%-40s %s\n' "$o" "$(flash "$o")"
done
