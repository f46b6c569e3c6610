// Black-box tests of what a station must never do, shared by mb2co-node
// (tests/node) and the real Uno image in mb2co-uno (tests/uno): run by itself
// after a restart, or act on a Modbus request it refused. The program runs
// with --can none on a pty and an EEPROM file; libmodbus is its master.
// Process: NodeProcess or UnoProcess. Addresses: docs/register-map.md.
#pragma once
#include <errno.h>
#include <gtest/gtest.h>

#include <string>
#include <thread>
#include <vector>

#include "node_harness.h"

namespace mb2co {
namespace test {

template <class Process>
class StationSafety : public ::testing::Test {
 protected:
  static constexpr int kHrRunCommand = 0, kHrNodeId = 2, kHrDebounce = 7, kHrSave = 11;
  static constexpr int kIrRunState = 1, kIrStopCause = 3;
  static constexpr int kDiRunState = 3;
  static constexpr int kCauseStopButton = 1, kCausePcSilent = 4;  // 2100h/4
  static constexpr uint32_t kWatchdogUs = 2000000;                // 2000h/9 default

  std::vector<std::string> args() const {
    return {"--can", "none", "--pty", dir_.path("station.pty"), "--eeprom", dir_.path("eeprom")};
  }
  /// Starts the program and opens the master on its pty.
  void start(Process& p, ModbusMaster& m) {
    ASSERT_TRUE(p.start(args())) << p.error();
    ASSERT_TRUE(m.open(p.device())) << m.error();
  }
  /// "save", then the poll docs/register-map.md describes: 1010h/1 reads 0
  /// while the save runs (it takes passes: ~1.5 s on the Uno), 1 when done.
  static void save(ModbusMaster& m) {
    const uint16_t signature[2] = {0x6576, 0x6173};  // 1010h/1 "save", high word first
    ASSERT_EQ(modbus_write_registers(m.ctx(), kHrSave, 2, signature), 2);
    uint16_t state[2] = {0, 0};
    for (int poll = 0; poll < 10000 && state[1] != 1; ++poll) {
      ASSERT_EQ(modbus_read_registers(m.ctx(), kHrSave, 2, state), 2);
    }
    EXPECT_EQ(state[1], 1) << "the save ended";
  }
  static int discrete_input(ModbusMaster& m, int address) {
    uint8_t bit = 0;
    return modbus_read_input_bits(m.ctx(), address, 1, &bit) == 1 ? bit : -1;
  }

