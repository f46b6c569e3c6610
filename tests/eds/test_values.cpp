// eds::parse_value / format_value / resolve: CiA 306 numbers, $NODEID
// expressions, reals, strings and hex dumps into bus bytes, with the range
// of each CiA 301 type (black box).
#include <gtest/gtest.h>

#include <cstring>

#include "eds_value.h"

using mb2co::eds::DataType;
using mb2co::eds::format_value;
using mb2co::eds::parse_unsigned;
using mb2co::eds::parse_value;
using mb2co::eds::resolve;
using mb2co::eds::Value;
using mb2co::eds::ValueKind;
using Bytes = std::vector<uint8_t>;

namespace {

Bytes bytes_of(DataType t, const std::string& text, std::optional<uint8_t> node = std::nullopt) {
  const auto r = parse_value(t, text, node);
  EXPECT_TRUE(r.value.has_value()) << text << ": " << r.error;
  return r.value ? r.value->bytes : Bytes{};
}

std::string error_of(DataType t, const std::string& text, std::optional<uint8_t> node = std::nullopt) {
  const auto r = parse_value(t, text, node);
  EXPECT_FALSE(r.value.has_value()) << text << " was accepted";
  return r.error;
}

}  // namespace

TEST(EdsValue, NumbersInDecimalHexAndOctal) {
  EXPECT_EQ(bytes_of(DataType::kUnsigned16, "4660"), (Bytes{0x34, 0x12}));
  EXPECT_EQ(bytes_of(DataType::kUnsigned16, "0x1234"), (Bytes{0x34, 0x12}));
  EXPECT_EQ(bytes_of(DataType::kUnsigned16, "0X1234"), (Bytes{0x34, 0x12}));
  EXPECT_EQ(bytes_of(DataType::kUnsigned16, "011064"), (Bytes{0x34, 0x12}));  // octal 11064 = 0x1234
  EXPECT_EQ(bytes_of(DataType::kUnsigned8, "0"), (Bytes{0}));
  EXPECT_EQ(bytes_of(DataType::kUnsigned8, "  7  "), (Bytes{7}));
  EXPECT_NE(error_of(DataType::kUnsigned8, "08").find("octal"), std::string::npos);
  EXPECT_NE(error_of(DataType::kUnsigned8, "0x").find("without digits"), std::string::npos);
  EXPECT_NE(error_of(DataType::kUnsigned8, "0x1G").find("hexadecimal"), std::string::npos);
  EXPECT_NE(error_of(DataType::kUnsigned8, "twelve").find("not a number"), std::string::npos);
  EXPECT_NE(error_of(DataType::kUnsigned64, "0x10000000000000000").find("64 bits"), std::string::npos);
  EXPECT_FALSE(parse_value(DataType::kUnsigned8, "").value.has_value());
}

TEST(EdsValue, EveryIntegerTypeAcceptsItsRangeAndRefusesOneBeyond) {
  for (const auto& t : mb2co::eds::all_types()) {
    if (t.kind != ValueKind::kSigned && t.kind != ValueKind::kUnsigned && t.kind != ValueKind::kBoolean)
      continue;
    const unsigned bits = t.kind == ValueKind::kBoolean ? 1u : t.bytes * 8u;
    SCOPED_TRACE(t.name);
    if (t.kind == ValueKind::kSigned) {
      const uint64_t max = (uint64_t{1} << (bits - 1)) - 1;
      const std::string max_text = std::to_string(max), min_text = "-" + std::to_string(max + 1);
      Bytes max_bytes(t.bytes, 0xFF), min_bytes(t.bytes, 0x00);
      max_bytes.back() = 0x7F;
      min_bytes.back() = 0x80;
      EXPECT_EQ(bytes_of(t.type, max_text), max_bytes);
      EXPECT_EQ(bytes_of(t.type, min_text), min_bytes);
      EXPECT_EQ(bytes_of(t.type, "-1"), Bytes(t.bytes, 0xFF));
      EXPECT_NE(error_of(t.type, std::to_string(max + 1)).find("out of range"), std::string::npos);
      EXPECT_NE(error_of(t.type, "-" + std::to_string(max + 2)).find("out of range"), std::string::npos);
    } else {
      const uint64_t max = bits == 64 ? UINT64_MAX : (uint64_t{1} << bits) - 1;
      EXPECT_EQ(bytes_of(t.type, std::to_string(max)),
                Bytes(t.bytes, t.kind == ValueKind::kBoolean ? 1 : 0xFF));
      EXPECT_NE(error_of(t.type, "-1").find("out of range"), std::string::npos);
      if (bits < 64) {
        EXPECT_NE(error_of(t.type, std::to_string(max + 1)).find("out of range"), std::string::npos);
      }
    }
  }
}

