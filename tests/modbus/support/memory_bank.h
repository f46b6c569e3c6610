// In-memory RegisterBank and DeviceIdentity for tests and the pty test slave.
// Addresses 0..size-1 of each table exist; rules add the failure cases the
// slave must translate into exceptions 02 and 04.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "modbus/register_bank.h"

namespace mb2co {
namespace modbus {
namespace test {

class MemoryBank : public RegisterBank {
 public:
  MemoryBank(uint32_t coils, uint32_t discrete_inputs, uint32_t input_registers, uint32_t holding_registers);

  // Rules (all-or-nothing writes are checked against them before commit).
  /// Holding registers [start, start+count) cannot be written: covers() false → 02.
  void set_read_only(uint16_t start, uint16_t count);
  /// Holding registers [start, start+count) reject values > max → 04.
  void set_limit(uint16_t start, uint16_t count, uint16_t max);
  /// Coil `address` rejects the value ON → 04.
  void set_coil_rejects_on(uint16_t address);
  /// Reading input register `address` fails → 04.
  void set_read_failure(uint16_t address);

  bool covers(Table table, Access access, uint16_t start, uint16_t count) override;
  Exception read_bits(Table table, uint16_t start, BitSpan out) override;
  Exception read_registers(Table table, uint16_t start, RegisterSpan out) override;
  Exception write_coils(uint16_t start, ConstBitSpan values) override;
  Exception write_registers(uint16_t start, ConstRegisterSpan values) override;

  std::vector<bool> coils;
  std::vector<bool> discrete_inputs;
  std::vector<uint16_t> input_registers;
  std::vector<uint16_t> holding_registers;
  /// Calls of read_*/write_* (covers() not counted): 0 proves nothing ran.
  unsigned data_calls = 0;

 private:
  struct Limit {
    uint16_t start, count, max;
  };
  uint32_t size(Table table) const;

  std::vector<bool> read_only_;
  std::vector<Limit> limits_;
  std::vector<uint16_t> coils_rejecting_on_;
  std::vector<uint16_t> read_failures_;
};

class FixedIdentity : public DeviceIdentity {
 public:
  FixedIdentity(std::string vendor, std::string product, std::string revision)
      : objects_{std::move(vendor), std::move(product), std::move(revision)} {}
  uint8_t copy_object(uint8_t id, uint8_t* out, uint8_t capacity) override;
  const std::string& object(uint8_t id) const { return objects_[id]; }

 private:
  std::string objects_[3];
};

}  // namespace test
}  // namespace modbus
}  // namespace mb2co
