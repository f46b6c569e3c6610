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
  const Status status = parse_message_csv(text, "set.csv", set);
  EXPECT_FALSE(status);
  return status.message();
}

TEST(Csv, ReadsColumnsInAnyOrderWithDefaults) {
  const std::string text =
      "# comment\n"
      "\n"
      "period_us, name ,id,dlc,ext\r\n"
      "10000,TPDO1,0x181,2,0\n"
      "20000,Ext,0x1ABCDEF,8,1\n";
  std::vector<MessageSpec> set;
  const Status status = parse_message_csv(text, "set.csv", set);
  ASSERT_TRUE(status) << status.message();
  ASSERT_EQ(set.size(), 2u);
  EXPECT_STREQ(set[0].name, "TPDO1");
  EXPECT_EQ(set[0].id, 0x181u);
  EXPECT_EQ(set[0].deadline_us, 10000u);  // defaults to the period
  EXPECT_EQ(set[0].jitter_us, 0u);
  EXPECT_EQ(set[0].c_ns, 0u);
  EXPECT_TRUE(set[1].extended);
  EXPECT_EQ(set[1].id, 0x1ABCDEFu);
}

TEST(Csv, OptionalColumnsMayBeEmpty) {
  std::vector<MessageSpec> set;
  const Status status = parse_message_csv(
      "name,id,ext,dlc,period_us,deadline_us,jitter_us,c_us,bits\n"
      "A,1,0,0,100,,,,\nB,2,0,0,100,90,5,7,\nC,3,0,0,100,,,,60\n",
      "set.csv", set);
  ASSERT_TRUE(status) << status.message();
  EXPECT_EQ(set[0].deadline_us, 100u);
  EXPECT_EQ(set[1].deadline_us, 90u);
  EXPECT_EQ(set[1].jitter_us, 5u);
  EXPECT_EQ(set[1].c_ns, 7000u);
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
  Status status = read_message_csv("/nonexistent/set.csv", set);
  EXPECT_FALSE(status);
  EXPECT_EQ(status.message(), "/nonexistent/set.csv: cannot open: No such file or directory");
  status = read_message_csv("/tmp", set);
  EXPECT_FALSE(status);
  EXPECT_EQ(status.message(), "/tmp: is a directory, not a CSV file");
}

// Times as exact decimals: "1040.0" is 1040 µs; c_us keeps up to three
// decimals (ns); a fraction the column cannot hold is refused, not rounded.
TEST(Csv, TimesAreExactDecimals) {
  std::vector<MessageSpec> set;
  const Status status = parse_message_csv(
      "name,id,ext,dlc,period_us,deadline_us,jitter_us,c_us\n"
      "A,1,0,8,10000.0,9000.000,5.0,1040.0\nB,2,0,8,10000,10000,0,1040.125\n",
      "set.csv", set);
  ASSERT_TRUE(status) << status.message();
  EXPECT_EQ(set[0].period_us, 10000u);
  EXPECT_EQ(set[0].deadline_us, 9000u);
  EXPECT_EQ(set[0].jitter_us, 5u);
  EXPECT_EQ(set[0].c_ns, 1040000u);
  EXPECT_EQ(set[1].c_ns, 1040125u);
  const std::string header = "name,id,ext,dlc,period_us,c_us\n";
  EXPECT_EQ(parse_error(header + "A,1,0,8,100.5,7\n"),
            "set.csv:2:9: period_us must be a whole number of µs 1..4294967295, got \"100.5\"");
  EXPECT_EQ(parse_error(header + "A,1,0,8,100,7.0005\n"),
            "set.csv:2:13: c_us must be µs 0.001..4294967295 with at most 3 decimals, got \"7.0005\"");
  EXPECT_EQ(parse_error(header + "A,1,0,8,100,7.\n"),
            "set.csv:2:13: c_us must be µs 0.001..4294967295 with at most 3 decimals, got \"7.\"");
}

// The file is UTF-8 text: a byte order mark is skipped, a NUL or a byte that
// is not UTF-8 is an error at its column (names reach JSON output intact).
TEST(Csv, TextIsUtf8WithoutNul) {
  std::vector<MessageSpec> set;
  const Status status =
      parse_message_csv("\xEF\xBB\xBFname,id,ext,dlc,period_us\nPDO \xC2\xB5s,1,0,8,100\n", "set.csv", set);
  ASSERT_TRUE(status) << status.message();
  EXPECT_STREQ(set[0].name, "PDO \xC2\xB5s");
  const std::string header = "name,id,ext,dlc,period_us\n";
  EXPECT_EQ(parse_error(header + "A\xFF"
                                 "B,1,0,8,100\n"),
            "set.csv:2:2: not valid UTF-8 (save the file as UTF-8)");
  EXPECT_EQ(parse_error(header + "A\xC0\x80,1,0,8,100\n"),
            "set.csv:2:2: not valid UTF-8 (save the file as UTF-8)")
      << "an overlong NUL";
  EXPECT_EQ(parse_error(header + std::string("A\0B,1,0,8,100\n", 15)),
            "set.csv:2:2: NUL byte (the file must be text)");
  EXPECT_EQ(parse_error("\xEF\xBB\xBFname,id,ext,dlc,period\n"),
            "set.csv:1:17: unknown column \"period\" (expected name,id,ext,dlc,period_us and optionally "
            "deadline_us,jitter_us,c_us,bits)")
      << "columns as an editor shows them: the BOM is not one";
}

}  // namespace
}  // namespace timing_cli
}  // namespace mb2co
