// SocketCAN port: see socketcan_port.h for the contract.
#include "platform/socketcan_port.h"

#include <errno.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <time.h>
#include <unistd.h>

#include "platform/socketcan_ring.h"

namespace mb2co {
namespace linux_port {

namespace {

constexpr uint32_t kStdIdMax = CAN_SFF_MASK;
constexpr uint32_t kExtIdMax = CAN_EFF_MASK;
constexpr size_t kMaxFilters = CAN_RAW_FILTER_MAX;

uint64_t clock_us(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1000000u + static_cast<uint64_t>(ts.tv_nsec) / 1000u;
}

/// transmit()'s refusal of a frame it cannot convert (not an errno).
constexpr int kInvalidFrame = -1;

bool queue_full(int err) {
  return err == EAGAIN || err == EWOULDBLOCK || err == ENOBUFS;
}

bool id_fits(uint32_t id, bool extended) {
  return id <= (extended ? kExtIdMax : kStdIdMax);
}

}  // namespace

bool to_kernel_frame(const CanFrame& in, struct ::can_frame& out) {
  if (in.dlc > CAN_MAX_DLEN || !id_fits(in.id, in.extended())) return false;
  memset(&out, 0, sizeof out);
  out.can_id = in.id;
  if (in.extended()) out.can_id |= CAN_EFF_FLAG;
  if (in.rtr()) {
    out.can_id |= CAN_RTR_FLAG;  // the dlc travels, the data does not
  } else {
    memcpy(out.data, in.data, in.dlc);
  }
  out.len = in.dlc;
  return true;
}

bool from_kernel_frame(const struct ::can_frame& in, CanFrame& out) {
  if ((in.can_id & CAN_ERR_FLAG) != 0 || in.len > CAN_MAX_DLEN) return false;
  const bool extended = (in.can_id & CAN_EFF_FLAG) != 0;
  const bool rtr = (in.can_id & CAN_RTR_FLAG) != 0;
  memset(&out, 0, sizeof out);
  out.id = in.can_id & (extended ? CAN_EFF_MASK : CAN_SFF_MASK);
  out.dlc = in.len;
  out.flags = static_cast<uint8_t>((extended ? CanFrame::kExtended : 0) | (rtr ? CanFrame::kRtr : 0));
  if (!rtr) memcpy(out.data, in.data, in.len);
  return true;
}

SocketCanPort::SocketCanPort()
    : fd_(-1),
      rcvbuf_bytes_(0),
      last_rx_overflows_(0),
      rcvtimeo_us_(0),
      clocks_read_(false),
      real_minus_mono_us_(0),
      read_mono_us_(0),
      tx_{},
      tx_count_(0),
      rx_kernel_{},
      rx_iov_{},
      rx_msgs_{},
      rx_control_{},
      tx_kernel_{},
      tx_iov_{},
      tx_msgs_{},
      counters_{},
      ring_{},
      ifname_{},
      error_{},
      io_note_{} {
  for (size_t i = 0; i < kBatch; ++i) {
    rx_iov_[i] = iovec{&rx_kernel_[i], sizeof rx_kernel_[i]};
    rx_msgs_[i].msg_hdr.msg_iov = &rx_iov_[i];
    rx_msgs_[i].msg_hdr.msg_iovlen = 1;
    rx_msgs_[i].msg_hdr.msg_control = rx_control_[i];
    rx_msgs_[i].msg_hdr.msg_controllen = kRxControlBytes;
    tx_iov_[i] = iovec{&tx_kernel_[i], sizeof tx_kernel_[i]};
    tx_msgs_[i].msg_hdr.msg_iov = &tx_iov_[i];
    tx_msgs_[i].msg_hdr.msg_iovlen = 1;
  }
}

SocketCanPort::~SocketCanPort() {
  close();
}

void SocketCanPort::close() {
  if (ring_ && ring_->staged() != 0) ring_->submit(0);
  ring_.reset();  // before the socket: its receive is cancelled first
  io_note_[0] = '\0';
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  rcvbuf_bytes_ = 0;
  last_rx_overflows_ = 0;
  rcvtimeo_us_ = 0;
  clocks_read_ = false;
  tx_count_ = 0;
  counters_ = SocketCanCounters{};
}

void SocketCanPort::describe(char* line, size_t cap, const char* what, int err) const {
  snprintf(line, cap, "socketcan %s: %s%s%s", ifname_, what, err != 0 ? ": " : "",
           err != 0 ? strerror(err) : "");
}

Status SocketCanPort::fail(const char* what, int err) const {
  char line[sizeof error_];
  describe(line, sizeof line, what, err);
  return Status::failure(line);
}

void SocketCanPort::note(const char* what, int err) {
  describe(error_, sizeof error_, what, err);
}

int SocketCanPort::fd() const {
  return ring_ ? ring_->fd() : fd_;
}

Status SocketCanPort::open(const char* ifname, int rcvbuf_bytes, IoPath wanted) {
  close();
  error_[0] = '\0';
  if (ifname == nullptr || ifname[0] == '\0' || strlen(ifname) >= sizeof ifname_) {
    snprintf(ifname_, sizeof ifname_, "?");
    return fail("interface name empty or longer than 15 characters", 0);
  }
  snprintf(ifname_, sizeof ifname_, "%s", ifname);

  // Blocking, so that receive_within() can wait in recvmmsg; every other
  // call passes MSG_DONTWAIT.
  const int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0) {
    const int err = errno;
    if (err == EAFNOSUPPORT) {
      return fail("this kernel has no AF_CAN (modules can, can-raw; or run under hil/uml/run-with-vcan.sh)",
                  0);
    }
    return fail("socket", err);
  }
  const unsigned index = if_nametoindex(ifname_);
  if (index == 0) {
    const int err = errno;
    ::close(fd);
    return err == ENODEV ? fail("no such interface", 0) : fail("if_nametoindex", err);
  }
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = static_cast<int>(index);
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    const int err = errno;
    ::close(fd);
    return err == ENODEV ? fail("not a CAN interface", 0) : fail("bind", err);
  }

