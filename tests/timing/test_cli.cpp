// Runs the built mb2co-timing on the CSV files in data/: the seed's figures
// end to end, the output formats, the SVG, and one-line errors with exit 1
// (runtime) or 2 (usage).
#include <gtest/gtest.h>

#include <string>

#include "program_run.h"

namespace {

const std::string kExe = MB2CO_TIMING_EXE;
const std::string kData = MB2CO_TIMING_DATA;

using Result = mb2co::test::ProgramResult;
using mb2co::test::slurp;

class Cli : public mb2co::test::ProgramTest {
 protected:
  Result run(const std::string& args) { return run_program(kExe, args); }
};

// The JSON object of the row whose name is `name` (rows are printed one per
// line by the command).
std::string row(const std::string& json, const std::string& name) {
  const size_t at = json.find("{\"name\": \"" + name + "\"");
  if (at == std::string::npos) return "";
  return json.substr(at, json.find('}', at) - at + 1);
}

TEST_F(Cli, SeedThreeMessageExampleAsJson) {
  const Result r = run("rta " + kData + "/seed_3msg.csv --bitrate 1000000 --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err, "");
  const std::string pdo3 = row(r.out, "PDO3");
  EXPECT_NE(pdo3.find("\"id\": 387"), std::string::npos) << pdo3;
  EXPECT_NE(pdo3.find("\"bits\": 1000"), std::string::npos) << pdo3;
  EXPECT_NE(pdo3.find("\"c_us\": 1000"), std::string::npos) << pdo3;
  EXPECT_NE(pdo3.find("\"busy_us\": 7000"), std::string::npos) << pdo3;
  EXPECT_NE(pdo3.find("\"instances\": 2"), std::string::npos) << pdo3;
  EXPECT_NE(pdo3.find("\"r_first_us\": 3000"), std::string::npos) << pdo3;
  EXPECT_NE(pdo3.find("\"r_us\": 3500"), std::string::npos) << pdo3;
  EXPECT_NE(pdo3.find("\"schedulable\": false"), std::string::npos) << pdo3;
  EXPECT_NE(pdo3.find("\"first_optimistic\": true"), std::string::npos) << pdo3;
  EXPECT_NE(row(r.out, "PDO2").find("\"schedulable\": true"), std::string::npos);
  EXPECT_NE(r.out.find("\"utilisation\": 0.971429"), std::string::npos) << r.out;
}

TEST_F(Cli, CheckExitsThreeOnAMissedDeadline) {
  EXPECT_EQ(run("rta " + kData + "/seed_3msg.csv --bitrate 1M --check").status, 3);
  EXPECT_EQ(run("rta " + kData + "/seed_four_pdo.csv --bitrate 1M --check").status, 0);
}

TEST_F(Cli, UnboundedIsNull) {
  const Result r = run("rta " + kData + "/unbounded.csv --bitrate 1M --json");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string b = row(r.out, "B");
  EXPECT_NE(b.find("\"r_us\": null"), std::string::npos) << b;
  EXPECT_NE(b.find("\"busy_us\": null"), std::string::npos) << b;
  EXPECT_NE(b.find("\"r_first_us\": 2000"), std::string::npos) << b;
  EXPECT_NE(b.find("\"unbounded\": \"utilisation\""), std::string::npos) << b;
  EXPECT_NE(row(r.out, "A").find("\"r_us\": 2000"), std::string::npos);
}

TEST_F(Cli, CsvOutputHasHeaderAndOneRowPerMessage) {
  const Result r = run("rta " + kData + "/seed_3msg.csv --bitrate 1M --csv");
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream lines(r.out);
  std::string header, line;
  std::getline(lines, header);
  EXPECT_EQ(header.rfind("name,id,ext,dlc,bits,c_us,", 0), 0u) << header;
  int rows = 0;
  while (std::getline(lines, line)) {
    ++rows;
    if (line.rfind("PDO3,", 0) == 0) {
      EXPECT_NE(line.find(",3000,3500,no,yes,"), std::string::npos) << line;
    }
  }
  EXPECT_EQ(rows, 3);
}

TEST_F(Cli, SeedFrameFigures) {
  Result r = run("frame --frame-bits course --dlc 8 --bitrate 50k --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"bits\": 130, \"c_us\": 2600}"), std::string::npos) << r.out;
  r = run("frame --frame-bits course --dlc 8 --bitrate 1M --json");
  EXPECT_NE(r.out.find("\"bits\": 130, \"c_us\": 130}"), std::string::npos) << r.out;
  r = run("frame --dlc 0 --json");
  EXPECT_NE(r.out.find("\"bits_unstuffed\": 47"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"bits\": 55,"), std::string::npos) << r.out;  // Davis by default
  r = run("frame --id 0x03E --data 3C3C3C3C3C3C3C1B --json");
  EXPECT_NE(r.out.find("\"stuff_bits\": 21, \"bits\": 132"), std::string::npos) << r.out;
}

TEST_F(Cli, SeedBandwidthFigures) {
  Result r = run("load " + kData + "/seed_four_pdo.csv --bitrate 100k --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"load_bps\": 65000.000"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"fits\": true"), std::string::npos) << r.out;
  r = run("load " + kData + "/seed_four_pdo_sync.csv --bitrate 100k --json");
  EXPECT_NE(r.out.find("\"load_bps\": 85000.000"), std::string::npos) << r.out;
  r = run("load " + kData + "/seed_four_pdo_sync.csv --bitrate 85k --json");
  EXPECT_NE(r.out.find("\"fits\": false"), std::string::npos) << r.out;
  const std::string five = kData + "/seed_five_nodes.csv --frame-bits course --window-us 100000 --json";
  r = run("load " + five + " --bitrate 100k");
  EXPECT_NE(r.out.find("\"window_bits\": 1347"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"window_capacity_bits\": 10000"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"window_fits\": true"), std::string::npos) << r.out;
  r = run("load " + five + " --bitrate 10k");
  EXPECT_NE(r.out.find("\"window_capacity_bits\": 1000"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"window_fits\": false"), std::string::npos) << r.out;
}

