// Independent peer: libmodbus (Debian libmodbus-dev) as the RTU master of
// mb2co-node --can none on the pty it creates. Every function code of the
// gateway's register map (docs/register-map.md), every exception, broadcast
// silence, a bad-CRC frame and a frame split by a gap longer than t3.5; the
// virtual buttons and LEDs of the control channel seen over Modbus.
// FC 08 and 2B are not in libmodbus 3.1.6's API: they go out with
// modbus_send_raw_request (libmodbus adds the CRC) and their responses are
// read from the port (tests/support/rtu_frames.h).
#include <errno.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "node_harness.h"
#include "rtu_frames.h"
#include "rtu_peer_test.h"

namespace mb2co {
namespace test {
namespace {

// Defaults of the gateway's maps (docs/register-map.md): mb2co-node's
// holding map ends with the REAL32 (14-15) and UNSIGNED64 (16-19) of 2500h.
constexpr int kHoldingCount = 20;
constexpr int kInputCount = 24;
constexpr int kCoilCount = 2;
constexpr int kDiscreteCount = 7;
constexpr int kHrRunCommand = 0, kHrLabLed = 1, kHrNodeId = 2, kHrBitrate = 3, kHrDebounce = 7,
              kHrHeartbeat = 8, kHrCyclePeriod = 9, kHrRestart = 13;
constexpr int kIrInputs = 0, kIrRunState = 1, kIrStopCause = 3, kIrStartCount = 4, kIrLeds = 11, kIrNmt = 22;
constexpr int kDiStop2 = 2, kDiRunState = 3;

unsigned counter(const std::string& line, const char* name) {
  const std::string v = field_of(line, name);
  return v.empty() ? ~0u : static_cast<unsigned>(std::stoul(v));
}

class Libmodbus : public RtuPeerTest<NodeProcess> {
 protected:
  void write_raw(const Bytes& adu) {
    ASSERT_EQ(write(fd_, adu.data(), adu.size()), static_cast<ssize_t>(adu.size()));
  }
  /// The exception code of the answer to `pdu`, -1 when it is no exception.
  int raw_exception(const Bytes& pdu) {
    const Bytes rsp = raw_transaction(pdu);
    return rsp.size() == 3u && rsp[1] == (pdu[0] | 0x80) ? rsp[2] : -1;
  }
  /// errno of a libmodbus call that must fail (0 when it succeeded).
  static int failure(int rc) { return rc == -1 ? errno : 0; }

