// SocketCAN port of the Linux build: one CAN_RAW socket bound to one
// interface (can0, vcan0, ...), handing classic frames in and out as
// mb2co::CanFrame. Non-blocking throughout; the owner polls fd() for POLLIN.
//
// Kernels without AF_CAN (no vcan) get interfaces from hil/uml/run-with-vcan.sh.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "canopen/can_frame.h"
#include "host/status.h"

struct can_frame;   // <linux/can.h>
struct can_filter;  // <linux/can.h>

namespace mb2co {
namespace linux_port {

/// A received frame and when the kernel queued it.
struct TimedCanFrame {
  CanFrame frame;       ///< data bytes beyond dlc (all of them for RTR) are zero
  uint64_t rx_time_us;  ///< CLOCK_MONOTONIC in µs: the kernel's SO_TIMESTAMP
                        ///< (wall clock) mapped onto the monotonic clock when
                        ///< present, else the time of the read. The core's
                        ///< 32-bit clock is this value truncated.
};

/// One kernel acceptance filter (CAN_RAW_FILTER): a frame passes when
/// (frame.id & mask) == (id & mask) and its format (standard/extended) is the
/// one given. Data and RTR frames pass alike.
struct CanAcceptance {
  uint32_t id;    ///< 11-bit, or 29-bit when extended
  uint32_t mask;  ///< bits of id that must match (0x7FF / 0x1FFFFFFF: exactly id)
  bool extended;

  static CanAcceptance exact(uint32_t can_id, bool is_extended = false) {
    return CanAcceptance{can_id, is_extended ? 0x1FFFFFFFu : 0x7FFu, is_extended};
  }
};

/// Traffic and failure counters. They only grow (open() and close() reset them).
struct SocketCanCounters {
  uint64_t rx_frames;   ///< frames handed out by receive()
  uint64_t rx_dropped;  ///< frames the kernel dropped for a full receive buffer (SO_RXQ_OVFL)
  uint64_t tx_frames;   ///< frames the kernel accepted
  uint64_t tx_dropped;  ///< sends refused because the queue was full (EAGAIN/ENOBUFS)
  uint64_t tx_errors;   ///< sends refused for any other reason (invalid frame, interface down)
  uint64_t io_errors;   ///< failed reads and unexpected records (not classic CAN frames)
};

/// Our frame as the kernel's: flags become CAN_EFF_FLAG/CAN_RTR_FLAG, bytes
/// beyond dlc are zeroed. False (nothing written) for dlc > 8 or an id that
/// does not fit its format.
bool to_kernel_frame(const CanFrame& in, struct ::can_frame& out);
/// The kernel's frame as ours. False for error frames and lengths > 8.
bool from_kernel_frame(const struct ::can_frame& in, CanFrame& out);

/// Owns one socket. Not copyable; not thread-safe (one owner thread).
class SocketCanPort {
 public:
  /// Receive buffer asked for at open (the kernel may grant less without
  /// CAP_NET_ADMIN: see rcvbuf_bytes()). A flood on a slow reader (user-mode
  /// Linux) needs more than the default ~200 KiB.
  static constexpr int kDefaultRcvbufBytes = 4 * 1024 * 1024;
  /// Frames per recvmmsg/sendmmsg call.
  static constexpr size_t kBatch = 32;

  SocketCanPort();
  ~SocketCanPort();
  SocketCanPort(const SocketCanPort&) = delete;
  SocketCanPort& operator=(const SocketCanPort&) = delete;

  /// Opens and binds a socket to interface `ifname`, receiving every frame of
  /// others (not our own). Fails when the kernel has no AF_CAN, the interface
  /// does not exist or is not CAN. Closes a previous one.
  Status open(const char* ifname, int rcvbuf_bytes = kDefaultRcvbufBytes);
  void close();
  bool is_open() const { return fd_ >= 0; }

  /// For poll()/epoll (POLLIN: frames are waiting). -1 when closed.
  int fd() const { return fd_; }

  /// The last failure of a call that has no caller to answer: send(),
  /// receive() (each counted in counters()) and the core's filter callback
  /// (kControl). One line without newline ("" when none since open()).
  const char* last_io_error() const { return error_; }

  /// Replaces the kernel filters; only matching frames are received from now
  /// on. count == 0 receives nothing; at most 512 entries. Fails for an id
  /// or mask out of range, or when the kernel refuses.
  Status set_filters(const CanAcceptance* filters, size_t count);
  /// Back to receiving every frame.
  Status accept_all();
  /// Receives what a device's acceptance ranges admit (CanControl::
  /// set_filters, platform/device_port.h): one kernel filter per range, its
  /// remote bit as CAN_RTR_FLAG; no extended frame. At most 512 ranges.
  Status set_ranges(const CanIdRange* ranges, size_t count);

  /// Takes up to `capacity` waiting frames without blocking; returns how many
  /// (0 when none are waiting or on a read error, counted in io_errors).
  size_t receive(TimedCanFrame* out, size_t capacity);
  /// One frame, false when none is waiting.
  bool receive(TimedCanFrame& out) { return receive(&out, 1) == 1; }

  /// Queues one frame without blocking. False when it was not queued: full
  /// queue (tx_dropped), invalid frame or interface down (tx_errors).
  bool send(const CanFrame& frame);
  /// Queues frames in order without blocking; returns how many were queued.
  /// The rest are dropped and counted like refused single sends.
  size_t send(const CanFrame* frames, size_t count);

  /// The port as the core's frame sink; valid while this object lives.
  CanSink sink() { return CanSink{&SocketCanPort::send_to, this}; }
  /// The core's controller settings (shared/platform/device_port.h), with sink()'s
  /// ctx: kernel filters from the device's acceptance ranges (set_ranges);
  /// no bit rate (a raw socket cannot set it: `ip link set can0 type can
  /// bitrate ...` does).
  static const CanControl kControl;

  const SocketCanCounters& counters() const { return counters_; }
  /// Receive buffer the kernel granted (bytes, as getsockopt reports it).
  int rcvbuf_bytes() const { return rcvbuf_bytes_; }

 private:
  static bool send_to(void* ctx, const CanFrame& frame);
  static void set_filters_of(void* ctx, const CanIdRange* ranges, uint8_t count);
  /// Replaces the kernel filters by kernel[0..count) (CAN_RAW_FILTER).
  Status install(const struct ::can_filter* kernel, size_t count);
  /// "socketcan IFACE: what[: strerror(err)]" into `line` (err 0: no errno text).
  void describe(char* line, size_t cap, const char* what, int err) const;
  Status fail(const char* what, int err) const;
  /// Keeps the failure of a call without a Status for last_io_error().
  void note(const char* what, int err);
  void count_refused(int err, uint64_t frames);

  int fd_;
  int rcvbuf_bytes_;
  uint32_t last_rx_overflows_;  ///< kernel's SO_RXQ_OVFL count at the last frame
  SocketCanCounters counters_;
  char ifname_[16];
  char error_[160];
};

}  // namespace linux_port
}  // namespace mb2co
