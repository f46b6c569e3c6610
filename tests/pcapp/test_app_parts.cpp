// Options, port detection, back-off, the cycle log, the status view.
#include <gtest/gtest.h>

#include <QCoreApplication>
#include <cstdio>
#include <fstream>

#include "backoff.h"
#include "cycle_log.h"
#include "options.h"
#include "port_finder.h"
#include "status_view.h"

using mb2co::Status;
using namespace mb2co::pcapp;

namespace {
// What the command line comes to: run, print `msg` and exit 0, or fail with `msg`.
enum class ParseOutcome { kRun, kExitOk, kError };

ParseOutcome parse(QStringList args, AppOptions& o, QString& msg) {
  args.prepend("mb2co-plant");
  const Status status = parse_options(args, o);
  if (!status) {
    msg = QString::fromStdString(status.message());
    return ParseOutcome::kError;
  }
  msg = o.exit_text;
  return o.exit_text.isEmpty() ? ParseOutcome::kRun : ParseOutcome::kExitOk;
}

// The picked port, or "" with the reason in `error`.
QString pick_arduino(const std::vector<PortInfo>& ports, QString& error) {
  QString path;
  const Status status = mb2co::pcapp::pick_arduino(ports, &path);
  if (!status) error = QString::fromStdString(status.message());
  return path;
}
}  // namespace

TEST(Options, Defaults) {
  AppOptions o;
  QString msg;
  ASSERT_EQ(parse({}, o, msg), ParseOutcome::kRun);
  EXPECT_FALSE(o.latency);
  EXPECT_EQ(o.baud, 115200);
  EXPECT_EQ(mb2co::modbus::parity_letter(o.parity), 'N');
  EXPECT_EQ(o.cycle_ms, -1);
  EXPECT_EQ(o.boot_wait_ms, -1);
  EXPECT_EQ(o.timeout_ms, -1) << "derived from the line";
  EXPECT_EQ(o.retries, 2);
}

TEST(Options, LatencyMode) {
  AppOptions o;
  QString msg;
  ASSERT_EQ(parse({"latency", "--remote", "--button", "stop2", "--presses", "5", "--no-reset-wait"}, o, msg),
            ParseOutcome::kRun);
  EXPECT_TRUE(o.latency);
  EXPECT_TRUE(o.remote);
  EXPECT_EQ(o.button, 4);
  EXPECT_EQ(o.presses, 5u);
  EXPECT_EQ(o.boot_wait_ms, 0);
  EXPECT_EQ(o.drift_ppm, 100u) << "the clock offset's drift term by default";
}

TEST(Options, DriftPpmBelongsToLatencyRemote) {
  AppOptions o;
  QString msg;
  ASSERT_EQ(parse({"latency", "--remote", "--drift-ppm", "0"}, o, msg), ParseOutcome::kRun)
      << msg.toStdString();
  EXPECT_EQ(o.drift_ppm, 0u);
  EXPECT_EQ(parse({"latency", "--drift-ppm", "50"}, o, msg), ParseOutcome::kError);
  EXPECT_EQ(msg.toStdString(), "--drift-ppm belongs to latency --remote");
  EXPECT_EQ(parse({"latency", "--remote", "--drift-ppm", "100001"}, o, msg), ParseOutcome::kError);
}

// docs/cli.md: the letters and the words, in any letter case, as every program takes them.
TEST(Options, ParityLettersAndWords) {
  const struct {
    const char* given;
    char parity;
  } cases[] = {{"E", 'E'}, {"even", 'E'}, {"Odd", 'O'}, {"o", 'O'}, {"NONE", 'N'}, {"n", 'N'}};
  for (const auto& c : cases) {
    AppOptions o;
    QString msg;
    ASSERT_EQ(parse({"--parity", c.given}, o, msg), ParseOutcome::kRun) << c.given;
    EXPECT_EQ(mb2co::modbus::parity_letter(o.parity), c.parity) << c.given;
  }
}

TEST(Options, BadValuesGiveOneLine) {
  const struct {
    QStringList args;
    const char* message;
  } cases[] = {
      {{"--cycle-ms", "0"}, "--cycle-ms must be a whole number 1..1000, got \"0\""},
      {{"--baud", "12345"}, "--baud must be a standard rate such as 9600, 19200, 115200, got \"12345\""},
      {{"--parity", "X"}, "--parity must be N, E or O (none, even, odd), got \"X\""},
      {{"--baud"}, "--baud needs a value"},
      {{"--slave", "2", "--slave", "3"}, "--slave given twice"},
      {{"--slave", "248"}, "--slave must be a whole number 1..247, got \"248\""},
      {{"--retries", "x"}, "--retries must be a whole number 0..10, got \"x\""},
      {{"run"}, "unknown mode \"run\" (station or latency) (try mb2co-plant --help)"},
      {{"latncy"}, "unknown mode \"latncy\" (did you mean latency?) (try mb2co-plant --help)"},
      {{"station", "latency"}, "unexpected argument \"latency\" (try mb2co-plant --help)"},
      {{"--presses", "3"},
       "--remote, --button, --presses and --csv belong to the latency mode (mb2co-plant latency ...)"},
      {{"latency", "--button", "GO"}, "--button must be START, STOP or STOP2, got \"GO\""},
      {{"--no-reset-wait", "--boot-wait-ms", "5"}, "--no-reset-wait and --boot-wait-ms exclude each other"},
      {{"--bogus"}, "unknown option --bogus (try mb2co-plant --help)"},
      {{"--cycels"}, "unknown option --cycels, did you mean --cycles? (try mb2co-plant --help)"},
      {{"--plain=yes"}, "--plain takes no value"},
  };
  for (const auto& c : cases) {
    AppOptions o;
    QString msg;
    EXPECT_EQ(parse(c.args, o, msg), ParseOutcome::kError) << c.message;
    EXPECT_EQ(msg.toStdString(), c.message);
    EXPECT_FALSE(msg.contains('\n'));
  }
}

