// Smallest firmware that links the Modbus slave for the ATmega328P: a bank
// over a few RAM registers, bytes from/to volatile stand-ins for the UART.
// Built by avr_size.sh only to measure what the slave costs in flash and RAM.
#include <stdint.h>

#include "modbus/slave.h"

using namespace mb2co::modbus;

namespace {

volatile uint8_t g_rx;      // stand-in for UDR0
volatile uint32_t g_clock;  // stand-in for micros()
volatile uint8_t g_tx;

class TinyBank : public RegisterBank {
 public:
  bool covers(Table table, Access access, uint16_t start, uint16_t count) override {
    if (access == Access::kWrite && table != Table::kHoldingRegisters && table != Table::kCoils) {
      return false;
    }
    return static_cast<uint32_t>(start) + count <= 16u;
  }
  Exception read_bits(Table, uint16_t start, BitSpan out) override {
    for (uint16_t i = 0; i < out.count; ++i) out.set(i, (regs_[0] >> ((start + i) & 15u)) & 1u);
    return Exception::kNone;
  }
  Exception read_registers(Table, uint16_t start, RegisterSpan out) override {
    for (uint16_t i = 0; i < out.count; ++i) out.set(i, regs_[start + i]);
    return Exception::kNone;
  }
  Exception write_coils(uint16_t start, ConstBitSpan values) override {
    for (uint16_t i = 0; i < values.count; ++i) {
      const uint16_t mask = static_cast<uint16_t>(1u << ((start + i) & 15u));
      regs_[0] = static_cast<uint16_t>(values.get(i) ? regs_[0] | mask : regs_[0] & ~mask);
    }
    return Exception::kNone;
  }
  Exception write_registers(uint16_t start, ConstRegisterSpan values) override {
    for (uint16_t i = 0; i < values.count; ++i) regs_[start + i] = values.get(i);
    return Exception::kNone;
  }

 private:
  uint16_t regs_[16] = {};
};

class TinyIdentity : public DeviceIdentity {
 public:
  uint8_t copy_object(uint8_t id, uint8_t* out, uint8_t capacity) override {
    static const char* const kObjects[3] = {"mb2co", "GW", "1"};
    uint8_t n = 0;
    while (kObjects[id][n] != '\0') {
      if (n < capacity) out[n] = static_cast<uint8_t>(kObjects[id][n]);
      ++n;
    }
    return n;
  }
};

bool send(void*, const uint8_t* data, uint16_t length) {
  for (uint16_t i = 0; i < length; ++i) g_tx = data[i];
  return true;
}

TinyBank g_bank;
TinyIdentity g_identity;

}  // namespace

int main() {
  Slave slave(g_bank, &g_identity, ByteSink{&send, nullptr}, 1, rtu_timing(115200));
  slave.begin(g_clock);
  for (;;) {
    if (g_rx != 0u) slave.on_byte(g_rx, g_clock);
    slave.process(g_clock);
  }
}
