// mb2co-od's EDS of an OD with every CiA 301 basic data type reads back as
// that OD (DataType, DefaultValue in the type's notation, Low/HighLimit of
// 24- to 64-bit integers and REALs), and written again reads back equal.
#include <gtest/gtest.h>

#include <cstring>

#include "eds_reader.h"
#include "eds_value.h"
#include "eds_writer.h"
#include "od_export.h"
#include "types_od.h"

namespace mb2co {
namespace {

namespace co = canopen;
using eds::DeviceDescription;
using eds::ParseResult;
using Bytes = std::vector<uint8_t>;

class TypesEds : public ::testing::Test {
 protected:
  test::types::od::TypesValues values{};
  co::ObjectDictionary od{test::types::od::TypesDefinition, reinterpret_cast<uint8_t*>(&values)};
  void SetUp() override { od.restore_defaults(0x0000, 0xFFFF); }
};

/// A limit's bytes as the EDS holds them (REALs: the IEEE bits of the
/// ordered key the OD stores).
Bytes limit_bytes(co::OdLimitValue v, uint8_t type, size_t n) {
  const uint64_t bits = co::od_type_kind(type) == co::kKindReal
                            ? static_cast<uint64_t>(co::od_real_limit_bits(v, static_cast<uint8_t>(n)))
                            : static_cast<uint64_t>(v);
  Bytes b(n);
  for (size_t i = 0; i < n; ++i) b[i] = static_cast<uint8_t>(bits >> (8 * i));
  return b;
}

TEST_F(TypesEds, EveryTypeReadsBackAsTheOdHoldsIt) {
  const std::string text = odtool::od_eds(od, "types");
  const ParseResult r = eds::parse(text, "eds");
  ASSERT_TRUE(r) << r.error.text();
  const DeviceDescription& m = *r.model;
  int limited = 0;
  for (uint16_t row = 0; row < od.row_count(); ++row) {
    const co::OdEntry e = od.entry(row);
    SCOPED_TRACE(::testing::Message() << std::hex << e.index << "/" << int{e.sub});
    const eds::SubObject* s = m.find(e.index, e.sub);
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(static_cast<uint16_t>(s->type), e.data_type());
    ASSERT_TRUE(s->default_value);
    if (!(e.attr & co::kAttrNodeId)) {
      // The default as the node holds it after a reset, byte for byte.
      uint8_t buf[64];
      const uint16_t n = od.copy_out(row, buf, sizeof buf);
      EXPECT_EQ(s->default_value->bytes, Bytes(buf, buf + n));
    }
    for (uint8_t i = 0; i < od.definition().limit_count; ++i) {
      const co::OdLimit& l = od.definition().limits[i];
      if (l.index != e.index || l.sub != e.sub) continue;
      ++limited;
      const size_t n = od.size_of(row);
      ASSERT_TRUE(s->low_limit && s->high_limit);
      EXPECT_EQ(s->low_limit->bytes, limit_bytes(l.min, e.data_type(), n));
      EXPECT_EQ(s->high_limit->bytes, limit_bytes(l.max, e.data_type(), n));
    }
  }
  EXPECT_EQ(limited, od.definition().limit_count);
  // The types' own notation in the file (CiA 306).
  EXPECT_NE(text.find("[2112]\nParameterName=REAL32\nObjectType=0x7\nDataType=0x0008\nAccessType=rw\n"
                      "DefaultValue=-1234.5625\n"),
            std::string::npos);
  EXPECT_NE(text.find("[2204]\nParameterName=limited REAL32\nObjectType=0x7\nDataType=0x0008\nAccessType=rw\n"
                      "DefaultValue=0\nLowLimit=-1.5\nHighLimit=2.5\n"),
            std::string::npos);
  EXPECT_NE(text.find("DataType=0x0015\nAccessType=rw\nDefaultValue=0\nLowLimit=-5000000000000\n"),
            std::string::npos);
  EXPECT_NE(text.find("DataType=0x000A\nAccessType=rw\nDefaultValue=010203000000\n"), std::string::npos);
}

TEST_F(TypesEds, WrittenAgainReadsBackEqual) {
  const ParseResult r = eds::parse(odtool::od_eds(od, "types"), "eds");
  ASSERT_TRUE(r) << r.error.text();
  const ParseResult again = eds::parse(eds::write_eds(*r.model), "eds");
  ASSERT_TRUE(again) << again.error.text();
  EXPECT_EQ(*again.model, *r.model);
}

}  // namespace
}  // namespace mb2co
