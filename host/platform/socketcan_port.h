// SocketCAN port of the Linux build: one CAN_RAW socket bound to one
// interface (can0, vcan0, ...), handing classic frames in and out as
// mb2co::CanFrame. Every call returns at once except receive_within(),
// which waits for the first frame; the owner polls fd() for POLLIN or waits
// in receive_within(). Frames go out one call each (send) or queued and
// sent together (queue/flush: one sendmmsg per kBatch frames).
// Opened with IoPath::kRing, the same calls go through io_uring instead
// (socketcan_ring.h): what flush_at_next_receive() left and the wait of
// the next receive are one system call. recvmmsg/sendmmsg stay the path
// where the kernel or the build has no io_uring, or MB2CO_IO_URING=0.
//
// Kernels without AF_CAN (no vcan) get interfaces from hil/uml/run-with-vcan.sh.
#pragma once
#include <linux/can.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <sys/uio.h>

#include <memory>

#include "canopen/can_frame.h"
#include "host/status.h"

namespace mb2co {
namespace linux_port {

/// A received frame and when the kernel queued it.
struct TimedCanFrame {
  CanFrame frame;       ///< data bytes beyond dlc (all of them for RTR) are zero
  uint64_t rx_time_us;  ///< CLOCK_MONOTONIC in µs: the kernel's SO_TIMESTAMP
                        ///< (wall clock) mapped onto the monotonic clock when
                        ///< present, else the time of the read. The core's
                        ///< 32-bit clock is this value truncated. The mapping
                        ///< (the offset between the two clocks) is read again
                        ///< when a frame falls more than kResyncUs from its
                        ///< last reading, so at most kResyncUs off after a
                        ///< step of the wall clock; never later than the read.
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

class SocketCanRing;

/// How frames move between the port and the kernel.
enum class IoPath : uint8_t {
  kCalls,  ///< recvmmsg/sendmmsg (and SO_RCVTIMEO for receive_within's wait)
  kRing,   ///< io_uring: sends and the wait for a frame in one io_uring_enter
};

/// Owns one socket. Not copyable; not thread-safe (one owner thread).
class SocketCanPort {
 public:
  /// Receive buffer asked for at open (the kernel may grant less without
  /// CAP_NET_ADMIN: see rcvbuf_bytes()). A flood on a slow reader (user-mode
  /// Linux) needs more than the default ~200 KiB.
  static constexpr int kDefaultRcvbufBytes = 4 * 1024 * 1024;
  /// Frames per recvmmsg/sendmmsg call.
  static constexpr size_t kBatch = 32;
  /// Frames queue() holds until flush(): a block transfer's sub-block (127)
  /// and its neighbours.
  static constexpr size_t kQueueFrames = 256;
  /// How far (µs) a received frame may fall from the last reading of the
  /// two clocks before they are read again (rx_time_us): under steady
  /// traffic twice per 100 ms instead of twice per receive call. NTP slews
  /// the wall clock by at most 500 ppm: < 50 µs of drift in that time.
  static constexpr uint64_t kResyncUs = 100000;

  SocketCanPort();
  ~SocketCanPort();
  SocketCanPort(const SocketCanPort&) = delete;
  SocketCanPort& operator=(const SocketCanPort&) = delete;

  /// Opens and binds a socket to interface `ifname`, receiving every frame of
  /// others (not our own). Fails when the kernel has no AF_CAN, the interface
  /// does not exist or is not CAN. Closes a previous one. `wanted`
  /// kRing: io_uring when this kernel and build have it and the
  /// environment does not say MB2CO_IO_URING=0, else kCalls (io_note()
  /// tells which and why).
  Status open(const char* ifname, int rcvbuf_bytes = kDefaultRcvbufBytes, IoPath wanted = IoPath::kCalls);
  /// On kRing, what flush_at_next_receive() staged goes out first.
  void close();
  bool is_open() const { return fd_ >= 0; }
  IoPath io_path() const { return ring_ ? IoPath::kRing : IoPath::kCalls; }
  /// One line without newline: the path open() chose and why ("" when closed).
  const char* io_note() const { return io_note_; }

  /// For poll()/epoll before a receive() (POLLIN: frames are waiting): the
  /// socket, or on kRing the ring's descriptor. -1 when closed.
  int fd() const;

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
  /// As receive(), but waits up to `wait_us` for the first frame (0: not at
  /// all): a poll() and a receive in one system call. Returns 0 after the
  /// wait, on a signal (EINTR) or a read error. The wait is the socket's
  /// SO_RCVTIMEO, set again only when the one set is longer than `wait_us`
  /// or shorter than half of it (then it may return up to half the wait
  /// early: the caller's loop just passes once more).
  size_t receive_within(TimedCanFrame* out, size_t capacity, uint32_t wait_us);

  /// Queues one frame without blocking. False when it was not queued: full
  /// queue (tx_dropped), invalid frame or interface down (tx_errors).
  bool send(const CanFrame& frame);
  /// Queues frames in order without blocking; returns how many were queued.
  /// The rest are dropped and counted like refused single sends.
  size_t send(const CanFrame* frames, size_t count);

