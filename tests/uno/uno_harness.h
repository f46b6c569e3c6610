// mb2co-uno as a child process for the tests: the real gateway image
// (mb2co-gateway.elf of this build tree) in simavr, with the control channel
// and the ready line of mb2co-node. Every wait polls a condition with a
// deadline that bounds only a failure.
#pragma once
#include <chrono>
#include <string>
#include <vector>

#include "line_child.h"
#include "node_harness.h"

namespace mb2co {
namespace test {

using namespace std::chrono_literals;

/// Path of the mb2co-uno binary and of the AVR image under test.
const char* uno_program();
const char* uno_elf();
/// True when the network tests run against `mb2co-uno --image network`
/// (mb2co-gateway-network.elf), false while they run against mb2co-node
/// because that image does not fit the part yet: tests/uno/CMakeLists.txt,
/// MB2CO_NET_GATEWAY.
bool network_gateway_is_uno();

/// Same control channel and ready line as mb2co-node's: a NodeProcess
/// started with mb2co-uno --elf <the image>.
class UnoProcess : public NodeProcess {
 public:
  /// Starts mb2co-uno --elf <the image> `args` and waits for its ready line
  /// (node id from the boot-up frame); false with the reason in error() when
  /// it does not come within `timeout`.
  bool start(const std::vector<std::string>& args, std::chrono::milliseconds timeout = 20s);
  /// The image's micros() now (`stack?`'s sim_us): at_us follows the wall
  /// clock and runs ahead of the image when the host is slow.
  uint32_t device_us();
  /// Waits for a "leds" line whose `field` has `value`.
  bool wait_led(const std::string& field, const std::string& value, std::chrono::milliseconds timeout,
                std::string* line = nullptr);
};

}  // namespace test
}  // namespace mb2co
