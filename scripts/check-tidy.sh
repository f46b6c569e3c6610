#!/usr/bin/env bash
# clang-tidy (.clang-tidy: bugprone-*, performance-*, a few misc/readability
# checks, warnings are errors) over our host sources: the portable core, the host
# Linux ports, pcapp/ and hil/, with the host build's compile_commands.json
# (scripts/build.sh makes it). The files are those git tracks, so Qt's moc
# and autogen sources in build/ are never checked (they are not ours).
# Exit 1 on any finding.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-tidy >/dev/null || { echo "check-tidy: clang-tidy not found (apt-get install clang-tidy)" >&2; exit 1; }
[ -f build/compile_commands.json ] || { echo "check-tidy: run scripts/build.sh first (build/compile_commands.json)" >&2; exit 1; }
mapfile -t files < <(git ls-files 'shared/*.cpp' 'host/*.cpp' 'firmware/linux/*.cpp' 'pcapp/*.cpp' 'hil/*.cpp')
out=$(printf '%s\n' "${files[@]}" | xargs -P "$(nproc)" -n 4 clang-tidy -p build --quiet 2>/dev/null || true)
if grep -qE "(error|warning): " <<<"$out"; then
  grep -E "(error|warning): " <<<"$out" | sort -u >&2
  exit 1
fi
echo "check-tidy: ${#files[@]} sources of shared/, host/, firmware/linux/, pcapp/ and hil/, no findings"