TEST(EdsValue, NodeIdExpressionsKeptSymbolicOrEvaluated) {
  const auto sym = parse_value(DataType::kUnsigned32, "$NODEID+0x180");
  ASSERT_TRUE(sym.value);
  EXPECT_TRUE(sym.value->node_id_relative);
  EXPECT_EQ(sym.value->bytes, (Bytes{0x80, 0x01, 0, 0}));  // the base
  const auto rev = parse_value(DataType::kUnsigned32, "0x180 + $NODEID");
  ASSERT_TRUE(rev.value);
  EXPECT_EQ(*rev.value, *sym.value);
  EXPECT_EQ(bytes_of(DataType::kUnsigned32, "$NODEID+0x180", 5), (Bytes{0x85, 0x01, 0, 0}));
  EXPECT_EQ(bytes_of(DataType::kUnsigned32, "0x180+$nodeid", 0x7F), (Bytes{0xFF, 0x01, 0, 0}));
  EXPECT_EQ(bytes_of(DataType::kUnsigned8, "$NODEID", 9), (Bytes{9}));
  EXPECT_FALSE(parse_value(DataType::kUnsigned32, "$NODEID+0x180", 5).value->node_id_relative);
  const auto resolved = resolve(DataType::kUnsigned32, *sym.value, 0x22);
  ASSERT_TRUE(resolved);
  EXPECT_EQ(resolved->bytes, (Bytes{0xA2, 0x01, 0, 0}));
  EXPECT_FALSE(resolved->node_id_relative);
  EXPECT_EQ(format_value(DataType::kUnsigned32, *sym.value), "$NODEID+0x180");
}

TEST(EdsValue, NodeIdExpressionsThatCannotFitOrParseAreRefused) {
  EXPECT_NE(error_of(DataType::kUnsigned8, "$NODEID+0xF0").find("out of range"), std::string::npos);
  EXPECT_NE(error_of(DataType::kUnsigned8, "$NODEID+0x90", 0x70).find("out of range"), std::string::npos);
  EXPECT_NE(error_of(DataType::kUnsigned8, "$NODEID+0xF0", 0x10).find("out of range"), std::string::npos);
  EXPECT_NE(error_of(DataType::kUnsigned32, "$NODEID-1").find("'+'"), std::string::npos);
  EXPECT_NE(error_of(DataType::kUnsigned32, "$NODEID+").find("missing"), std::string::npos);
  EXPECT_NE(error_of(DataType::kUnsigned32, "0x180-$NODEID").find("'+'"), std::string::npos);
  EXPECT_NE(error_of(DataType::kUnsigned32, "$NODEID+0x180+1").find("hexadecimal"), std::string::npos);
  EXPECT_NE(error_of(DataType::kReal32, "$NODEID+1").find("$NODEID in a value of type REAL32"),
            std::string::npos);
  EXPECT_NE(error_of(DataType::kOctetString, "$NODEID").find("$NODEID"), std::string::npos);
}

TEST(EdsValue, RealsAreFiniteDecimalNumbersThatRoundTrip) {
  float f = 0;
  const Bytes b = bytes_of(DataType::kReal32, "1.5");
  ASSERT_EQ(b.size(), 4u);
  std::memcpy(&f, b.data(), 4);
  EXPECT_EQ(f, 1.5f);
  double d = 0;
  const Bytes b64 = bytes_of(DataType::kReal64, "-2e-3");
  ASSERT_EQ(b64.size(), 8u);
  std::memcpy(&d, b64.data(), 8);
  EXPECT_EQ(d, -2e-3);
  for (const char* text : {"0.1", "-0", "3.4028235e38", "1e-45", "123456.79"}) {
    const auto v = parse_value(DataType::kReal32, text);
    ASSERT_TRUE(v.value) << text;
    EXPECT_EQ(*parse_value(DataType::kReal32, format_value(DataType::kReal32, *v.value)).value, *v.value)
        << text;
  }
  EXPECT_NE(error_of(DataType::kReal32, "1e39").find("out of range"), std::string::npos);
  EXPECT_NE(error_of(DataType::kReal64, "nan").find("finite"), std::string::npos);
  EXPECT_NE(error_of(DataType::kReal64, "inf").find("finite"), std::string::npos);
  EXPECT_NE(error_of(DataType::kReal64, "1.5x").find("not a decimal number"), std::string::npos);
}

