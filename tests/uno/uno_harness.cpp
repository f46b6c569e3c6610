#include "uno_harness.h"

namespace mb2co {
namespace test {

const char* uno_program() {
  return MB2CO_UNO;
}
const char* uno_elf() {
  return MB2CO_UNO_ELF;
}
bool network_gateway_is_uno() {
  return MB2CO_NET_GATEWAY_UNO != 0;
}

bool UnoProcess::start(const std::vector<std::string>& args, std::chrono::milliseconds timeout) {
  std::vector<std::string> argv{uno_program(), "--elf", uno_elf()};
  argv.insert(argv.end(), args.begin(), args.end());
  return start_command(argv, timeout);
}

uint32_t UnoProcess::device_us() {
  const std::string v = field_of(ask("stack?", "stack "), "sim_us");
  return v.empty() ? 0 : static_cast<uint32_t>(std::stoul(v));
}

bool UnoProcess::wait_led(const std::string& field, const std::string& value,
                          std::chrono::milliseconds timeout, std::string* line) {
  return wait_event(
      "leds ", [&](const std::string& l) { return field_of(l, field) == value; }, timeout, line);
}

}  // namespace test
}  // namespace mb2co
