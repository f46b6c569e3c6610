#!/usr/bin/env bash
# Every C++ source of ours is laid out as .clang-format says (clang-format
# from Debian's clang-format package). Lists the files that are not and
# exits 1; `clang-format -i FILE` lays one out. The OD lists are tables and
# say "clang-format off" themselves.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format >/dev/null || { echo "check-format: clang-format not found (apt-get install clang-format)" >&2; exit 1; }
bad=()
while IFS= read -r f; do
  clang-format --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done < <(git ls-files '*.cpp' '*.h')
if ((${#bad[@]})); then
  echo "check-format: not laid out as .clang-format says (clang-format -i FILE):" >&2
  printf '  %s\n' "${bad[@]}" >&2
  exit 1
fi
echo "check-format: $(git ls-files '*.cpp' '*.h' | wc -l) C++ files laid out as .clang-format says"
