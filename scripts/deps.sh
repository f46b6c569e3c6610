#!/usr/bin/env bash
# Installs the Debian packages mb2co needs, only those missing.
# Usage: scripts/deps.sh            (sourced by demo.sh and test.sh)
set -euo pipefail

MB2CO_PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libgtest-dev libgmock-dev libbenchmark-dev valgrind
  gcc-avr avr-libc binutils-avr arduino-core-avr avrdude arduino-builder
  simavr libsimavr-dev libelf-dev clang-tidy clang-tools clang clang-format libclang-rt-14-dev
  libmodbus-dev mbpoll python3-pymodbus python3-serial-asyncio
  qt6-base-dev qt6-serialport-dev
  user-mode-linux can-utils python3-can iproute2 kmod
)

missing=()
for p in "${MB2CO_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "mb2co: installing missing Debian packages: ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