  // Larger receive buffer: FORCE passes rmem_max when we may (CAP_NET_ADMIN).
  if (rcvbuf_bytes > 0 &&
      setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &rcvbuf_bytes, sizeof rcvbuf_bytes) != 0) {
    setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf_bytes, sizeof rcvbuf_bytes);
  }
  socklen_t len = sizeof rcvbuf_bytes_;
  getsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf_bytes_, &len);
  // Both optional: without them, rx time is the read time and drops go uncounted.
  const int on = 1;
  setsockopt(fd, SOL_SOCKET, SO_TIMESTAMP, &on, sizeof on);
  setsockopt(fd, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on);
  fd_ = fd;
  const char* off = getenv("MB2CO_IO_URING");
  if (wanted != IoPath::kRing) {
    describe(io_note_, sizeof io_note_, "recvmmsg/sendmmsg", 0);
  } else if (off != nullptr && strcmp(off, "0") == 0) {
    describe(io_note_, sizeof io_note_, "recvmmsg/sendmmsg, io_uring off (MB2CO_IO_URING=0)", 0);
  } else {
    const char* what = "";
    int err = 0;
    ring_ = SocketCanRing::create(fd_, kRxControlBytes, &what, &err);
    char why[96];
    snprintf(why, sizeof why, "recvmmsg/sendmmsg, no io_uring: %s", what);
    describe(io_note_, sizeof io_note_,
             ring_ ? "io_uring (a pass's sends and its wait in one system call)" : why, ring_ ? 0 : err);
  }
  return Status::ok();
}

