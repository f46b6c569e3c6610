// Data function codes 01 02 03 04 05 06 0F 10 17 (bits and registers share
// one path per kind of request). Each follows the state
// diagram of the application protocol spec §6: quantity/value/byte count
// (03), then address range (02), then execution (04 or the bank's code).
// The request is read into locals before the response overwrites the buffer.
#include <string.h>

#include "modbus/slave.h"

namespace mb2co {
namespace modbus {
namespace {

bool quantity_ok(uint16_t quantity, uint16_t max) {
  return quantity >= 1u && quantity <= max;
}

// start + quantity - 1 must not pass 65535 ("Starting Address + Quantity == OK").
bool range_fits(uint16_t start, uint16_t quantity) {
  return static_cast<uint32_t>(start) + quantity <= 0x10000ul;
}

bool accessible(RegisterBank& bank, Table table, Access access, uint16_t start, uint16_t quantity) {
  return range_fits(start, quantity) && bank.covers(table, access, start, quantity);
}

}  // namespace

SlaveCore::Reply SlaveCore::read(uint16_t pdu_length, Table table) {
  uint8_t* p = pdu();
  const bool bits = table == Table::kCoils || table == Table::kDiscreteInputs;
  if (pdu_length != 5u) return Reply{0, Exception::kIllegalDataValue};
  const uint16_t start = get_be16(p + 1);
  const uint16_t quantity = get_be16(p + 3);
  if (!quantity_ok(quantity, bits ? kMaxReadBits : kMaxReadRegisters)) {
    return Reply{0, Exception::kIllegalDataValue};
  }
  if (!accessible(bank_, table, Access::kRead, start, quantity)) {
    return Reply{0, Exception::kIllegalDataAddress};
  }
  const uint16_t bytes = bits ? packed_bit_bytes(quantity) : static_cast<uint16_t>(2u * quantity);
  if (!fits(static_cast<uint16_t>(2u + bytes))) return Reply{0, Exception::kServerDeviceFailure};
  Exception e;
  if (bits) {
    memset(p + 2, 0, bytes);
    e = bank_.read_bits(table, start, BitSpan{p + 2, quantity});
  } else {
    e = bank_.read_registers(table, start, RegisterSpan{p + 2, quantity});
  }
  if (e != Exception::kNone) return Reply{0, e};
  p[1] = static_cast<uint8_t>(bytes);
  return Reply{static_cast<uint16_t>(2u + bytes), Exception::kNone};
}

SlaveCore::Reply SlaveCore::write_single_coil(uint16_t pdu_length) {
  const uint8_t* p = pdu();
  if (pdu_length != 5u) return Reply{0, Exception::kIllegalDataValue};
  const uint16_t address = get_be16(p + 1);
  const uint16_t value = get_be16(p + 3);
  if (value != kCoilOn && value != kCoilOff) return Reply{0, Exception::kIllegalDataValue};
  const uint8_t bit = value == kCoilOn ? 1u : 0u;
  return write_checked(Table::kCoils, address, 1, &bit);  // the response echoes the request
}

SlaveCore::Reply SlaveCore::write_single_register(uint16_t pdu_length) {
  const uint8_t* p = pdu();
  if (pdu_length != 5u) return Reply{0, Exception::kIllegalDataValue};
  const uint16_t address = get_be16(p + 1);
  // Every 16-bit value is legal (the diagram's 0000..FFFF check cannot fail).
  return write_checked(Table::kHoldingRegisters, address, 1, p + 3);  // echo
}

SlaveCore::Reply SlaveCore::write_multiple(uint16_t pdu_length, Table table) {
  const uint8_t* p = pdu();
  const bool coils = table == Table::kCoils;
  if (pdu_length < 6u) return Reply{0, Exception::kIllegalDataValue};
  const uint16_t start = get_be16(p + 1);
  const uint16_t quantity = get_be16(p + 3);
  const uint8_t byte_count = p[5];
  const uint16_t expected_bytes = coils ? packed_bit_bytes(quantity) : static_cast<uint16_t>(2u * quantity);
  if (!quantity_ok(quantity, coils ? kMaxWriteCoils : kMaxWriteRegisters) || byte_count != expected_bytes ||
      pdu_length != 6u + byte_count) {
    return Reply{0, Exception::kIllegalDataValue};
  }
  return write_checked(table, start, quantity, p + 6);  // function, start, quantity: in place
}

// FC 05, 06, 0F, 10 after their own checks: the address range (02), then the
// write; every response is 5 bytes of the request echoed. One path for the
// four. A single address always passes range_fits().
SlaveCore::Reply SlaveCore::write_checked(Table table, uint16_t start, uint16_t quantity,
                                          const uint8_t* values) {
  if (!accessible(bank_, table, Access::kWrite, start, quantity)) {
    return Reply{0, Exception::kIllegalDataAddress};
  }
  const Exception e = table == Table::kCoils
                          ? bank_.write_coils(start, ConstBitSpan{values, quantity})
                          : bank_.write_registers(start, ConstRegisterSpan{values, quantity});
  return Reply{5, e};
}

SlaveCore::Reply SlaveCore::read_write_registers(uint16_t pdu_length) {
  uint8_t* p = pdu();
  if (pdu_length < 10u) return Reply{0, Exception::kIllegalDataValue};
  const uint16_t read_start = get_be16(p + 1);
  const uint16_t read_quantity = get_be16(p + 3);
  const uint16_t write_start = get_be16(p + 5);
  const uint16_t write_quantity = get_be16(p + 7);
  const uint8_t byte_count = p[9];
  if (!quantity_ok(read_quantity, kMaxReadRegisters) ||
      !quantity_ok(write_quantity, kMaxReadWriteWriteRegs) || byte_count != 2u * write_quantity ||
      pdu_length != 10u + byte_count) {
    return Reply{0, Exception::kIllegalDataValue};
  }
  if (!accessible(bank_, Table::kHoldingRegisters, Access::kRead, read_start, read_quantity) ||
      !accessible(bank_, Table::kHoldingRegisters, Access::kWrite, write_start, write_quantity)) {
    return Reply{0, Exception::kIllegalDataAddress};
  }
  if (!fits(static_cast<uint16_t>(2u + 2u * read_quantity))) {
    return Reply{0, Exception::kServerDeviceFailure};  // checked before anything is written
  }
  // The write is performed before the read (spec §6.17). The read output
  // overlaps the write data only after write_registers has returned.
  Exception e = bank_.write_registers(write_start, ConstRegisterSpan{p + 10, write_quantity});
  if (e != Exception::kNone) return Reply{0, e};
  e = bank_.read_registers(Table::kHoldingRegisters, read_start, RegisterSpan{p + 2, read_quantity});
  if (e != Exception::kNone) return Reply{0, e};
  p[1] = static_cast<uint8_t>(2u * read_quantity);
  return Reply{static_cast<uint16_t>(2u + 2u * read_quantity), Exception::kNone};
}

}  // namespace modbus
}  // namespace mb2co
