// The app's register addresses come from the gateway OD's maps; they must be
// what docs/register-map.md (the user's reference) says.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "canopen/od.h"
#include "gateway/gateway_od.h"
#include "register_layout.h"

using namespace mb2co::pcapp;

namespace {
struct DocRow {
  RegTable table;
  uint16_t address;
  uint8_t width;
};

/// "XXXXh/SS" -> where docs/register-map.md puts it (holding wins like in the app).
std::map<std::string, DocRow> read_doc() {
  std::ifstream in(MB2CO_REGISTER_MAP_DOC);
  EXPECT_TRUE(in.good());
  std::map<std::string, DocRow> rows;
  RegTable table = RegTable::kNone;
  const std::regex row(R"(^\| (\d+)(?:-(\d+))? \| ([0-9A-F]{4}h/[0-9A-F]{2}) \|)");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("## Holding registers", 0) == 0)
      table = RegTable::kHolding;
    else if (line.rfind("## Input registers", 0) == 0)
      table = RegTable::kInput;
    else if (line.rfind("## ", 0) == 0)
      table = RegTable::kNone;
    std::smatch m;
    if (table == RegTable::kNone || !std::regex_search(line, m, row)) continue;
    const uint16_t first = static_cast<uint16_t>(std::stoi(m[1]));
    const uint8_t width = m[2].matched ? static_cast<uint8_t>(std::stoi(m[2]) - first + 1) : 1;
    if (rows.count(m[3]) == 0 || table == RegTable::kHolding) rows[m[3]] = DocRow{table, first, width};
  }
  return rows;
}

std::string od_name(const FieldSpec& s) {
  char b[16];
  std::snprintf(b, sizeof b, "%04Xh/%02X", s.index, s.sub);
  return b;
}
}  // namespace

TEST(RegisterLayout, EveryFieldWhereTheRegisterMapDocSaysIt) {
  const std::map<std::string, DocRow> doc = read_doc();
  ASSERT_GT(doc.size(), 20u);
  const RegisterLayout layout = default_layout();
  for (int f = 0; f < kFieldCount; ++f) {
    const FieldSpec& s = field_spec(static_cast<Field>(f));
    SCOPED_TRACE(s.name);
    const auto it = doc.find(od_name(s));
    ASSERT_NE(it, doc.end()) << "the default map lacks " << od_name(s);
    EXPECT_EQ(layout.at[f].table, it->second.table);
    EXPECT_EQ(layout.at[f].address, it->second.address);
    EXPECT_EQ(layout.at[f].width, it->second.width);
  }
}

TEST(RegisterLayout, KnownAddressesOfTheDefaultMap) {
  const RegisterLayout l = default_layout();
  EXPECT_EQ(l[Field::kRunCommand].table, RegTable::kHolding);
  EXPECT_EQ(l[Field::kRunCommand].address, 0);
  EXPECT_EQ(l[Field::kLabLed].address, 1);
  EXPECT_EQ(l[Field::kInputs].table, RegTable::kInput);
  EXPECT_EQ(l[Field::kInputs].address, 0);
  EXPECT_EQ(l[Field::kEdgeUs].address, 12);
  EXPECT_EQ(l[Field::kEdgeUs].width, 2);
  EXPECT_EQ(l[Field::kNmtState].address, 22);
  EXPECT_EQ(l.mapped[1].size(), 24u);  // the last: 2003h, damaged saved sets found
  // 14 registers, and on the host the REAL32 (2) and UNSIGNED64 (4) of 2500h.
  const size_t holding = MB2CO_CONFIG_WIDE_TYPES ? 20u : 14u;
  EXPECT_EQ(l.mapped[0].size(), holding);
  ASSERT_EQ(l.writable.size(), holding);
  EXPECT_TRUE(l.writable[0]);
  EXPECT_FALSE(l.writable[9]);  // half of the 32-bit 1006h is never written alone
}

TEST(RegisterLayout, FollowsAChangedMap) {
  mb2co::gateway::od::GatewayValues values{};
  mb2co::canopen::ObjectDictionary od(mb2co::gateway::od::GatewayDefinition,
                                      reinterpret_cast<uint8_t*>(&values));
  od.restore_defaults(0x0000, 0xFFFF);
  // Input map: an unmapped hole first, so everything moves up by one.
  const uint16_t row = od.find(0x2401, 1);
  od.set(row, 0);
  const RegisterLayout l = layout_from_od(od);
  EXPECT_EQ(l[Field::kInputs].table, RegTable::kNone);
  EXPECT_EQ(l[Field::kRunState].address, 1);
  EXPECT_FALSE(l.mapped[1][0]);
  EXPECT_TRUE(l.mapped[1][1]);
}
