// A serial line in virtual time, one UartChannel per direction (full duplex,
// as a USB serial adapter is). Each character takes char_bits / baud (11
// bits for Modbus RTU 8E1) and is complete at the end of its stop bit, with
// that exact time, so gaps between characters are real and the receiver's
// t1.5/t3.5 framing sees what a UART would. Characters of a second send()
// follow the first back to back; a gap can be put inside a frame (a PC whose
// USB stack splits it). An unplugged line loses every character that is not
// complete when it is unplugged, and whatever is sent while it is.
//
// The receiver pulls completed characters (take(), what a UART ring buffer
// holds); on_sent() tells it when the last character of a send() is complete.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include <deque>
#include <functional>

#include "sim/event_queue.h"

namespace mb2co {
namespace sim {

struct SerialChar {
  uint8_t byte;
  SimNs end_ns;  ///< end of its stop bit
};

class UartChannel final : public Handler {
 public:
  UartChannel(EventQueue& queue, uint32_t baud, uint8_t char_bits);

  /// Sends `n` bytes starting at now() (or when the line is free). With
  /// `gap_ns` > 0 the line stays idle that long before byte `gap_index`.
  void send(const uint8_t* data, size_t n, size_t gap_index = 0, SimNs gap_ns = 0);
  void set_connected(bool connected);
  bool connected() const { return connected_; }
  /// When the line is free again (≤ now(): free).
  SimNs free_at() const { return free_ns_; }
  /// Time of `n` characters back to back, rounded down to whole ns.
  SimNs chars_ns(uint64_t n) const { return n * char_bits_ * kNsPerS / baud_; }

  /// True when a character complete at or before `until_ns` waits.
  bool ready(SimNs until_ns) const { return !line_.empty() && line_.front().end_ns <= until_ns; }
  /// When the oldest character waiting is complete (~0: none waits).
  SimNs first_end() const { return line_.empty() ? ~SimNs{0} : line_.front().end_ns; }
  /// Takes the oldest character complete at or before `until_ns`.
  bool take(SimNs until_ns, SerialChar* out);
  /// Called when the last character of a send() is complete (now()).
  std::function<void()> on_sent;
  /// The station that takes the characters, when it sleeps over idle
  /// passes (null: none): told when first_end() comes earlier (a character
  /// sent onto an empty line).
  Sleeper* reader = nullptr;

  uint64_t bytes_sent() const { return sent_; }
  uint64_t bytes_lost() const { return lost_; }

  void on_event(uint32_t code, uint64_t arg) override;

 private:
  EventQueue& q_;
  uint32_t baud_;
  uint8_t char_bits_;
  SimNs free_ns_ = 0;
  bool connected_ = true;
  std::deque<SerialChar> line_;  ///< sent, in order of completion
  uint64_t sent_ = 0;
  uint64_t lost_ = 0;
};

/// The USB serial cable between a PC and its Arduino.
struct SerialLink {
  SerialLink(EventQueue& queue, uint32_t baud, uint8_t char_bits)
      : to_node(queue, baud, char_bits), to_pc(queue, baud, char_bits) {}
  void set_connected(bool connected) {
    to_node.set_connected(connected);
    to_pc.set_connected(connected);
  }
  UartChannel to_node;
  UartChannel to_pc;
};

}  // namespace sim
}  // namespace mb2co
