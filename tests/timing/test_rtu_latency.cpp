// Modbus RTU timing and the button-to-LED bound, against hand-computed
// examples (seed 000 §11).
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "timing/latency.h"
#include "timing/line_latency.h"
#include "timing/rtu_timing.h"

namespace mb2co {
namespace timing {
namespace {

SerialFormat format(uint32_t baud, modbus::Parity parity, uint8_t stop_bits) {
  SerialFormat f;
  f.baud = baud;
  f.parity = parity;
  f.stop_bits = stop_bits;
  return f;
}

TEST(Rtu, CharacterAndFrameTimes) {
  EXPECT_EQ(char_bits(format(9600, modbus::Parity::kEven, 1)), 11);
  EXPECT_EQ(char_bits(format(9600, modbus::Parity::kNone, 1)), 10);
  EXPECT_EQ(char_bits(format(9600, modbus::Parity::kNone, 2)), 11);
  // 8 bytes of 11 bits at 9600 baud: 88/9600 s = 9.1666... ms.
  EXPECT_EQ(serial_frame_ns_floor(format(9600, modbus::Parity::kEven, 1), 8), 9166666u);
  EXPECT_EQ(serial_frame_ns_ceil(format(9600, modbus::Parity::kEven, 1), 8), 9166667u);
}

TEST(Rtu, SilenceTimes) {
  // 3.5 x 11 bits at 9600 baud = 4010.4 µs, 1.5 x 11 = 1718.75 µs: rounded
  // up to whole µs as the slave's framer does.
  EXPECT_EQ(t35_ns(format(9600, modbus::Parity::kEven, 1)), 4011000u);
  EXPECT_EQ(t15_ns(format(9600, modbus::Parity::kEven, 1)), 1719000u);
  EXPECT_EQ(t35_ns(format(19200, modbus::Parity::kEven, 1)), 2006000u);
  EXPECT_EQ(t35_ns(format(10000, modbus::Parity::kNone, 1)), 3500000u);  // 3.5 x 1 ms
  // Above 19200 baud the spec fixes 1.75 ms and 0.75 ms.
  EXPECT_EQ(t35_ns(format(115200, modbus::Parity::kEven, 1)), 1750000u);
  EXPECT_EQ(t15_ns(format(38400, modbus::Parity::kEven, 1)), 750000u);
}

TEST(Rtu, ExchangeSizes) {
  EXPECT_EQ(read_bits_exchange(1).request_bytes, 8);
  EXPECT_EQ(read_bits_exchange(1).response_bytes, 6);
  EXPECT_EQ(read_bits_exchange(9).response_bytes, 7);
  EXPECT_EQ(read_registers_exchange(2).response_bytes, 9);
  EXPECT_EQ(write_single_exchange().response_bytes, 8);
  EXPECT_EQ(write_bits_exchange(10).request_bytes, 11);
  EXPECT_EQ(write_registers_exchange(2).request_bytes, 13);
  EXPECT_EQ(write_registers_exchange(2).response_bytes, 8);
}

TEST(Rtu, FormatValidation) {
  EXPECT_TRUE(serial_format_valid(SerialFormat{}));
  EXPECT_FALSE(serial_format_valid(format(0, modbus::Parity::kEven, 1)));
  EXPECT_FALSE(serial_format_valid(format(9600, modbus::Parity::kEven, 3)));
}

// 10,000 baud 8N1: one character = 1 ms, t3.5 = 3.5 ms.
LatencyParams hand_example() {
  LatencyParams p;
  p.serial = format(10000, modbus::Parity::kNone, 1);
  p.debounce_us = 20000;
  p.fw_loop_us = 2000;
  p.pc_cycle_us = 50000;
  p.pc_compute_us = 1000;
  p.master_end_us = 0;
  p.inhibit_us = 10000;
  p.can_up_best_ns = 400000;
  p.can_up_worst_ns = 1500000;
  p.can_down_best_ns = 400000;
  p.can_down_worst_ns = 1200000;
  return p;  // read FC 02 (8 + 6 bytes), write FC 05 (8 + 8 bytes)
}

uint64_t ms(double v) {
  return static_cast<uint64_t>(v * 1e6 + 0.5);
}

const LatencyTerm& term(const LatencyBound& b, const char* name) {
  for (size_t i = 0; i < b.count; ++i) {
    if (std::strcmp(b.terms[i].name, name) == 0) return b.terms[i];
  }
  ADD_FAILURE() << "no term " << name;
  return b.terms[0];
}

TEST(Latency, PollCycleByHand) {
  const PollCycle c = poll_cycle(hand_example());
  EXPECT_EQ(c.read.best_ns, ms(8 + 3.5 + 6));       // request, t3.5, response
  EXPECT_EQ(c.read.worst_ns, ms(8 + 3.5 + 2 + 6));  // + one firmware loop
  EXPECT_EQ(c.write.best_ns, ms(8 + 3.5 + 8));
  EXPECT_EQ(c.busy_best_ns, ms(17.5 + 1 + 19.5));
  EXPECT_EQ(c.busy_worst_ns, ms(19.5 + 1 + 21.5));
  EXPECT_EQ(c.period_ns, ms(50));
  LatencyParams back_to_back = hand_example();
  back_to_back.pc_cycle_us = 0;
  EXPECT_EQ(poll_cycle(back_to_back).period_ns, ms(42));
}

TEST(Latency, ModbusOnlyByHand) {
  const LatencyBound b = modbus_only_latency(hand_example());
  ASSERT_EQ(b.count, 9u);
  EXPECT_EQ(term(b, "debounce").best_ns, ms(20));
  EXPECT_EQ(term(b, "input_pass").worst_ns, ms(2));
  EXPECT_EQ(term(b, "poll_wait").worst_ns, ms(50 + 2));
  EXPECT_EQ(term(b, "read_response").best_ns, ms(6));
  EXPECT_EQ(term(b, "write_request").worst_ns, ms(8));
  EXPECT_EQ(term(b, "slave_end").best_ns, ms(3.5));
  EXPECT_EQ(term(b, "write_pass").worst_ns, ms(2));
  EXPECT_EQ(b.best_ns, ms(20 + 6 + 1 + 8 + 3.5));
  EXPECT_EQ(b.worst_ns, ms(20 + 2 + 52 + 6 + 1 + 8 + 3.5 + 2));
}

TEST(Latency, ModbusCanopenByHand) {
  const LatencyBound b = modbus_canopen_latency(hand_example());
  ASSERT_EQ(b.count, 15u);
  EXPECT_EQ(term(b, "inhibit_up").worst_ns, ms(10 + 2));  // inhibit, then one loop
  EXPECT_EQ(term(b, "can_up").best_ns, ms(0.4));
  EXPECT_EQ(term(b, "can_down").worst_ns, ms(1.2));
  EXPECT_EQ(b.best_ns, ms(38.5 + 0.4 + 0.4));
  EXPECT_EQ(b.worst_ns, ms(94.5 + 12 + 1.5 + 2 + 12 + 1.2 + 2));
  // The breakdown adds up.
  uint64_t best = 0, worst = 0;
  for (size_t i = 0; i < b.count; ++i) {
    best += b.terms[i].best_ns;
    worst += b.terms[i].worst_ns;
    EXPECT_LE(b.terms[i].best_ns, b.terms[i].worst_ns) << b.terms[i].name;
  }
  EXPECT_EQ(best, b.best_ns);
  EXPECT_EQ(worst, b.worst_ns);
}

TEST(Latency, NoInhibitTimeMeansNoWait) {
  LatencyParams p = hand_example();
  p.inhibit_us = 0;
  EXPECT_EQ(term(modbus_canopen_latency(p), "inhibit_up").worst_ns, 0u);
}

TEST(Latency, CanHopsFromTheDefaultLine) {
  const LineCanConfig cfg;  // 3 stations at 125 kbit/s, TPDO1 3 bytes
  const size_t n = line_message_count(cfg);
  std::vector<MessageSpec> specs(n);
  std::vector<RtaMessage> rta(n);
  std::vector<RtaResult> results(n);
  LatencyParams p;
  LineStatus line = LineStatus::kOk;
  ASSERT_EQ(
      fill_can_hops(cfg, WorstCase::kDavis, 2, 1, {specs.data(), rta.data(), results.data(), n}, &p, &line),
      HopStatus::kOk);
  // A 3-byte frame: 85 bits worst (Davis) = 680 µs, 68 bits bare = 544 µs.
  EXPECT_EQ(p.can_up_best_ns, 544000u);
  EXPECT_EQ(p.can_down_best_ns, 544000u);
  EXPECT_EQ(p.can_down_worst_ns, 1360000u);  // TPDO1.1: blocked 680 + own 680
  EXPECT_EQ(p.can_up_worst_ns, 2040000u);    // TPDO1.2: + TPDO1.1 680
  EXPECT_EQ(
      fill_can_hops(cfg, WorstCase::kDavis, 2, 2, {specs.data(), rta.data(), results.data(), n}, &p, &line),
      HopStatus::kNode);
}

}  // namespace
}  // namespace timing
}  // namespace mb2co
