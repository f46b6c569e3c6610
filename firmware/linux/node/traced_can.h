// mb2co-node's CAN port with a trace (--trace-can): every frame the node
// sends (once the port queued it for its flush) and every frame it takes in goes to a
// CanLogFile, stamped with the host's CLOCK_REALTIME as candump stamps its
// lines, so the trace lines up with a `candump -L` of the same bus.
#pragma once
#include "host/can_log_file.h"
#include "platform/socketcan_port.h"

namespace mb2co {
namespace node {

class TracedCan {
 public:
  /// Both must outlive this object (and the gateway holding sink()).
  TracedCan(linux_port::SocketCanPort& port, CanLogFile& log) : port_(port), log_(log) {}
  TracedCan(const TracedCan&) = delete;
  TracedCan& operator=(const TracedCan&) = delete;

  /// The port's sink that also writes what was sent.
  CanSink sink() { return CanSink{&TracedCan::send_to, this}; }
  /// SocketCanPort::kControl for sink()'s ctx (the core hands it that ctx).
  static const CanControl kControl;
  /// A frame the node took from the port.
  void received(const CanFrame& frame) {
    if (log_.is_open()) log_.write(realtime_us(), frame);
  }
  void flush() { log_.flush(); }

 private:
  static bool send_to(void* ctx, const CanFrame& frame);
  static void set_filters_of(void* ctx, const CanIdRange* ranges, uint8_t count);
  static uint64_t realtime_us();

  linux_port::SocketCanPort& port_;
  CanLogFile& log_;
};

}  // namespace node
}  // namespace mb2co
