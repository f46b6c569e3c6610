// A serial segment's line on Linux: a tty or a pty (port::SerialPort) as the
// link's ByteSink, bytes handed on stamped with CLOCK_MONOTONIC, and the echo
// of an RS-485 adapter (it hands back every byte we send) taken out, because
// the link must not hear itself (serial_link.h's contract).
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "host/status.h"
#include "platform/device_port.h"
#include "segment_options.h"
#include "serial_port.h"

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
  bool is_echo(uint8_t byte);

  static const size_t kEchoCapacity = 512;
  port::SerialPort port_;
  bool echo_ = false;
  uint8_t expected_[kEchoCapacity];  ///< our bytes whose echo is still to come, ring
  size_t expected_head_ = 0;
  size_t expected_count_ = 0;
  uint32_t echo_dropped_ = 0;
  uint32_t write_failures_ = 0;
};

}  // namespace bridge
}  // namespace mb2co
