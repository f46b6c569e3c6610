// The data types of CiA 309-3's ASCII mapping, as CANopenNode's gateway
// (309/CO_gateway_ascii.c, 301/CO_fifo.c) writes and reads them: the words
// b, i8..i64, u8..u64, x8..x64 (unsigned shown in hex), r32, r64, vs, os,
// us, d and CANopenNode's "hex" (the type of a read without one). Plain C++
// without OS or Qt: the command parser and its fuzz target use it.
//
// Numbers are read as C's strtoul(..., 0) reads them (decimal, 0x.. hex,
// 0.. octal) but whole and range-checked for the type; a visible string is
// "quoted" (a quote inside doubled) or one word; octet, unicode strings and
// domains are base64 (RFC 2045 alphabet, one line); hex is bytes as pairs of
// hex digits, spaces between them optional.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include <string>
#include <vector>

namespace mb2co {
namespace master {
namespace ascii {

enum class DataType : uint8_t {
  kHex,  ///< bytes in hex, CANopenNode's own (not CiA 309-3)
  kBoolean,
  kI8,
  kI16,
  kI32,
  kI64,
  kU8,
  kU16,
  kU32,
  kU64,
  kX8,  ///< unsigned, shown 0x.. (CANopenNode's own)
  kX16,
  kX32,
  kX64,
  kR32,
  kR64,
  kVisibleString,
  kOctetString,
  kUnicodeString,
  kDomain,
};

/// "u16" for kU16.
const char* type_word(DataType t);
/// The type of a lower-case word; false for another word.
bool type_of_word(const std::string& word, DataType* t);
/// Bytes of a fixed-size type; 0 for hex and the strings (any length).
size_t type_size(DataType t);

/// The value as the gateway prints it: decimal (i, u, b), 0x with the
/// type's digits (x), %g (r), "quoted" (vs: NUL, CR and LF left out, a
/// quote doubled), base64 (os, us, d), hex pairs "0A 1B" (hex). A value
/// whose length is not its type's prints as hex, as CANopenNode does.
std::string format_value(DataType t, const uint8_t* bytes, size_t n);

/// C's strtoul(text, 0) for a whole token within [0, max]; no sign.
bool parse_unsigned(const std::string& text, uint64_t max, uint64_t* out);
/// The same with an optional sign, within [min, max].
bool parse_signed(const std::string& text, int64_t min, int64_t max, int64_t* out);

/// A number, boolean or real token as the little-endian bytes of `t`
/// (a fixed-size type). False when it is not one or out of range.
bool parse_fixed_value(DataType t, const std::string& token, std::vector<uint8_t>* out);

std::string encode_base64(const uint8_t* bytes, size_t n);
/// RFC 2045's alphabet; '=' padding optional. False for any other character.
bool decode_base64(const std::string& text, std::vector<uint8_t>* out);

}  // namespace ascii
}  // namespace master
}  // namespace mb2co