  NodeProcess& node_ = peer_;
};

TEST_F(Libmodbus, ReadsEveryTable) {
  uint16_t hr[kHoldingCount];
  ASSERT_EQ(modbus_read_registers(ctx_, 0, kHoldingCount, hr), kHoldingCount);  // FC 03
  EXPECT_EQ(hr[kHrRunCommand], 0);
  EXPECT_EQ(hr[kHrNodeId], 1);
  EXPECT_EQ(hr[kHrBitrate], 500);
  EXPECT_EQ(hr[kHrDebounce], 20);
  EXPECT_EQ(hr[kHrHeartbeat], 100);
  uint16_t ir[kInputCount];
  ASSERT_EQ(modbus_read_input_registers(ctx_, 0, kInputCount, ir), kInputCount);  // FC 04
  EXPECT_EQ(ir[kIrRunState], 0);
  EXPECT_EQ(ir[kIrNmt], 5) << "self-started: operational without a bus";
  EXPECT_EQ(ir[20], 4) << "previous station of node 1 in the default ring of 4";
  EXPECT_EQ(ir[21], 2) << "next station";
  uint8_t bits[kDiscreteCount];
  ASSERT_EQ(modbus_read_bits(ctx_, 0, kCoilCount, bits), kCoilCount);  // FC 01
  EXPECT_EQ(bits[0], 0);
  EXPECT_EQ(bits[1], 0);
  ASSERT_EQ(modbus_read_input_bits(ctx_, 0, kDiscreteCount, bits), kDiscreteCount);  // FC 02
  for (int i = 0; i < 3; ++i) EXPECT_EQ(bits[i], 0) << "button " << i << " not pressed";
}

TEST_F(Libmodbus, WritesEveryWay) {
  ASSERT_EQ(modbus_write_bit(ctx_, 0, 1), 1);  // FC 05: RUN command
  EXPECT_EQ(master_.holding_register(kHrRunCommand), 1) << "coil 0 and HR 0 are the same OD entry";
  EXPECT_EQ(master_.input_register(kIrRunState), 1) << "RUN state follows the command";
  uint8_t bit = 0;
  ASSERT_EQ(modbus_read_input_bits(ctx_, kDiRunState, 1, &bit), 1);
  EXPECT_EQ(bit, 1);

  ASSERT_EQ(modbus_write_register(ctx_, kHrLabLed, 1), 1);  // FC 06: lab LED
  std::string leds;
  EXPECT_TRUE(node_.wait_event(
      "leds ", [](const std::string& l) { return field_of(l, "lab") == "1"; }, 10s, &leds));
  EXPECT_EQ(field_of(leds, "self"), "1");
  EXPECT_EQ(master_.input_register(kIrLeds) & 0x09, 0x09) << "LEDs RUN-self and lab as driven";

  const uint8_t off[2] = {0, 0};
  ASSERT_EQ(modbus_write_bits(ctx_, 0, 2, off), 2);  // FC 0F
  EXPECT_EQ(master_.holding_register(kHrLabLed), 0);
  EXPECT_EQ(master_.input_register(kIrRunState), 0);

  const uint16_t times[2] = {50, 200};
  ASSERT_EQ(modbus_write_registers(ctx_, kHrDebounce, 2, times), 2);  // FC 10
  const uint16_t period[2] = {0x0001, 0x86A0};                        // 100000 µs, high word first
  ASSERT_EQ(modbus_write_registers(ctx_, kHrCyclePeriod, 2, period), 2);
  uint16_t back[4];
  ASSERT_EQ(modbus_read_registers(ctx_, kHrDebounce, 4, back), 4);
  EXPECT_EQ(back[0], 50);
  EXPECT_EQ(back[1], 200);
  EXPECT_EQ(back[2], 0x0001);
  EXPECT_EQ(back[3], 0x86A0);

  const uint16_t one = 1;
  uint16_t rw[2];
  ASSERT_EQ(modbus_write_and_read_registers(ctx_, kHrLabLed, 1, &one, kHrRunCommand, 2, rw), 2);  // FC 17
  EXPECT_EQ(rw[0], 0);
  EXPECT_EQ(rw[1], 1) << "FC 17 writes before it reads";
}

TEST_F(Libmodbus, DiagnosticsEchoAndCounters) {
  const Bytes echo = raw_transaction({0x08, 0x00, 0x00, 0x12, 0x34, 0x56});
  EXPECT_EQ(echo, (Bytes{1, 0x08, 0x00, 0x00, 0x12, 0x34, 0x56}));
  EXPECT_EQ(master_.holding_register(0), 0);
  EXPECT_EQ(raw_exception({0x03, 0x00, 0x00, 0x00, 0x7E}), 3);
  EXPECT_EQ(diag_counter(0x0B), 4u);  // echo, read, exception, this request
  EXPECT_EQ(diag_counter(0x0C), 0u);
  EXPECT_EQ(diag_counter(0x0D), 1u);
  EXPECT_EQ(diag_counter(0x0E), 7u);  // the three above + the four counter reads
  EXPECT_EQ(diag_counter(0x12), 0u);
  EXPECT_EQ(raw_transaction({0x08, 0x00, 0x0A, 0x00, 0x00}), (Bytes{1, 0x08, 0x00, 0x0A, 0x00, 0x00}));
  EXPECT_EQ(diag_counter(0x0B), 1u) << "08/0A cleared the counters";
  EXPECT_EQ(diag_counter(0x0D), 0u);
}

TEST_F(Libmodbus, DeviceIdentification) {
  const Bytes rsp = raw_transaction({0x2B, 0x0E, 0x01, 0x00});
  Bytes expected{1, 0x2B, 0x0E, 0x01, 0x81, 0x00, 0x00, 3};
  const std::string objects[3] = {"mb2co", "mb2co gateway", "0.1.0"};  // vendor, 1008h, 100Ah of the OD
  for (uint8_t id = 0; id < 3; ++id) {
    expected.push_back(id);
    expected.push_back(static_cast<uint8_t>(objects[id].size()));
    expected.insert(expected.end(), objects[id].begin(), objects[id].end());
  }
  EXPECT_EQ(rsp, expected);
  EXPECT_EQ(raw_exception({0x2B, 0x0E, 0x04, 0x03}), 2) << "no object 3 in the basic category";
  EXPECT_EQ(raw_exception({0x2B, 0x0E, 0x07, 0x00}), 3) << "bad read code";
}

TEST_F(Libmodbus, EveryException) {
  uint8_t id[64];
  EXPECT_EQ(failure(modbus_report_slave_id(ctx_, sizeof id, id)), EMBXILFUN);  // FC 11
  EXPECT_EQ(raw_exception({0x08, 0x00, 0x03, 0x00, 0x00}), 1) << "unsupported sub-function";

  uint16_t regs[2];
  uint8_t bits[2];
  EXPECT_EQ(failure(modbus_read_registers(ctx_, kHoldingCount, 1, regs)), EMBXILADD) << "beyond the map";
  EXPECT_EQ(failure(modbus_read_registers(ctx_, kHoldingCount - 1, 2, regs)), EMBXILADD)
      << "runs past the map";
  EXPECT_EQ(failure(modbus_read_input_registers(ctx_, kInputCount, 1, regs)), EMBXILADD);
  EXPECT_EQ(failure(modbus_read_bits(ctx_, kCoilCount, 1, bits)), EMBXILADD);
  EXPECT_EQ(failure(modbus_read_input_bits(ctx_, kDiscreteCount - 1, 2, bits)), EMBXILADD);
  EXPECT_EQ(failure(modbus_write_register(ctx_, kHrCyclePeriod, 1)), EMBXILADD) << "half of a 32-bit entry";

  EXPECT_EQ(raw_exception({0x03, 0x00, 0x00, 0x00, 0x7E}), 3) << "126 registers";
  EXPECT_EQ(raw_exception({0x03, 0xFF, 0xFF, 0x00, 0x7E}), 3) << "03 before 02";
  EXPECT_EQ(raw_exception({0x05, 0x00, 0x00, 0x12, 0x34}), 3) << "coil value neither 0000h nor FF00h";

  EXPECT_EQ(failure(modbus_write_register(ctx_, kHrRunCommand, 2)), EMBXSFAIL) << "RUN command limit 0..1";
  EXPECT_EQ(failure(modbus_write_register(ctx_, kHrBitrate, 300)), EMBXSFAIL) << "bit rate refused by the OD";
  const uint16_t values[2] = {5, 300};
  EXPECT_EQ(failure(modbus_write_registers(ctx_, kHrNodeId, 2, values)), EMBXSFAIL);
  ASSERT_EQ(modbus_read_registers(ctx_, kHrNodeId, 2, regs), 2);
  EXPECT_EQ(regs[0], 1) << "a refused multiple write changes nothing";
  EXPECT_EQ(regs[1], 500);
}

TEST_F(Libmodbus, BroadcastIsExecutedButNeverAnswered) {
  ASSERT_EQ(modbus_set_slave(ctx_, MODBUS_BROADCAST_ADDRESS), 0);
  modbus_set_response_timeout(ctx_, 0, 300000);
  EXPECT_EQ(failure(modbus_write_register(ctx_, kHrLabLed, 1)), ETIMEDOUT) << "a reply came to a broadcast";
  const uint16_t times[2] = {30, 150};
  EXPECT_EQ(failure(modbus_write_registers(ctx_, kHrDebounce, 2, times)), ETIMEDOUT);
  ASSERT_EQ(modbus_set_slave(ctx_, 1), 0);
  EXPECT_EQ(master_.holding_register(kHrLabLed), 1);
  EXPECT_EQ(master_.holding_register(kHrDebounce), 30);
  EXPECT_EQ(master_.holding_register(kHrHeartbeat), 150);
  EXPECT_EQ(diag_counter(0x0F), 2u) << "both broadcasts counted as unanswered";
}

TEST_F(Libmodbus, BadCrcFrameIgnoredAndCounted) {
  Bytes bad = with_crc({1, 0x06, 0x00, kHrDebounce, 0x00, 77});
  bad.back() ^= 0x5A;
  write_raw(bad);
  // The node has handled the frame once it reports it; a response would
  // have been written before the report.
  EXPECT_TRUE(node_.wait_counters([](const std::string& l) { return counter(l, "comm") == 1; }));
  EXPECT_EQ(drain(fd_), 0u) << "a frame with a bad CRC was answered";
  EXPECT_EQ(diag_counter(0x0C), 1u);
  EXPECT_EQ(master_.holding_register(kHrDebounce), 20) << "not executed";
}

TEST_F(Libmodbus, FrameSplitByGapLongerThanT35Discarded) {
  const Bytes adu = with_crc({1, 0x06, 0x00, kHrDebounce, 0x00, 77});
  write_raw(Bytes(adu.begin(), adu.begin() + 3));
  // The node reports the first part as a (too short) frame of its own only
  // after t3.5 of silence: the gap is then longer than t3.5 by construction.
  EXPECT_TRUE(node_.wait_counters([](const std::string& l) { return counter(l, "comm") == 1; }));
  write_raw(Bytes(adu.begin() + 3, adu.end()));
  EXPECT_TRUE(node_.wait_counters([](const std::string& l) { return counter(l, "comm") == 2; }));
  EXPECT_EQ(drain(fd_), 0u);
  EXPECT_EQ(diag_counter(0x0C), 2u);
  EXPECT_EQ(diag_counter(0x0B), 2u) << "only the two counter reads were good frames";
  EXPECT_EQ(master_.holding_register(kHrDebounce), 20);
}

TEST_F(Libmodbus, ButtonsAndLedsThroughTheControlChannel) {
  EXPECT_EQ(node_.ask("click START 30", "ok"), "ok");
  EXPECT_TRUE(master_.wait_input(kIrStartCount, 1, 10s)) << "START press counted";
  EXPECT_EQ(node_.ask("press STOP2", "ok"), "ok");
  EXPECT_TRUE(master_.wait_input(kIrInputs, 0x04, 10s)) << "STOP2 held (6000h/1 bit 2)";
  uint8_t bit = 0;
  ASSERT_EQ(modbus_read_input_bits(ctx_, kDiStop2, 1, &bit), 1);
  EXPECT_EQ(bit, 1);
  EXPECT_EQ(master_.input_register(kIrStopCause), 2) << "STOP2 pressed here";
  EXPECT_EQ(node_.ask("release STOP2", "ok"), "ok");
  EXPECT_TRUE(master_.wait_input(kIrInputs, 0, 10s));

  ASSERT_EQ(modbus_write_register(ctx_, kHrRunCommand, 1), 1);
  EXPECT_EQ(master_.input_register(kIrRunState), 0) << "the STOP2 latch holds until the PC writes RUN 0";
  ASSERT_EQ(modbus_write_register(ctx_, kHrRunCommand, 0), 1);
  ASSERT_EQ(modbus_write_register(ctx_, kHrRunCommand, 1), 1);
  EXPECT_EQ(master_.input_register(kIrRunState), 1);
  // The reply to leds? reads like an LED event: take the first one stamped
  // after the question.
  const uint32_t asked_at = monotonic_us();
  ASSERT_TRUE(node_.child.send_line("leds?"));
  std::string leds;
  EXPECT_TRUE(node_.wait_event(
      "leds ", [&](const std::string& l) { return static_cast<int32_t>(at_us_of(l) - asked_at) >= 0; }, 10s,
      &leds));
  EXPECT_EQ(field_of(leds, "self"), "1") << leds;
  // No CAN: both neighbours are unknown, their LEDs blink; the line says so
  // instead of changing at every toggle.
  EXPECT_EQ(field_of(leds, "prev"), "blink") << leds;
  EXPECT_EQ(field_of(leds, "next"), "blink") << leds;

  // Words in any letter case; help lists the commands.
  EXPECT_EQ(node_.ask("Click start 30", "ok"), "ok");
  EXPECT_TRUE(master_.wait_input(kIrStartCount, 2, 10s)) << "the lower-case START counted too";
  EXPECT_EQ(node_.ask("help", "help ").rfind("help press B", 0), 0u);
  EXPECT_EQ(node_.ask("leds? now", "error"), "error unexpected 'now'");

  EXPECT_EQ(node_.ask("press FOO", "error"), "error unknown button 'FOO' (START, STOP, STOP2)");
  EXPECT_EQ(node_.ask("click STOP 0", "error"), "error bad click duration '0' (1..60000 ms)");
  EXPECT_EQ(node_.ask("jump", "error"), "error unknown command 'jump' (help lists them)");
  EXPECT_EQ(node_.ask("quit", "bye"), "bye");
  EXPECT_EQ(node_.child.wait_exit(10s), 0) << "quit ends the node";
  EXPECT_NE(access(dir_.path("peer.pty").c_str(), F_OK), 0) << "pty link removed";
}

}  // namespace
}  // namespace test
}  // namespace mb2co
