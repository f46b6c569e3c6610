// FC 08 counters and modes, broadcast rules (serial line spec §2.1, §6.1).
#include <gtest/gtest.h>

#include "modbus/master_codec.h"
#include "support/slave_harness.h"

namespace mb2co {
namespace modbus {
namespace test {
namespace {

class ModbusDiagnostics : public ::testing::Test {
 protected:
  SlaveHarness h;

  Bytes diag(uint16_t sub, uint16_t data = 0, uint8_t address = kSlaveAddress) {
    Bytes adu(8);
    adu.resize(build_diagnostics(adu.data(), 8, address, sub, data));
    return adu;
  }
  /// Reads a counter through FC 08 (the request itself is counted first).
  uint16_t counter(uint16_t sub) {
    const Bytes req = diag(sub);
    const Bytes rsp = h.transact(req);
    Response r;
    EXPECT_EQ(parse_response(req.data(), uint16_t(req.size()), rsp.data(), uint16_t(rsp.size()), r),
              ParseStatus::kOk);
    return r.diag_value();
  }
};

TEST_F(ModbusDiagnostics, ReturnQueryDataEchoesAnyData) {
  const Bytes req = with_crc({1, 0x08, 0x00, 0x00, 0xA5, 0x37, 0x01, 0x02, 0x03});
  EXPECT_EQ(h.transact(req), req);
  const Bytes bare = with_crc({1, 0x08, 0x00, 0x00});
  EXPECT_EQ(h.transact(bare), bare);
}

TEST_F(ModbusDiagnostics, CountersFollowTheSerialLineSpec) {
  h.transact(read_holding(0, 1));                       // answered
  h.transact(read_holding(0, 126));                     // exception 03
  h.transact(write_register(1, 1, kBroadcastAddress));  // broadcast: executed, silent
  h.transact(read_holding(0, 1, 9));                    // another slave's
  Bytes bad = read_holding(0, 1);
  bad[2] ^= 0xFF;
  h.transact(bad);  // CRC error
  // So far: 4 good frames on the bus, 3 for us, 1 exception, 1 unanswered.
  EXPECT_EQ(counter(diag::kBusMessageCount), 5u);  // + this request
  EXPECT_EQ(counter(diag::kBusCommErrorCount), 1u);
  EXPECT_EQ(counter(diag::kBusExceptionCount), 1u);
  EXPECT_EQ(counter(diag::kServerMessageCount), 3u + 4u);  // + the 4 counter reads
  EXPECT_EQ(counter(diag::kServerNoResponseCount), 1u);
  EXPECT_EQ(counter(diag::kBusCharOverrunCount), 0u);
  EXPECT_EQ(counter(diag::kReturnDiagnosticRegister), 0u);
  EXPECT_EQ(counter(diag::kServerNakCount), 0u);
  EXPECT_EQ(counter(diag::kServerBusyCount), 0u);
}

TEST_F(ModbusDiagnostics, ClearCountersEchoesAndClears) {
  Bytes bad = read_holding(0, 1);
  bad.back() ^= 1;
  h.transact(bad);
  h.transact(read_holding(0, 126));
  const Bytes req = diag(diag::kClearCounters);
  EXPECT_EQ(h.transact(req), req);
  EXPECT_EQ(counter(diag::kBusCommErrorCount), 0u);
  EXPECT_EQ(counter(diag::kBusExceptionCount), 0u);
  EXPECT_EQ(counter(diag::kBusMessageCount), 3u);  // the three counter reads
}

TEST_F(ModbusDiagnostics, OverrunCountedAndClearedBy14) {
  h.transact(Bytes(300, 1));
  h.transact(Bytes(260, 1));
  EXPECT_EQ(counter(diag::kBusCharOverrunCount), 2u);
  const Bytes req = diag(diag::kClearOverrun);
  EXPECT_EQ(h.transact(req), req);
  EXPECT_EQ(counter(diag::kBusCharOverrunCount), 0u);
  EXPECT_GT(counter(diag::kBusMessageCount), 0u) << "14 clears only the overrun counter";
}

TEST_F(ModbusDiagnostics, BadSubFunctionAndData) {
  for (uint16_t sub : std::initializer_list<uint16_t>{0x03, 0x05, 0x09, 0x13, 0x15, 0xFFFF}) {
    EXPECT_EQ(h.transact(diag(sub)), with_crc({1, 0x88, 0x01})) << sub;
  }
  EXPECT_EQ(h.transact(diag(diag::kBusMessageCount, 1)), with_crc({1, 0x88, 0x03}));
  EXPECT_EQ(h.transact(diag(diag::kRestartCommunications, 0x1234)), with_crc({1, 0x88, 0x03}));
  EXPECT_EQ(h.transact(with_crc({1, 0x08, 0x00, 0x0B, 0x00})), with_crc({1, 0x88, 0x03}));
  EXPECT_EQ(h.transact(with_crc({1, 0x08, 0x00})), with_crc({1, 0x88, 0x03}));
  EXPECT_FALSE(h.slave.listen_only());
}

TEST_F(ModbusDiagnostics, RestartAnswersThenClearsCounters) {
  h.transact(read_holding(0, 126));
  for (uint16_t data : std::initializer_list<uint16_t>{0x0000, 0xFF00}) {
    const Bytes req = diag(diag::kRestartCommunications, data);
    EXPECT_EQ(h.transact(req), req);
    EXPECT_EQ(h.slave.counters().exceptions, 0u);
    EXPECT_EQ(h.slave.counters().bus_messages, 0u);
  }
}

TEST_F(ModbusDiagnostics, ListenOnlyMonitorsButNeitherActsNorAnswers) {
  EXPECT_TRUE(h.transact(diag(diag::kForceListenOnly)).empty()) << "04 is never answered";
  EXPECT_TRUE(h.slave.listen_only());
  EXPECT_TRUE(h.transact(write_register(3, 3)).empty());
  EXPECT_TRUE(h.transact(write_register(3, 3, kBroadcastAddress)).empty());
  EXPECT_TRUE(h.transact(diag(diag::kClearCounters)).empty());
  EXPECT_TRUE(h.transact(diag(diag::kRestartCommunications, 0, kBroadcastAddress)).empty());
  EXPECT_EQ(h.bank.holding_registers[3], 0);
  EXPECT_EQ(h.bank.data_calls, 0u);
  EXPECT_TRUE(h.slave.listen_only());
  EXPECT_EQ(h.slave.counters().bus_messages, 5u);
  EXPECT_EQ(h.slave.counters().no_responses, 5u) << "04 itself and the four ignored";
  // Only 08/01 (to us) ends it, and it is not answered either.
  EXPECT_TRUE(h.transact(diag(diag::kRestartCommunications)).empty());
  EXPECT_FALSE(h.slave.listen_only());
  EXPECT_EQ(h.slave.counters().bus_messages, 0u) << "restart clears the counters";
  EXPECT_EQ(h.transact(write_register(3, 3)).size(), 8u);
  EXPECT_EQ(h.bank.holding_registers[3], 3);
}

TEST_F(ModbusDiagnostics, BroadcastWritesExecutedNeverAnswered) {
  Bytes adu(32);
  const uint16_t values[2] = {0x0A0B, 0x0C0D};
  adu.resize(build_write_registers(adu.data(), 32, kBroadcastAddress, 50, 2, values));
  EXPECT_TRUE(h.transact(adu).empty());
  EXPECT_EQ(h.bank.holding_registers[50], 0x0A0B);
  EXPECT_EQ(h.bank.holding_registers[51], 0x0C0D);

  adu.resize(32);
  const uint8_t bits[1] = {0x05};
  adu.resize(build_write_coils(adu.data(), 32, kBroadcastAddress, 60, 3, bits));
  EXPECT_TRUE(h.transact(adu).empty());
  EXPECT_TRUE(h.bank.coils[60] && !h.bank.coils[61] && h.bank.coils[62]);

  adu.resize(32);
  adu.resize(build_write_single_coil(adu.data(), 32, kBroadcastAddress, 61, true));
  EXPECT_TRUE(h.transact(adu).empty());
  EXPECT_TRUE(h.bank.coils[61]);

  EXPECT_TRUE(h.transact(write_register(52, 7, kBroadcastAddress)).empty());
  EXPECT_EQ(h.bank.holding_registers[52], 7);
  EXPECT_TRUE(h.responses.empty());
  EXPECT_EQ(h.slave.counters().no_responses, 4u);
  EXPECT_EQ(h.slave.counters().server_messages, 4u);
}

TEST_F(ModbusDiagnostics, BroadcastReadsAndDiagnosticsNotExecuted) {
  const unsigned calls = h.bank.data_calls;
  EXPECT_TRUE(h.transact(read_holding(0, 1, kBroadcastAddress)).empty());
  Bytes rw(32);
  const uint16_t v = 5;
  rw.resize(build_read_write_registers(rw.data(), 32, kBroadcastAddress, 0, 1, 70, 1, &v));
  EXPECT_TRUE(h.transact(rw).empty());
  EXPECT_EQ(h.bank.holding_registers[70], 0) << "FC 17 returns data: not a broadcast write";
  EXPECT_TRUE(h.transact(diag(diag::kForceListenOnly, 0, kBroadcastAddress)).empty());
  EXPECT_FALSE(h.slave.listen_only());
  EXPECT_EQ(h.bank.data_calls, calls);
  EXPECT_TRUE(h.responses.empty());
}

TEST_F(ModbusDiagnostics, BroadcastExceptionsCountedButSilent) {
  EXPECT_TRUE(h.transact(write_register(kReadOnlyStart, 1, kBroadcastAddress)).empty());
  EXPECT_TRUE(h.transact(write_register(kLimitedStart, 5000, kBroadcastAddress)).empty());
  EXPECT_EQ(h.slave.counters().exceptions, 2u);
  EXPECT_EQ(h.slave.counters().no_responses, 2u);
  EXPECT_TRUE(h.responses.empty());
}

}  // namespace
}  // namespace test
}  // namespace modbus
}  // namespace mb2co
