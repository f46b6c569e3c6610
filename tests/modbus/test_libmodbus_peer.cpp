// Independent peer: libmodbus (Debian libmodbus-dev) as the RTU master of our
// slave on a pty (tests/modbus/pty_slave.cpp). Every function code, every
// exception, broadcast silence, a bad-CRC frame and a frame split by a gap
// longer than t3.5. FC 08 and 2B are not in libmodbus 3.1.6's API: they go
// out with modbus_send_raw_request (libmodbus adds the CRC) and their
// responses are read from the port and checked with a bitwise CRC
// (tests/support/rtu_frames.h).
#include <errno.h>
#include <gtest/gtest.h>
#include <modbus.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <vector>

#include "rtu_frames.h"
#include "support/slave_process.h"
#include "support/test_layout.h"

namespace mb2co {
namespace modbus {
namespace test {
namespace {

using mb2co::test::Bytes;
using mb2co::test::drain;
using mb2co::test::read_response;
using mb2co::test::with_crc;
using namespace std::chrono_literals;

// Counter values from a pty_slave "--events" line.
unsigned field(const std::string& line, const std::string& name) {
  const size_t at = line.find(" " + name + "=");
  return at == std::string::npos ? ~0u : static_cast<unsigned>(std::stoul(line.substr(at + name.size() + 2)));
}

class LibmodbusPeer : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(slave_.start(MB2CO_PTY_SLAVE, {"--events"})) << slave_.error();
    ctx_ = modbus_new_rtu(slave_.device().c_str(), 115200, 'N', 8, 1);
    ASSERT_NE(ctx_, nullptr);
    ASSERT_EQ(modbus_set_slave(ctx_, kSlaveAddress), 0);
    ASSERT_EQ(modbus_connect(ctx_), 0) << modbus_strerror(errno);
    // Short only because the peer is our own slave (see DESIGN §10).
    modbus_set_response_timeout(ctx_, 0, 500000);
    fd_ = modbus_get_socket(ctx_);
  }
  void TearDown() override {
    if (ctx_ != nullptr) {
      modbus_close(ctx_);
      modbus_free(ctx_);
    }
    EXPECT_EQ(slave_.stop(), 0) << "pty_slave exit status";
  }

  /// Waits until the slave reports counters satisfying `match`.
  std::string wait_counters(const std::function<bool(const std::string&)>& match) {
    std::string line;
    EXPECT_TRUE(slave_.wait_line(
        [&](const std::string& l) { return l.rfind("counters ", 0) == 0 && match(l); }, 5s, &line))
        << "slave never reported the expected counters";
    return line;
  }
  /// Bytes the slave has written and nobody read yet (after wait_counters the
  /// slave has already written any response, so none means it stayed silent).
  size_t pending_bytes() { return drain(fd_); }
  void write_raw(const Bytes& adu) {
    ASSERT_EQ(write(fd_, adu.data(), adu.size()), static_cast<ssize_t>(adu.size()));
  }
  /// Sends a raw PDU to slave 1 via libmodbus and reads the response whose
  /// length follows from its header (FC 08, 2B, or an exception).
  Bytes raw_transaction(const Bytes& pdu) {
    Bytes req{kSlaveAddress};
    req.insert(req.end(), pdu.begin(), pdu.end());
    EXPECT_GT(modbus_send_raw_request(ctx_, req.data(), static_cast<int>(req.size())), 0);
    const Bytes rsp = read_response(fd_, pdu.size(), 1s);
    EXPECT_FALSE(rsp.empty()) << "no response, or a wrong CRC";
    return rsp;
  }
  uint16_t diag_counter(uint8_t sub) {
    const Bytes rsp = raw_transaction({0x08, 0x00, sub, 0x00, 0x00});
    EXPECT_EQ(rsp.size(), 6u);
    return rsp.size() == 6u ? static_cast<uint16_t>(rsp[4] << 8 | rsp[5]) : 0xFFFF;
  }
  /// Sends a raw request whose answer must be an exception; returns its code.
  int raw_exception(const Bytes& pdu) {
    const Bytes rsp = raw_transaction(pdu);
    if (rsp.size() != 3u || rsp[1] != (pdu[0] | 0x80)) return -1;
    return rsp[2];
  }

