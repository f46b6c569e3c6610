#include "bus_loop.h"

#include <poll.h>
#include <time.h>
#include <unistd.h>

#include "stop_signal.h"

namespace mb2co {
namespace master {

Status BusLoop::open(const char* ifname) {
  catch_stop_signals();
  return port_.open(ifname);
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
  const CanSink out = port_.sink();
  NextDeadline next(now_us());
  next.at(end);
  for (int i = 0; i < count_; ++i) services_[i]->next_deadline(next);
  uint32_t at_us = end;
  next.result(&at_us);
  // Round up: waking a little late is harmless, waking early costs a pass.
  const uint32_t wait_us = time_until(next.now_us(), at_us);
  // The CAN socket first (-1 without one: poll() skips it), then each
  // watcher's descriptors, counted to hand them back.
  fds_.assign(1, pollfd{port_.fd(), POLLIN, 0});
  size_t counts[kMaxServices];
  for (int i = 0; i < watcher_count_; ++i) {
    const size_t before = fds_.size();
    watchers_[i]->poll_fds(&fds_);
    counts[i] = fds_.size() - before;
  }
  const int wait_ms = static_cast<int>((wait_us + 999u) / 1000u);
  poll(fds_.data(), fds_.size(), wait_ms);  // EINTR when a signal came during the wait
  // A signal that came between two waits only set the flag: read it here,
  // or a SIGINT outside poll() would be lost.
  if (stop_signalled()) interrupted_ = true;
  if (fds_[0].revents & POLLIN) {
    linux_port::TimedCanFrame frames[linux_port::SocketCanPort::kBatch];
    size_t got = 0;
    while ((got = port_.receive(frames, linux_port::SocketCanPort::kBatch)) > 0) {
      for (size_t k = 0; k < got; ++k) {
        const uint32_t at = clock_.at(static_cast<uint32_t>(frames[k].rx_time_us));
        for (int i = 0; i < count_; ++i) services_[i]->on_frame(frames[k].frame, at, out);
      }
    }
  }
  const uint32_t now = clock_.at(now_us());
  size_t at = 1;
  for (int i = 0; i < watcher_count_; ++i) {
    watchers_[i]->on_poll(fds_.data() + at, counts[i], now);
    at += counts[i];
  }
  for (int i = 0; i < count_; ++i) services_[i]->process(now, out);
}

}  // namespace master
}  // namespace mb2co
