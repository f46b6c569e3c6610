#!/bin/bash
# The table of docs/cli.md, made by running every program of a build tree:
# --help's exit status, --version's output, a usage error's exit status, and
# whether "--bitrate 500k" (mb2co-lab: --bitrates) is accepted.
#
# Usage: tests/cli/cli_table.sh BUILD_DIR            print the table
#        tests/cli/cli_table.sh BUILD_DIR --check DOC  exit 1 (and a diff) when DOC's table differs
#        tests/cli/cli_table.sh BUILD_DIR --write DOC  replace DOC's table
# The table stands in DOC between the lines "<!-- cli-table begin -->" and
# "<!-- cli-table end -->". No program is started for real: every probe ends
# in an unknown option (or is --help/--version), each under a 20 s timeout.
set -euo pipefail

[[ $# == 1 || $# == 3 ]] || { echo "usage: cli_table.sh BUILD_DIR [--check|--write DOC]" >&2; exit 2; }
build=$1
src=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
probe=--no-such-option

# name|executable|words before the options (a subcommand)
programs=(
  "mb2co-timing|$build/pcapp/timing/mb2co-timing|frame"
  "mb2co-lab|$build/hil/lab/mb2co-lab|"
  "mb2co-od|$build/pcapp/odtool/mb2co-od|"
  "mb2co-uno|$build/hil/uno/mb2co-uno|"
  "mb2co-plant|$build/pcapp/plant/mb2co-plant|"
  "mb2co-master|$build/pcapp/master/mb2co-master|"
  "mb2co-node|$build/firmware/linux/node/mb2co-node|"
  "mb2co-bridge|$build/firmware/linux/bridge/mb2co-bridge|"
  "mb2co-serial-io-node|$build/firmware/linux/bridge/mb2co-serial-io-node|"
  "mb2co-serial-hub|$build/firmware/linux/bridge/mb2co-serial-hub|"
  "mb2co-demo|$build/hil/demo/mb2co-demo|"
  "run-with-vcan.sh|$src/hil/uml/run-with-vcan.sh|"
)

out=$(mktemp) err=$(mktemp)
trap 'rm -f "$out" "$err"' EXIT

# Runs the program; sets $rc, fills $out and $err.
run() {
  rc=0
  QT_QPA_PLATFORM=offscreen timeout 20 "$@" >"$out" 2>"$err" </dev/null || rc=$?
}

# First line of a file, '|' escaped for a Markdown cell.
first_line() { head -n1 "$1" | sed 's/|/\\|/g'; }

table() {
  echo "| program | \`--help\` exit | \`--version\` prints | usage error exit | \`--bitrate 500k\` |"
  echo "|---|---|---|---|---|"
  local entry name exe sub words help_rc version usage_rc bitrate option
  for entry in "${programs[@]}"; do
    IFS='|' read -r name exe sub <<<"$entry"
    if [[ ! -x $exe ]]; then
      echo "cli_table: $exe not built" >&2
      exit 1
    fi
    words=()
    [[ -z $sub ]] || words=("$sub")
    run "$exe" "${words[@]}" --help
    help_rc=$rc
    option=""
    if grep -q -- '--bitrate[ =]' "$out"; then
      option=--bitrate
    elif grep -q -- '--bitrates[ =]' "$out"; then
      option=--bitrates
    fi
    run "$exe" --version
    if ((rc == 0)); then version="\`$(first_line "$out")\`"; else version="exit $rc: $(first_line "$err")"; fi
    run "$exe" "${words[@]}" "$probe"
    usage_rc=$rc
    if [[ -z $option ]]; then
      bitrate="no bit rate option"
    else
      run "$exe" "${words[@]}" "$option" 500k "$probe"
      if grep -q -- "$probe" "$err"; then
        bitrate="accepted"
      else
        bitrate="refused: $(first_line "$err")"
      fi
      [[ $option == --bitrate ]] || bitrate="$bitrate (\`$option 500k\`)"
    fi
    echo "| $name${sub:+ $sub} | $help_rc | $version | $usage_rc | $bitrate |"
  done
}

[[ $# == 3 ]] || { table; exit 0; }
mode=$2 doc=$3
begin="<!-- cli-table begin -->" end="<!-- cli-table end -->"
if ! grep -qx "$begin" "$doc" || ! grep -qx "$end" "$doc"; then
  echo "cli_table: no $begin/$end lines in $doc" >&2
  exit 2
fi
new=$(mktemp)
trap 'rm -f "$out" "$err" "$new"' EXIT
{
  sed "/^$begin\$/q" "$doc"
  table
  sed -n "/^$end\$/,\$p" "$doc"
} >"$new"
case $mode in
  --write) cp "$new" "$doc" ;;
  --check)
    diff -u "$doc" "$new" || {
      echo "cli_table: $doc is not what the programs do; regenerate: tests/cli/cli_table.sh $build --write $doc" >&2
      exit 1
    }
    ;;
  *) echo "usage: cli_table.sh BUILD_DIR [--check|--write DOC]" >&2; exit 2 ;;
esac
