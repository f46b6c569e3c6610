#!/usr/bin/env bash
# Installs the Debian packages mb2co needs, only those missing, and npm's
# canopen peer of tests/peers (see the end).
# Usage: scripts/deps.sh            (sourced by demo.sh and test.sh)
set -euo pipefail

MB2CO_PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libgtest-dev libgmock-dev libbenchmark-dev valgrind
  gcc-avr avr-libc binutils-avr arduino-core-avr avrdude arduino-builder
  simavr libsimavr-dev libelf-dev clang-tidy clang-tools clang clang-format libclang-rt-14-dev
  libmodbus-dev mbpoll python3-pymodbus python3-serial-asyncio liburing-dev
  qt6-base-dev qt6-serialport-dev
  user-mode-linux can-utils python3-can iproute2 kmod
  make g++ python3  # node-gyp, for the npm peer's native modules
)
# Node.js and npm: the machine's own (nodesource's nodejs carries npm and the
# headers); without one, Debian's.
command -v node >/dev/null && command -v npm >/dev/null || MB2CO_PACKAGES+=(nodejs npm libnode-dev)

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

# npm's canopen as an independent CANopen peer (tests/peers): the versions
# pinned by tests/peers/npm/package-lock.json, installed into its
# node_modules with the native builds of socketcan and node-crc (node-gyp;
# npm 11 runs only the install scripts package.json's allowScripts names).
# Skipped when what is installed matches the lock file and this Node.js.
peer_dir=$(cd "$(dirname "$0")/.." && pwd)/tests/peers/npm
peer_stamp=$peer_dir/node_modules/.mb2co-installed
peer_signature() {
  {
    node --version
    node -p 'process.versions.modules'
    cat "$peer_dir/package.json" "$peer_dir/package-lock.json"
  } | sha256sum | cut -d' ' -f1
}
peer_loads() {
  (cd "$peer_dir" && node -e 'require("canopen"); require("socketcan"); require("node-crc")') >/dev/null 2>&1
}
if [ -f "$peer_stamp" ] && [ "$(cat "$peer_stamp")" = "$(peer_signature)" ] && peer_loads; then
  : # installed and matching
else
  echo "mb2co: installing npm's canopen peer into $peer_dir/node_modules"
  # The distribution's Node.js headers (nodesource's nodejs and Debian's
  # libnode-dev put them in /usr/include/node) spare node-gyp a download.
  if [ -f /usr/include/node/node_api.h ] && [ -f /usr/include/node/common.gypi ]; then
    export npm_config_nodedir=/usr
  fi
  rm -f "$peer_stamp"
  (cd "$peer_dir" && npm ci --no-audit --no-fund --loglevel=error)
  peer_loads || {
    echo "mb2co: npm's canopen peer installed but does not load (native builds?)" >&2
    exit 1
  }
  peer_signature >"$peer_stamp"
fi
