#include "bus_loop.h"

#include <poll.h>
#include <time.h>

#include "platform/stop_signal.h"

namespace mb2co {
namespace master {

Status BusLoop::open(const char* ifname) {
  port::catch_stop_signals();
  return port_.open(ifname, linux_port::SocketCanPort::kDefaultRcvbufBytes, linux_port::IoPath::kRing);
}

bool BusLoop::add(BusService* service) {
  if (count_ == kMaxServices) return false;
  services_[count_++] = service;
  return true;
}

bool BusLoop::add_watcher(PollWatcher* watcher) {
  if (watcher_count_ == kMaxServices || !add(watcher)) return false;
  watchers_[watcher_count_++] = watcher;
  return true;
}

void BusLoop::remove(BusService* service) {
  for (int i = 0; i < watcher_count_; ++i) {
    if (watchers_[i] != service) continue;
    for (int k = i + 1; k < watcher_count_; ++k) watchers_[k - 1] = watchers_[k];
    watchers_[--watcher_count_] = nullptr;
    break;
  }
  for (int i = 0; i < count_; ++i) {
    if (services_[i] != service) continue;
    for (int k = i + 1; k < count_; ++k) services_[k - 1] = services_[k];
    services_[--count_] = nullptr;
    return;
  }
}

uint32_t BusLoop::now_us() const {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint32_t>(static_cast<uint64_t>(ts.tv_sec) * 1000000u +
                               static_cast<uint64_t>(ts.tv_nsec) / 1000u);
}

void BusLoop::pass(uint32_t end) {
  const CanSink out = port_.queue_sink();
  // The deadlines against the last pass's time: no clock read here. That
  // time is older than now by the last pass's own work, so the wait may end
  // that much late (microseconds; the wait is rounded up to ms for poll()).
  NextDeadline next(now_);
  next.at(end);
  for (int i = 0; i < count_; ++i) services_[i]->next_deadline(next);
  uint32_t at_us = end;
  next.result(&at_us);
  uint32_t wait_us = time_until(next.now_us(), at_us);
  // Frames the kernel had no room for are sent again soon.
  if (port_.queued() != 0 && wait_us > kRetrySendUs) wait_us = kRetrySendUs;
  linux_port::TimedCanFrame frames[linux_port::SocketCanPort::kBatch];
  const size_t batch = linux_port::SocketCanPort::kBatch;
  size_t got = 0;
  if (watcher_count_ == 0 && (wait_us == 0 || wait_us > 2 * kTimerSlackUs)) {
    // Wait and read in one system call (a segmented transfer's round trip:
    // this receive and the request's send, nothing else; on io_uring the
    // send that the last pass staged is in this call too). The socket's
    // timeout counts in jiffies: it is set kTimerSlackUs short, and the
    // rest of the wait, if no frame came, is a precise poll() next pass.
    got = port_.receive_within(frames, batch, wait_us == 0 ? 0 : wait_us - kTimerSlackUs);
  } else {
    port_.flush();  // what the last pass staged goes before the poll, not after it
    got = wait_polling(wait_us) ? port_.receive(frames, batch) : 0;
  }
  // A signal that came between two waits only set the flag: read it here,
  // or a SIGINT outside the wait would be lost.
  if (port::stop_requested()) interrupted_ = true;
  // The pass's time: the newest frame's receive time when frames came (no
  // clock read), else the clock's.
  bool heard = false;
  uint32_t at = 0;
  while (got > 0) {
    for (size_t k = 0; k < got; ++k) {
      at = clock_.at(static_cast<uint32_t>(frames[k].rx_time_us));
      for (int i = 0; i < count_; ++i) services_[i]->on_frame(frames[k].frame, at, out);
    }
    heard = true;
    // Fewer than asked: the socket was empty (no extra call to find out).
    if (got < batch) break;
    got = port_.receive(frames, batch);
  }
  const uint32_t now = heard ? at : clock_.at(now_us());
  now_ = now;
  size_t from = 1;
  for (int i = 0; i < watcher_count_; ++i) {
    watchers_[i]->on_poll(fds_.data() + from, counts_[i], now);
    from += counts_[i];
  }
  for (int i = 0; i < count_; ++i) services_[i]->process(now, out);
  // What the pass queued, in order: sent with the next pass's wait (one
  // io_uring_enter), or now (sendmmsg, kBatch frames per call).
  port_.flush_at_next_receive();
}

bool BusLoop::wait_polling(uint32_t wait_us) {
  // The CAN socket first (-1 without one: poll() skips it), then each
  // watcher's descriptors, counted to hand them back.
  fds_.assign(1, pollfd{port_.fd(), POLLIN, 0});
  for (int i = 0; i < watcher_count_; ++i) {
    const size_t before = fds_.size();
    watchers_[i]->poll_fds(&fds_);
    counts_[i] = fds_.size() - before;
  }
  // Round up: waking a little late is harmless, waking early costs a pass.
  const int wait_ms = static_cast<int>((wait_us + 999u) / 1000u);
  poll(fds_.data(), fds_.size(), wait_ms);  // EINTR when a signal came during the wait
  return (fds_[0].revents & POLLIN) != 0;
}

}  // namespace master
}  // namespace mb2co