  SlaveProcess slave_;
  modbus_t* ctx_ = nullptr;
  int fd_ = -1;
};

TEST_F(LibmodbusPeer, ReadCoilsAndDiscreteInputs) {
  uint8_t bits[2000];
  ASSERT_EQ(modbus_write_bit(ctx_, 17, 1), 1);
  ASSERT_EQ(modbus_read_bits(ctx_, 16, 3, bits), 3);
  EXPECT_EQ(bits[0], 0);
  EXPECT_EQ(bits[1], 1);
  EXPECT_EQ(bits[2], 0);
  ASSERT_EQ(modbus_read_input_bits(ctx_, 0, 2000, bits), 2000);
  for (int i = 0; i < 2000; ++i) ASSERT_EQ(bits[i], i % 3 == 0 ? 1 : 0) << i;
}

TEST_F(LibmodbusPeer, ReadRegisters) {
  uint16_t regs[125];
  ASSERT_EQ(modbus_read_input_registers(ctx_, 0, 125, regs), 125);
  for (int i = 0; i < 125; ++i) ASSERT_EQ(regs[i], 0x1000 + i);
  ASSERT_EQ(modbus_read_registers(ctx_, kReadOnlyStart, 2, regs), 2);
  EXPECT_EQ(regs[0], 0xA000 + kReadOnlyStart);
}

TEST_F(LibmodbusPeer, WriteFunctions) {
  ASSERT_EQ(modbus_write_register(ctx_, 3, 0xCAFE), 1);
  const uint8_t bits[10] = {1, 0, 1, 1, 0, 0, 1, 1, 1, 0};
  ASSERT_EQ(modbus_write_bits(ctx_, 30, 10, bits), 10);
  const uint16_t values[3] = {11, 22, 33};
  ASSERT_EQ(modbus_write_registers(ctx_, 40, 3, values), 3);
  uint16_t regs[4];
  ASSERT_EQ(modbus_write_and_read_registers(ctx_, 43, 1, values, 40, 4, regs), 4);
  EXPECT_EQ(regs[0], 11);
  EXPECT_EQ(regs[2], 33);
  EXPECT_EQ(regs[3], 11) << "FC 17 writes before it reads";
  ASSERT_EQ(modbus_read_registers(ctx_, 3, 1, regs), 1);
  EXPECT_EQ(regs[0], 0xCAFE);
  uint8_t back[10];
  ASSERT_EQ(modbus_read_bits(ctx_, 30, 10, back), 10);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(back[i], bits[i]) << i;
}

TEST_F(LibmodbusPeer, WritesAtTheQuantityLimits) {
  std::vector<uint8_t> bits(1968);
  for (size_t i = 0; i < bits.size(); ++i) bits[i] = static_cast<uint8_t>(i % 2);
  ASSERT_EQ(modbus_write_bits(ctx_, 0, 1968, bits.data()), 1968);
  std::vector<uint16_t> values(123);
  for (size_t i = 0; i < values.size(); ++i) values[i] = static_cast<uint16_t>(i);
  ASSERT_EQ(modbus_write_registers(ctx_, 120, 123, values.data()), 123);
  std::vector<uint16_t> regs(125);
  ASSERT_EQ(modbus_write_and_read_registers(ctx_, 120, 121, values.data(), 120, 125, regs.data()), 125);
  EXPECT_EQ(regs[120], 120);
  uint8_t back[2000];
  ASSERT_EQ(modbus_read_bits(ctx_, 0, 2000, back), 2000);
  EXPECT_EQ(back[1967], 1);
}

TEST_F(LibmodbusPeer, DiagnosticsEchoAndCounters) {
  const Bytes echo = raw_transaction({0x08, 0x00, 0x00, 0x12, 0x34, 0x56});
  EXPECT_EQ(echo, (Bytes{1, 0x08, 0x00, 0x00, 0x12, 0x34, 0x56}));
  uint16_t reg;
  ASSERT_EQ(modbus_read_registers(ctx_, 0, 1, &reg), 1);
  EXPECT_EQ(modbus_read_registers(ctx_, 0, 126, &reg), -1);  // refused by libmodbus itself
  EXPECT_EQ(raw_exception({0x03, 0x00, 0x00, 0x00, 0x7E}), 3);
  EXPECT_EQ(diag_counter(0x0B), 4u);  // echo, read, exception, this request
  EXPECT_EQ(diag_counter(0x0C), 0u);
  EXPECT_EQ(diag_counter(0x0D), 1u);
  EXPECT_EQ(diag_counter(0x0E), 7u);  // the three above + the four counter reads
  EXPECT_EQ(diag_counter(0x0F), 0u);
  EXPECT_EQ(diag_counter(0x12), 0u);
  EXPECT_EQ(raw_transaction({0x08, 0x00, 0x0A, 0x00, 0x00}), (Bytes{1, 0x08, 0x00, 0x0A, 0x00, 0x00}));
  EXPECT_EQ(diag_counter(0x0B), 1u);
  EXPECT_EQ(raw_exception({0x08, 0x00, 0x03, 0x00, 0x00}), 1);  // unsupported sub-function
}

TEST_F(LibmodbusPeer, ListenOnlyAndRestart) {
  write_raw(with_crc({kSlaveAddress, 0x08, 0x00, 0x04, 0x00, 0x00}));
  wait_counters([](const std::string& l) { return field(l, "noresp") == 1; });
  EXPECT_EQ(pending_bytes(), 0u);
  errno = 0;
  EXPECT_EQ(modbus_write_register(ctx_, 5, 5), -1);
  EXPECT_EQ(errno, ETIMEDOUT);
  write_raw(with_crc({kSlaveAddress, 0x08, 0x00, 0x01, 0x00, 0x00}));
  wait_counters([](const std::string& l) { return field(l, "bus") == 0; });  // restart clears
  EXPECT_EQ(pending_bytes(), 0u) << "restart from listen-only is not answered";
  uint16_t reg = 1;
  ASSERT_EQ(modbus_read_registers(ctx_, 5, 1, &reg), 1);
  EXPECT_EQ(reg, 0) << "the write in listen-only mode was not executed";
}

TEST_F(LibmodbusPeer, DeviceIdentification) {
  const Bytes rsp = raw_transaction({0x2B, 0x0E, 0x01, 0x00});
  const Bytes expected{1, 0x2B, 0x0E, 0x01, 0x81, 0x00, 0x00, 3,   0,   5, 'm', 'b', '2', 'c', 'o', 1,
                       8, 'M',  'B',  '2',  'C',  'O',  '-',  'G', 'W', 2, 5,   '0', '.', '1', '.', '0'};
  EXPECT_EQ(rsp, expected);
  const Bytes one = raw_transaction({0x2B, 0x0E, 0x04, 0x02});
  EXPECT_EQ(one, (Bytes{1, 0x2B, 0x0E, 0x04, 0x81, 0x00, 0x00, 1, 2, 5, '0', '.', '1', '.', '0'}));
  EXPECT_EQ(raw_exception({0x2B, 0x0E, 0x04, 0x03}), 2);
  EXPECT_EQ(raw_exception({0x2B, 0x0E, 0x07, 0x00}), 3);
}

TEST_F(LibmodbusPeer, EveryException) {
  uint8_t id[64];
  EXPECT_EQ(modbus_report_slave_id(ctx_, sizeof id, id), -1);  // FC 11
  EXPECT_EQ(errno, EMBXILFUN);
  uint16_t reg = 0;
  EXPECT_EQ(modbus_read_registers(ctx_, kHoldingRegisterCount, 1, &reg), -1);
  EXPECT_EQ(errno, EMBXILADD);
  EXPECT_EQ(modbus_write_register(ctx_, kReadOnlyStart, 1), -1);
  EXPECT_EQ(errno, EMBXILADD);
  uint8_t bit;
  EXPECT_EQ(modbus_read_input_bits(ctx_, kDiscreteInputCount - 1, 2, &bit), -1);
  EXPECT_EQ(errno, EMBXILADD);
  EXPECT_EQ(raw_exception({0x01, 0x00, 0x00, 0x07, 0xD1}), 3);  // 2001 coils
  EXPECT_EQ(raw_exception({0x05, 0x00, 0x00, 0x12, 0x34}), 3);  // coil value
  EXPECT_EQ(raw_exception({0x03, 0xFF, 0xFF, 0x00, 0x7E}), 3) << "03 before 02";
  EXPECT_EQ(modbus_read_input_registers(ctx_, kFailingInputRegister, 1, &reg), -1);
  EXPECT_EQ(errno, EMBXSFAIL);
  const uint16_t values[2] = {5, kLimitMax + 1};
  EXPECT_EQ(modbus_write_registers(ctx_, kLimitedStart, 2, values), -1);
  EXPECT_EQ(errno, EMBXSFAIL);
  ASSERT_EQ(modbus_read_registers(ctx_, kLimitedStart, 1, &reg), 1);
  EXPECT_EQ(reg, 0) << "a failed multiple write changes nothing";
  EXPECT_EQ(modbus_write_bit(ctx_, kCoilRejectingOn, 1), -1);
  EXPECT_EQ(errno, EMBXSFAIL);
}

TEST_F(LibmodbusPeer, BroadcastIsExecutedButNeverAnswered) {
  ASSERT_EQ(modbus_set_slave(ctx_, MODBUS_BROADCAST_ADDRESS), 0);
  modbus_set_response_timeout(ctx_, 0, 300000);
  errno = 0;
  EXPECT_EQ(modbus_write_register(ctx_, 9, 0x0909), -1);
  EXPECT_EQ(errno, ETIMEDOUT) << "a reply came to a broadcast";
  const uint16_t values[2] = {7, 8};
  EXPECT_EQ(modbus_write_registers(ctx_, 10, 2, values), -1);
  EXPECT_EQ(errno, ETIMEDOUT);
  ASSERT_EQ(modbus_set_slave(ctx_, kSlaveAddress), 0);
  uint16_t regs[3];
  ASSERT_EQ(modbus_read_registers(ctx_, 9, 3, regs), 3);
  EXPECT_EQ(regs[0], 0x0909);
  EXPECT_EQ(regs[1], 7);
  EXPECT_EQ(regs[2], 8);
  EXPECT_EQ(diag_counter(0x0F), 2u) << "both broadcasts counted as unanswered";
}

TEST_F(LibmodbusPeer, BadCrcFrameIgnoredAndCounted) {
  Bytes bad = with_crc({kSlaveAddress, 0x06, 0x00, 0x07, 0x12, 0x34});
  bad.back() ^= 0x5A;
  write_raw(bad);
  wait_counters([](const std::string& l) { return field(l, "comm") == 1; });
  EXPECT_EQ(pending_bytes(), 0u) << "a frame with a bad CRC was answered";
  EXPECT_EQ(diag_counter(0x0C), 1u);
  uint16_t reg = 1;
  ASSERT_EQ(modbus_read_registers(ctx_, 7, 1, &reg), 1);
  EXPECT_EQ(reg, 0);
}

TEST_F(LibmodbusPeer, FrameSplitByGapLongerThanT35Discarded) {
  const Bytes adu = with_crc({kSlaveAddress, 0x06, 0x00, 0x08, 0x56, 0x78});
  write_raw(Bytes(adu.begin(), adu.begin() + 3));
  // The slave reports the first part as a frame of its own only after t3.5
  // of silence: the gap is then longer than t3.5 by construction.
  wait_counters([](const std::string& l) { return field(l, "comm") == 1; });
  write_raw(Bytes(adu.begin() + 3, adu.end()));
  wait_counters([](const std::string& l) { return field(l, "comm") == 2; });
  EXPECT_EQ(pending_bytes(), 0u);
  EXPECT_EQ(diag_counter(0x0C), 2u);
  EXPECT_EQ(diag_counter(0x0B), 2u) << "only the two counter reads were good frames";
  uint16_t reg = 1;
  ASSERT_EQ(modbus_read_registers(ctx_, 8, 1, &reg), 1);
  EXPECT_EQ(reg, 0);
}

}  // namespace
}  // namespace test
}  // namespace modbus
}  // namespace mb2co
