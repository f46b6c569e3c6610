// mb2co-uno's command line, exit codes, pty link, control channel and EEPROM
// file: bad options exit 2 with one line, a missing or invalid image or CAN
// interface 1 with one line, SIGINT/SIGTERM/quit 0 with the link removed and
// the simulated/wall line; a node id saved in the EEPROM (2000h/1 + 1010h
// "save" over Modbus) is the id of the next start.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>

#include <cstdio>
#include <fstream>

#include "node_harness.h"
#include "uno_harness.h"

namespace mb2co {
namespace test {
namespace {

/// Runs mb2co-uno with `args` to its exit; the exit status, stderr in `err`.
int run(const std::vector<std::string>& args, std::string* err) {
  LineChild c;
  std::vector<std::string> argv{uno_program()};
  argv.insert(argv.end(), args.begin(), args.end());
  if (!c.start(argv)) return -2;
  c.close_stdin();
  const int status = c.wait_exit(20s);
  *err = c.stderr_text();
  return status;
}

bool one_line(const std::string& s) {
  return !s.empty() && s.find('\n') == s.size() - 1;
}

bool exists(const std::string& path) {
  struct stat st {};
  return lstat(path.c_str(), &st) == 0;
}

TEST(UnoCli, BadOptionsExit2WithOneLine) {
  const std::vector<std::vector<std::string>> bad = {
      {"--bogus"}, {"--can"}, {"--duration", "0"}, {"--duration", "x"}, {"--node-id", "3"}};
  for (const auto& args : bad) {
    std::string err;
    EXPECT_EQ(run(args, &err), 2) << args[0];
    EXPECT_TRUE(one_line(err)) << err;
    EXPECT_EQ(err.rfind("mb2co-uno: ", 0), 0u) << err;
  }
}

TEST(UnoCli, MissingOrInvalidImageExits1WithOneLine) {
  TempDir dir;
  std::string err;
  EXPECT_EQ(run({"--elf", dir.path("nothing.elf"), "--can", "none"}, &err), 1);
  EXPECT_TRUE(one_line(err)) << err;
  EXPECT_NE(err.find("nothing.elf"), std::string::npos) << err;
  std::ofstream(dir.path("text.elf")) << "not an ELF file\n";
  EXPECT_EQ(run({"--elf", dir.path("text.elf"), "--can", "none"}, &err), 1);
  EXPECT_TRUE(one_line(err)) << err;
  std::ofstream(dir.path("short.eeprom")) << "too short";
  EXPECT_EQ(run({"--elf", uno_elf(), "--can", "none", "--eeprom", dir.path("short.eeprom")}, &err), 1);
  EXPECT_TRUE(one_line(err)) << err;
}

TEST(UnoCli, MissingCanInterfaceExits1WithOneLine) {
  TempDir dir;
  std::string err;
  EXPECT_EQ(run({"--elf", uno_elf(), "--can", "nosuch0", "--pty", dir.path("uno.pty")}, &err), 1);
  EXPECT_TRUE(one_line(err)) << err;
  EXPECT_FALSE(exists(dir.path("uno.pty"))) << "no link left behind";
}

TEST(UnoCli, SignalsAndQuitExit0AndRemoveTheLink) {
  TempDir dir;
  for (int how = 0; how < 3; ++how) {
    UnoProcess uno;
    ASSERT_TRUE(uno.start({"--can", "none", "--pty", dir.path("uno.pty")})) << uno.error();
    EXPECT_TRUE(exists(dir.path("uno.pty")));
    if (how == 2) {
      EXPECT_EQ(uno.ask("quit", "bye"), "bye");
      EXPECT_EQ(uno.child.wait_exit(10s), 0);
    } else {
      EXPECT_EQ(uno.stop(how == 0 ? SIGTERM : SIGINT), 0);
    }
    EXPECT_FALSE(exists(dir.path("uno.pty")));
    EXPECT_NE(uno.child.stderr_text().find(" s simulated in "), std::string::npos) << uno.child.stderr_text();
  }
}

TEST(UnoCli, ControlChannelAnswersEveryLine) {
  TempDir dir;
  UnoProcess uno;
  ASSERT_TRUE(uno.start({"--can", "none", "--pty", dir.path("uno.pty")})) << uno.error();
  EXPECT_EQ(uno.ask("press START", "ok"), "ok");
  EXPECT_EQ(uno.ask("release START", "ok"), "ok");
  EXPECT_EQ(uno.ask("press FOO", "error").rfind("error unknown button", 0), 0u);
  EXPECT_EQ(uno.ask("click STOP 0", "error").rfind("error bad click duration", 0), 0u);
  EXPECT_EQ(uno.ask("state?", "error").rfind("error state?", 0), 0u);
  EXPECT_EQ(uno.ask("jump", "error"), "error unknown command 'jump' (help lists them)");
  EXPECT_EQ(uno.ask("press stop2", "ok"), "ok") << "button names in any letter case";
  EXPECT_EQ(uno.ask("RELEASE Stop2", "ok"), "ok");
  EXPECT_EQ(uno.ask("help", "help ").rfind("help press B", 0), 0u);
  const std::string leds = uno.ask("leds?", "leds ");
  EXPECT_EQ(field_of(leds, "self"), "0");
  EXPECT_NE(at_us_of(leds), 0u);
  EXPECT_EQ(uno.stop(), 0);
}

TEST(UnoCli, NodeIdSavedInEepromSurvivesARestart) {
  TempDir dir;
  const std::string eeprom = dir.path("uno.eeprom");
  {
    UnoProcess uno;
    ASSERT_TRUE(uno.start({"--can", "none", "--pty", dir.path("uno.pty"), "--eeprom", eeprom}))
        << uno.error();
    EXPECT_EQ(uno.node_id(), 1) << "no file yet: an erased EEPROM";
    ModbusMaster m;
    ASSERT_TRUE(m.open(uno.device(), 2000ms)) << m.error();
    ASSERT_EQ(modbus_write_register(m.ctx(), 2, 9), 1);  // 2000h/1 node id, from the next reset
    const uint16_t save[2] = {0x6576, 0x6173};  // 1010h/1 = "save", 1.5 s of EEPROM writes on the Uno
    const uint32_t before_us = uno.device_us();
    ASSERT_EQ(modbus_write_registers(m.ctx(), 11, 2, save), 2) << modbus_strerror(errno);
    // Answered at once; done when 1010h/1 reads 1 again (docs/register-map.md).
    uint16_t state[2] = {0, 0};
    for (int poll = 0; poll < 100000 && state[1] != 1; ++poll) {
      ASSERT_EQ(modbus_read_registers(m.ctx(), 11, 2, state), 2) << modbus_strerror(errno);
    }
    ASSERT_EQ(state[1], 1) << "the save ended";
    // A first save programs a whole slot (header, payload, CRC: > 400 bytes)
    // at 3.3 ms a byte in the board model (simavr alone: at once).
    const double took_ms = (uno.device_us() - before_us) / 1000.0;
    std::printf("first save: %.1f ms of the image's time\n", took_ms);
    RecordProperty("first_save_ms", std::to_string(took_ms));
    EXPECT_GT(took_ms, 400 * 3.3);
    m.close();
    EXPECT_EQ(uno.ask("quit", "bye"), "bye");
    EXPECT_EQ(uno.child.wait_exit(10s), 0);
  }
  struct stat st {};
  ASSERT_EQ(stat(eeprom.c_str(), &st), 0);
  EXPECT_EQ(st.st_size, 1024);
  UnoProcess again;
  ASSERT_TRUE(again.start({"--can", "none", "--pty", dir.path("uno.pty"), "--eeprom", eeprom}))
      << again.error();
  EXPECT_EQ(again.node_id(), 9) << "boot-up 709h: the saved id";
  EXPECT_EQ(again.stop(), 0);
}

// --image network: mb2co-gateway-network.elf of this build tree on the
// station's wiring (the panel's buttons and LEDs), the gateway's control
// channel. While that image is built larger than the part (OVERSIZE), the
// board refuses it with one line naming the file.
TEST(UnoCli, NetworkImageIsTheStationBoardWithItsOwnFile) {
  TempDir dir;
  LineChild help;
  ASSERT_TRUE(help.start({uno_program(), "--help"}));
  EXPECT_TRUE(help.wait_prefix("  --image gateway|network|ionode|echo", 10s));
  EXPECT_EQ(help.wait_exit(10s), 0);
  UnoProcess uno;
  const bool started = uno.start_command(
      {uno_program(), "--image", "network", "--can", "none", "--pty", dir.path("uno.pty")}, 20s);
  if (!network_gateway_is_uno()) {
    EXPECT_FALSE(started);
    EXPECT_EQ(uno.child.wait_exit(10s), 1);
    EXPECT_NE(uno.child.stderr_text().find("/mb2co-gateway-network.elf: "), std::string::npos)
        << uno.child.stderr_text();
    EXPECT_TRUE(one_line(uno.child.stderr_text())) << uno.child.stderr_text();
  } else {
    ASSERT_TRUE(started) << uno.error();
    ModbusMaster m;
    ASSERT_TRUE(m.open(uno.device(), 2000ms)) << m.error();
    // Network view (docs/gateway-network.md): the gateway itself, node 1.
    const Bytes view = m.raw_transaction({0x2B, 0x0D, 0x80, 0, 0, 0, 0, 0, 0, 0, 0, 0});
    // The answer as read: slave address, the 12-byte header, then 4 bytes a node.
    ASSERT_GE(view.size(), 17u) << "no FC 2Bh/0Dh answer";
    EXPECT_EQ(view[13], 1) << "the first node listed is the gateway's own";
    EXPECT_EQ(uno.stop(), 0);
  }
  // The station's wiring, whatever the file: the panel's buttons and LEDs.
  UnoProcess wired;
  ASSERT_TRUE(wired.start_command({uno_program(), "--image", "network", "--elf", uno_elf(), "--can", "none",
                                   "--pty", dir.path("wired.pty")},
                                  20s))
      << wired.error();
  EXPECT_EQ(wired.ask("press STOP2", "ok"), "ok");
  EXPECT_EQ(wired.ask("release STOP2", "ok"), "ok");
  const std::string leds = wired.ask("leds?", "leds ");
  for (const char* led : {"self", "prev", "next", "lab", "canerr"})
    EXPECT_NE(field_of(leds, led), "") << led << " in " << leds;
  EXPECT_EQ(wired.ask("state?", "error").rfind("error state?", 0), 0u) << "the gateway's control channel";
  EXPECT_EQ(wired.stop(), 0);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
