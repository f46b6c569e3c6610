#!/usr/bin/env bash
# On the AVR an int is 16 bits: `uint16_t ms * 1000u` is computed in 16 bits
# and wraps before it is widened, where the host (32-bit int) is right, so no
# host test sees it (a 100 ms TPDO event timer fired every 34.5 ms on the Uno
# this way). This checks every source built for the AVR for the AVR target
# (int = 16 bits there too):
#  * clang-tidy: a multiplication widened after it was computed in int
#    (bugprone-implicit-widening-of-multiplication-result); a sum, difference,
#    product or shift computed in 16 bits and then widened by a cast, an
#    initialisation, an assignment, a return, an argument or a comparison
#    (bugprone-misplaced-widening-cast with CheckImplicitCasts: it works out
#    the bits the operands can need, so `0x600u + node_id` passes);
#  * clang's warnings, which clang-tidy shows only when named: signed/unsigned
#    compares that only the AVR has (int16_t < uint16_t is an unsigned compare
#    there), unsigned results compared with 0 (`a - b < 0` with uint16_t a, b
#    is never true on the AVR), `1 << 15` (negative there), shift counts past
#    the width, constants that overflow or do not fit;
#  * clang-query: 16-bit +, -, *, << as an operand of 32-bit arithmetic
#    (`now_us + (a - b)`, `t32 += a - b`, `x32 / (a + b)`), which the checks
#    above do not look at.
# Not covered: 16-bit overflow that stays 16-bit (`(n + 7) / 8` for n near
# 65535), and time spans: deadlines for time_reached() must be < 2^31 us.
# Run from anywhere; scripts/test.sh calls it. Exit 1 on any finding.
set -euo pipefail
cd "$(dirname "$0")/../.."
command -v clang-tidy >/dev/null || { echo "check-int16: clang-tidy not found (apt-get install clang-tidy)" >&2; exit 1; }
# clang-query comes with clang-tidy (Debian's clang-tidy-14 depends on clang-tools-14).
query=$(command -v clang-query || command -v clang-query-14 || echo /usr/lib/llvm-14/bin/clang-query)
[[ -x $query ]] || { echo "check-int16: clang-query not found (apt-get install clang-tools)" >&2; exit 1; }
arduino=/usr/share/arduino/hardware/arduino/avr
sources=(shared/crc/*.cpp shared/canopen/*.cpp shared/modbus/*.cpp shared/gateway/*.cpp shared/ionode/*.cpp
         shared/mcp2515/*.cpp firmware/avr/port/*.cpp firmware/avr/sketches/*/*.cpp)
# The network profile: its image compiles the most code (FC 2Bh/0Dh).
flags=(--target=avr -mmcu=atmega328p -std=gnu++14 -fno-exceptions -fno-rtti -Wall -Wextra
       -Wshift-sign-overflow -Wtautological-unsigned-zero-compare
       -Ishared/profiles/network -Ishared -Ishared/mcp2515 -Ifirmware/avr -I"$arduino/cores/arduino" -I"$arduino/variants/standard"
       -isystem /usr/lib/avr/include -D__AVR_ATmega328P__ -DF_CPU=16000000L -DARDUINO=10819)
checks='-*,bugprone-implicit-widening-of-multiplication-result,bugprone-misplaced-widening-cast'
for w in sign-compare tautological-unsigned-zero-compare tautological-constant-out-of-range-compare \
         shift-sign-overflow shift-count-overflow shift-count-negative integer-overflow constant-conversion; do
  checks+=",clang-diagnostic-$w"
done
config='{CheckOptions: [{key: bugprone-misplaced-widening-cast.CheckImplicitCasts, value: true}]}'
narrow='hasType(hasCanonicalType(anyOf(asString("int"), asString("unsigned int"))))'
wide='binaryOperator(unless(hasOperatorName("=")), hasType(hasCanonicalType(anyOf(asString("long"), asString("unsigned long")))))'
matcher="binaryOperator(hasAnyOperatorName(\"+\",\"-\",\"*\",\"<<\"), $narrow,
  unless(hasLHS(ignoringParenImpCasts(integerLiteral()))),
  hasParent(expr(anyOf(implicitCastExpr(hasParent($wide)), parenExpr(hasParent(implicitCastExpr(hasParent($wide))))))))"
export checks config query matcher
# One line per finding, "file:line:col: warning: ... [name]", from both tools.
check_one() {
  clang-tidy -quiet -checks="$checks" -config="$config" "$1" -- "${@:2}" 2>&1 | grep -E '(warning|error):' || true
  { "$query" -c 'set output diag' -c "match $matcher" "$1" -- "${@:2}" 2>&1 || true; } |  # 1: no match
    sed -nE 's/^(.*): note: "root" binds here$/\1: warning: 16-bit int arithmetic as an operand of 32-bit arithmetic [int16-arith-in-long]/p; /: error:|^Error|Error (parsing|building)/p'
}
export -f check_one
# Self-test: one hazard of each kind must be found (a tool that silently
# matches nothing would pass every source).
canary=$(mktemp --suffix=.cpp)
trap 'rm -f "$canary"' EXIT
cat >"$canary" <<'CANARY'
#include <stdint.h>
uint32_t mul(uint16_t ms) { return ms * 1000u; }
uint32_t shl(uint16_t x) { return x << 4; }
bool cmp(int16_t a, uint16_t b) { return a < b; }
uint32_t add(uint32_t now_us, uint16_t a, uint16_t b) { return now_us + (a - b); }
CANARY
found=$(check_one "$canary" "${flags[@]}" | grep -oE '\[[a-z0-9-]+\]$' | sort -u | tr -d '[]' | tr '\n' ' ')
if [[ $found != "bugprone-implicit-widening-of-multiplication-result bugprone-misplaced-widening-cast clang-diagnostic-sign-compare int16-arith-in-long " ]]; then
  echo "check-int16: the self-test found ${found:-nothing }instead of its four kinds (clang-tidy or clang-query not working as expected)" >&2
  exit 1
fi
report=$(printf '%s\n' "${sources[@]}" | xargs -P "$(nproc)" -I{} bash -c 'check_one "$@"' _ {} "${flags[@]}" | sort -u)
if [[ -n $report ]]; then
  echo "$report"
  echo "check-int16: $(wc -l <<<"$report") finding(s) in code built for the AVR (16-bit int): widen an operand before the operation" >&2
  exit 1
fi
echo "check-int16: ${#sources[@]} AVR sources, no 16-bit int hazards"