Status SocketCanPort::set_filters(const CanAcceptance* filters, size_t count) {
  if (fd_ < 0) return fail("not open", 0);
  if (count > kMaxFilters) return fail("more than 512 filters", 0);
  can_filter kernel[kMaxFilters];
  for (size_t i = 0; i < count; ++i) {
    const CanAcceptance& f = filters[i];
    if (!id_fits(f.id, f.extended) || !id_fits(f.mask, f.extended)) {
      return fail("filter id or mask out of range", 0);
    }
    // The format bit always takes part, RTR never does.
    kernel[i].can_id = f.id | (f.extended ? CAN_EFF_FLAG : 0u);
    kernel[i].can_mask = f.mask | CAN_EFF_FLAG;
  }
  return install(kernel, count);
}

Status SocketCanPort::accept_all() {
  const CanAcceptance all[] = {{0, 0, false}, {0, 0, true}};
  return set_filters(all, 2);
}

Status SocketCanPort::set_ranges(const CanIdRange* ranges, size_t count) {
  if (fd_ < 0) return fail("not open", 0);
  if (count > kMaxFilters) return fail("more than 512 filters", 0);
  can_filter kernel[kMaxFilters];
  // The remote bit of a range is the kernel's CAN_RTR_FLAG; the format bit
  // always takes part (standard frames only).
  const auto kernel_bits = [](uint16_t v) {
    return (v & CAN_SFF_MASK) | ((v & kCanRangeRemote) != 0 ? CAN_RTR_FLAG : 0u);
  };
  for (size_t i = 0; i < count; ++i) {
    kernel[i].can_id = kernel_bits(ranges[i].id);
    kernel[i].can_mask = kernel_bits(ranges[i].mask) | CAN_EFF_FLAG;
  }
  return install(kernel, count);
}

Status SocketCanPort::install(const can_filter* kernel, size_t count) {
  const socklen_t bytes = static_cast<socklen_t>(count * sizeof(can_filter));
  if (setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, count ? kernel : nullptr, bytes) != 0) {
    return fail("CAN_RAW_FILTER", errno);
  }
  return Status::ok();
}

const CanControl SocketCanPort::kControl = {nullptr, &SocketCanPort::set_filters_of};

void SocketCanPort::set_filters_of(void* ctx, const CanIdRange* ranges, uint8_t count) {
  // A refusal leaves the previous filters (last_io_error() tells); the
  // device ignores frames it does not consume, so an open filter is safe.
  SocketCanPort& port = *static_cast<SocketCanPort*>(ctx);
  const Status done = port.set_ranges(ranges, count);
  if (!done) snprintf(port.error_, sizeof port.error_, "%s", done.message().c_str());
}

size_t SocketCanPort::receive(TimedCanFrame* out, size_t capacity) {
  if (ring_) return ring_receive(out, capacity, 0);
  return receive_with(out, capacity, MSG_DONTWAIT);
}

size_t SocketCanPort::receive_within(TimedCanFrame* out, size_t capacity, uint32_t wait_us) {
  if (fd_ < 0 || capacity == 0) return 0;
  if (ring_) return ring_receive(out, capacity, wait_us);
  if (wait_us == 0) return receive_with(out, capacity, MSG_DONTWAIT);
  // Waking early costs a pass, waking late misses a deadline: a timeout
  // already set is kept while it is no longer than the wait and at least
  // half of it (a transfer's wait moves by microseconds from frame to frame).
  if (rcvtimeo_us_ == 0 || rcvtimeo_us_ > wait_us || rcvtimeo_us_ < wait_us / 2) {
    const timeval tv{static_cast<time_t>(wait_us / 1000000u), static_cast<suseconds_t>(wait_us % 1000000u)};
    if (setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv) != 0) {
      note("SO_RCVTIMEO", errno);
      return receive_with(out, capacity, MSG_DONTWAIT);  // the caller's loop comes back
    }
    rcvtimeo_us_ = wait_us;
  }
  // Blocks for the first frame only, then takes what else is waiting.
  return receive_with(out, capacity, MSG_WAITFORONE);
}