  /// Takes a frame for the next flush(). False (not taken, counted like a
  /// refused send) for an invalid frame, or when kQueueFrames are waiting
  /// and a flush could not make room.
  bool queue(const CanFrame& frame);
  /// Sends the queued frames in order, kBatch per system call. Frames the
  /// kernel has no room for (full queue) stay queued, in order, for the
  /// next flush; frames it refuses otherwise (interface down) are dropped
  /// and counted in tx_errors. Returns how many went out.
  size_t flush();
  /// flush() for an owner that calls receive() or receive_within() next
  /// (or flush() or close()): on kRing the frames are staged and go out in
  /// that call's own system call, in order before its wait; a refusal is
  /// known and handled as flush() would after it. On kCalls: flush().
  void flush_at_next_receive();
  /// Frames waiting for flush() (not those staged for the next receive).
  size_t queued() const { return tx_count_; }

  /// The port as the core's frame sink; valid while this object lives.
  CanSink sink() { return CanSink{&SocketCanPort::send_to, this}; }
  /// The same through queue(): the owner's loop calls flush() after each
  /// pass (a sub-block of 127 frames then costs 4 system calls, not 127).
  CanSink queue_sink() { return CanSink{&SocketCanPort::queue_to, this}; }
  /// The core's controller settings (shared/platform/device_port.h), with sink()'s
  /// ctx: kernel filters from the device's acceptance ranges (set_ranges);
  /// no bit rate (a raw socket cannot set it: `ip link set can0 type can
  /// bitrate ...` does).
  static const CanControl kControl;

  const SocketCanCounters& counters() const { return counters_; }
  /// Receive buffer the kernel granted (bytes, as getsockopt reports it).
  int rcvbuf_bytes() const { return rcvbuf_bytes_; }

 private:
  class RingTaker;
  friend class RingTaker;
  static bool send_to(void* ctx, const CanFrame& frame);
  static bool queue_to(void* ctx, const CanFrame& frame);
  /// recvmmsg with `flags` into `out`; see receive().
  size_t receive_with(TimedCanFrame* out, size_t capacity, int flags);
  /// One received record as `slot`: false (counted in io_errors) when it
  /// is not a whole classic frame. Reads the control messages of `hdr`.
  bool take(const void* payload, size_t len, bool truncated, msghdr& hdr, TimedCanFrame& slot,
            bool* clocks_read_now);
  /// kRing's receive: submits what is staged, waits up to `wait_us` when no
  /// frame waits, takes what came.
  size_t ring_receive(TimedCanFrame* out, size_t capacity, uint32_t wait_us);
  /// Moves tx_'s frames to the ring's next submission, in order, while no
  /// earlier submission's sends are in flight.
  void stage_queued();
  /// Frames the ring had refused, back in front of tx_ in order (the
  /// queue was full) or dropped and counted (any other refusal).
  void requeue(const CanFrame* frames, size_t count, int err);
  /// The kernel's receive time (wall clock, µs) on the monotonic clock
  /// (see rx_time_us); `*read_now`: the clocks were read during this
  /// receive call (they are read at most once per call).
  uint64_t monotonic_of(uint64_t stamp_real_us, bool* read_now);
  /// Reads both clocks: the offset between them and the monotonic time.
  void read_clocks();
  /// Sends frames[0..count) until the kernel refuses one or one is
  /// invalid; how many went out, `*err` the refusal's errno (0: all went;
  /// kInvalidFrame, -1: frames[returned] cannot be converted).
  size_t transmit(const CanFrame* frames, size_t count, int* err);
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
  uint32_t last_rx_overflows_;   ///< kernel's SO_RXQ_OVFL count at the last frame
  uint32_t rcvtimeo_us_;         ///< SO_RCVTIMEO set for receive_within (0: none yet)
  bool clocks_read_;             ///< real_minus_mono_us_ and read_mono_us_ hold
  uint64_t real_minus_mono_us_;  ///< CLOCK_REALTIME - CLOCK_MONOTONIC at the last reading
  uint64_t read_mono_us_;        ///< CLOCK_MONOTONIC at the last reading
  CanFrame tx_[kQueueFrames];    ///< queue(): [0, tx_count_) wait for flush()
  size_t tx_count_;
  /// recvmmsg/sendmmsg's descriptors, pointing into this object (it never
  /// moves): set up once by the constructor, so a call fills in only the
  /// frames it moves (a segmented transfer's receive of one frame cost 770
  /// instructions setting up 32 slots, now a tenth of that).
  static constexpr size_t kRxControlBytes = CMSG_SPACE(sizeof(timeval)) + CMSG_SPACE(sizeof(uint32_t));
  struct ::can_frame rx_kernel_[kBatch];
  iovec rx_iov_[kBatch];
  mmsghdr rx_msgs_[kBatch];
  alignas(cmsghdr) char rx_control_[kBatch][kRxControlBytes];
  struct ::can_frame tx_kernel_[kBatch];
  iovec tx_iov_[kBatch];
  mmsghdr tx_msgs_[kBatch];
  SocketCanCounters counters_;
  std::unique_ptr<SocketCanRing> ring_;  ///< kRing: set by open(); the calls above are unused then
  char ifname_[16];
  char error_[160];
  char io_note_[160];
};

}  // namespace linux_port
}  // namespace mb2co
