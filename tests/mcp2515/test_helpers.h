// Frames and a fixture shared by the MCP2515 driver tests.
#pragma once
#include <gtest/gtest.h>

#include <cstring>
#include <initializer_list>
#include <ostream>

#include "mcp2515.h"
#include "mcp2515_model.h"

namespace mb2co {

inline bool operator==(const CanFrame& a, const CanFrame& b) {
  if (a.id != b.id || a.dlc != b.dlc || a.flags != b.flags) return false;
  return a.rtr() || std::memcmp(a.data, b.data, a.dlc) == 0;
}
inline std::ostream& operator<<(std::ostream& os, const CanFrame& f) {
  os << std::hex << "0x" << f.id << (f.extended() ? "x" : "") << (f.rtr() ? " RTR" : "") << " [" << std::dec
     << int{f.dlc} << "]";
  for (int i = 0; i < f.dlc && !f.rtr(); ++i) os << ' ' << std::hex << int{f.data[i]} << std::dec;
  return os;
}

namespace mcp2515::test {

using model::Mcp2515Model;

inline CanFrame frame(uint32_t id, std::initializer_list<uint8_t> data = {}, uint8_t flags = 0) {
  CanFrame f{};
  f.id = id;
  f.flags = flags;
  f.dlc = static_cast<uint8_t>(data.size());
  uint8_t i = 0;
  for (uint8_t b : data) f.data[i++] = b;
  return f;
}
inline CanFrame remote(uint32_t id, uint8_t dlc, uint8_t flags = 0) {
  CanFrame f = frame(id, {}, static_cast<uint8_t>(flags | CanFrame::kRtr));
  f.dlc = dlc;
  return f;
}

/// A driver on a model chip, started at 500 kbit/s in normal mode.
class DriverTest : public ::testing::Test {
 protected:
  void SetUp() override { ASSERT_TRUE(driver.begin(Bitrate::k500k, Mode::kNormal)); }

  /// service() as the main loop would: only when INT is low.
  uint8_t service_if_int() { return chip.int_low() ? driver.service() : 0; }

  /// Everything the driver can hand out now (service + receive until empty).
  std::vector<CanFrame> drain() {
    std::vector<CanFrame> out;
    for (int rounds = 0; rounds < 100 && chip.int_low(); ++rounds) {
      driver.service();
      CanFrame f;
      while (driver.receive(f)) out.push_back(f);
    }
    return out;
  }

  Mcp2515Model chip;
  Driver driver{chip.spi()};
};

}  // namespace mcp2515::test
}  // namespace mb2co