void SocketCanPort::read_clocks() {
  const uint64_t mono_us = clock_us(CLOCK_MONOTONIC);
  real_minus_mono_us_ = clock_us(CLOCK_REALTIME) - mono_us;
  read_mono_us_ = mono_us;
  clocks_read_ = true;
}

uint64_t SocketCanPort::monotonic_of(uint64_t stamp_real_us, bool* read_now) {
  // Unsigned wrap-around: a stamp before the offset lands far outside the
  // window, so the clocks are read and it is clamped below.
  uint64_t at = stamp_real_us - real_minus_mono_us_;
  const bool inside = clocks_read_ && at + kResyncUs >= read_mono_us_ && at <= read_mono_us_ + kResyncUs;
  if (!inside && !*read_now) {  // once per call at most: a backlog older than the window is no reason
    read_clocks();
    *read_now = true;
    at = stamp_real_us - real_minus_mono_us_;
  }
  // Every frame of this call came before a reading made for it (a
  // wall-clock step can put the stamp after it).
  return *read_now && at > read_mono_us_ ? read_mono_us_ : at;
}

size_t SocketCanPort::receive_with(TimedCanFrame* out, size_t capacity, int flags) {
  if (fd_ < 0 || capacity == 0) return 0;
  const size_t batch = capacity < kBatch ? capacity : kBatch;
  const int got = recvmmsg(fd_, rx_msgs_, static_cast<unsigned>(batch), flags, nullptr);
  if (got <= 0) {
    if (got < 0 && !queue_full(errno) && errno != EINTR) {
      ++counters_.io_errors;
      note("receive", errno);
    }
    return 0;
  }
  bool clocks_read_now = false;
  size_t stored = 0;
  for (size_t i = 0; i < static_cast<size_t>(got); ++i) {
    msghdr& hdr = rx_msgs_[i].msg_hdr;
    if (take(&rx_kernel_[i], rx_msgs_[i].msg_len, (hdr.msg_flags & MSG_TRUNC) != 0, hdr, out[stored],
             &clocks_read_now)) {
      ++stored;
    }
    hdr.msg_controllen = kRxControlBytes;  // the kernel shortened it to what it wrote
  }
  counters_.rx_frames += stored;
  return stored;
}

bool SocketCanPort::take(const void* payload, size_t len, bool truncated, msghdr& hdr, TimedCanFrame& slot,
                         bool* clocks_read_now) {
  can_frame kernel;
  const bool whole = len == sizeof kernel && !truncated;
  if (whole) memcpy(&kernel, payload, sizeof kernel);
  if (!whole || !from_kernel_frame(kernel, slot.frame)) {
    ++counters_.io_errors;
    return false;
  }
  bool stamped = false;
  for (cmsghdr* c = CMSG_FIRSTHDR(&hdr); c != nullptr; c = CMSG_NXTHDR(&hdr, c)) {
    if (c->cmsg_level != SOL_SOCKET) continue;
    if (c->cmsg_type == SCM_TIMESTAMP) {
      timeval tv{};
      memcpy(&tv, CMSG_DATA(c), sizeof tv);
      slot.rx_time_us = monotonic_of(
          static_cast<uint64_t>(tv.tv_sec) * 1000000u + static_cast<uint64_t>(tv.tv_usec), clocks_read_now);
      stamped = true;
    } else if (c->cmsg_type == SO_RXQ_OVFL) {
      uint32_t overflows = 0;  // the kernel's wrapping drop count for this socket
      memcpy(&overflows, CMSG_DATA(c), sizeof overflows);
      counters_.rx_dropped += static_cast<uint32_t>(overflows - last_rx_overflows_);
      last_rx_overflows_ = overflows;
    }
  }
  if (!stamped) slot.rx_time_us = clock_us(CLOCK_MONOTONIC);  // no SO_TIMESTAMP: the read's time
  return true;
}

