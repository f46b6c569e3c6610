#!/usr/bin/env bash
# Runs every test: installs what is missing, builds host and AVR, runs ctest
# (unit, integration on ptys, vcan under user-mode Linux), checks AVR size budgets
# and that the sketches build as the Arduino IDE builds them, runs each
# libFuzzer target briefly.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
scripts/check-format.sh
scripts/build.sh
echo "== AVR build (avr-g++ $(avr-g++ -dumpversion)) and size budgets"
firmware/avr/build-and-check.sh
firmware/avr/check-int16.sh
scripts/check-tidy.sh
echo "== Arduino IDE route: the sketches built by arduino-builder"
firmware/avr/arduino/ide-build.sh
echo "== libFuzzer targets, a fixed short run each (tests/fuzz/run.sh ci; long runs by hand: docs/performance.md)"
tests/fuzz/run.sh ci
echo "== ctest"
ctest --test-dir build --output-on-failure -j"$(nproc)" --timeout 600