TEST_F(Cli, LineConfiguration) {
  const Result r = run("rta --line 4 --bitrate 125k --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("\"message_count\": 8"), std::string::npos) << r.out;
  EXPECT_NE(row(r.out, "TPDO1.1").find("\"r_us\": 1360"), std::string::npos) << r.out;  // 680 blocked + 680
  EXPECT_NE(row(r.out, "HB.4").find("\"id\": 1796"), std::string::npos) << r.out;
}

TEST_F(Cli, SvgOfTheBusyPeriod) {
  const std::string svg = dir_ + "/pdo3.svg";
  const Result r = run("rta " + kData + "/seed_3msg.csv --bitrate 1M --svg " + svg + " --message PDO3");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string text = slurp(svg);
  EXPECT_EQ(text.rfind("<svg", 0), 0u);
  EXPECT_NE(text.find("R1 = 3500 \xC2\xB5s"), std::string::npos);
  size_t rects = 0;
  for (size_t at = text.find("<rect"); at != std::string::npos; at = text.find("<rect", at + 1)) ++rects;
  EXPECT_EQ(rects, 1u + 7u);  // background + the 7 frames of the busy period
}

TEST_F(Cli, LatencyReportsBothPaths) {
  const Result r = run("latency --json");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* key : {"\"modbus_best_us\"", "\"modbus_worst_us\"", "\"canopen_best_us\"",
                          "\"canopen_worst_us\"", "\"poll_period_us\"", "\"terms\""}) {
    EXPECT_NE(r.out.find(key), std::string::npos) << key;
  }
  // A slower firmware loop adds to the worst case, never to the best.
  const Result slow = run("latency --fw-loop-us 5000 --csv");
  const Result fast = run("latency --fw-loop-us 1000 --csv");
  ASSERT_EQ(slow.status, 0) << slow.err;
  auto total = [](const std::string& csv) { return csv.substr(csv.find("\ntotal,") + 1); };
  EXPECT_NE(total(slow.out), total(fast.out));
  EXPECT_EQ(total(slow.out).substr(0, total(slow.out).find(',', 6)),
            total(fast.out).substr(0, total(fast.out).find(',', 6)));
}