/// The ring's completions into a receive's `out`, refused sends collected
/// (in order) for requeue().
class SocketCanPort::RingTaker : public RingCompletions {
 public:
  RingTaker(SocketCanPort& port, TimedCanFrame* out, size_t capacity)
      : port_(port), out_(out), capacity_(capacity) {}

  bool on_record(const void* payload, size_t len, bool truncated, msghdr& control) override {
    if (stored_ == capacity_) return false;
    if (port_.take(payload, len, truncated, control, out_[stored_], &clocks_read_now_)) ++stored_;
    return true;
  }
  void on_refused(const struct ::can_frame& frame, int err) override {
    // The first refusal decides for the sends it cancelled after it.
    if (err != ECANCELED || refusal_ == 0) refusal_ = err;
    if (refused_ < SocketCanRing::kTxSlots && from_kernel_frame(frame, refused_frames_[refused_])) ++refused_;
  }
  void on_receive_error(int err) override {
    ++port_.counters_.io_errors;
    port_.note("receive", err);
  }

  size_t stored() const { return stored_; }
  /// Hands the refused sends back to the port.
  void requeue() const {
    if (refused_ != 0) port_.requeue(refused_frames_, refused_, refusal_);
  }

 private:
  SocketCanPort& port_;
  TimedCanFrame* out_;
  size_t capacity_;
  size_t stored_ = 0;
  bool clocks_read_now_ = false;
  int refusal_ = 0;
  size_t refused_ = 0;
  CanFrame refused_frames_[SocketCanRing::kTxSlots];
};

size_t SocketCanPort::ring_receive(TimedCanFrame* out, size_t capacity, uint32_t wait_us) {
  if (capacity == 0) return 0;
  // Frames already waiting are taken without a system call, unless sends
  // are staged: they go now, with no wait.
  if (ring_->staged() != 0 || !ring_->ready()) {
    const int err = ring_->submit(ring_->ready() ? 0 : wait_us);
    if (err != 0 && err != EINTR) {
      ++counters_.io_errors;
      note("io_uring_enter", err);
    }
  }
  RingTaker taker(*this, out, capacity);
  ring_->reap(taker);
  taker.requeue();
  counters_.rx_frames += taker.stored();
  return taker.stored();
}

void SocketCanPort::stage_queued() {
  // A new submission's sends could overtake the refused ones of the last.
  if (ring_->in_flight() != 0) return;
  size_t n = 0;
  can_frame kernel;
  while (n < tx_count_ && to_kernel_frame(tx_[n], kernel) && ring_->stage(kernel)) ++n;
  counters_.tx_frames += n;  // taken back by requeue() for those the kernel refuses
  memmove(tx_, tx_ + n, (tx_count_ - n) * sizeof tx_[0]);
  tx_count_ -= n;
}

void SocketCanPort::requeue(const CanFrame* frames, size_t count, int err) {
  counters_.tx_frames -= count;
  if (!queue_full(err)) {
    count_refused(err, count);  // refused for good (interface down), as flush() drops them
    return;
  }
  // Older than what tx_ holds: in front, in order (they all fit: at most
  // kTxSlots); the newest that no longer fit are dropped.
  static_assert(SocketCanRing::kTxSlots <= kQueueFrames, "a submission's refused sends fit the queue");
  const size_t kept = count + tx_count_ <= kQueueFrames ? tx_count_ : kQueueFrames - count;
  if (kept < tx_count_) count_refused(err, tx_count_ - kept);
  memmove(tx_ + count, tx_, kept * sizeof tx_[0]);
  memcpy(tx_, frames, count * sizeof tx_[0]);
  tx_count_ = count + kept;
}

void SocketCanPort::count_refused(int err, uint64_t frames) {
  if (queue_full(err)) {
    counters_.tx_dropped += frames;
  } else {
    counters_.tx_errors += frames;
    if (err != 0) note("send", err);
  }
}

bool SocketCanPort::send(const CanFrame& frame) {
  return send(&frame, 1) == 1;
}

