// A map's count (2400h-2403h sub 0) is refused above its entries: the last
// map, 2403h, too (its capacity was once taken from the next index, which
// does not exist: 2403h/0 = 9 and 200 were accepted, and the register bank
// would have read the rows after 2403h as map entries).
#include <gtest/gtest.h>

#include "gateway/gateway.h"

namespace mb2co {
namespace test {
namespace {

TEST(MapCapacity, EveryMapRefusesACountAboveItsEntries) {
  const CanSink nowhere{[](void*, const CanFrame&) { return true; }, nullptr};
  gateway::Gateway gw(gateway::GatewayPorts{nowhere, modbus::ByteSink{nullptr, nullptr}, nullptr, 115200});
  gw.start(0, 1);
  const struct {
    uint16_t index;
    uint8_t entries;
  } maps[] = {{0x2400, gateway::kHoldingMapSize},
              {0x2401, gateway::kInputMapSize},
              {0x2402, gateway::kCoilMapSize},
              {0x2403, gateway::kDiscreteMapSize}};
  for (const auto& m : maps) {
    SCOPED_TRACE(m.index);
    uint8_t count = m.entries;
    EXPECT_EQ(gw.od().write(m.index, 0, &count, 1), canopen::kSdoOk);
    count = static_cast<uint8_t>(m.entries + 1u);
    EXPECT_EQ(gw.od().write(m.index, 0, &count, 1), canopen::kAbortValueTooHigh);
    count = 200;
    EXPECT_EQ(gw.od().write(m.index, 0, &count, 1), canopen::kAbortValueTooHigh);
  }
}

}  // namespace
}  // namespace test
}  // namespace mb2co
