// The value parsers every program's command line shares (docs/cli.md): bit
// rates, parity, unsigned ranges and durations. Host-only. Each failure is one
// line naming the option and what it accepts, without the program's prefix;
// a bad value is a usage error (exit 2).
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "host/status.h"
#include "modbus/parity.h"

namespace mb2co {
namespace cli {

/// Bare bit rates below this are refused: "--bitrate 500" was 500 bit/s in one
/// program and 500 kbit/s in others; a CAN bit rate is never that low.
constexpr uint32_t kMinBareBitrate = 10000;

/// "500k", "500000", "1M", "1000k", "62.5k" → bit/s in [min_bps, max_bps].
/// A bare number below kMinBareBitrate is refused with "did you mean 500k?".
Status parse_bitrate(const std::string& option, const std::string& text, uint32_t min_bps, uint32_t max_bps,
                     uint32_t* bps);
/// As parse_bitrate, and the rate must be one of `allowed` (bit/s, not empty).
Status parse_bitrate_in(const std::string& option, const std::string& text,
                        const std::vector<uint32_t>& allowed, uint32_t* bps);
/// "125k,1M" → each as parse_bitrate_in, in the order given.
Status parse_bitrate_list(const std::string& option, const std::string& text,
                          const std::vector<uint32_t>& allowed, std::vector<uint32_t>* bps);
/// 500000 → "500k", 1000000 → "1M", 62500 → "62.5k", 12345 → "12345".
std::string bitrate_text(uint32_t bps);
/// "125k, 250k, 500k or 1M".
std::string bitrates_text(const std::vector<uint32_t>& bps);
/// The CAN bit rates the gateways support (CiA 301 table), bit/s.
const std::vector<uint32_t>& can_bitrates();

/// N, E, O, none, even, odd in any letter case.
Status parse_parity(const std::string& option, const std::string& text, modbus::Parity* parity);
/// "none", "even" or "odd" (the letter: modbus::parity_letter).
const char* parity_word(modbus::Parity parity);

/// Decimal digits only, within [min, max].
Status parse_uint(const std::string& option, const std::string& text, uint64_t min, uint64_t max,
                  uint64_t* value);

/// "30" or "30s" (seconds), "250ms", "1.5s", "2min", "1h" → milliseconds
/// within [min_ms, max_ms]; a bare number is seconds.
Status parse_duration_ms(const std::string& option, const std::string& text, uint64_t min_ms, uint64_t max_ms,
                         uint64_t* ms);
/// 1500 → "1.5 s", 250 → "250 ms", 120000 → "120 s".
std::string duration_text(uint64_t ms);

}  // namespace cli
}  // namespace mb2co
