// Every data function code against the in-memory bank: normal responses,
// quantity limits at the exact boundaries, exceptions in the order of the
// application protocol's state diagrams, all-or-nothing multiple writes.
#include <gtest/gtest.h>

#include "modbus/master_codec.h"
#include "support/slave_harness.h"

namespace mb2co {
namespace modbus {
namespace test {
namespace {

Bytes request(uint8_t function, std::initializer_list<uint16_t> words, Bytes tail = {}) {
  Bytes adu{kSlaveAddress, function};
  for (uint16_t w : words) {
    adu.push_back(static_cast<uint8_t>(w >> 8));
    adu.push_back(static_cast<uint8_t>(w));
  }
  adu.insert(adu.end(), tail.begin(), tail.end());
  return with_crc(adu);
}

Bytes exception(uint8_t function, Exception code) {
  return with_crc({kSlaveAddress, static_cast<uint8_t>(function | 0x80), static_cast<uint8_t>(code)});
}

Bytes cat(Bytes a, const Bytes& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

Bytes register_bytes(uint16_t count, uint16_t value) {
  Bytes b;
  for (uint16_t i = 0; i < count; ++i) {
    b.push_back(static_cast<uint8_t>(value >> 8));
    b.push_back(static_cast<uint8_t>(value));
  }
  return b;
}

class ModbusFunctions : public ::testing::Test {
 protected:
  SlaveHarness h;
  Bytes ask(const Bytes& adu) { return h.transact(adu); }
};

TEST_F(ModbusFunctions, ReadCoils) {
  h.bank.coils[3] = h.bank.coils[4] = h.bank.coils[12] = true;
  // Coils 3..13: bits LSB first, the unused high bits of the last byte are 0.
  EXPECT_EQ(ask(request(0x01, {3, 11})), with_crc({1, 0x01, 2, 0x03, 0x02}));
}

TEST_F(ModbusFunctions, ReadDiscreteInputs) {
  // Inputs 0..9 are i % 3 == 0: 0, 3, 6, 9 → 0b01001001, 0b10.
  EXPECT_EQ(ask(request(0x02, {0, 10})), with_crc({1, 0x02, 2, 0x49, 0x02}));
}

TEST_F(ModbusFunctions, ReadHoldingRegisters) {
  h.bank.holding_registers[7] = 0xBEEF;
  h.bank.holding_registers[8] = 0x0102;
  EXPECT_EQ(ask(request(0x03, {7, 2})), with_crc({1, 0x03, 4, 0xBE, 0xEF, 0x01, 0x02}));
}

TEST_F(ModbusFunctions, ReadInputRegisters) {
  EXPECT_EQ(ask(request(0x04, {0x10, 2})), with_crc({1, 0x04, 4, 0x10, 0x10, 0x10, 0x11}));
}

TEST_F(ModbusFunctions, WriteSingleCoilEchoes) {
  const Bytes on = request(0x05, {9, 0xFF00});
  EXPECT_EQ(ask(on), on);
  EXPECT_TRUE(h.bank.coils[9]);
  const Bytes off = request(0x05, {9, 0x0000});
  EXPECT_EQ(ask(off), off);
  EXPECT_FALSE(h.bank.coils[9]);
}

TEST_F(ModbusFunctions, WriteSingleRegisterEchoes) {
  const Bytes req = request(0x06, {12, 0xFFFF});
  EXPECT_EQ(ask(req), req);
  EXPECT_EQ(h.bank.holding_registers[12], 0xFFFF);
}

TEST_F(ModbusFunctions, WriteMultipleCoils) {
  // Coils 20..29 = 1,0,1,1,0,0,1,1 | 1,0 (spec example pattern CD 01).
  EXPECT_EQ(ask(request(0x0F, {20, 10}, {2, 0xCD, 0x01})), with_crc({1, 0x0F, 0, 20, 0, 10}));
  const bool expected[10] = {1, 0, 1, 1, 0, 0, 1, 1, 1, 0};
  for (size_t i = 0; i < 10; ++i) EXPECT_EQ(h.bank.coils[20 + i], expected[i]) << i;
}

TEST_F(ModbusFunctions, WriteMultipleRegisters) {
  EXPECT_EQ(ask(request(0x10, {30, 2}, {4, 0x00, 0x0A, 0x01, 0x02})), with_crc({1, 0x10, 0, 30, 0, 2}));
  EXPECT_EQ(h.bank.holding_registers[30], 0x000A);
  EXPECT_EQ(h.bank.holding_registers[31], 0x0102);
}

TEST_F(ModbusFunctions, ReadWriteMultipleRegistersWritesBeforeReading) {
  h.bank.holding_registers[41] = 0x1111;
  // Read 40..42, write 41..42: the read sees the new values.
  EXPECT_EQ(ask(request(0x17, {40, 3, 41, 2}, {4, 0xAA, 0xBB, 0xCC, 0xDD})),
            with_crc({1, 0x17, 6, 0x00, 0x00, 0xAA, 0xBB, 0xCC, 0xDD}));
}

TEST_F(ModbusFunctions, UnsupportedFunctionCodes) {
  for (uint8_t f : std::initializer_list<uint8_t>{0x00, 0x07, 0x0B, 0x11, 0x16, 0x18, 0x2A, 0x7F, 0x81}) {
    EXPECT_EQ(ask(with_crc({1, f, 0, 0, 0, 1})), exception(f, Exception::kIllegalFunction)) << int(f);
  }
  EXPECT_EQ(h.bank.data_calls, 0u);
  EXPECT_EQ(h.slave.counters().exceptions, 9u);
}

struct Limit {
  uint8_t function;
  uint16_t max;
};

TEST_F(ModbusFunctions, ReadQuantityLimitsAtTheBoundaries) {
  for (Limit l : {Limit{0x01, 2000}, Limit{0x02, 2000}, Limit{0x03, 125}, Limit{0x04, 125}}) {
    const Bytes ok = ask(request(l.function, {0, l.max}));
    ASSERT_GE(ok.size(), 3u);
    EXPECT_EQ(ok[1], l.function);
    EXPECT_EQ(ok[2], 250) << "byte count";
    EXPECT_EQ(ask(request(l.function, {0, uint16_t(l.max + 1)})),
              exception(l.function, Exception::kIllegalDataValue));
    EXPECT_EQ(ask(request(l.function, {0, 0})), exception(l.function, Exception::kIllegalDataValue));
    EXPECT_EQ(ask(request(l.function, {0, 1})).at(1), l.function);
  }
}

// Writes at the maximum go above the read-only/limited registers (100..119).
// A quantity one above the maximum is checked with a short request: the full
// frame would not fit in 256 bytes (it would be an overrun, not an exception).
TEST_F(ModbusFunctions, WriteQuantityLimitsAtTheBoundaries) {
  EXPECT_EQ(ask(request(0x0F, {0, 1968}, cat({246}, Bytes(246, 0x00)))).at(1), 0x0F);
  EXPECT_EQ(ask(request(0x0F, {0, 1969}, cat({247}, Bytes(247, 0x00)))),
            exception(0x0F, Exception::kIllegalDataValue));
  EXPECT_EQ(ask(request(0x0F, {0, 0}, {0})), exception(0x0F, Exception::kIllegalDataValue));

  EXPECT_EQ(ask(request(0x10, {120, 123}, cat({246}, register_bytes(123, 1)))).at(1), 0x10);
  EXPECT_EQ(ask(request(0x10, {0, 124}, {248, 0, 1})), exception(0x10, Exception::kIllegalDataValue));
  EXPECT_EQ(ask(request(0x10, {0, 0}, {0})), exception(0x10, Exception::kIllegalDataValue));

  EXPECT_EQ(ask(request(0x17, {0, 125, 120, 121}, cat({242}, register_bytes(121, 2)))).at(1), 0x17);
  EXPECT_EQ(ask(request(0x17, {0, 126, 0, 1}, {2, 0, 0})), exception(0x17, Exception::kIllegalDataValue));
  EXPECT_EQ(ask(request(0x17, {0, 1, 0, 122}, {244, 0, 2})), exception(0x17, Exception::kIllegalDataValue));
  EXPECT_EQ(ask(request(0x17, {0, 0, 0, 1}, {2, 0, 0})), exception(0x17, Exception::kIllegalDataValue));
  EXPECT_EQ(ask(request(0x17, {0, 1, 0, 0}, {0})), exception(0x17, Exception::kIllegalDataValue));
}

TEST_F(ModbusFunctions, ByteCountAndLengthMismatchesAreIllegalValue) {
  // Byte count not matching the quantity, then not matching the frame.
  EXPECT_EQ(ask(request(0x0F, {0, 9}, {1, 0xFF})), exception(0x0F, Exception::kIllegalDataValue));
  EXPECT_EQ(ask(request(0x0F, {0, 9}, {2, 0xFF})), exception(0x0F, Exception::kIllegalDataValue));
  EXPECT_EQ(ask(request(0x10, {0, 1}, {4, 0, 1, 0, 2})), exception(0x10, Exception::kIllegalDataValue));
  EXPECT_EQ(ask(request(0x10, {0, 2}, {4, 0, 1})), exception(0x10, Exception::kIllegalDataValue));
  EXPECT_EQ(ask(request(0x17, {0, 1, 0, 1}, {4, 0, 1})), exception(0x17, Exception::kIllegalDataValue));
  // Fixed-length requests one byte short or long.
  EXPECT_EQ(ask(with_crc({1, 0x03, 0, 0, 0})), exception(0x03, Exception::kIllegalDataValue));
  EXPECT_EQ(ask(with_crc({1, 0x06, 0, 0, 0, 1, 0})), exception(0x06, Exception::kIllegalDataValue));
  EXPECT_EQ(ask(with_crc({1, 0x01})), exception(0x01, Exception::kIllegalDataValue));
  EXPECT_EQ(h.bank.data_calls, 0u);
}

TEST_F(ModbusFunctions, AddressRangeAtTheBoundaries) {
  // Last coil and register exist; one further does not.
  EXPECT_EQ(ask(request(0x01, {kCoilCount - 1, 1})).at(1), 0x01);
  EXPECT_EQ(ask(request(0x01, {kCoilCount - 1, 2})), exception(0x01, Exception::kIllegalDataAddress));
  EXPECT_EQ(ask(request(0x02, {kDiscreteInputCount, 1})), exception(0x02, Exception::kIllegalDataAddress));
  EXPECT_EQ(ask(request(0x03, {kHoldingRegisterCount - 125, 125})).at(1), 0x03);
  EXPECT_EQ(ask(request(0x03, {kHoldingRegisterCount - 124, 125})),
            exception(0x03, Exception::kIllegalDataAddress));
  EXPECT_EQ(ask(request(0x04, {kInputRegisterCount, 1})), exception(0x04, Exception::kIllegalDataAddress));
  EXPECT_EQ(ask(request(0x05, {kCoilCount, 0xFF00})), exception(0x05, Exception::kIllegalDataAddress));
  EXPECT_EQ(ask(request(0x06, {kHoldingRegisterCount, 1})), exception(0x06, Exception::kIllegalDataAddress));
  EXPECT_EQ(ask(request(0x0F, {kCoilCount - 1, 2}, {1, 3})), exception(0x0F, Exception::kIllegalDataAddress));
  EXPECT_EQ(ask(request(0x10, {kHoldingRegisterCount - 1, 2}, {4, 0, 1, 0, 2})),
            exception(0x10, Exception::kIllegalDataAddress));
  EXPECT_EQ(ask(request(0x17, {kHoldingRegisterCount, 1, 0, 1}, {2, 0, 1})),
            exception(0x17, Exception::kIllegalDataAddress));
  EXPECT_EQ(ask(request(0x17, {0, 1, kHoldingRegisterCount, 1}, {2, 0, 1})),
            exception(0x17, Exception::kIllegalDataAddress));
  EXPECT_EQ(h.bank.holding_registers[0], 0) << "FC 17 wrote although its read range was bad";
}

TEST(ModbusAddressSpace, StartPlusQuantityMustNotPass65535) {
  // A bank that covers the whole 64 Ki address space: the slave's own check.
  SlaveHarness h;
  MemoryBank full(65536, 65536, 65536, 65536);
  Bytes out;
  Slave s(full, nullptr, ByteSink{&keep_last, &out}, 1, h.timing);
  auto ask = [&](const Bytes& adu) {
    out.clear();
    uint32_t t = h.now_us += 100000;
    for (uint8_t b : adu) s.on_byte(b, t += h.timing.char_us);
    s.process(t + h.timing.t35_us);
    h.now_us = t + h.timing.t35_us;
    return out;
  };
  EXPECT_EQ(ask(request(0x03, {0xFFFF, 1})).at(1), 0x03);
  EXPECT_EQ(ask(request(0x03, {0xFFFF, 2})), exception(0x03, Exception::kIllegalDataAddress));
  EXPECT_EQ(ask(request(0x01, {0xFFF0, 16})).at(1), 0x01);
  EXPECT_EQ(ask(request(0x01, {0xFFF0, 17})), exception(0x01, Exception::kIllegalDataAddress));
  EXPECT_EQ(ask(request(0x06, {0xFFFF, 5})).at(1), 0x06);
  EXPECT_EQ(full.holding_registers[0xFFFF], 5);
  EXPECT_EQ(ask(request(0x10, {0xFFFF, 2}, {4, 0, 1, 0, 2})),
            exception(0x10, Exception::kIllegalDataAddress));
  EXPECT_EQ(full.holding_registers[0], 0);
}

TEST_F(ModbusFunctions, ExceptionOrderQuantityBeforeAddress) {
  // Both the quantity and the address are wrong: 03 wins (state diagrams).
  EXPECT_EQ(ask(request(0x03, {0xFFFF, 126})), exception(0x03, Exception::kIllegalDataValue));
  EXPECT_EQ(ask(request(0x01, {0xFFFF, 2001})), exception(0x01, Exception::kIllegalDataValue));
  EXPECT_EQ(ask(request(0x10, {0xFFFF, 124}, {248, 0, 1})), exception(0x10, Exception::kIllegalDataValue));
  // FC 05: the value is checked before the address.
  EXPECT_EQ(ask(request(0x05, {kCoilCount, 0x1234})), exception(0x05, Exception::kIllegalDataValue));
  EXPECT_EQ(ask(request(0x05, {0, 0x00FF})), exception(0x05, Exception::kIllegalDataValue));
}

TEST_F(ModbusFunctions, ExceptionOrderAddressBeforeExecution) {
  // Range covers a read-only register (02) and a value the limit rejects (04): 02.
  EXPECT_EQ(ask(request(0x10, {kLimitedStart - 1, 2}, {4, 0xFF, 0xFF, 0xFF, 0xFF})),
            exception(0x10, Exception::kIllegalDataAddress));
  EXPECT_EQ(h.bank.data_calls, 0u);
}

TEST_F(ModbusFunctions, WriteToReadOnlyIsIllegalAddress) {
  EXPECT_EQ(ask(request(0x06, {kReadOnlyStart, 1})), exception(0x06, Exception::kIllegalDataAddress));
  EXPECT_EQ(h.bank.holding_registers[kReadOnlyStart], 0xA000 + kReadOnlyStart);
  // Reading it is fine.
  EXPECT_EQ(ask(request(0x03, {kReadOnlyStart, 1})).at(1), 0x03);
}

TEST_F(ModbusFunctions, ExecutionFailuresAreServerDeviceFailure) {
  EXPECT_EQ(ask(request(0x06, {kLimitedStart, kLimitMax + 1})),
            exception(0x06, Exception::kServerDeviceFailure));
  EXPECT_EQ(ask(request(0x04, {kFailingInputRegister - 1, 3})),
            exception(0x04, Exception::kServerDeviceFailure));
  EXPECT_EQ(ask(request(0x05, {kCoilRejectingOn, 0xFF00})), exception(0x05, Exception::kServerDeviceFailure));
  EXPECT_EQ(h.slave.counters().exceptions, 3u);
}

TEST_F(ModbusFunctions, MultipleRegisterWriteIsAllOrNothing) {
  // 108, 109 read-only, so start at the limited block: 110 ok, 111 too big.
  EXPECT_EQ(ask(request(0x10, {kLimitedStart, 3}, {6, 0, 5, 0x03, 0xE9, 0, 6})),
            exception(0x10, Exception::kServerDeviceFailure));
  EXPECT_EQ(h.bank.holding_registers[kLimitedStart], 0);
  EXPECT_EQ(h.bank.holding_registers[kLimitedStart + 2], 0);
  // The same through FC 17: nothing written, nothing read.
  EXPECT_EQ(ask(request(0x17, {0, 1, kLimitedStart, 2}, {4, 0, 5, 0xFF, 0xFF})),
            exception(0x17, Exception::kServerDeviceFailure));
  EXPECT_EQ(h.bank.holding_registers[kLimitedStart], 0);
  // Within the limit it all lands.
  EXPECT_EQ(ask(request(0x10, {kLimitedStart, 2}, {4, 0x03, 0xE8, 0, 1})).at(1), 0x10);
  EXPECT_EQ(h.bank.holding_registers[kLimitedStart], 1000);
  EXPECT_EQ(h.bank.holding_registers[kLimitedStart + 1], 1);
}

TEST_F(ModbusFunctions, MultipleCoilWriteIsAllOrNothing) {
  EXPECT_EQ(ask(request(0x0F, {kCoilRejectingOn - 7, 8}, {1, 0xFF})),
            exception(0x0F, Exception::kServerDeviceFailure));
  for (size_t i = 0; i < 8; ++i) EXPECT_FALSE(h.bank.coils[kCoilRejectingOn - 7u + i]);
  EXPECT_EQ(ask(request(0x0F, {kCoilRejectingOn - 7, 8}, {1, 0x7F})).at(1), 0x0F);
  EXPECT_TRUE(h.bank.coils[kCoilRejectingOn - 7]);
}

}  // namespace
}  // namespace test
}  // namespace modbus
}  // namespace mb2co
