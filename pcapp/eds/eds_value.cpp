#include "eds_value.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "host/status.h"

namespace mb2co {
namespace eds {

namespace {

bool ieq_prefix(std::string_view s, std::string_view prefix) {
  if (s.size() < prefix.size()) return false;
  for (size_t i = 0; i < prefix.size(); ++i) {
    char c = s[i];
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
    if (c != prefix[i]) return false;
  }
  return true;
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

int digit_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return 99;
}

/// Digits of one base into a uint64; fails on a bad digit, none, or overflow.
Status parse_digits(std::string_view s, unsigned base, uint64_t* out) {
  if (s.empty()) return Status::failure("a number without digits");
  uint64_t v = 0;
  for (const char c : s) {
    const int d = digit_value(c);
    if (d >= static_cast<int>(base)) {
      return Status::failure(base == 8
                                 ? "'" + std::string(1, c) + "' in an octal number (a leading 0 means octal)"
                             : base == 16 ? "'" + std::string(1, c) + "' in a hexadecimal number"
                                          : "not a number");
    }
    if (v > (UINT64_MAX - static_cast<uint64_t>(d)) / base) return Status::failure("a number beyond 64 bits");
    v = v * base + static_cast<uint64_t>(d);
  }
  *out = v;
  return Status::ok();
}

/// CiA 306 integer literal without sign: 0x hex, leading-0 octal, decimal.
Status parse_magnitude(std::string_view s, uint64_t* out) {
  if (s.size() >= 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) return parse_digits(s.substr(2), 16, out);
  if (s.size() >= 2 && s[0] == '0') return parse_digits(s.substr(1), 8, out);
  return parse_digits(s, 10, out);
}

struct Range {
  bool is_signed;
  int64_t min;  // signed types
  int64_t max;
  uint64_t umax;  // unsigned types
};

Range range_of(const TypeInfo& t) {
  Range r{false, 0, 0, 0};
  const unsigned bits = t.kind == ValueKind::kBoolean ? 1u : t.bytes * 8u;
  if (t.kind == ValueKind::kSigned) {
    r.is_signed = true;
    r.max = bits == 64 ? INT64_MAX : static_cast<int64_t>((uint64_t{1} << (bits - 1)) - 1);
    r.min = -r.max - 1;
  } else {
    r.umax = bits == 64 ? UINT64_MAX : (uint64_t{1} << bits) - 1;
  }
  return r;
}

void put_le(uint64_t v, uint8_t bytes, Value* out) {
  out->bytes.resize(bytes);
  for (uint8_t i = 0; i < bytes; ++i) out->bytes[i] = static_cast<uint8_t>(v >> (8 * i));
}

uint64_t get_le(const std::vector<uint8_t>& b) {
  uint64_t v = 0;
  for (size_t i = 0; i < b.size() && i < 8; ++i) v |= static_cast<uint64_t>(b[i]) << (8 * i);
  return v;
}

int64_t get_signed(const std::vector<uint8_t>& b) {
  const uint64_t v = get_le(b);
  const size_t n = b.size() < 8 ? b.size() : 8;
  if (n == 0 || n == 8) return static_cast<int64_t>(v);
  const uint64_t sign = uint64_t{1} << (8 * n - 1);
  return static_cast<int64_t>((v ^ sign) - sign);  // sign-extend
}

std::string hex_text(uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "0x%llX", static_cast<unsigned long long>(v));
  return buf;
}

/// Signed value `negative ? -mag : mag` within `r`, as two's complement.
bool fit(const Range& r, bool negative, uint64_t mag, uint64_t* out) {
  if (r.is_signed) {
    if (negative) {
      if (mag > static_cast<uint64_t>(r.max) + 1) return false;
      *out = ~mag + 1;
      return true;
    }
    if (mag > static_cast<uint64_t>(r.max)) return false;
    *out = mag;
    return true;
  }
  if (negative && mag != 0) return false;
  if (mag > r.umax) return false;
  *out = mag;
  return true;
}

ValueResult fail(std::string why) {
  ValueResult r;
  r.error = std::move(why);
  return r;
}

ValueResult ok(Value v) {
  ValueResult r;
  r.value = std::move(v);
  return r;
}

ValueResult parse_integer(const TypeInfo& t, std::string_view text, std::optional<uint8_t> node_id) {
  const Range range = range_of(t);
  // $NODEID, $NODEID+N, N+$NODEID
  const size_t at = [&] {
    for (size_t i = 0; i + 7 <= text.size(); ++i) {
      if (ieq_prefix(text.substr(i), "$NODEID")) return i;
    }
    return std::string_view::npos;
  }();
  if (at != std::string_view::npos) {
    std::string_view rest;
    if (at == 0) {
      rest = trim(text.substr(7));
      if (!rest.empty()) {
        if (rest[0] != '+') return fail("expected '+' after $NODEID");
        rest = trim(rest.substr(1));
        if (rest.empty()) return fail("a number missing after '$NODEID+'");
      }
    } else {
      if (!trim(text.substr(at + 7)).empty()) return fail("text after $NODEID in 'N+$NODEID'");
      rest = trim(text.substr(0, at));
      if (rest.empty() || rest.back() != '+') return fail("expected '+' before $NODEID");
      rest = trim(rest.substr(0, rest.size() - 1));
      if (rest.empty()) return fail("a number missing before '+$NODEID'");
    }
    uint64_t base = 0;
    if (!rest.empty()) {
      const Status parsed = parse_magnitude(rest, &base);
      if (!parsed) return fail(parsed.message());
    }
    Value v;
    uint64_t bits = 0;
    if (node_id) {
      if (base > UINT64_MAX - *node_id || !fit(range, false, base + *node_id, &bits)) {
        return fail("$NODEID+" + hex_text(base) + " with node id " + std::to_string(*node_id) +
                    " is out of range for " + t.name);
      }
    } else {
      if (base > UINT64_MAX - 127 || !fit(range, false, base + 127, &bits) ||
          !fit(range, false, base, &bits)) {
        return fail("$NODEID+" + hex_text(base) + " is out of range for " + t.name +
                    " with node ids up to 127");
      }
      v.node_id_relative = true;
    }
    put_le(bits, t.bytes, &v);
    return ok(v);
  }
  std::string_view digits = text;
  bool negative = false;
  if (!digits.empty() && (digits[0] == '-' || digits[0] == '+')) {
    negative = digits[0] == '-';
    digits.remove_prefix(1);
  }
  if (digits.empty()) return fail("an empty value for " + std::string(t.name));
  uint64_t mag = 0;
  const Status parsed = parse_magnitude(digits, &mag);
  if (!parsed) return fail(parsed.message());
  uint64_t bits = 0;
  if (!fit(range, negative, mag, &bits)) {
    return fail("'" + std::string(text) + "' is out of range for " + t.name);
  }
  Value v;
  put_le(bits, t.bytes, &v);
  return ok(v);
}

template <class F>
ValueResult parse_real(const TypeInfo& t, std::string_view text) {
  F f = 0;
  const char* end = text.data() + text.size();
  const auto res = std::from_chars(text.data(), end, f, std::chars_format::general);
  if (res.ec == std::errc::result_out_of_range)
    return fail("'" + std::string(text) + "' is out of range for " + t.name);
  if (res.ec != std::errc() || res.ptr != end)
    return fail("'" + std::string(text) + "' is not a decimal number");
  if (!std::isfinite(f)) return fail("'" + std::string(text) + "' is not a finite number");
  Value v;
  v.bytes.resize(sizeof f);
  std::memcpy(v.bytes.data(), &f, sizeof f);  // little-endian host, as the bus
  return ok(v);
}

ValueResult parse_hex_bytes(const TypeInfo& t, std::string_view text) {
  Value v;
  int high = -1;
  for (const char c : text) {
    if (c == ' ') continue;
    const int d = digit_value(c);
    if (d > 15) return fail(std::string("'") + c + "' in the hex dump of a " + t.name);
    if (high < 0) {
      high = d;
    } else {
      v.bytes.push_back(static_cast<uint8_t>(high * 16 + d));
      high = -1;
    }
  }
  if (high >= 0) return fail(std::string("an odd number of hex digits in a ") + t.name);
  if (t.type == DataType::kUnicodeString && v.bytes.size() % 2 != 0) {
    return fail("a UNICODE_STRING of an odd number of bytes (UTF-16 units are 2 bytes)");
  }
  return ok(v);
}

}  // namespace

std::optional<uint64_t> parse_unsigned(std::string_view text, uint64_t max) {
  uint64_t v = 0;
  if (text.empty() || !parse_magnitude(text, &v) || v > max) return std::nullopt;
  return v;
}

ValueResult parse_value(DataType type, std::string_view text, std::optional<uint8_t> node_id) {
  const TypeInfo* t = type_info(static_cast<uint16_t>(type));
  if (t == nullptr) return fail("unknown data type");
  text = trim(text);
  const bool has_nodeid = [&] {
    for (size_t i = 0; i + 7 <= text.size(); ++i) {
      if (ieq_prefix(text.substr(i), "$NODEID")) return true;
    }
    return false;
  }();
  if (has_nodeid && t->kind != ValueKind::kSigned && t->kind != ValueKind::kUnsigned &&
      t->kind != ValueKind::kBoolean && t->kind != ValueKind::kVisibleString) {
    return fail(std::string("$NODEID in a value of type ") + t->name);
  }
  switch (t->kind) {
    case ValueKind::kBoolean:
    case ValueKind::kSigned:
    case ValueKind::kUnsigned:
      return parse_integer(*t, text, node_id);
    case ValueKind::kReal:
      return t->bytes == 4 ? parse_real<float>(*t, text) : parse_real<double>(*t, text);
    case ValueKind::kVisibleString: {
      Value v;
      for (const char c : text) {
        const auto u = static_cast<unsigned char>(c);
        if (u < 0x20 || u > 0x7E)
          return fail("a VISIBLE_STRING holds printable ASCII only (byte " + hex_text(u) + ")");
        v.bytes.push_back(u);
      }
      return ok(v);
    }
    case ValueKind::kHexBytes:
      return parse_hex_bytes(*t, text);
  }
  return fail("unknown data type");
}

std::string format_value(DataType type, const Value& value) {
  const TypeInfo* t = type_info(static_cast<uint16_t>(type));
  if (t == nullptr) return "";
  switch (t->kind) {
    case ValueKind::kBoolean:
    case ValueKind::kUnsigned:
      return (value.node_id_relative ? "$NODEID+" : "") + hex_text(get_le(value.bytes));
    case ValueKind::kSigned: {
      const int64_t v = get_signed(value.bytes);
      return (value.node_id_relative ? "$NODEID+" : "") + std::to_string(v);
    }
    case ValueKind::kReal: {
      char buf[64];
      std::to_chars_result res{};
      if (t->bytes == 4 && value.bytes.size() == 4) {
        float f = 0;
        std::memcpy(&f, value.bytes.data(), 4);
        res = std::to_chars(buf, buf + sizeof buf, f);
      } else if (value.bytes.size() == 8) {
        double d = 0;
        std::memcpy(&d, value.bytes.data(), 8);
        res = std::to_chars(buf, buf + sizeof buf, d);
      } else {
        return "";
      }
      return std::string(buf, res.ptr);
    }
    case ValueKind::kVisibleString:
      return std::string(value.bytes.begin(), value.bytes.end());
    case ValueKind::kHexBytes: {
      static const char digits[] = "0123456789ABCDEF";
      std::string s;
      for (const uint8_t b : value.bytes) {
        s += digits[b >> 4];
        s += digits[b & 15];
      }
      return s;
    }
  }
  return "";
}

std::optional<Value> resolve(DataType type, const Value& value, uint8_t node_id) {
  if (!value.node_id_relative) return value;
  const TypeInfo* t = type_info(static_cast<uint16_t>(type));
  if (t == nullptr ||
      (t->kind != ValueKind::kSigned && t->kind != ValueKind::kUnsigned && t->kind != ValueKind::kBoolean)) {
    return std::nullopt;
  }
  const Range range = range_of(*t);
  uint64_t bits = 0;
  if (range.is_signed) {
    const int64_t base = get_signed(value.bytes);
    if (base > range.max - node_id) return std::nullopt;
    const int64_t sum = base + node_id;
    if (!fit(range, sum < 0, sum < 0 ? ~static_cast<uint64_t>(sum) + 1 : static_cast<uint64_t>(sum), &bits)) {
      return std::nullopt;
    }
  } else {
    const uint64_t base = get_le(value.bytes);
    if (base > UINT64_MAX - node_id || !fit(range, false, base + node_id, &bits)) return std::nullopt;
  }
  Value v;
  put_le(bits, t->bytes, &v);
  return v;
}

std::optional<int> compare_values(DataType type, const Value& a, const Value& b) {
  const TypeInfo* t = type_info(static_cast<uint16_t>(type));
  if (t == nullptr || a.node_id_relative || b.node_id_relative) return std::nullopt;
  switch (t->kind) {
    case ValueKind::kBoolean:
    case ValueKind::kUnsigned: {
      const uint64_t x = get_le(a.bytes), y = get_le(b.bytes);
      return x < y ? -1 : x > y ? 1 : 0;
    }
    case ValueKind::kSigned: {
      const int64_t x = get_signed(a.bytes), y = get_signed(b.bytes);
      return x < y ? -1 : x > y ? 1 : 0;
    }
    case ValueKind::kReal: {
      if (a.bytes.size() != t->bytes || b.bytes.size() != t->bytes) return std::nullopt;
      double x = 0, y = 0;
      if (t->bytes == 4) {
        float fx = 0, fy = 0;
        std::memcpy(&fx, a.bytes.data(), 4);
        std::memcpy(&fy, b.bytes.data(), 4);
        x = fx;
        y = fy;
      } else {
        std::memcpy(&x, a.bytes.data(), 8);
        std::memcpy(&y, b.bytes.data(), 8);
      }
      return x < y ? -1 : x > y ? 1 : 0;
    }
    case ValueKind::kVisibleString:
    case ValueKind::kHexBytes:
      return std::nullopt;
  }
  return std::nullopt;
}

ValueResult parse_value_for(const SubObject& sub, std::string_view text, std::optional<uint8_t> node_id) {
  ValueResult r = parse_value(sub.type, text, node_id);
  if (!r.value || r.value->node_id_relative) return r;
  const auto limit = [&](const std::optional<Value>& l) -> std::optional<Value> {
    if (!l) return std::nullopt;
    return node_id ? resolve(sub.type, *l, *node_id) : *l;
  };
  const std::optional<Value> low = limit(sub.low_limit), high = limit(sub.high_limit);
  if (low && compare_values(sub.type, *r.value, *low).value_or(0) < 0) {
    return fail("'" + std::string(trim(text)) + "' is below the LowLimit " + format_value(sub.type, *low));
  }
  if (high && compare_values(sub.type, *r.value, *high).value_or(0) > 0) {
    return fail("'" + std::string(trim(text)) + "' is above the HighLimit " + format_value(sub.type, *high));
  }
  return r;
}

std::optional<Value> configured_value(const SubObject& sub, uint8_t node_id) {
  const std::optional<Value>& v = sub.parameter_value ? sub.parameter_value : sub.default_value;
  if (!v) return std::nullopt;
  return resolve(sub.type, *v, node_id);
}

}  // namespace eds
}  // namespace mb2co