size_t SocketCanPort::send(const CanFrame* frames, size_t count) {
  // What flush_at_next_receive() staged goes first (the kernel has taken it
  // when submit() returns).
  if (ring_ && ring_->staged() != 0) flush();
  size_t sent = 0;
  while (sent < count) {
    if (fd_ < 0) {
      note("not open", 0);
      count_refused(0, count - sent);
      return sent;
    }
    int err = 0;
    sent += transmit(frames + sent, count - sent, &err);
    if (err == 0) continue;
    if (err == kInvalidFrame) {
      note("invalid frame (dlc > 8 or id out of range)", 0);
      err = 0;
    }
    count_refused(err, count - sent);
    return sent;
  }
  return sent;
}

size_t SocketCanPort::transmit(const CanFrame* frames, size_t count, int* err) {
  *err = 0;
  size_t sent = 0;
  while (sent < count) {
    // Convert up to one batch, stopping before an invalid frame.
    size_t n = 0;
    while (n < kBatch && sent + n < count && to_kernel_frame(frames[sent + n], tx_kernel_[n])) ++n;
    if (n == 0) {  // frames[sent] is invalid
      *err = kInvalidFrame;
      return sent;
    }
    const int done = sendmmsg(fd_, tx_msgs_, static_cast<unsigned>(n), MSG_DONTWAIT);
    if (done <= 0) {
      if (done < 0 && errno == EINTR) continue;
      *err = done < 0 ? errno : EAGAIN;
      return sent;
    }
    sent += static_cast<size_t>(done);
    counters_.tx_frames += static_cast<uint64_t>(done);
  }
  return sent;
}

bool SocketCanPort::queue(const CanFrame& frame) {
  can_frame probe;
  if (!to_kernel_frame(frame, probe)) {
    note("invalid frame (dlc > 8 or id out of range)", 0);
    count_refused(0, 1);
    return false;
  }
  if (tx_count_ == kQueueFrames) flush();
  if (tx_count_ == kQueueFrames) {
    count_refused(EAGAIN, 1);  // the kernel's queue and ours are full
    return false;
  }
  tx_[tx_count_++] = frame;
  return true;
}

void SocketCanPort::flush_at_next_receive() {
  if (ring_) {
    stage_queued();
  } else {
    flush();
  }
}

size_t SocketCanPort::flush() {
  if (ring_) {
    // The kernel takes the staged frames inside submit(); its refusals are
    // reaped by the next receive (requeue()).
    stage_queued();
    const size_t staged = ring_->staged();
    if (staged == 0) return 0;
    const int err = ring_->submit(0);
    if (err != 0 && err != EINTR) {
      ++counters_.io_errors;
      note("io_uring_enter", err);
    }
    return staged;
  }
  if (tx_count_ == 0) return 0;
  if (fd_ < 0) {
    note("not open", 0);
    count_refused(0, tx_count_);
    tx_count_ = 0;
    return 0;
  }
  int err = 0;
  const size_t sent = transmit(tx_, tx_count_, &err);  // queue() let only valid frames in
  size_t dropped = 0;
  if (err != 0 && !queue_full(err)) {
    // Refused for good (interface down): the rest goes, as a send's would.
    dropped = tx_count_ - sent;
    count_refused(err, dropped);
  }
  const size_t kept = tx_count_ - sent - dropped;  // the kernel's queue is full: next flush
  memmove(tx_, tx_ + sent, kept * sizeof tx_[0]);
  tx_count_ = kept;
  return sent;
}

bool SocketCanPort::send_to(void* ctx, const CanFrame& frame) {
  return static_cast<SocketCanPort*>(ctx)->send(frame);
}

bool SocketCanPort::queue_to(void* ctx, const CanFrame& frame) {
  return static_cast<SocketCanPort*>(ctx)->queue(frame);
}

}  // namespace linux_port
}  // namespace mb2co
