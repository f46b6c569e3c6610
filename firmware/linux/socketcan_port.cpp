// SocketCAN port: see socketcan_port.h for the contract.
#include "socketcan_port.h"

#include <errno.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <time.h>
#include <unistd.h>

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
    : fd_(-1), rcvbuf_bytes_(0), last_rx_overflows_(0), counters_{}, ifname_{}, error_{} {}

SocketCanPort::~SocketCanPort() {
  close();
}

void SocketCanPort::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  rcvbuf_bytes_ = 0;
  last_rx_overflows_ = 0;
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

Status SocketCanPort::open(const char* ifname, int rcvbuf_bytes) {
  close();
  error_[0] = '\0';
  if (ifname == nullptr || ifname[0] == '\0' || strlen(ifname) >= sizeof ifname_) {
    snprintf(ifname_, sizeof ifname_, "?");
    return fail("interface name empty or longer than 15 characters", 0);
  }
  snprintf(ifname_, sizeof ifname_, "%s", ifname);

  const int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
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
  if (fd_ < 0 || capacity == 0) return 0;
  const size_t batch = capacity < kBatch ? capacity : kBatch;
  // Room for SCM_TIMESTAMP and SO_RXQ_OVFL per frame.
  constexpr size_t kControlBytes = CMSG_SPACE(sizeof(timeval)) + CMSG_SPACE(sizeof(uint32_t));
  can_frame frames[kBatch];
  iovec iov[kBatch];
  mmsghdr msgs[kBatch];
  alignas(cmsghdr) char control[kBatch][kControlBytes];
  memset(msgs, 0, sizeof msgs);
  for (size_t i = 0; i < batch; ++i) {
    iov[i] = iovec{&frames[i], sizeof frames[i]};
    msgs[i].msg_hdr.msg_iov = &iov[i];
    msgs[i].msg_hdr.msg_iovlen = 1;
    msgs[i].msg_hdr.msg_control = control[i];
    msgs[i].msg_hdr.msg_controllen = kControlBytes;
  }
  const int got = recvmmsg(fd_, msgs, static_cast<unsigned>(batch), MSG_DONTWAIT, nullptr);
  if (got <= 0) {
    if (got < 0 && !queue_full(errno) && errno != EINTR) {
      ++counters_.io_errors;
      note("receive", errno);
    }
    return 0;
  }
  // SO_TIMESTAMP is wall-clock time: shift it by the frame's age onto the
  // monotonic clock. A step of the wall clock shows as age 0 (read time).
  const uint64_t mono_us = clock_us(CLOCK_MONOTONIC);
  const uint64_t real_us = clock_us(CLOCK_REALTIME);
  size_t stored = 0;
  for (size_t i = 0; i < static_cast<size_t>(got); ++i) {
    const msghdr& hdr = msgs[i].msg_hdr;
    TimedCanFrame& slot = out[stored];
    if (msgs[i].msg_len != sizeof(can_frame) || (hdr.msg_flags & MSG_TRUNC) != 0 ||
        !from_kernel_frame(frames[i], slot.frame)) {
      ++counters_.io_errors;
      continue;
    }
    slot.rx_time_us = mono_us;
    for (cmsghdr* c = CMSG_FIRSTHDR(&hdr); c != nullptr; c = CMSG_NXTHDR(const_cast<msghdr*>(&hdr), c)) {
      if (c->cmsg_level != SOL_SOCKET) continue;
      if (c->cmsg_type == SCM_TIMESTAMP) {
        timeval tv{};
        memcpy(&tv, CMSG_DATA(c), sizeof tv);
        const uint64_t stamp_us =
            static_cast<uint64_t>(tv.tv_sec) * 1000000u + static_cast<uint64_t>(tv.tv_usec);
        const uint64_t age_us = stamp_us <= real_us ? real_us - stamp_us : 0;
        if (age_us <= mono_us) slot.rx_time_us = mono_us - age_us;
      } else if (c->cmsg_type == SO_RXQ_OVFL) {
        uint32_t overflows = 0;  // the kernel's wrapping drop count for this socket
        memcpy(&overflows, CMSG_DATA(c), sizeof overflows);
        counters_.rx_dropped += static_cast<uint32_t>(overflows - last_rx_overflows_);
        last_rx_overflows_ = overflows;
      }
    }
    ++stored;
  }
  counters_.rx_frames += stored;
  return stored;
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
  size_t sent = 0;
  while (sent < count) {
    if (fd_ < 0) {
      note("not open", 0);
      count_refused(0, count - sent);
      return sent;
    }
    // Convert up to one batch, stopping before an invalid frame.
    can_frame kernel[kBatch];
    iovec iov[kBatch];
    mmsghdr msgs[kBatch];
    memset(msgs, 0, sizeof msgs);
    size_t n = 0;
    while (n < kBatch && sent + n < count && to_kernel_frame(frames[sent + n], kernel[n])) {
      iov[n] = iovec{&kernel[n], sizeof kernel[n]};
      msgs[n].msg_hdr.msg_iov = &iov[n];
      msgs[n].msg_hdr.msg_iovlen = 1;
      ++n;
    }
    if (n == 0) {  // frames[sent] is invalid
      note("invalid frame (dlc > 8 or id out of range)", 0);
      count_refused(0, count - sent);
      return sent;
    }
    const int done = sendmmsg(fd_, msgs, static_cast<unsigned>(n), MSG_DONTWAIT);
    if (done <= 0) {
      if (done < 0 && errno == EINTR) continue;
      count_refused(done < 0 ? errno : EAGAIN, count - sent);
      return sent;
    }
    sent += static_cast<size_t>(done);
    counters_.tx_frames += static_cast<uint64_t>(done);
  }
  return sent;
}

bool SocketCanPort::send_to(void* ctx, const CanFrame& frame) {
  return static_cast<SocketCanPort*>(ctx)->send(frame);
}

}  // namespace linux_port
}  // namespace mb2co
