#include "memory_bank.h"

#include <string.h>

#include <algorithm>

namespace mb2co {
namespace modbus {
namespace test {

MemoryBank::MemoryBank(uint32_t coil_count, uint32_t discrete_count, uint32_t input_count,
                       uint32_t holding_count)
    : coils(coil_count),
      discrete_inputs(discrete_count),
      input_registers(input_count),
      holding_registers(holding_count),
      read_only_(holding_count) {}

void MemoryBank::set_read_only(uint16_t start, uint16_t count) {
  for (uint32_t a = start; a < uint32_t{start} + count && a < read_only_.size(); ++a) {
    read_only_[a] = true;
  }
}

void MemoryBank::set_limit(uint16_t start, uint16_t count, uint16_t max) {
  limits_.push_back(Limit{start, count, max});
}

void MemoryBank::set_coil_rejects_on(uint16_t address) {
  coils_rejecting_on_.push_back(address);
}

void MemoryBank::set_read_failure(uint16_t address) {
  read_failures_.push_back(address);
}

uint32_t MemoryBank::size(Table table) const {
  switch (table) {
    case Table::kCoils:
      return static_cast<uint32_t>(coils.size());
    case Table::kDiscreteInputs:
      return static_cast<uint32_t>(discrete_inputs.size());
    case Table::kInputRegisters:
      return static_cast<uint32_t>(input_registers.size());
    case Table::kHoldingRegisters:
      return static_cast<uint32_t>(holding_registers.size());
  }
  return 0;
}

bool MemoryBank::covers(Table table, Access access, uint16_t start, uint16_t count) {
  const uint32_t end = uint32_t{start} + count;
  if (end > size(table)) return false;
  if (access == Access::kWrite) {
    if (table == Table::kDiscreteInputs || table == Table::kInputRegisters) return false;
    if (table == Table::kHoldingRegisters) {
      for (uint32_t a = start; a < end; ++a) {
        if (read_only_[a]) return false;
      }
    }
  }
  return true;
}

Exception MemoryBank::read_bits(Table table, uint16_t start, BitSpan out) {
  ++data_calls;
  const std::vector<bool>& bits = table == Table::kCoils ? coils : discrete_inputs;
  for (uint16_t i = 0; i < out.count; ++i) out.set(i, bits.at(start + i));
  return Exception::kNone;
}

Exception MemoryBank::read_registers(Table table, uint16_t start, RegisterSpan out) {
  ++data_calls;
  const bool input = table == Table::kInputRegisters;
  const std::vector<uint16_t>& regs = input ? input_registers : holding_registers;
  for (uint16_t i = 0; i < out.count; ++i) {
    const uint16_t a = static_cast<uint16_t>(start + i);
    if (input && std::count(read_failures_.begin(), read_failures_.end(), a) != 0) {
      return Exception::kServerDeviceFailure;
    }
    out.set(i, regs.at(a));
  }
  return Exception::kNone;
}

Exception MemoryBank::write_coils(uint16_t start, ConstBitSpan values) {
  ++data_calls;
  for (uint16_t i = 0; i < values.count; ++i) {  // validate everything first
    const uint16_t a = static_cast<uint16_t>(start + i);
    if (values.get(i) && std::count(coils_rejecting_on_.begin(), coils_rejecting_on_.end(), a) != 0) {
      return Exception::kServerDeviceFailure;
    }
  }
  for (uint16_t i = 0; i < values.count; ++i) coils.at(start + i) = values.get(i);
  return Exception::kNone;
}

Exception MemoryBank::write_registers(uint16_t start, ConstRegisterSpan values) {
  ++data_calls;
  for (uint16_t i = 0; i < values.count; ++i) {
    const uint32_t a = uint32_t{start} + i;
    for (const Limit& l : limits_) {
      if (a >= l.start && a < uint32_t{l.start} + l.count && values.get(i) > l.max) {
        return Exception::kServerDeviceFailure;
      }
    }
  }
  for (uint16_t i = 0; i < values.count; ++i) holding_registers.at(start + i) = values.get(i);
  return Exception::kNone;
}

uint8_t FixedIdentity::copy_object(uint8_t id, uint8_t* out, uint8_t capacity) {
  const std::string& s = objects_[id];
  const size_t full = std::min<size_t>(s.size(), 255);
  memcpy(out, s.data(), std::min<size_t>(full, capacity));
  return static_cast<uint8_t>(full);
}

}  // namespace test
}  // namespace modbus
}  // namespace mb2co
