// The parser of shared/host/cli.h on a small program with subcommands and
// global options: what runs, what is a usage error (and its one line), and
// that --help, --version and --list-options come from the same table.
#include <gtest/gtest.h>

#include <sstream>

#include "host/cli.h"

namespace {

using namespace mb2co;
using namespace mb2co::cli;

const Program& tool() {
  static const Program p = [] {
    Program t;
    t.name = "tool";
    t.description = "A tool.\n";
    t.commands = {
        Command{"send",
                "send frames",
                "[FILE]",
                1,
                {bitrate_of("--bitrate", can_bitrates(), "CAN bit rate"), flag("--loop", "again and again"),
                 uint_range("--count", "N", 1, 10, "frames")}},
        Command{"watch", "watch the bus", "", 0, {parity("--parity", "serial parity")}},
    };
    t.global_options = {text("--interface", "IFACE", "CAN interface").with_short('i')};
    t.footer = "exit status: 0 done\n";
    return t;
  }();
  return p;
}

Parsed run(std::vector<std::string> words) {
  words.insert(words.begin(), "tool");
  std::vector<const char*> argv;
  argv.reserve(words.size());
  for (const std::string& w : words) argv.push_back(w.c_str());
  return parse(tool(), static_cast<int>(argv.size()), argv.data());
}

std::string error_of(const std::vector<std::string>& words) {
  const Parsed p = run(words);
  EXPECT_EQ(p.action, Action::kUsageError);
  return p.text;
}

TEST(CliParse, OptionsInEitherFormAndOperands) {
  const Parsed p = run({"-i", "vcan0", "send", "--bitrate=500k", "--loop", "f.log", "--count", "3"});
  ASSERT_EQ(p.action, Action::kRun) << p.text;
  ASSERT_NE(p.args.command, nullptr);
  EXPECT_EQ(p.args.command->name, "send");
  EXPECT_EQ(p.args.get("--interface"), "vcan0");
  EXPECT_EQ(p.args.bitrate_bps("--bitrate", 0), 500000u);
  EXPECT_TRUE(p.args.has("--loop"));
  EXPECT_EQ(p.args.uint("--count", 1), 3u);
  EXPECT_EQ(p.args.operands, std::vector<std::string>{"f.log"});
  const Parsed after = run({"watch", "--parity", "even", "--interface", "can1"});
  ASSERT_EQ(after.action, Action::kRun) << after.text;
  EXPECT_EQ(after.args.get("--interface"), "can1") << "a global option after the command";
  EXPECT_EQ(after.args.parity("--parity", Parity::kNone), Parity::kEven);
  EXPECT_EQ(after.args.uint("--count", 7), 7u) << "the fallback when absent";
}

TEST(CliParse, DoubleDashEndsTheOptions) {
  const Parsed p = run({"send", "--", "--loop"});
  ASSERT_EQ(p.action, Action::kRun) << p.text;
  EXPECT_FALSE(p.args.has("--loop"));
  EXPECT_EQ(p.args.operands, std::vector<std::string>{"--loop"});
}

TEST(CliParse, NegativeNumbersAreValuesAndOperands) {
  // mb2co-master write 2 2000 6 i8 -5: "-5" is no option of anyone.
  const Parsed p = run({"send", "-5", "--count", "3"});
  ASSERT_EQ(p.action, Action::kRun) << p.text;
  EXPECT_EQ(p.args.operands, std::vector<std::string>{"-5"});
  EXPECT_EQ(run({"send", "-12"}).args.operands, std::vector<std::string>{"-12"});
  EXPECT_EQ(error_of({"send", "-x"}), "unknown option -x (try tool send --help)");
}

TEST(CliParse, UsageErrorsSayWhatIsWrongInOneLine) {
  EXPECT_EQ(error_of({"send", "--bitrate"}), "--bitrate needs a value");
  EXPECT_EQ(error_of({"send", "--bitrate", "--loop"}), "--bitrate needs a value");
  EXPECT_EQ(error_of({"send", "--bitrate="}), "--bitrate needs a value");
  EXPECT_EQ(error_of({"send", "--bitrate", "500"}),
            "--bitrate must be at least 10000 as a bare number (bit/s), got \"500\"; did you mean 500k?");
  EXPECT_EQ(error_of({"send", "--count", "11"}), "--count must be a whole number 1..10, got \"11\"");
  EXPECT_EQ(error_of({"send", "--loop", "--loop"}), "--loop given twice");
  EXPECT_EQ(error_of({"send", "--loop=yes"}), "--loop takes no value");
  EXPECT_EQ(error_of({"send", "--bogus"}), "unknown option --bogus (try tool send --help)");
  EXPECT_EQ(error_of({"send", "--parity", "E"}), "--parity is not an option of send (try tool send --help)");
  EXPECT_EQ(error_of({"send", "a", "b"}), "unexpected argument \"b\" (try tool send --help)");
  EXPECT_EQ(error_of({}), "missing command (send or watch) (try tool --help)");
  EXPECT_EQ(error_of({"sned"}), "unknown command \"sned\" (did you mean send?) (try tool --help)");
  EXPECT_EQ(error_of({"frob"}), "unknown command \"frob\" (send or watch) (try tool --help)");
  EXPECT_EQ(error_of({"--bogus", "send"}), "unknown option --bogus (try tool --help)");
  EXPECT_EQ(error_of({"-i"}), "--interface needs a value");
  EXPECT_EQ(error_of({"-i", "--count", "3"}), "--interface needs a value");
}

TEST(CliParse, ANearOptionNameIsOfferedAsGitDoes) {
  EXPECT_EQ(error_of({"send", "--bitrat", "500k"}),
            "unknown option --bitrat, did you mean --bitrate? (try tool send --help)");
  EXPECT_EQ(error_of({"send", "--cuont", "3"}),
            "unknown option --cuont, did you mean --count? (try tool send --help)")
      << "two letters swapped are one edit";
  EXPECT_EQ(error_of({"send", "--interfase", "can0"}),
            "unknown option --interfase, did you mean --interface? (try tool send --help)")
      << "a global option is near too";
  EXPECT_EQ(error_of({"--interfase", "can0", "send"}),
            "unknown option --interfase, did you mean --interface? (try tool --help)");
  EXPECT_EQ(error_of({"send", "--bogus"}), "unknown option --bogus (try tool send --help)") << "nothing near";
}

TEST(CliParse, FewerOperandsThanTheCommandNeedsAreMissing) {
  Program p;
  p.name = "hub";
  Command c;
  c.operands = "MEMBER MEMBER [MEMBER]...";
  c.min_operands = 2;
  c.max_operands = 8;
  p.commands = {c};
  const char* one[] = {"hub", "a"};
  const Parsed r = parse(p, 2, one);
  ASSERT_EQ(r.action, Action::kUsageError);
  EXPECT_EQ(r.text, "missing operand: MEMBER MEMBER [MEMBER]... (try hub --help)");
  const char* two[] = {"hub", "a", "b"};
  EXPECT_EQ(parse(p, 3, two).action, Action::kRun);
}

TEST(CliParse, HelpOfTheCommandNamedWhereverItStands) {
  const Parsed send = run({"send", "--bitrate", "nonsense", "--help"});
  ASSERT_EQ(send.action, Action::kHelp);
  EXPECT_EQ(send.text.rfind("usage: tool send [options] [FILE]\nsend frames\n", 0), 0u) << send.text;
  EXPECT_NE(send.text.find("  --bitrate B"), std::string::npos);
  EXPECT_NE(send.text.find("  -i, --interface IFACE"), std::string::npos)
      << "globals in every command's help";
  EXPECT_EQ(send.text.find("--parity"), std::string::npos) << "watch's option";
  const Parsed all = run({"-h"});
  ASSERT_EQ(all.action, Action::kHelp);
  EXPECT_EQ(all.text.rfind("usage: tool COMMAND [options]\n", 0), 0u) << all.text;
  EXPECT_NE(all.text.find("  watch"), std::string::npos);
  EXPECT_NE(all.text.find("  -h, --help"), std::string::npos) << "the short form in the program's help too";
  EXPECT_EQ(run({"send", "--", "--help"}).action, Action::kRun) << "an operand after --";
}

TEST(CliParse, VersionIsTheProjectsOne) {
  const Parsed v = run({"watch", "--version"});
  ASSERT_EQ(v.action, Action::kVersion);
  EXPECT_EQ(v.text, std::string("tool ") + MB2CO_VERSION + "\n");
  EXPECT_STREQ(version(), MB2CO_VERSION);
}

TEST(CliParse, ListOptionsGivesTheWordsOfTheTable) {
  const Parsed commands = run({"--list-options"});
  ASSERT_EQ(commands.action, Action::kListOptions);
  EXPECT_EQ(commands.text.rfind("send\nwatch\n", 0), 0u) << commands.text;
  const Parsed send = run({"send", "--list-options"});
  EXPECT_NE(send.text.find("--bitrate choice 125k 250k 500k 1M\n"), std::string::npos) << send.text;
  EXPECT_NE(send.text.find("--loop flag\n"), std::string::npos);
  EXPECT_NE(send.text.find("--interface value\n"), std::string::npos);
  EXPECT_EQ(run({"watch", "--list-options"}).text.find("--loop"), std::string::npos);
}

TEST(CliParse, FinishEarlyPrintsAndGivesTheExitStatus) {
  std::ostringstream out, err;
  EXPECT_EQ(finish_early(tool(), run({"send", "--bogus"}), out, err), kExitUsage);
  EXPECT_EQ(err.str(), "tool: unknown option --bogus (try tool send --help)\n");
  EXPECT_EQ(out.str(), "");
  std::ostringstream out2, err2;
  EXPECT_EQ(finish_early(tool(), run({"--version"}), out2, err2), kExitDone);
  EXPECT_EQ(err2.str(), "");
  EXPECT_EQ(finish_early(tool(), run({"watch"}), out2, err2), -1) << "go on and run";
}

TEST(CliParse, RefusedOptionsNameTheirOwner) {
  Program p;
  p.name = "uno";
  p.commands = {Command{"", "", "", 0, {refused("--bitrate", "is the node's: set it in the EEPROM")}}};
  const char* argv[] = {"uno", "--bitrate", "500k"};
  const Parsed r = parse(p, 3, argv);
  ASSERT_EQ(r.action, Action::kUsageError);
  EXPECT_EQ(r.text, "--bitrate is the node's: set it in the EEPROM");
  EXPECT_EQ(help_text(p, &p.commands[0]).find("--bitrate"), std::string::npos) << "hidden from --help";
}

}  // namespace
