#include "modbus/master_codec.h"

#include "crc/crc16.h"

namespace mb2co {
namespace modbus {
namespace {

// Appends fields to a bounded buffer; finish() adds the CRC, 0 on overflow.
class AduWriter {
 public:
  AduWriter(uint8_t* out, uint16_t capacity, uint8_t address, uint8_t function)
      : out_(out), capacity_(capacity) {
    u8(address);
    u8(function);
  }
  void u8(uint8_t v) {
    if (length_ < capacity_) {
      out_[length_] = v;
    } else {
      overflow_ = true;
    }
    ++length_;
  }
  void u16(uint16_t v) {
    u8(static_cast<uint8_t>(v >> 8));
    u8(static_cast<uint8_t>(v & 0xFFu));
  }
  uint16_t finish() {
    if (overflow_ || length_ + kCrcBytes > capacity_ || length_ + kCrcBytes > kMaxAduBytes) {
      return 0;
    }
    return append_crc(out_, length_);
  }

 private:
  uint8_t* out_;
  uint16_t capacity_;
  uint16_t length_ = 0;
  bool overflow_ = false;
};

bool is_read(uint8_t function) {
  return function >= fc::kReadCoils && function <= fc::kReadInputRegisters;
}

}  // namespace

uint16_t build_read_request(uint8_t* out, uint16_t capacity, uint8_t address, uint8_t function,
                            uint16_t start, uint16_t quantity) {
  if (!is_read(function)) return 0;
  AduWriter w(out, capacity, address, function);
  w.u16(start);
  w.u16(quantity);
  return w.finish();
}

uint16_t build_write_single_coil(uint8_t* out, uint16_t capacity, uint8_t address, uint16_t coil, bool on) {
  AduWriter w(out, capacity, address, fc::kWriteSingleCoil);
  w.u16(coil);
  w.u16(on ? kCoilOn : kCoilOff);
  return w.finish();
}

uint16_t build_write_single_register(uint8_t* out, uint16_t capacity, uint8_t address, uint16_t reg,
                                     uint16_t value) {
  AduWriter w(out, capacity, address, fc::kWriteSingleRegister);
  w.u16(reg);
  w.u16(value);
  return w.finish();
}

uint16_t build_write_coils(uint8_t* out, uint16_t capacity, uint8_t address, uint16_t start,
                           uint16_t quantity, const uint8_t* packed) {
  const uint16_t bytes = packed_bit_bytes(quantity);
  if (bytes > 0xFFu) return 0;
  AduWriter w(out, capacity, address, fc::kWriteMultipleCoils);
  w.u16(start);
  w.u16(quantity);
  w.u8(static_cast<uint8_t>(bytes));
  for (uint16_t i = 0; i < bytes; ++i) w.u8(packed[i]);
  return w.finish();
}

uint16_t build_write_registers(uint8_t* out, uint16_t capacity, uint8_t address, uint16_t start,
                               uint16_t quantity, const uint16_t* values) {
  if (quantity > 0x7Fu) return 0;  // byte count is one byte
  AduWriter w(out, capacity, address, fc::kWriteMultipleRegisters);
  w.u16(start);
  w.u16(quantity);
  w.u8(static_cast<uint8_t>(2u * quantity));
  for (uint16_t i = 0; i < quantity; ++i) w.u16(values[i]);
  return w.finish();
}

uint16_t build_read_write_registers(uint8_t* out, uint16_t capacity, uint8_t address, uint16_t read_start,
                                    uint16_t read_quantity, uint16_t write_start, uint16_t write_quantity,
                                    const uint16_t* values) {
  if (write_quantity > 0x7Fu) return 0;
  AduWriter w(out, capacity, address, fc::kReadWriteMultipleRegisters);
  w.u16(read_start);
  w.u16(read_quantity);
  w.u16(write_start);
  w.u16(write_quantity);
  w.u8(static_cast<uint8_t>(2u * write_quantity));
  for (uint16_t i = 0; i < write_quantity; ++i) w.u16(values[i]);
  return w.finish();
}

uint16_t build_diagnostics(uint8_t* out, uint16_t capacity, uint8_t address, uint16_t sub,
                           const uint8_t* data, uint16_t data_length) {
  AduWriter w(out, capacity, address, fc::kDiagnostics);
  w.u16(sub);
  for (uint16_t i = 0; i < data_length; ++i) w.u8(data[i]);
  return w.finish();
}

uint16_t build_diagnostics(uint8_t* out, uint16_t capacity, uint8_t address, uint16_t sub, uint16_t data) {
  uint8_t field[2];
  put_be16(field, data);
  return build_diagnostics(out, capacity, address, sub, field, 2);
}

uint16_t build_read_device_id(uint8_t* out, uint16_t capacity, uint8_t address, uint8_t code,
                              uint8_t object_id) {
  AduWriter w(out, capacity, address, fc::kEncapsulatedInterface);
  w.u8(kMeiReadDeviceId);
  w.u8(code);
  w.u8(object_id);
  return w.finish();
}

}  // namespace modbus
}  // namespace mb2co