// A run that failed with one line on stderr, nothing on stdout, and the exit
// status of docs/cli.md: 1 for what the run met (a file), 2 for the command line.
void expect_one_line_error(const Result& r, const std::string& message, int status) {
  EXPECT_EQ(r.status, status);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, "mb2co-timing: " + message + "\n");
}

TEST_F(Cli, BadFilesNameLineAndColumnWithExit1) {
  const std::string d = kData + "/";
  expect_one_line_error(run("rta " + d + "bad_id.csv --bitrate 1M"),
                        d + "bad_id.csv:3:6: id must be 0..0x7FF for ext=0 (use ext=1 for 29-bit "
                            "ids), got \"0x900\"",
                        1);
  expect_one_line_error(run("rta " + d + "bad_fields.csv --bitrate 1M"),
                        d + "bad_fields.csv:3:18: expected 6 fields, found 5", 1);
  expect_one_line_error(run("load " + d + "bad_duplicate.csv --bitrate 1M"),
                        d + "bad_duplicate.csv:4:3: id 385 already used on line 2 (CAN ids must "
                            "be unique)",
                        1);
  expect_one_line_error(run("rta " + d + "bad_header.csv --bitrate 1M"),
                        d + "bad_header.csv:1:17: unknown column \"period\" (expected "
                            "name,id,ext,dlc,period_us and optionally "
                            "deadline_us,jitter_us,c_us,bits)",
                        1);
  expect_one_line_error(run("rta " + d + "bad_number.csv --bitrate 1M"),
                        d + "bad_number.csv:2:25: jitter_us must be an integer 0..4294967295, "
                            "got \"-5\"",
                        1);
  expect_one_line_error(run("rta " + d + "missing.csv --bitrate 1M"),
                        d + "missing.csv: cannot open: No such file or directory", 1);
  expect_one_line_error(
      run("rta " + d + "seed_3msg.csv --bitrate 1M --svg /nonexistent/x.svg --message PDO3"),
      "/nonexistent/x.svg: cannot write", 1);
}

