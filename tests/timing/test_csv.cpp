// The CSV reader of mb2co-timing: accepted forms and one-line errors with
// line and column.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "csv_set.h"

namespace mb2co {
namespace timing_cli {
namespace {

using timing::MessageSpec;

std::string parse_error(const std::string& text) {
  std::vector<MessageSpec> set;
  std::string error;
  EXPECT_FALSE(parse_message_csv(text, "set.csv", set, error));
  return error;
}

TEST(Csv, ReadsColumnsInAnyOrderWithDefaults) {
  const std::string text =
      "# comment\n"
      "\n"
      "period_us, name ,id,dlc,ext\r\n"
      "10000,TPDO1,0x181,2,0\n"
      "20000,Ext,0x1ABCDEF,8,1\n";
  std::vector<MessageSpec> set;
  std::string error;
  ASSERT_TRUE(parse_message_csv(text, "set.csv", set, error)) << error;
  ASSERT_EQ(set.size(), 2u);
  EXPECT_STREQ(set[0].name, "TPDO1");
  EXPECT_EQ(set[0].id, 0x181u);
  EXPECT_EQ(set[0].deadline_us, 10000u);  // defaults to the period
  EXPECT_EQ(set[0].jitter_us, 0u);
  EXPECT_EQ(set[0].c_us, 0u);
  EXPECT_TRUE(set[1].extended);
  EXPECT_EQ(set[1].id, 0x1ABCDEFu);
}

TEST(Csv, OptionalColumnsMayBeEmpty) {
  std::vector<MessageSpec> set;
  std::string error;
  ASSERT_TRUE(parse_message_csv(
      "name,id,ext,dlc,period_us,deadline_us,jitter_us,c_us,bits\n"
      "A,1,0,0,100,,,,\nB,2,0,0,100,90,5,7,\nC,3,0,0,100,,,,60\n",
      "set.csv", set, error))
      << error;
  EXPECT_EQ(set[0].deadline_us, 100u);
  EXPECT_EQ(set[1].deadline_us, 90u);
  EXPECT_EQ(set[1].jitter_us, 5u);
  EXPECT_EQ(set[1].c_us, 7u);
  EXPECT_EQ(set[2].bits, 60u);
}

TEST(Csv, ErrorsNameLineAndColumn) {
  const std::string header = "name,id,ext,dlc,period_us\n";
  EXPECT_EQ(parse_error(header + "A,0x800,0,8,100\n"),
            "set.csv:2:3: id must be 0..0x7FF for ext=0 (use ext=1 for 29-bit ids), got \"0x800\"");
  EXPECT_EQ(parse_error(header + "A,1,0,9,100\n"), "set.csv:2:7: dlc must be 0..8, got \"9\"");
  EXPECT_EQ(parse_error(header + "A,1,0,8,abc\n"),
            "set.csv:2:9: period_us must be a whole number of µs 1..4294967295, got \"abc\"");
  EXPECT_EQ(parse_error(header + "A,1,0,8,0\n"),
            "set.csv:2:9: period_us must be a whole number of µs 1..4294967295, got \"0\"");
  EXPECT_EQ(parse_error(header + "A,1,0,8\n"), "set.csv:2:8: expected 5 fields, found 4");
  EXPECT_EQ(parse_error(header + "A,1,0,8,5,6\n"), "set.csv:2:11: expected 5 fields, found 6");
  EXPECT_EQ(parse_error(header + "A,1,2,8,5\n"), "set.csv:2:5: ext must be 0 or 1, got \"2\"");
  EXPECT_EQ(parse_error(header + "A,1,0,8,5\nB,0x001,0,8,5\n"),
            "set.csv:3:3: id 0x001 already used on line 2 (CAN ids must be unique)");
  EXPECT_EQ(parse_error(header + "A,1,0,8,5\nA,2,0,8,5\n"), "set.csv:3:1: name \"A\" used twice");
  EXPECT_EQ(parse_error(header + ",1,0,8,5\n"), "set.csv:2:1: empty name");
  EXPECT_EQ(parse_error("name,id,ext,dlc\n"), "set.csv:1:1: missing column \"period_us\"");
  EXPECT_EQ(parse_error("name,id,ext,dlc,period_us,prio\n"),
            "set.csv:1:27: unknown column \"prio\" (expected name,id,ext,dlc,period_us and "
            "optionally deadline_us,jitter_us,c_us,bits)");
  EXPECT_EQ(parse_error("# nothing\n"), "set.csv:2:1: empty file: expected a header line");
  EXPECT_EQ(parse_error(header), "set.csv:2:1: no messages after the header");
  EXPECT_EQ(parse_error(header + "\"A\",1,0,8,5\n"), "set.csv:2:1: quoted fields are not supported");
  EXPECT_EQ(parse_error("name,id,ext,dlc,period_us,c_us,bits\nA,1,0,8,5,3,4\n"),
            "set.csv:2:13: give c_us or bits, not both");
}

TEST(Csv, ExtendedIdsBeyond29BitsAndHugeNumbersAreRejected) {
  const std::string header = "name,id,ext,dlc,period_us\n";
  EXPECT_EQ(parse_error(header + "A,0x20000000,1,8,100\n"),
            "set.csv:2:3: id must be 0..0x1FFFFFFF for ext=1, got \"0x20000000\"");
  EXPECT_EQ(parse_error(header + "A,1,0,8,4294967296\n"),
            "set.csv:2:9: period_us must be a whole number of µs 1..4294967295, got "
            "\"4294967296\"");
}

TEST(Csv, MissingFileIsOneLine) {
  std::vector<MessageSpec> set;
  std::string error;
  EXPECT_FALSE(read_message_csv("/nonexistent/set.csv", set, error));
  EXPECT_EQ(error, "/nonexistent/set.csv: cannot open: No such file or directory");
}

}  // namespace
}  // namespace timing_cli
}  // namespace mb2co