  TempDir dir_;
};

TYPED_TEST_SUITE_P(StationSafety);

// A saved RUN command is not a parameter: after a restart the station is
// stopped with nobody on Modbus, and the watchdog runs from power-on (its
// stop cause shows up without any request). The PC starts it again.
TYPED_TEST_P(StationSafety, SavedRunCommandDoesNotStartTheStationAtPowerUp) {
  using T = StationSafety<TypeParam>;
  {
    TypeParam p;
    ModbusMaster m;
    this->start(p, m);
    ASSERT_EQ(modbus_write_register(m.ctx(), T::kHrRunCommand, 1), 1);
    ASSERT_TRUE(m.wait_input(T::kIrRunState, 1, 10s));
    T::save(m);
    m.close();
    ASSERT_EQ(p.stop(), 0);
  }
  TypeParam p;
  ASSERT_TRUE(p.start(this->args())) << p.error();
  // No request at all until the station's own clock (not the host's: a busy
  // host slows the simulated Uno down) is past the watchdog time; every LED
  // line meanwhile (events and answers) shows RUN-self dark.
  const uint32_t first_us = p.device_us();
  int lines = 0;
  for (;;) {
    const std::string line = p.ask("leds?", "leds ");
    ASSERT_FALSE(line.empty()) << "no answer to leds?";
    ASSERT_EQ(field_of(line, "self"), "0") << "the station ran by itself: " << line;
    ++lines;
    if (p.device_us() - first_us >= T::kWatchdogUs + 500000u) break;
    std::this_thread::sleep_for(20ms);  // poll interval of the condition above
  }
  EXPECT_GT(lines, 1);

  ModbusMaster m;
  ASSERT_TRUE(m.open(p.device())) << m.error();
  EXPECT_EQ(m.holding_register(T::kHrRunCommand), 0) << "the RUN command was restored from the EEPROM";
  EXPECT_EQ(m.input_register(T::kIrRunState), 0);
  EXPECT_EQ(m.input_register(T::kIrStopCause), T::kCausePcSilent) << "the watchdog did not run from power-on";
  // The PC acknowledges the stop (RUN 0), then commands RUN.
  ASSERT_EQ(modbus_write_register(m.ctx(), T::kHrRunCommand, 1), 1);
  EXPECT_EQ(m.input_register(T::kIrRunState), 0) << "a latched stop needs RUN 0 first";
  ASSERT_EQ(modbus_write_register(m.ctx(), T::kHrRunCommand, 0), 1);
  ASSERT_EQ(modbus_write_register(m.ctx(), T::kHrRunCommand, 1), 1);
  EXPECT_TRUE(m.wait_input(T::kIrRunState, 1, 10s));
  m.close();
  EXPECT_EQ(p.stop(), 0);
}

// FC 10 HR 0..2 = [0, 0, 0]: RUN command 0 would acknowledge the latched
// stop, but node id 0 is refused, so the request is refused whole and the
// latch holds.
TYPED_TEST_P(StationSafety, RefusedMultipleWriteKeepsALatchedStop) {
  using T = StationSafety<TypeParam>;
  TypeParam p;
  ModbusMaster m;
  this->start(p, m);
  ASSERT_EQ(modbus_write_register(m.ctx(), T::kHrRunCommand, 1), 1);
  ASSERT_TRUE(m.wait_input(T::kIrRunState, 1, 10s));
  ASSERT_EQ(p.ask("click STOP 60", "ok"), "ok");
  ASSERT_TRUE(m.wait_input(T::kIrStopCause, T::kCauseStopButton, 10s));
  ASSERT_EQ(m.input_register(T::kIrRunState), 0);

  const uint16_t zeros[3] = {0, 0, 0};
  errno = 0;
  EXPECT_EQ(modbus_write_registers(m.ctx(), T::kHrRunCommand, 3, zeros), -1);
  EXPECT_EQ(errno, EMBXSFAIL) << "exception 04: node id 0 is below 2000h/1's limit";
  EXPECT_EQ(m.holding_register(T::kHrRunCommand), 1) << "the refused request changed the RUN command";
  EXPECT_EQ(m.input_register(T::kIrRunState), 0) << "the refused request released the latched stop";
  EXPECT_EQ(T::discrete_input(m, T::kDiRunState), 0);
  EXPECT_EQ(m.input_register(T::kIrStopCause), T::kCauseStopButton);
  // The latch still needs its acknowledgement.
  ASSERT_EQ(modbus_write_register(m.ctx(), T::kHrRunCommand, 1), 1);
  EXPECT_EQ(m.input_register(T::kIrRunState), 0);
  m.close();
  EXPECT_EQ(p.stop(), 0);
}

// FC 10 HR 11..13 = ["save", 3]: restart request 3 is above 2001h's limit,
// so the request is refused whole and nothing is saved.
TYPED_TEST_P(StationSafety, RefusedMultipleWriteSavesNothing) {
  using T = StationSafety<TypeParam>;
  {
    TypeParam p;
    ModbusMaster m;
    this->start(p, m);
    ASSERT_EQ(modbus_write_register(m.ctx(), T::kHrDebounce, 33), 1);
    ASSERT_EQ(modbus_write_register(m.ctx(), T::kHrNodeId, 9), 1);
    const uint16_t save_and_bad_restart[3] = {0x6576, 0x6173, 3};
    errno = 0;
    EXPECT_EQ(modbus_write_registers(m.ctx(), T::kHrSave, 3, save_and_bad_restart), -1);
    EXPECT_EQ(errno, EMBXSFAIL);
    m.close();
    ASSERT_EQ(p.stop(), 0);
  }
  TypeParam p;
  ModbusMaster m;
  this->start(p, m);
  EXPECT_EQ(p.node_id(), 1) << "the refused request saved node id 9";
  EXPECT_EQ(m.holding_register(T::kHrDebounce), 20);
  EXPECT_EQ(m.holding_register(T::kHrNodeId), 1);
  m.close();
  EXPECT_EQ(p.stop(), 0);
}

REGISTER_TYPED_TEST_SUITE_P(StationSafety, SavedRunCommandDoesNotStartTheStationAtPowerUp,
                            RefusedMultipleWriteKeepsALatchedStop, RefusedMultipleWriteSavesNothing);

}  // namespace test
}  // namespace mb2co