TEST(EdsValue, StringsAndHexDumps) {
  EXPECT_EQ(bytes_of(DataType::kVisibleString, "Uno+MCP2515"),
            Bytes({'U', 'n', 'o', '+', 'M', 'C', 'P', '2', '5', '1', '5'}));
  EXPECT_TRUE(bytes_of(DataType::kVisibleString, "").empty());
  EXPECT_NE(error_of(DataType::kVisibleString, "caf\xC3\xA9").find("printable ASCII"), std::string::npos);
  EXPECT_EQ(bytes_of(DataType::kOctetString, "0102aB"), (Bytes{0x01, 0x02, 0xAB}));
  EXPECT_EQ(bytes_of(DataType::kDomain, "01 02"), (Bytes{0x01, 0x02}));
  EXPECT_EQ(format_value(DataType::kOctetString, Value{{0x01, 0xAB}, false}), "01AB");
  EXPECT_NE(error_of(DataType::kOctetString, "012").find("odd number of hex digits"), std::string::npos);
  EXPECT_NE(error_of(DataType::kDomain, "0x01").find("'x'"), std::string::npos);
  EXPECT_EQ(bytes_of(DataType::kUnicodeString, "41004200"), (Bytes{0x41, 0, 0x42, 0}));
  EXPECT_NE(error_of(DataType::kUnicodeString, "410042").find("UTF-16"), std::string::npos);
}

TEST(EdsValue, FormatThenParseGivesTheSameBytesForEveryType) {
  const struct {
    DataType type;
    const char* text;
  } cases[] = {{DataType::kBoolean, "1"},
               {DataType::kInteger8, "-128"},
               {DataType::kInteger24, "-8388608"},
               {DataType::kInteger40, "549755813887"},
               {DataType::kInteger64, "-9223372036854775808"},
               {DataType::kUnsigned24, "0xABCDEF"},
               {DataType::kUnsigned40, "0xFFFFFFFFFF"},
               {DataType::kUnsigned48, "0x123456789ABC"},
               {DataType::kUnsigned56, "0xFFFFFFFFFFFFFF"},
               {DataType::kUnsigned64, "18446744073709551615"},
               {DataType::kTimeOfDay, "0x0000123456"},
               {DataType::kReal64, "0.1"},
               {DataType::kInteger16, "$NODEID+5"}};
  for (const auto& c : cases) {
    const auto v = parse_value(c.type, c.text);
    ASSERT_TRUE(v.value) << c.text << ": " << v.error;
    const std::string text = format_value(c.type, *v.value);
    const auto back = parse_value(c.type, text);
    ASSERT_TRUE(back.value) << text;
    EXPECT_EQ(*back.value, *v.value) << c.text << " -> " << text;
  }
}

TEST(EdsValue, UnsignedHelperForCountsAndIndices) {
  EXPECT_EQ(parse_unsigned("0x1A00", 0xFFFF), 0x1A00u);
  EXPECT_EQ(parse_unsigned("12", 0xFF), 12u);
  EXPECT_FALSE(parse_unsigned("256", 0xFF));
  EXPECT_FALSE(parse_unsigned("-1", 0xFF));
  EXPECT_FALSE(parse_unsigned("", 0xFF));
}

TEST(EdsValue, ValueForASubObjectKeepsItsLimits) {
  mb2co::eds::SubObject sub;
  sub.type = DataType::kInteger16;
  sub.low_limit = parse_value(DataType::kInteger16, "-10").value;
  sub.high_limit = parse_value(DataType::kInteger16, "$NODEID+10").value;  // 10 + node id
  EXPECT_EQ(mb2co::eds::parse_value_for(sub, "-10").value->bytes, (Bytes{0xF6, 0xFF}));
  EXPECT_NE(mb2co::eds::parse_value_for(sub, "-11").error.find("below the LowLimit -10"), std::string::npos);
  EXPECT_TRUE(mb2co::eds::parse_value_for(sub, "15", 5).value);
  EXPECT_NE(mb2co::eds::parse_value_for(sub, "16", 5).error.find("above the HighLimit 15"),
            std::string::npos);
  EXPECT_TRUE(mb2co::eds::parse_value_for(sub, "1000").value);  // no node id: the high limit is unknown
  EXPECT_NE(mb2co::eds::parse_value_for(sub, "0x8000").error.find("out of range"), std::string::npos);
}

TEST(EdsValue, ConfiguredValueIsParameterValueElseDefaultResolved) {
  mb2co::eds::SubObject sub;
  sub.type = DataType::kUnsigned32;
  EXPECT_FALSE(mb2co::eds::configured_value(sub, 3));
  sub.default_value = parse_value(DataType::kUnsigned32, "$NODEID+0x180").value;
  EXPECT_EQ(mb2co::eds::configured_value(sub, 3)->bytes, (Bytes{0x83, 0x01, 0, 0}));
  sub.parameter_value = parse_value(DataType::kUnsigned32, "0x80000183").value;
  EXPECT_EQ(mb2co::eds::configured_value(sub, 3)->bytes, (Bytes{0x83, 0x01, 0, 0x80}));
}