TEST(PortFinder, ArduinoIds) {
  EXPECT_TRUE(is_arduino_usb(0x2341, 0x0043));  // Uno R3
  EXPECT_TRUE(is_arduino_usb(0x2A03, 0x0043));
  EXPECT_TRUE(is_arduino_usb(0x1A86, 0x7523));  // CH340 clone
  EXPECT_FALSE(is_arduino_usb(0x1A86, 0x5523));
  EXPECT_FALSE(is_arduino_usb(0x0403, 0x6001));  // FTDI
}

TEST(PortFinder, PicksTheOneArduino) {
  std::vector<PortInfo> ports(3);
  ports[0].path = "/dev/ttyS0";
  ports[1].path = "/dev/ttyACM0";
  ports[1].arduino = true;
  ports[1].has_ids = true;
  ports[1].vendor_id = 0x2341;
  ports[1].product_id = 0x43;
  ports[2].path = "/dev/ttyUSB0";
  QString error;
  EXPECT_EQ(pick_arduino(ports, error), "/dev/ttyACM0");
  EXPECT_TRUE(is_arduino_port(ports, "/dev/ttyACM0"));
  EXPECT_FALSE(is_arduino_port(ports, "/dev/ttyUSB0"));
  EXPECT_TRUE(format_ports(ports).contains("/dev/ttyACM0  2341:0043  [Arduino]\n"));
  ports[2].arduino = true;
  EXPECT_TRUE(pick_arduino(ports, error).isEmpty());
  EXPECT_EQ(error, "several Arduinos found (/dev/ttyACM0, /dev/ttyUSB0): choose one with --port");
  ports[1].arduino = ports[2].arduino = false;
  EXPECT_TRUE(pick_arduino(ports, error).isEmpty());
  EXPECT_TRUE(error.startsWith("no Arduino found"));
}

TEST(Backoff, DoublesUpToTheCapAndResets) {
  Backoff b(100, 1000);
  EXPECT_EQ(b.next_ms(), 100u);
  EXPECT_EQ(b.next_ms(), 200u);
  EXPECT_EQ(b.next_ms(), 400u);
  EXPECT_EQ(b.next_ms(), 800u);
  EXPECT_EQ(b.next_ms(), 1000u);
  EXPECT_EQ(b.next_ms(), 1000u);
  b.reset();
  EXPECT_EQ(b.next_ms(), 100u);
}

TEST(CycleLog, CsvAndJsonlRows) {
  const std::vector<const char*> names = {"cycle", "state", "level_ml"};
  const std::vector<LogValue> row = {{12, nullptr}, {0, "moving"}, {-3, nullptr}};
  std::string s;
  format_csv_header(names, s);
  format_row(LogFormat::kCsv, names, row, s);
  EXPECT_EQ(s, "cycle,state,level_ml\n12,moving,-3\n");
  s.clear();
  format_row(LogFormat::kJsonl, names, row, s);
  EXPECT_EQ(s, "{\"cycle\":12,\"state\":\"moving\",\"level_ml\":-3}\n");
}

TEST(CycleLog, FileByExtension) {
  const std::string path = ::testing::TempDir() + "pcapp_log_test.jsonl";
  {
    CycleLog log;
    const Status opened = log.open(path, {"a"});
    ASSERT_TRUE(opened) << opened.message();
    log.write({{1, nullptr}});
    log.write({{2, nullptr}});
  }
  std::ifstream in(path);
  std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(all, "{\"a\":1}\n{\"a\":2}\n");
  CycleLog log;
  Status status = log.open(::testing::TempDir() + "x.txt", {"a"});
  EXPECT_FALSE(status);
  EXPECT_EQ(status.message(),
            "--log " + ::testing::TempDir() + "x.txt: want a name ending in .csv or .jsonl");
  status = log.open("/nonexistent-dir/x.csv", {"a"});
  EXPECT_FALSE(status);
  EXPECT_EQ(status.message(), "--log /nonexistent-dir/x.csv: No such file or directory");
}

TEST(StatusView, PlainLinesOrOneLiveLine) {
  char buf[512] = {};
  std::FILE* f = fmemopen(buf, sizeof buf, "w");
  StatusView plain(f, false);
  plain.status("ignored");
  plain.event(1.5, "state moving");
  plain.finish();
  std::fclose(f);
  EXPECT_STREQ(buf, "1.500 state moving\n");

  char tbuf[512] = {};
  f = fmemopen(tbuf, sizeof tbuf, "w");
  StatusView term(f, true);
  term.status("station moving");
  term.event(2, "state stopped");
  term.status("station stopped");
  term.finish();
  std::fclose(f);
  EXPECT_STREQ(tbuf, "\r\033[Kstation moving\r\033[K2.000 state stopped\n\r\033[Kstation stopped\n");
}
