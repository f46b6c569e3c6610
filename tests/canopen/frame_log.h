// Test helper: a CanSink that records frames, and compact frame builders, so
// tests read like the traces in the seeds: F(0x603, {0x40, 0x00, 0x10, ...}).
#pragma once
#include <stdint.h>

#include <cstdio>
#include <initializer_list>
#include <string>
#include <vector>

#include "canopen/can_frame.h"

namespace mb2co {
namespace test {

inline CanFrame F(uint32_t id, std::initializer_list<uint8_t> bytes) {
  CanFrame f = {};
  f.id = id;
  f.dlc = static_cast<uint8_t>(bytes.size());
  uint8_t i = 0;
  for (uint8_t b : bytes) f.data[i++] = b;
  return f;
}

inline CanFrame Rtr(uint32_t id, uint8_t dlc = 0) {
  CanFrame f = {};
  f.id = id;
  f.dlc = dlc;
  f.flags = CanFrame::kRtr;
  return f;
}

/// "<583> 42 00 10 00 91 01 03 00" as in seed 004 §2.11.
inline std::string to_string(const CanFrame& f) {
  char buf[64];
  int n = std::snprintf(buf, sizeof buf, "<%03X>", static_cast<unsigned>(f.id));
  if (f.rtr()) n += std::snprintf(buf + n, sizeof buf - static_cast<size_t>(n), " RTR");
  for (uint8_t i = 0; i < f.dlc && !f.rtr(); ++i) {
    n += std::snprintf(buf + n, sizeof buf - static_cast<size_t>(n), " %02X", f.data[i]);
  }
  return buf;
}

class FrameLog {
 public:
  CanSink sink() { return CanSink{&FrameLog::send, this}; }
  std::vector<CanFrame> frames;
  /// Frames sent since the last take(), as strings; clears the log.
  std::vector<std::string> take() {
    std::vector<std::string> out;
    for (const CanFrame& f : frames) out.push_back(to_string(f));
    frames.clear();
    return out;
  }
  bool refuse = false;  ///< simulate a full transmit queue

 private:
  static bool send(void* ctx, const CanFrame& f) {
    FrameLog& log = *static_cast<FrameLog*>(ctx);
    if (log.refuse) return false;
    log.frames.push_back(f);
    return true;
  }
};

}  // namespace test
}  // namespace mb2co
