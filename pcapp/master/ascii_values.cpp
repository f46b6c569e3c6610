#include "ascii_values.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

namespace mb2co {
namespace master {
namespace ascii {

namespace {

struct TypeRow {
  DataType type;
  const char* word;
  uint8_t size;
};
const TypeRow kTypes[] = {
    {DataType::kHex, "hex", 0},
    {DataType::kBoolean, "b", 1},
    {DataType::kI8, "i8", 1},
    {DataType::kI16, "i16", 2},
    {DataType::kI32, "i32", 4},
    {DataType::kI64, "i64", 8},
    {DataType::kU8, "u8", 1},
    {DataType::kU16, "u16", 2},
    {DataType::kU32, "u32", 4},
    {DataType::kU64, "u64", 8},
    {DataType::kX8, "x8", 1},
    {DataType::kX16, "x16", 2},
    {DataType::kX32, "x32", 4},
    {DataType::kX64, "x64", 8},
    {DataType::kR32, "r32", 4},
    {DataType::kR64, "r64", 8},
    {DataType::kVisibleString, "vs", 0},
    {DataType::kOctetString, "os", 0},
    {DataType::kUnicodeString, "us", 0},
    {DataType::kDomain, "d", 0},
};

const TypeRow& row_of(DataType t) {
  for (const TypeRow& r : kTypes)
    if (r.type == t) return r;
  return kTypes[0];
}

const char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

int base64_digit(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

uint64_t le_value(const uint8_t* p, size_t n) {
  uint64_t v = 0;
  for (size_t i = n; i-- > 0;) v = v << 8 | p[i];
  return v;
}

void put_le(uint64_t v, size_t n, std::vector<uint8_t>* out) {
  out->clear();
  for (size_t i = 0; i < n; ++i) out->push_back(static_cast<uint8_t>(v >> (8 * i)));
}

/// Sign-extends the low `bytes` bytes of `v`.
int64_t signed_of(uint64_t v, size_t bytes) {
  if (bytes < 8) {
    const uint64_t sign = 1ull << (8 * bytes - 1);
    v = (v ^ sign) - sign;
  }
  int64_t s;
  memcpy(&s, &v, sizeof s);
  return s;
}

std::string hex_bytes(const uint8_t* p, size_t n) {
  std::string s;
  char b[4];
  for (size_t i = 0; i < n; ++i) {
    snprintf(b, sizeof b, i ? " %02X" : "%02X", p[i]);
    s += b;
  }
  return s;
}

/// Digits of `text` from `i` on in `base`, accumulated without overflow
/// beyond `max`. False for no digit, another character or a value > max.
bool digits(const std::string& text, size_t i, unsigned base, uint64_t max, uint64_t* out) {
  if (i >= text.size()) return false;
  uint64_t v = 0;
  for (; i < text.size(); ++i) {
    const char c = text[i];
    unsigned d;
    if (c >= '0' && c <= '9')
      d = static_cast<unsigned>(c - '0');
    else if (c >= 'a' && c <= 'f')
      d = static_cast<unsigned>(c - 'a' + 10);
    else if (c >= 'A' && c <= 'F')
      d = static_cast<unsigned>(c - 'A' + 10);
    else
      return false;
    if (d >= base || d > max || v > (max - d) / base) return false;
    v = v * base + d;
  }
  *out = v;
  return true;
}

}  // namespace

const char* type_word(DataType t) {
  return row_of(t).word;
}

bool type_of_word(const std::string& word, DataType* t) {
  for (const TypeRow& r : kTypes) {
    if (word == r.word) {
      *t = r.type;
      return true;
    }
  }
  return false;
}

size_t type_size(DataType t) {
  return row_of(t).size;
}

bool parse_unsigned(const std::string& text, uint64_t max, uint64_t* out) {
  if (text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X'))
    return digits(text, 2, 16, max, out);
  if (text.size() > 1 && text[0] == '0') return digits(text, 1, 8, max, out);
  return digits(text, 0, 10, max, out);
}

bool parse_signed(const std::string& text, int64_t min, int64_t max, int64_t* out) {
  const bool negative = !text.empty() && text[0] == '-';
  const bool sign = negative || (!text.empty() && text[0] == '+');
  uint64_t magnitude = 0;
  // The magnitude of min may be 2^63: parsed as unsigned, then bounded.
  const uint64_t limit = negative ? 0ull - static_cast<uint64_t>(min) : static_cast<uint64_t>(max);
  if (negative && min >= 0) return false;
  if (!parse_unsigned(text.substr(sign ? 1 : 0), limit, &magnitude)) return false;
  if (negative) {
    const uint64_t v = 0ull - magnitude;
    memcpy(out, &v, sizeof v);
  } else {
    *out = static_cast<int64_t>(magnitude);
  }
  return true;
}

bool parse_fixed_value(DataType t, const std::string& token, std::vector<uint8_t>* out) {
  const size_t n = type_size(t);
  switch (t) {
    case DataType::kBoolean: {
      uint64_t v = 0;
      if (!parse_unsigned(token, 1, &v)) return false;
      put_le(v, 1, out);
      return true;
    }
    case DataType::kU8:
    case DataType::kU16:
    case DataType::kU32:
    case DataType::kU64:
    case DataType::kX8:
    case DataType::kX16:
    case DataType::kX32:
    case DataType::kX64: {
      uint64_t v = 0;
      const uint64_t max = n == 8 ? UINT64_MAX : (1ull << (8 * n)) - 1;
      if (!parse_unsigned(token, max, &v)) return false;
      put_le(v, n, out);
      return true;
    }
    case DataType::kI8:
    case DataType::kI16:
    case DataType::kI32:
    case DataType::kI64: {
      int64_t v = 0;
      const int64_t max = n == 8 ? INT64_MAX : static_cast<int64_t>((1ull << (8 * n - 1)) - 1);
      if (!parse_signed(token, -max - 1, max, &v)) return false;
      uint64_t bits;
      memcpy(&bits, &v, sizeof bits);
      put_le(bits, n, out);
      return true;
    }
    case DataType::kR32:
    case DataType::kR64: {
      if (token.empty() || token.find('\0') != std::string::npos) return false;
      char* end = nullptr;
      const double d = strtod(token.c_str(), &end);
      if (end != token.c_str() + token.size()) return false;
      uint64_t bits = 0;
      if (t == DataType::kR32) {
        const float f = static_cast<float>(d);
        uint32_t b32;
        memcpy(&b32, &f, sizeof b32);
        bits = b32;
      } else {
        memcpy(&bits, &d, sizeof bits);
      }
      put_le(bits, n, out);
      return true;
    }
    default:
      return false;
  }
}

std::string format_value(DataType t, const uint8_t* bytes, size_t n) {
  const size_t size = type_size(t);
  if (size != 0 && n != size) return hex_bytes(bytes, n);
  char b[40];
  const uint64_t v = size ? le_value(bytes, n) : 0;
  switch (t) {
    case DataType::kBoolean:
    case DataType::kU8:
    case DataType::kU16:
    case DataType::kU32:
    case DataType::kU64:
      snprintf(b, sizeof b, "%llu", static_cast<unsigned long long>(v));
      return b;
    case DataType::kI8:
    case DataType::kI16:
    case DataType::kI32:
    case DataType::kI64:
      snprintf(b, sizeof b, "%lld", static_cast<long long>(signed_of(v, n)));
      return b;
    case DataType::kX8:
    case DataType::kX16:
    case DataType::kX32:
    case DataType::kX64:
      snprintf(b, sizeof b, "0x%0*llX", static_cast<int>(2 * n), static_cast<unsigned long long>(v));
      return b;
    case DataType::kR32: {
      const uint32_t b32 = static_cast<uint32_t>(v);
      float f;
      memcpy(&f, &b32, sizeof f);
      snprintf(b, sizeof b, "%g", static_cast<double>(f));
      return b;
    }
    case DataType::kR64: {
      double d;
      memcpy(&d, &v, sizeof d);
      snprintf(b, sizeof b, "%g", d);
      return b;
    }
    case DataType::kVisibleString: {
      // One line whatever the bytes: CANopenNode leaves out NUL and CR; LF
      // too here, or the answer would end in the middle.
      std::string s = "\"";
      for (size_t i = 0; i < n; ++i) {
        const char c = static_cast<char>(bytes[i]);
        if (c == '\0' || c == '\r' || c == '\n') continue;
        s += c;
        if (c == '"') s += '"';
      }
      return s + "\"";
    }
    case DataType::kOctetString:
    case DataType::kUnicodeString:
    case DataType::kDomain:
      return encode_base64(bytes, n);
    case DataType::kHex:
      break;
  }
  return hex_bytes(bytes, n);
}

std::string encode_base64(const uint8_t* bytes, size_t n) {
  std::string s;
  s.reserve((n + 2) / 3 * 4);
  for (size_t i = 0; i < n; i += 3) {
    const uint32_t b0 = bytes[i];
    const uint32_t b1 = i + 1 < n ? bytes[i + 1] : 0;
    const uint32_t b2 = i + 2 < n ? bytes[i + 2] : 0;
    const uint32_t w = b0 << 16 | b1 << 8 | b2;
    s += kBase64[(w >> 18) & 0x3F];
    s += kBase64[(w >> 12) & 0x3F];
    s += i + 1 < n ? kBase64[(w >> 6) & 0x3F] : '=';
    s += i + 2 < n ? kBase64[w & 0x3F] : '=';
  }
  return s;
}

bool decode_base64(const std::string& text, std::vector<uint8_t>* out) {
  size_t end = text.size();
  size_t pads = 0;
  while (end > 0 && text[end - 1] == '=' && pads < 2) {
    --end;
    ++pads;
  }
  // A quantum of one character carries no whole byte: not base64.
  if (end % 4 == 1) return false;
  if (pads && (end + pads) % 4 != 0) return false;
  out->clear();
  uint32_t word = 0;
  int bits = 0;
  for (size_t i = 0; i < end; ++i) {
    const int d = base64_digit(text[i]);
    if (d < 0) return false;
    word = (word << 6) | static_cast<uint32_t>(d);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out->push_back(static_cast<uint8_t>(word >> bits));
      word &= (1u << bits) - 1;
    }
  }
  return true;
}

}  // namespace ascii
}  // namespace master
}  // namespace mb2co
