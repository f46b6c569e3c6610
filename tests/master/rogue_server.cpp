#include "rogue_server.h"

#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace mb2co {
namespace test {

Bytes8 mux(const CanFrame& r, uint8_t cmd, uint32_t value) {
  return {cmd,
          r.data[1],
          r.data[2],
          r.data[3],
          static_cast<uint8_t>(value),
          static_cast<uint8_t>(value >> 8),
          static_cast<uint8_t>(value >> 16),
          static_cast<uint8_t>(value >> 24)};
}

bool RogueServer::start(Handler handler) {
  handler_ = std::move(handler);
  progress_at_ = Clock::now();
  fd_ = socket(PF_CAN, SOCK_RAW | SOCK_CLOEXEC, CAN_RAW);
  if (fd_ < 0) {
    error_ = std::string("socket: ") + std::strerror(errno);
    return false;
  }
  ifreq ifr{};
  std::strncpy(ifr.ifr_name, "vcan0", IFNAMSIZ - 1);
  can_filter only_requests = {0x600u + kNode, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG};
  // A sub-block of 127 frames goes out in one sendmmsg: room for it.
  const int sndbuf = 1 << 20;
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  if (ioctl(fd_, SIOCGIFINDEX, &ifr) != 0 ||
      setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, &only_requests, sizeof only_requests) != 0 ||
      setsockopt(fd_, SOL_SOCKET, SO_SNDBUF, &sndbuf, sizeof sndbuf) != 0) {
    error_ = std::string("vcan0: ") + std::strerror(errno);
    return false;
  }
  addr.can_ifindex = ifr.ifr_ifindex;
  if (bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 || pipe2(stop_pipe_, O_CLOEXEC) != 0) {
    error_ = std::string("bind: ") + std::strerror(errno);
    return false;
  }
  thread_ = std::thread([this] { run(); });
  return true;
}

void RogueServer::stop() {
  if (thread_.joinable()) {
    const char x = 1;
    (void)!write(stop_pipe_[1], &x, 1);
    thread_.join();
  }
  for (int* fd : {&fd_, &stop_pipe_[0], &stop_pipe_[1]}) {
    if (*fd >= 0) close(*fd);
    *fd = -1;
  }
}

void RogueServer::progress() {
  std::lock_guard<std::mutex> lock(mutex_);
  progress_at_ = Clock::now();
}

void RogueServer::send(const std::vector<Bytes8>& frames) {
  std::vector<can_frame> out(frames.size());
  std::vector<iovec> iov(frames.size());
  std::vector<mmsghdr> msgs(frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    out[i] = can_frame{};
    out[i].can_id = 0x580u + kNode;
    out[i].can_dlc = 8;
    std::memcpy(out[i].data, frames[i].data(), 8);
    iov[i] = iovec{&out[i], sizeof out[i]};
    msgs[i] = mmsghdr{};
    msgs[i].msg_hdr.msg_iov = &iov[i];
    msgs[i].msg_hdr.msg_iovlen = 1;
  }
  size_t done = 0;
  while (done < frames.size()) {
    const int n = sendmmsg(fd_, &msgs[done], static_cast<unsigned>(frames.size() - done), 0);
    if (n > 0) {
      done += static_cast<size_t>(n);
      continue;
    }
    if (errno != ENOBUFS && errno != EAGAIN && errno != EINTR) break;  // the test sees missing frames
    pollfd p = {fd_, POLLOUT, 0};
    poll(&p, 1, 100);  // the queue drains; a bound, not a synchronisation
  }
  std::lock_guard<std::mutex> lock(mutex_);
  frames_sent_ += done;
}

void RogueServer::heartbeat(uint8_t state) {
  can_frame f{};
  f.can_id = 0x700u + kNode;
  f.can_dlc = 1;
  f.data[0] = state;
  if (write(fd_, &f, sizeof f) != static_cast<ssize_t>(sizeof f)) error_ = "heartbeat not sent";
}

void RogueServer::send_later(std::chrono::milliseconds delay, const Bytes8& frame) {
  later_.emplace_back(Clock::now() + delay, frame);
}

void RogueServer::receive(const CanFrame& f) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (abort_code_ != 0) {
      ++frames_after_abort_;
      if (!keep_answering_) return;
    } else if (f.dlc == 8 && f.data[0] == 0x80) {
      abort_code_ = static_cast<uint32_t>(f.data[4]) | static_cast<uint32_t>(f.data[5]) << 8 |
                    static_cast<uint32_t>(f.data[6]) << 16 | static_cast<uint32_t>(f.data[7]) << 24;
      abort_at_ = Clock::now();
      later_.clear();
      aborted_.notify_all();
      return;
    }
  }
  handler_(*this, f);
}

bool RogueServer::take_frame(int flags) {
  can_frame k{};
  if (recv(fd_, &k, sizeof k, flags) != static_cast<ssize_t>(sizeof k)) return false;
  CanFrame f{};
  f.id = k.can_id & CAN_SFF_MASK;
  f.dlc = k.can_dlc;
  std::memcpy(f.data, k.data, 8);
  receive(f);
  return true;
}

void RogueServer::run() {
  for (;;) {
    int wait_ms = -1;
    if (!later_.empty()) {
      const auto first = std::min_element(later_.begin(), later_.end(),
                                          [](const auto& a, const auto& b) { return a.first < b.first; });
      const auto left = std::chrono::ceil<std::chrono::milliseconds>(first->first - Clock::now());
      wait_ms = static_cast<int>(std::max<int64_t>(0, left.count()));
    }
    pollfd p[2] = {{fd_, POLLIN, 0}, {stop_pipe_[0], POLLIN, 0}};
    poll(p, 2, wait_ms);
    if (p[1].revents) {
      // What the master sent before the test stopped us is already queued
      // on the socket (vcan delivers at the send, before the master exits
      // and the test calls stop()): taken before leaving, not lost to the
      // order in which poll() reports the two.
      while (take_frame(MSG_DONTWAIT)) {
      }
      return;
    }
    if (p[0].revents & POLLIN) take_frame(MSG_DONTWAIT);
    const auto now = Clock::now();
    for (size_t i = 0; i < later_.size();) {
      if (later_[i].first > now) {
        ++i;
        continue;
      }
      const Bytes8 frame = later_[i].second;
      later_.erase(later_.begin() + static_cast<long>(i));
      send(frame);
    }
  }
}

bool RogueServer::wait_abort(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  return aborted_.wait_for(lock, timeout, [this] { return abort_code_ != 0; });
}

uint32_t RogueServer::abort_code() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return abort_code_;
}

Clock::time_point RogueServer::abort_at() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return abort_at_;
}

Clock::time_point RogueServer::progress_at() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return progress_at_;
}

uint64_t RogueServer::frames_sent() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return frames_sent_;
}

uint64_t RogueServer::frames_after_abort() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return frames_after_abort_;
}

}  // namespace test
}  // namespace mb2co
