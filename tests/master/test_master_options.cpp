// mb2co-master's command line on the shared layer (pcapp/master/cli_options.h),
// without a bus: every subcommand has its --help and its function, global
// options stand before or after the subcommand, watch's --heartbeat is not
// the SDO watchdog, the gateway's PORT:SLAVE and serial line are read, and
// every usage error is one line and exit 2 before anything is opened.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include "bus_loop.h"
#include "cli_options.h"
#include "commands.h"
#include "exit_codes.h"
#include "transport.h"

namespace mb2co {
namespace master {
namespace {

cli::Parsed parse(std::vector<std::string> words) {
  words.insert(words.begin(), "mb2co-master");
  std::vector<const char*> argv;
  argv.reserve(words.size());
  for (const std::string& w : words) argv.push_back(w.c_str());
  return cli::parse(program(), static_cast<int>(argv.size()), argv.data());
}

/// The options of a run that parses; fails the test otherwise.
Options options_of(const std::vector<std::string>& words) {
  const cli::Parsed p = parse(words);
  Options o;
  EXPECT_EQ(p.action, cli::Action::kRun) << p.text;
  const Status s = apply_options(p.args, &o);
  EXPECT_TRUE(s) << s.message();
  return o;
}

/// What main() prints and returns for a usage error: (exit status, stderr).
std::pair<int, std::string> usage_error(const std::vector<std::string>& words) {
  const cli::Parsed p = parse(words);
  std::ostringstream out, err;
  int code = cli::finish_early(program(), p, out, err);
  if (code < 0) {
    Options o;
    const Status s = apply_options(p.args, &o);
    code = s ? -1 : fail(err, kExitUsage, s.message());
  }
  EXPECT_TRUE(out.str().empty());
  return {code, err.str()};
}

TEST(MasterOptions, EverySubcommandHasItsHelpAndItsFunction) {
  ASSERT_GE(program().commands.size(), 10u);
  for (const cli::Command& c : program().commands) {
    EXPECT_NE(command_function(c.name), nullptr) << c.name;
    const cli::Parsed p = parse({c.name, "--help"});
    ASSERT_EQ(p.action, cli::Action::kHelp) << c.name;
    EXPECT_EQ(p.text.rfind("usage: mb2co-master " + c.name + " [options]", 0), 0u) << p.text;
    for (const cli::Option& o : c.options) EXPECT_NE(p.text.find(o.name), std::string::npos) << c.name;
    EXPECT_NE(p.text.find("--watchdog MS"), std::string::npos) << "the global options too: " << c.name;
    EXPECT_NE(p.text.find("2 usage error"), std::string::npos) << "the exit codes in the footer";
  }
  EXPECT_EQ(command_function("fly"), nullptr);
  const std::string sync = parse({"sync", "--help"}).text;
  EXPECT_NE(sync.find("--period MS"), std::string::npos);
  EXPECT_EQ(sync.find("--raw"), std::string::npos) << "watch's options are not sync's";
  EXPECT_EQ(parse({"--version"}).text, std::string("mb2co-master ") + cli::version() + "\n");
}

TEST(MasterOptions, GlobalOptionsBeforeOrAfterTheSubcommand) {
  Options o = options_of({"-i", "vcan1", "read", "2,3", "1018", "1", "u32", "-t", "300", "--json"});
  EXPECT_EQ(o.command, "read");
  EXPECT_EQ(o.iface, "vcan1");
  EXPECT_EQ(o.timeout_ms, 300u);
  EXPECT_TRUE(o.json);
  EXPECT_EQ(o.args.operands, (std::vector<std::string>{"2,3", "1018", "1", "u32"}));
  o = options_of({"scan"});
  EXPECT_EQ(o.iface, "can0");
  EXPECT_EQ(o.timeout_ms, 1000u);
  EXPECT_EQ(o.watchdog_ms, 0u);
  EXPECT_FALSE(o.json);
  // A negative VALUE is an operand, not an option.
  o = options_of({"write", "2", "2000", "6", "i8", "-5"});
  EXPECT_EQ(o.args.operands.back(), "-5");
}

TEST(MasterOptions, WatchHeartbeatIsWatchsOwnTheWatchdogIsGlobal) {
  Options o = options_of({"watch", "--nodes", "3", "--heartbeat", "400"});
  EXPECT_EQ(o.args.uint("--heartbeat", 1000), 400u);
  EXPECT_EQ(o.watchdog_ms, 0u) << "watch --heartbeat is not the SDO watchdog";
  o = options_of({"--watchdog", "500", "upload", "4-6", "1F50", "1", "up", "--segmented"});
  EXPECT_EQ(o.watchdog_ms, 500u);
  EXPECT_TRUE(o.args.has("--segmented"));
  const auto e = usage_error({"read", "2", "1000", "0", "--heartbeat", "500"});
  EXPECT_EQ(e.first, 2);
  EXPECT_EQ(e.second, "mb2co-master: --heartbeat is not an option of read (try mb2co-master read --help)\n");
}

TEST(MasterOptions, GatewayPortSlaveAndSerialLine) {
  Options o = options_of(
      {"--via-modbus", "/dev/ttyACM0:9", "--baud", "19200", "--parity", "even", "read", "2", "1000", "0"});
  EXPECT_EQ(o.gateway_port, "/dev/ttyACM0");
  EXPECT_EQ(o.gateway_slave, 9u);
  EXPECT_EQ(o.baud, 19200u);
  EXPECT_EQ(o.parity, 'E');
  o = options_of({"--via-modbus", "/tmp/st3", "scan", "1", "10"});
  EXPECT_EQ(o.gateway_port, "/tmp/st3");
  EXPECT_EQ(o.gateway_slave, 1u);
  EXPECT_EQ(o.baud, 115200u);
  EXPECT_EQ(o.parity, 'N');
  EXPECT_TRUE(via_modbus_refusal(o).empty());
}

TEST(MasterOptions, UsageErrorsAreOneLineAndExit2) {
  struct Case {
    std::vector<std::string> words;
    const char* says;
  } const cases[] = {
      {{"fly"}, "unknown command \"fly\""},
      {{}, "missing command"},
      {{"read", "1", "1000", "0", "-t"}, "--timeout needs a value"},
      {{"read", "1", "1000", "0", "--eds", "--json"}, "--eds needs a value"},
      {{"-t", "0", "scan"}, "--timeout must be a whole number 1..600000, got \"0\""},
      // -t's value is missing: the command's name is taken as it.
      {{"-t", "read", "1", "1000", "0"}, "--timeout must be a whole number 1..600000, got \"read\""},
      {{"sync", "--count", "0"}, "--count must be a whole number 1..1000000"},
      {{"watch", "--for", "1h"}, "--for must be a duration"},
      {{"scan", "1", "2", "3"}, "unexpected argument \"3\""},
      {{"--via-modbus", "/dev/ttyACM0", "--parity", "X", "scan"}, "--parity must be N, E or O"},
      {{"--parity", "E", "scan"}, "--parity is the serial line's: only with --via-modbus PORT"},
      {{"--baud", "9600", "scan"}, "--baud is the serial line's"},
      {{"--via-modbus", "/dev/ttyACM0:0", "scan"}, "--via-modbus SLAVE must be 1..247, got \"0\""},
      {{"--via-modbus", "/dev/ttyACM0:248", "scan"}, "--via-modbus SLAVE must be 1..247, got \"248\""},
      {{"--via-modbus", "/dev/ttyACM0", "watch"}, "watch needs raw CAN frames"},
      {{"--via-modbus", "/dev/ttyACM0", "sync"}, "sync needs raw CAN frames"},
      {{"--via-modbus", "/dev/ttyACM0", "--watchdog", "500", "read", "2", "1000", "0"},
       "--watchdog (the watchdog listens to heartbeats) needs raw CAN frames"},
      {{"--via-modbus", "/dev/ttyACM0", "upload", "2", "1F50", "1", "f", "--block"},
       "upload --block (block transfer) needs raw CAN frames"},
  };
  for (const Case& c : cases) {
    const auto e = usage_error(c.words);
    EXPECT_EQ(e.first, kExitUsage) << c.says;
    EXPECT_EQ(e.second.rfind("mb2co-master: ", 0), 0u) << e.second;
    EXPECT_NE(e.second.find(c.says), std::string::npos) << e.second;
    EXPECT_EQ(std::count(e.second.begin(), e.second.end(), '\n'), 1) << "one line: " << e.second;
  }
}

/// A transport that counts the commands' attempts to open it and has no bus
/// behind it: opening fails as a missing interface does.
class NoBus : public Transport {
 public:
  Status open(const Options&) override {
    ++opened;
    return Status::failure("no bus here");
  }
  std::unique_ptr<TransferNetwork> transfers(const Options&) override { return nullptr; }
  Status nmt(canopen::NmtCommand, uint8_t) override { return Status::failure("not open"); }
  BusLoop* bus() override { return &loop; }  // never opened: watch and sync get past their check
  int opened = 0;
  BusLoop loop;
};

/// Runs the command of `words` on `transport` as main() does.
int run_command(const std::vector<std::string>& words, NoBus* transport, std::string* err) {
  Options o = options_of(words);
  const CommandFunction run = command_function(o.command);
  if (run == nullptr) return -1;
  std::ostringstream out, e;
  const int code = run(o, *transport, out, e);
  *err = e.str();
  EXPECT_TRUE(out.str().empty()) << out.str();
  return code;
}

TEST(MasterOptions, BadOperandsAreUsageErrorsBeforeTheInterfaceIsOpened) {
  struct Case {
    std::vector<std::string> words;
    const char* says;
  } const cases[] = {
      {{"scan", "5", "2"}, "scan: LAST below FIRST"},
      {{"read", "2", "1G00", "0", "u8"}, "read: index must be hexadecimal 0000..FFFF, got \"1G00\""},
      {{"read", "2", "1000", "0", "q7"},
       "read: TYPE must be one of b u8 u16 u24 u32 u64 i8 i16 i32 i64 r32 r64 vs os us d, got \"q7\""},
      {{"write", "2", "2000", "6", "u16", "70000"}, "out of range"},
      {{"upload", "2", "1F50", "1", "f", "--block", "--segmented"}, "--block or --segmented, not both"},
      {{"download", "2", "1F50", "1", "/nonexistent/file"}, "download: cannot read /nonexistent/file"},
      {{"nmt", "start", "128"}, "nmt: node id must be 1..127 or all, got \"128\""},
      {{"nmt", "jump", "3"},
       "nmt: the NMT command must be start, stop, preop, reset or reset-comm, got \"jump\""},
      {{"sync", "--count", "3"}, "--count above 1 needs --period MS"},
      {{"sync", "--overflow", "1"}, "--overflow 1 is not allowed"},
      {{"sync", "--cob-id", "0x800"}, "sync: --cob-id must be 0..2047 (decimal, 0x.. or ..h), got \"0x800\""},
      {{"watch", "--nodes", "5-2"}, "a node range must run upwards (5-7), got \"5-2\""},
      {{"watch", "--life", "3"}, "only with --guard"},
      {{"dump", "3"}, "dump: needs --eds FILE"},
      {{"configure", "/nonexistent/net.cpj"}, "configure: "},
  };
  for (const Case& c : cases) {
    NoBus transport;
    std::string err;
    EXPECT_EQ(run_command(c.words, &transport, &err), kExitUsage) << c.says;
    EXPECT_EQ(transport.opened, 0) << c.says;
    EXPECT_NE(err.find(c.says), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << "one line: " << err;
  }
  // Good words: the interface is opened, and its absence is exit 3.
  NoBus transport;
  std::string err;
  EXPECT_EQ(run_command({"nmt", "start", "3"}, &transport, &err), kExitBus);
  EXPECT_EQ(transport.opened, 1);
  EXPECT_EQ(err, "mb2co-master: no bus here\n");
}

}  // namespace
}  // namespace master
}  // namespace mb2co
