// The register layout of tests/modbus/pty_slave.cpp, shared with the peers
// that talk to it (the Python peers repeat these numbers in their headers).
#pragma once
#include <stdint.h>

#include "memory_bank.h"

namespace mb2co {
namespace modbus {
namespace test {

constexpr uint8_t kSlaveAddress = 1;
constexpr uint16_t kCoilCount = 2048;
constexpr uint16_t kDiscreteInputCount = 2048;   ///< input i is (i % 3 == 0)
constexpr uint16_t kInputRegisterCount = 256;    ///< register i holds 0x1000 + i
constexpr uint16_t kHoldingRegisterCount = 256;  ///< all 0 at start, except:
constexpr uint16_t kReadOnlyStart = 100;         ///< 100..109 read-only (0xA000 + i): write → 02
constexpr uint16_t kReadOnlyCount = 10;
constexpr uint16_t kLimitedStart = 110;  ///< 110..119 accept values ≤ 1000: else → 04
constexpr uint16_t kLimitedCount = 10;
constexpr uint16_t kLimitMax = 1000;
constexpr uint16_t kFailingInputRegister = 200;  ///< reading it → 04
constexpr uint16_t kCoilRejectingOn = 2047;      ///< writing ON → 04

inline void apply_test_layout(MemoryBank& bank) {
  for (uint32_t i = 0; i < bank.discrete_inputs.size(); ++i) bank.discrete_inputs[i] = i % 3 == 0;
  for (uint32_t i = 0; i < bank.input_registers.size(); ++i) {
    bank.input_registers[i] = static_cast<uint16_t>(0x1000 + i);
  }
  for (uint16_t i = 0; i < kReadOnlyCount; ++i) {
    bank.holding_registers[kReadOnlyStart + i] = static_cast<uint16_t>(0xA000 + kReadOnlyStart + i);
  }
  bank.set_read_only(kReadOnlyStart, kReadOnlyCount);
  bank.set_limit(kLimitedStart, kLimitedCount, kLimitMax);
  bank.set_read_failure(kFailingInputRegister);
  bank.set_coil_rejects_on(kCoilRejectingOn);
}

inline FixedIdentity test_identity() {
  return FixedIdentity("mb2co", "MB2CO-GW", "0.1.0");
}

}  // namespace test
}  // namespace modbus
}  // namespace mb2co
