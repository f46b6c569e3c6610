// libFuzzer target: the gateway's Modbus tables as windows onto its OD
// (OdRegisterBank), driven directly, with the gateway's hooks behind it
// (node id, bit rate, RUN latch, maps 2400h-2403h, save without storage).
// Each record: byte 0 bits 0..1 table, bit 2 write, bit 3 run the gateway's
// loop first; byte 1 start; byte 2 count - 1 (0..31); then the values
// (2 bytes per register, 1 bit per coil), fewer if the input ends.
// Invariants (violations abort): a refused write (any exception) leaves every
// stored value and the OD revision exactly as they were; after every write
// every numeric value is one its entry's type and limits allow; the const
// entries never change.
#include <stdint.h>
#include <string.h>

#include <vector>

#include "fuzz_support.h"
#include "gateway/gateway.h"

namespace {

using namespace mb2co;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  gateway::GatewayPorts ports{CanSink{&fuzz::drop_frame, nullptr},
                              modbus::ByteSink{&fuzz::drop_bytes, nullptr}, nullptr, 115200};
  gateway::Gateway g(ports);
  uint32_t now = 1000;
  g.start(now);
  gateway::OdRegisterBank bank(g.od());
  const std::vector<uint8_t> consts = fuzz::const_values(g.od());
  const fuzz::ValueRange values_stored = fuzz::value_range(g.od());
  fuzz::require_all_allowed(g.od(), "a default beyond its entry's limits");
  std::vector<uint8_t> at_check = values_stored.snapshot();  // every value allowed then
  size_t i = 0;
  while (i + 3 <= size) {
    const uint8_t op = data[i];
    const uint16_t start = data[i + 1];
    const uint16_t count = static_cast<uint16_t>((data[i + 2] & 31u) + 1u);
    i += 3;
    const modbus::Table table = static_cast<modbus::Table>(op & 3u);
    const bool bits = table == modbus::Table::kCoils || table == modbus::Table::kDiscreteInputs;
    if (op & 8u) g.process(now += 1000u, 0);
    uint8_t values[64] = {};
    const size_t n = bits ? (count + 7u) / 8u : 2u * count;
    const size_t take = size - i < n ? size - i : n;
    memcpy(values, data + i, take);
    i += take;
    if (!(op & 4u)) {
      uint8_t out[64];
      if (bank.covers(table, modbus::Access::kRead, start, count)) {
        if (bits)
          bank.read_bits(table, start, modbus::BitSpan{out, count});
        else
          bank.read_registers(table, start, modbus::RegisterSpan{out, count});
      }
      continue;
    }
    if (table != modbus::Table::kCoils && table != modbus::Table::kHoldingRegisters) continue;
    if (!bank.covers(table, modbus::Access::kWrite, start, count)) continue;
    const std::vector<uint8_t> before = values_stored.snapshot();
    const uint16_t revision = g.od().revision();
    const modbus::Exception ex = bits ? bank.write_coils(start, modbus::ConstBitSpan{values, count})
                                      : bank.write_registers(start, modbus::ConstRegisterSpan{values, count});
    if (ex != modbus::Exception::kNone) {
      fuzz::require(values_stored.unchanged_since(before), "a refused write changed a stored value");
      fuzz::require(g.od().revision() == revision, "a refused write changed the OD revision");
    }
    fuzz::require_changed_allowed(g.od(), values_stored, at_check,
                                  "a stored value beyond its entry's limits");
  }
  fuzz::require(fuzz::const_values(g.od()) == consts, "a const entry changed");
  return 0;
}
