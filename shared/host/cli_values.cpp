#include "host/cli_values.h"

#include <cctype>

namespace mb2co {
namespace cli {
namespace {

/// "12" or "1.25" times `scale` → a whole number; false when not a number,
/// when it has more fraction digits than `scale` can take, or above 2^53.
bool scaled_decimal(const std::string& text, uint64_t scale, uint64_t* out) {
  const size_t dot = text.find('.');
  const std::string whole = text.substr(0, dot);
  const std::string frac = dot == std::string::npos ? "" : text.substr(dot + 1);
  if (whole.empty() || whole.size() > 15 || (dot != std::string::npos && frac.empty())) return false;
  uint64_t v = 0;
  for (const char c : whole) {
    if (c < '0' || c > '9') return false;
    v = v * 10u + static_cast<uint64_t>(c - '0');
  }
  v *= scale;
  uint64_t unit = scale;
  for (const char c : frac) {
    if (c < '0' || c > '9' || unit % 10u != 0) return false;
    unit /= 10u;
    v += unit * static_cast<uint64_t>(c - '0');
  }
  *out = v;
  return true;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

Status parse_bitrate(const std::string& option, const std::string& text, uint32_t min_bps, uint32_t max_bps,
                     uint32_t* bps) {
  std::string digits = text;
  uint64_t scale = 1;
  if (!digits.empty() && (digits.back() == 'k' || digits.back() == 'K')) {
    scale = 1000;
    digits.pop_back();
  } else if (!digits.empty() && digits.back() == 'M') {
    scale = 1000000;
    digits.pop_back();
  }
  uint64_t v = 0;
  if (!scaled_decimal(digits, scale, &v)) {
    return Status::failure(option + " must be a bit rate such as 500k, 1M or 125000 (bit/s), got \"" + text +
                           "\"");
  }
  if (scale == 1 && v < kMinBareBitrate) {
    return Status::failure(option + " must be at least " + std::to_string(kMinBareBitrate) +
                           " as a bare number (bit/s), got \"" + text + "\"; did you mean " + text + "k?");
  }
  if (v < min_bps || v > max_bps) {
    return Status::failure(option + " must be " + bitrate_text(min_bps) + ".." + bitrate_text(max_bps) +
                           " bit/s, got \"" + text + "\"");
  }
  *bps = static_cast<uint32_t>(v);
  return Status::ok();
}

Status parse_bitrate_in(const std::string& option, const std::string& text,
                        const std::vector<uint32_t>& allowed, uint32_t* bps) {
  uint32_t v = 0;
  Status s = parse_bitrate(option, text, 1, UINT32_MAX, &v);
  if (!s) return s;
  for (const uint32_t a : allowed) {
    if (a == v) {
      *bps = v;
      return Status::ok();
    }
  }
  return Status::failure(option + " must be " + bitrates_text(allowed) + ", got \"" + text + "\"");
}

Status parse_bitrate_list(const std::string& option, const std::string& text,
                          const std::vector<uint32_t>& allowed, std::vector<uint32_t>* bps) {
  std::vector<uint32_t> list;
  size_t start = 0;
  for (;;) {
    const size_t comma = text.find(',', start);
    const std::string item =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    uint32_t v = 0;
    Status s = parse_bitrate_in(option, item, allowed, &v);
    if (!s) return s;
    list.push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  *bps = list;
  return Status::ok();
}

std::string bitrate_text(uint32_t bps) {
  if (bps >= 1000000 && bps % 1000000 == 0) return std::to_string(bps / 1000000) + "M";
  if (bps >= 1000 && bps % 100 == 0) {
    std::string s = std::to_string(bps / 1000);
    if (bps % 1000 != 0) s += "." + std::to_string(bps % 1000 / 100);
    return s + "k";
  }
  return std::to_string(bps);
}

std::string bitrates_text(const std::vector<uint32_t>& bps) {
  std::string s;
  for (size_t i = 0; i < bps.size(); ++i) {
    if (i > 0) s += i + 1 == bps.size() ? " or " : ", ";
    s += bitrate_text(bps[i]);
  }
  return s;
}

const std::vector<uint32_t>& can_bitrates() {
  static const std::vector<uint32_t> rates = {125000, 250000, 500000, 1000000};
  return rates;
}

Status parse_parity(const std::string& option, const std::string& text, Parity* parity) {
  const std::string t = lower(text);
  if (t == "n" || t == "none") {
    *parity = Parity::kNone;
  } else if (t == "e" || t == "even") {
    *parity = Parity::kEven;
  } else if (t == "o" || t == "odd") {
    *parity = Parity::kOdd;
  } else {
    return Status::failure(option + " must be N, E or O (none, even, odd), got \"" + text + "\"");
  }
  return Status::ok();
}

char parity_letter(Parity parity) {
  return parity == Parity::kEven ? 'E' : parity == Parity::kOdd ? 'O' : 'N';
}

const char* parity_word(Parity parity) {
  return parity == Parity::kEven ? "even" : parity == Parity::kOdd ? "odd" : "none";
}

Status parse_uint(const std::string& option, const std::string& text, uint64_t min, uint64_t max,
                  uint64_t* value) {
  uint64_t v = 0;
  bool ok = !text.empty() && text.size() <= 19;
  for (const char c : text) ok = ok && c >= '0' && c <= '9';
  if (ok) {
    for (const char c : text) v = v * 10u + static_cast<uint64_t>(c - '0');
  }
  if (!ok || v < min || v > max) {
    return Status::failure(option + " must be a whole number " + std::to_string(min) + ".." +
                           std::to_string(max) + ", got \"" + text + "\"");
  }
  *value = v;
  return Status::ok();
}

Status parse_duration_ms(const std::string& option, const std::string& text, uint64_t min_ms, uint64_t max_ms,
                         uint64_t* ms) {
  struct Unit {
    const char* suffix;
    uint64_t ms;
  };
  // Longest suffixes first: "ms" before "s", "min" before nothing.
  static const Unit kUnits[] = {{"min", 60000}, {"ms", 1}, {"s", 1000}, {"h", 3600000}, {"", 1000}};
  for (const Unit& u : kUnits) {
    const std::string suffix = u.suffix;
    if (text.size() < suffix.size() ||
        text.compare(text.size() - suffix.size(), suffix.size(), suffix) != 0) {
      continue;
    }
    uint64_t v = 0;
    if (!scaled_decimal(text.substr(0, text.size() - suffix.size()), u.ms, &v)) break;
    if (v < min_ms || v > max_ms) break;
    *ms = v;
    return Status::ok();
  }
  return Status::failure(option + " must be a duration " + duration_text(min_ms) + ".." +
                         duration_text(max_ms) + " (seconds, or with a unit: 250ms, 1.5s, 2min), got \"" +
                         text + "\"");
}

std::string duration_text(uint64_t ms) {
  if (ms % 1000 != 0) {
    if (ms < 1000) return std::to_string(ms) + " ms";
    std::string frac = std::to_string(ms % 1000 + 1000).substr(1);
    while (frac.back() == '0') frac.pop_back();
    return std::to_string(ms / 1000) + "." + frac + " s";
  }
  return std::to_string(ms / 1000) + " s";
}

}  // namespace cli
}  // namespace mb2co
