// A serial segment's line on Linux: a tty or a pty (port::SerialPort) as the
// link's ByteSink, bytes handed on stamped with CLOCK_MONOTONIC, and the echo
// of an RS-485 adapter (it hands back every byte we send) taken out, because
// the link must not hear itself (serial_link.h's contract).
//
// Echo: each message we write is expected back whole and in one run (our
// UART sends it without gaps; bytes of others cannot be inside it without a
// collision). Bytes that read before it (others' messages that were in the
// input queue when we wrote) are passed on: while incoming bytes match the
// front message's start they are held back; a mismatch releases them, in
// order, with their stamps. A message whose echo does not begin within
// kEchoTimeoutUs is no longer expected (the adapter does not echo it).
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "host/status.h"
#include "platform/device_port.h"
#include "platform/serial_port.h"
#include "segment_options.h"

namespace mb2co {
namespace bridge {

class SegmentLine {
 public:
  /// Opens --serial or --pty of `o` (checked by segment_bus_config before).
  Status open(const SegmentOptions& o);
  int fd() const { return port_.fd(); }
  const port::SerialPort& port() const { return port_; }

  /// The link's sink: writes whole messages; with echo suppression on,
  /// remembers them to take their echo out of the input.
  modbus::ByteSink sink() { return modbus::ByteSink{&SegmentLine::write, this}; }

  /// Reads what waits and hands each byte that is not our echo to
  /// `on_byte(ctx, byte, stamp_us)`. Fails when the port does.
  Status read(void (*on_byte)(void* ctx, uint8_t byte, uint32_t byte_us), void* ctx);

  uint32_t echo_bytes_dropped() const { return echo_dropped_; }
  uint32_t write_failures() const { return write_failures_; }

 private:
  static bool write(void* ctx, const uint8_t* data, uint16_t length);
  /// One byte from the port through the echo filter to `on_byte`.
  void filter(uint8_t byte, uint32_t stamp_us, void (*on_byte)(void*, uint8_t, uint32_t), void* ctx);
  void drop_front();

  static const size_t kMaxMessage = 64;  ///< longest stuffed message, with room
  static const size_t kMaxExpected = 16;
  static const uint32_t kEchoTimeoutUs = 200000;
  struct Expected {
    uint8_t bytes[kMaxMessage];
    uint8_t length;
    uint32_t written_us;
  };
  port::SerialPort port_;
  bool echo_ = false;
  Expected expected_[kMaxExpected];  ///< our messages whose echo is still to come, ring
  size_t expected_head_ = 0;
  size_t expected_count_ = 0;
  size_t matched_ = 0;  ///< bytes of the front message matched (held back)
  uint32_t held_stamps_[kMaxMessage];
  uint32_t echo_dropped_ = 0;
  uint32_t write_failures_ = 0;
};

}  // namespace bridge
}  // namespace mb2co
