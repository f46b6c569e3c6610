// CAN frames in can-utils' text notation: the frame field of cansend and
// `candump -L` ("123#11223344", "01234567#" with 8 hex digits = extended,
// "7FF#R", "123#R8" for an RTR with dlc 8), and whole `candump -L` log lines
// "(1.000000) can0 123#11", which canplayer replays and Wireshark opens.
#pragma once
#include <stdint.h>
#include <stdio.h>

#include <string>

#include "canopen/can_frame.h"

namespace mb2co {

inline std::string candump_frame_text(const CanFrame& frame) {
  char out[40];
  int n = snprintf(out, sizeof out, frame.extended() ? "%08X#" : "%03X#", static_cast<unsigned>(frame.id));
  if (frame.rtr()) {
    snprintf(out + n, sizeof out - static_cast<size_t>(n), frame.dlc ? "R%u" : "R",
             static_cast<unsigned>(frame.dlc));
    return out;
  }
  for (unsigned i = 0; i < frame.dlc && i < 8; ++i)
    n += snprintf(out + n, sizeof out - static_cast<size_t>(n), "%02X", static_cast<unsigned>(frame.data[i]));
  return out;
}

/// One `candump -L` line (with '\n') for a frame seen at t_us on `iface`.
inline std::string candump_log_line(uint64_t t_us, const std::string& iface, const CanFrame& frame) {
  char stamp[40];
  snprintf(stamp, sizeof stamp, "(%010llu.%06llu) ", static_cast<unsigned long long>(t_us / 1000000),
           static_cast<unsigned long long>(t_us % 1000000));
  return stamp + iface + " " + candump_frame_text(frame) + "\n";
}

}  // namespace mb2co
