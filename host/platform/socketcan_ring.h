// The io_uring path of SocketCanPort (socketcan_port.h): one ring per
// socket through which a pass's sends and the wait for the next received
// frame are one system call (io_uring_enter). Inside user-mode Linux every
// system call is a trap through the host: a request/response protocol (a
// segmented SDO transfer) needs one send and one receive per exchange, and
// here they cost one call instead of two.
//
// The receive is one multishot recvmsg kept armed across calls, its frames
// in a ring of kRxBuffers provided buffers: a flood fills them, the receive
// ends (ENOBUFS) and the rest waits in the socket's own bounded buffer until
// the owner takes frames and the receive is armed again. Nothing grows.
// The sends of one submission are linked: the first the kernel refuses
// cancels the rest, which come back in order for the next try.
//
// Only socketcan_port.cpp uses it; without liburing at build time create()
// fails and the port keeps its recvmmsg/sendmmsg path.
#pragma once
#include <linux/can.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/socket.h>

#include <memory>

namespace mb2co {
namespace linux_port {

/// What reaping a ring's completions hands over, in the kernel's order.
class RingCompletions {
 public:
  /// A received record: `payload` of `len` bytes (truncated: it did not fit
  /// the buffer), its control messages in `control`. False when the owner
  /// has no room now: the record stays for the next reap.
  virtual bool on_record(const void* payload, size_t len, bool truncated, msghdr& control) = 0;
  /// A send the kernel refused with errno `err` (ECANCELED: an earlier one
  /// of its submission was refused, this one was not tried).
  virtual void on_refused(const struct ::can_frame& frame, int err) = 0;
  /// The receive failed with errno `err` (it is armed again by the next submit).
  virtual void on_receive_error(int err) = 0;

 protected:
  ~RingCompletions() = default;
};

class SocketCanRing {
 public:
  /// Received frames the owner has not taken yet, at most (the buffers).
  static constexpr size_t kRxBuffers = 64;
  /// Sends handed to the kernel and not completed, at most.
  static constexpr size_t kTxSlots = 256;

  /// A ring for the bound CAN socket `sock_fd` with its receive armed, the
  /// control messages of each frame up to `control_bytes`. nullptr when
  /// this kernel or build has none: *what names the step, *err its errno
  /// (0: none).
  static std::unique_ptr<SocketCanRing> create(int sock_fd, size_t control_bytes, const char** what,
                                               int* err);
  ~SocketCanRing();
  SocketCanRing(const SocketCanRing&) = delete;
  SocketCanRing& operator=(const SocketCanRing&) = delete;

  /// The ring's descriptor: POLLIN when completions wait.
  int fd() const;
  /// Sends submitted and not yet reaped.
  size_t in_flight() const { return in_flight_; }
  /// Sends staged for the next submit().
  size_t staged() const { return staged_; }
  /// Completions waiting to be reaped (no system call).
  bool ready() const;

  /// Stages `frame` after the staged sends. False when kTxSlots are busy.
  bool stage(const struct ::can_frame& frame);
  /// Submits the staged sends (and the receive, when it ended) and waits
  /// until they completed and, with `wait_us` > 0, until a frame came or
  /// `wait_us` passed: one io_uring_enter. 0, or the errno (EINTR: a signal).
  int submit(uint32_t wait_us);
  /// Hands the waiting completions to `to` in order, giving each received
  /// frame's buffer back, until on_record() has no room.
  void reap(RingCompletions& to);

 private:
  struct Impl;
  explicit SocketCanRing(Impl* impl);
  std::unique_ptr<Impl> impl_;
  size_t in_flight_ = 0;
  size_t staged_ = 0;
};

}  // namespace linux_port
}  // namespace mb2co