TEST_F(Cli, BadCommandLinesWithExit2) {
  const std::string set = kData + "/seed_3msg.csv";
  expect_one_line_error(run("rta " + set), "missing --bitrate B (bit/s) for " + set, 2);
  expect_one_line_error(run("rta " + set + " --bitrate fast"),
                        "--bitrate must be a bit rate such as 500k, 1M or 125000 (bit/s), got \"fast\"", 2);
  expect_one_line_error(run("rta " + set + " --bitrate"), "--bitrate needs a value", 2);
  expect_one_line_error(run("rta " + set + " --bitrate --json"), "--bitrate needs a value", 2);
  expect_one_line_error(run("rta " + set + " --bitrate 1M --bitrate 500k"), "--bitrate given twice", 2);
  expect_one_line_error(run("rta " + set + " --bitrate 2M"), "--bitrate must be 1k..1M bit/s, got \"2M\"", 2);
  expect_one_line_error(run("rta " + set + " --bitrate 1M --frame-bits exact"),
                        "--frame-bits must be course|davis, got \"exact\"", 2);
  expect_one_line_error(run("rta " + set + " --bitrate 1M --json --csv"), "choose one of --json and --csv",
                        2);
  expect_one_line_error(run("rta " + set + " --bitrate 1M --window-us 5"),
                        "--window-us is not an option of rta (try mb2co-timing rta --help)", 2);
  expect_one_line_error(run("rta " + set + " --bitrate 1M --bogus"),
                        "unknown option --bogus (try mb2co-timing rta --help)", 2);
  expect_one_line_error(run("rta " + set + " --bitrate 1M --svg x.svg"),
                        "options --svg FILE and --message NAME go together", 2);
  expect_one_line_error(run("rta " + set + " --bitrate 1M --svg x.svg --message NOPE"),
                        "--message: no message named \"NOPE\"", 2);
  expect_one_line_error(run("rta " + set + " --bitrate 1M --sync-us 100"),
                        "--sync-us describes a line: add --line N", 2);
  expect_one_line_error(run("rta " + set + " extra.csv --bitrate 1M"),
                        "unexpected argument \"extra.csv\" (try mb2co-timing rta --help)", 2);
  expect_one_line_error(run("rta --line 3 --tpdo-inhibit-100us 0"),
                        "event-driven TPDO1 needs --tpdo-inhibit-100us > 0 (its minimum "
                        "inter-arrival time)",
                        2);
  expect_one_line_error(
      run("bogus"),
      "unknown command \"bogus\" (frame, load, rta, latency or serial) (try mb2co-timing --help)", 2);
  expect_one_line_error(run(""),
                        "missing command (frame, load, rta, latency or serial) (try mb2co-timing --help)", 2);
  expect_one_line_error(run("frame --data 123"), "--data/--rtr needs --id", 2);
  expect_one_line_error(run("latency --button-node 1"),
                        "--button-node and --pc-node must be different nodes within 1..--line", 2);
  expect_one_line_error(run("latency --parity space"),
                        "--parity must be N, E or O (none, even, odd), got \"space\"", 2);
}

// "--bitrate 500" was 500 bit/s here and 500 kbit/s elsewhere: refused, with the likely meaning.
TEST_F(Cli, BareBitrateBelow10000IsRefusedWithAHint) {
  expect_one_line_error(
      run("rta --line 3 --bitrate 500"),
      "--bitrate must be at least 10000 as a bare number (bit/s), got \"500\"; did you mean 500k?", 2);
  const Result k = run("rta --line 3 --bitrate 500k --json");
  const Result bps = run("rta --line 3 --bitrate 500000 --json");
  EXPECT_EQ(k.status, 0);
  EXPECT_EQ(k.out, bps.out);
  EXPECT_NE(k.out.find("\"bitrate\": 500000"), std::string::npos) << k.out;
  EXPECT_EQ(run("rta --line 3 --bitrate 1000k --json").out, run("rta --line 3 --bitrate 1M --json").out);
}

// Parity letters and words in any case mean the same (docs/cli.md).
TEST_F(Cli, ParityLettersAndWordsAgree) {
  const std::string even = run("latency --parity even --json").out;
  EXPECT_FALSE(even.empty());
  EXPECT_EQ(run("latency --parity E --json").out, even);
  EXPECT_EQ(run("latency --parity Even --json").out, even);
  const std::string none = run("latency --parity n --json").out;
  EXPECT_EQ(run("latency --parity NONE --json").out, none);
  EXPECT_NE(none, even);
}

TEST_F(Cli, HelpPerCommandAndVersion) {
  const Result all = run("--help");
  EXPECT_EQ(all.status, 0);
  EXPECT_NE(all.out.find("latency"), std::string::npos);
  const Result rta = run("rta --help");
  EXPECT_EQ(rta.status, 0);
  EXPECT_EQ(rta.out.rfind("usage: mb2co-timing rta [options] [FILE.csv]\n", 0), 0u) << rta.out;
  EXPECT_NE(rta.out.find("--check"), std::string::npos);
  EXPECT_EQ(rta.out.find("--window-us"), std::string::npos) << "load's option in rta's help";
  const Result v = run("--version");
  EXPECT_EQ(v.status, 0);
  EXPECT_EQ(v.out, std::string("mb2co-timing ") + MB2CO_VERSION + "\n");
}

}  // namespace
