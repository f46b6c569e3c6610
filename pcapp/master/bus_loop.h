// The master's one thread: a SocketCAN port, the monotonic clock and the
// portable services of shared/canopen/master, run by one loop that sleeps
// exactly until the earliest deadline any service reports (no periodic
// wake-up: an idle master costs nothing). Frames come in batches
// (recvmmsg) with their kernel receive times, which are also the pass's
// time when there are any (no clock read); what the services send is
// queued and goes out in batches (sendmmsg) at the end of the pass, or,
// where the port has io_uring, in the next pass's wait: one system call.
#pragma once
#include <poll.h>
#include <stdint.h>

#include <vector>

#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "host/status.h"
#include "platform/socketcan_port.h"
#include "service_clock.h"

namespace mb2co {
namespace master {

/// What the loop drives. Each call gets the same `now_us` the loop took once
/// per pass, so services agree on time; a frame comes with its receive time.
/// Both from one ServiceClock: a service never sees the time go back. Not
/// owned by the loop.
class BusService {
 public:
  virtual void on_frame(const CanFrame& frame, uint32_t now_us, const CanSink& sink) = 0;
  virtual void process(uint32_t now_us, const CanSink& sink) = 0;
  virtual void next_deadline(NextDeadline& d) const = 0;

 protected:
  ~BusService() = default;  // never deleted through this interface
};

/// A service with descriptors of its own for the loop's poll() (serve's
/// sockets beside the bus): asked for them before each wait, told what
/// poll() found right after it, before the frames are handed out.
class PollWatcher : public BusService {
 public:
  /// Appends its descriptors (fd, events).
  virtual void poll_fds(std::vector<pollfd>* fds) = 0;
  /// The `n` entries it appended, with revents, in the same order.
  virtual void on_poll(const pollfd* fds, size_t n, uint32_t now_us) = 0;

 protected:
  ~PollWatcher() = default;
};

class BusLoop {
 public:
  static const int kMaxServices = 8;

  /// Opens `ifname` receiving every frame (a master listens to all of them).
  Status open(const char* ifname);
  /// Adds a service; false when kMaxServices are there already.
  bool add(BusService* service);
  /// Adds a watcher: a service whose descriptors the loop polls too.
  /// False when kMaxServices are there already.
  bool add_watcher(PollWatcher* watcher);
  /// Takes a service (or watcher) out again (it may go out of scope then).
  void remove(BusService* service);

  /// Runs passes until `done()` is true (checked after every pass) or
  /// `limit_us` µs have passed (at most kLongestRunUs: the wrapping clock's
  /// horizon). True when done() ended it. SIGINT/SIGTERM end it early too
  /// (interrupted() then tells).
  static const uint32_t kLongestRunUs = 2000000000u;
  template <class Done>
  bool run_until(Done done, uint32_t limit_us) {
    if (limit_us > kLongestRunUs) limit_us = kLongestRunUs;
    now_ = clock_.at(now_us());
    const uint32_t end = now_ + limit_us;
    for (;;) {
      pass(end);
      const bool finished = done();
      if (finished || interrupted_ || time_reached(now_, end)) {
        port_.flush();  // what the last pass left for the next wait: there is none
        return finished;
      }
    }
  }
  /// Sends one frame now (NMT, SYNC by hand), after what a pass left
  /// queued. False when the kernel refused it.
  bool send(const CanFrame& frame) {
    port_.flush();
    return port_.send(frame);
  }
  /// Sends at once (outside passes: an NMT command, aborts after run_until).
  /// The services get a sink that queues, flushed at the end of each pass.
  CanSink sink() { return port_.sink(); }
  uint32_t now_us() const;
  /// A SIGINT or SIGTERM arrived (watch ends, transfers are aborted cleanly).
  bool interrupted() const { return interrupted_; }
  const linux_port::SocketCanPort& port() const { return port_; }

 private:
  /// One wait until the earliest deadline (or `end`) that reads the frames
  /// too, then frames in, every service's process(), and what they queued
  /// out. System calls of a pass that hears one frame and answers it: the
  /// wait-and-receive and one send, or on the port's io_uring path both in
  /// one (the send goes with the next pass's wait); with watchers, a poll() more.
  void pass(uint32_t end);
  /// poll() of the CAN socket and the watchers' descriptors (counts_ says
  /// how many each added), precise to the µs timer; true when frames wait.
  bool wait_polling(uint32_t wait_us);

  /// Longest wait (µs) while frames the kernel had no room for are queued.
  static const uint32_t kRetrySendUs = 1000;
  /// How late a receive's SO_RCVTIMEO may end (µs): the kernel counts it in
  /// jiffies, 10 ms at HZ=100. Shorter waits are poll()s (a SYNC period).
  static const uint32_t kTimerSlackUs = 10000;

  linux_port::SocketCanPort port_;
  BusService* services_[kMaxServices] = {};
  int count_ = 0;
  PollWatcher* watchers_[kMaxServices] = {};
  int watcher_count_ = 0;
  std::vector<pollfd> fds_;           ///< the CAN socket, then each watcher's (kept: no allocation per pass)
  size_t counts_[kMaxServices] = {};  ///< descriptors each watcher added to fds_
  ServiceClock clock_;
  uint32_t now_ = 0;  ///< the last pass's time (from clock_)
  bool interrupted_ = false;
};

}  // namespace master
}  // namespace mb2co
