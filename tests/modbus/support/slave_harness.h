// A Slave on a virtual line: requests are fed byte by byte with the exact
// stamps a UART would give at the configured baud; responses are captured.
#pragma once
#include <stdint.h>

#include <vector>

#include "crc/crc16.h"
#include "memory_bank.h"
#include "modbus/master_codec.h"
#include "modbus/rtu_timing.h"
#include "modbus/slave.h"
#include "test_layout.h"

namespace mb2co {
namespace modbus {
namespace test {

using Bytes = std::vector<uint8_t>;

/// Appends the CRC to a hand-written ADU body.
inline Bytes with_crc(Bytes body) {
  const uint16_t n = static_cast<uint16_t>(body.size());
  body.resize(n + 2u);
  append_crc(body.data(), n);
  return body;
}

/// FC 03 and FC 06 requests built by the master codec.
inline Bytes read_holding(uint16_t start, uint16_t quantity, uint8_t address = kSlaveAddress) {
  Bytes adu(8);
  adu.resize(build_read_request(adu.data(), 8, address, fc::kReadHoldingRegisters, start, quantity));
  return adu;
}
inline Bytes write_register(uint16_t reg, uint16_t value, uint8_t address = kSlaveAddress) {
  Bytes adu(8);
  adu.resize(build_write_single_register(adu.data(), 8, address, reg, value));
  return adu;
}

/// A ByteSink write that keeps the last ADU in the Bytes behind `ctx`.
inline bool keep_last(void* ctx, const uint8_t* data, uint16_t length) {
  static_cast<Bytes*>(ctx)->assign(data, data + length);
  return true;
}

class SlaveHarness {
 public:
  static constexpr uint32_t kBaud = 19200;  // t1.5 and t3.5 from the character time

  explicit SlaveHarness(uint32_t start_us = 1000000u)
      : bank(kCoilCount, kDiscreteInputCount, kInputRegisterCount, kHoldingRegisterCount),
        identity(test_identity()),
        timing(rtu_timing(kBaud)),
        slave(bank, &identity, ByteSink{&SlaveHarness::capture, this}, kSlaveAddress, timing),
        now_us(start_us) {
    apply_test_layout(bank);
  }

  /// Feeds `adu` back to back, the first character `silence_us` after the
  /// previous one ended; `now_us` ends at the last character's stamp.
  void feed(const Bytes& adu, uint32_t silence_us = 0) {
    for (size_t i = 0; i < adu.size(); ++i) {
      now_us += timing.char_us + (i == 0 ? silence_us : 0u);
      slave.on_byte(adu[i], now_us);
    }
  }
  /// Lets `us` of silence pass, calling process() at its end.
  void wait(uint32_t us) {
    now_us += us;
    slave.process(now_us);
  }
  /// Sends a request after a quiet line and lets the frame end. Returns the
  /// response it produced, or an empty vector when it stayed silent.
  Bytes transact(const Bytes& adu) {
    const size_t before = responses.size();
    feed(adu, timing.t35_us);
    wait(timing.t35_us);
    return responses.size() > before ? responses.back() : Bytes{};
  }

  MemoryBank bank;
  FixedIdentity identity;
  RtuTiming timing;
  Slave slave;
  uint32_t now_us;
  std::vector<Bytes> responses;
  bool sink_accepts = true;

 private:
  static bool capture(void* ctx, const uint8_t* data, uint16_t length) {
    auto* self = static_cast<SlaveHarness*>(ctx);
    if (!self->sink_accepts) return false;
    self->responses.emplace_back(data, data + length);
    return true;
  }
};

}  // namespace test
}  // namespace modbus
}  // namespace mb2co
