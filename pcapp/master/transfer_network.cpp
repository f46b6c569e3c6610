#include "transfer_network.h"

#include <cstdio>

#include "abort_text.h"

namespace mb2co {
namespace master {

std::string Transfer::failure() const {
  if (!finished || result == canopen::kSdoOk) return std::string();
  char line[240];
  if (!gateway_error.empty()) {
    std::snprintf(line, sizeof line, "node %u %04Xh/%u: %s", node, index, sub, gateway_error.c_str());
    return line;
  }
  const char* why = node_lost   ? "node lost (no heartbeat within the consumer time), transfer aborted"
                    : by_server ? "SDO abort"
                                : "SDO abort sent";
  std::snprintf(line, sizeof line, "node %u %04Xh/%u: %s %08Xh (%s)", node, index, sub, why,
                static_cast<unsigned>(result), abort_text(result));
  std::string text = line;
  // Our own size bound: say which, or "out of memory" reads as a crash.
  if (upload && result == canopen::kAbortOutOfMemory && !by_server && !node_lost)
    text +=
        ": the object is longer than " + std::to_string(max_bytes) + " bytes, the most this command takes";
  return text;
}

}  // namespace master
}  // namespace mb2co
