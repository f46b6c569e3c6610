// A malicious SDO server for mb2co-master's tests (issue 22 item 4): node 5
// on vcan0, a raw CAN socket in a thread of the test, answering each request
// of the master the way a test's handler says (a 4 GB size, segments
// without end, sub-blocks that never get through ...). It notes when it
// last made progress and when the master's abort came, on the monotonic
// clock, so a test can check that the master ended within -t of the last
// progress without sleeping.
#pragma once
#include <stdint.h>

#include <array>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "canopen/can_frame.h"

namespace mb2co {
namespace test {

using Clock = std::chrono::steady_clock;
using Bytes8 = std::array<uint8_t, 8>;

/// An answer to request `r`: `cmd`, the request's multiplexer (index,
/// sub), then `value` little-endian.
Bytes8 mux(const CanFrame& r, uint8_t cmd, uint32_t value = 0);

class RogueServer {
 public:
  static const uint8_t kNode = 5;
  /// Called on the server's thread for every frame of the master on 605h
  /// but its abort.
  using Handler = std::function<void(RogueServer& server, const CanFrame& request)>;

  RogueServer() = default;
  ~RogueServer() { stop(); }
  RogueServer(const RogueServer&) = delete;
  RogueServer& operator=(const RogueServer&) = delete;

  /// Opens vcan0 (receiving 605h only) and starts answering. False with
  /// error() when the socket cannot be set up.
  bool start(Handler handler);
  /// From now on the handler also gets the master's requests after its
  /// abort (a scan asks a lost read again); still counted in
  /// frames_after_abort(). Call before start().
  void keep_answering_after_abort() { keep_answering_ = true; }
  /// Stops the thread after it has taken every request already queued
  /// (what it noted stays readable).
  void stop();
  const std::string& error() const { return error_; }

  // ---- from the handler (the server's thread) ----
  /// Frames on 585h now, in one sendmmsg where possible.
  void send(const std::vector<Bytes8>& frames);
  void send(const Bytes8& frame) { send(std::vector<Bytes8>{frame}); }
  /// Node 5's heartbeat (705h) with NMT `state` now (05h operational, 04h
  /// stopped): the node shows it is there without answering.
  void heartbeat(uint8_t state);
  /// A frame on 585h `delay` from now (a slow server), unless the master
  /// aborted meanwhile.
  void send_later(std::chrono::milliseconds delay, const Bytes8& frame);
  /// The transfer moves on with the frames sent next: their time is the
  /// last progress (noted before they go out, so the master cannot have
  /// seen them earlier).
  void progress();

  // ---- from the test ----
  /// Waits until the master's abort (80h) arrived; false at `timeout`.
  bool wait_abort(std::chrono::milliseconds timeout);
  /// The master's abort code (0: none yet) and when it came.
  uint32_t abort_code() const;
  Clock::time_point abort_at() const;
  /// The last progress() (the server's start when never called).
  Clock::time_point progress_at() const;
  /// Frames the server sent, and frames of the master after its abort.
  uint64_t frames_sent() const;
  uint64_t frames_after_abort() const;

 private:
  void run();
  /// Reads one queued request (recv `flags`) into the handler; false when none.
  bool take_frame(int flags);
  void receive(const CanFrame& f);

  Handler handler_;
  int fd_ = -1;
  int stop_pipe_[2] = {-1, -1};
  std::thread thread_;
  std::string error_;
  std::vector<std::pair<Clock::time_point, Bytes8>> later_;  ///< server thread only

  mutable std::mutex mutex_;
  std::condition_variable aborted_;
  uint32_t abort_code_ = 0;
  Clock::time_point abort_at_{};
  Clock::time_point progress_at_{};
  uint64_t frames_sent_ = 0;
  uint64_t frames_after_abort_ = 0;
  bool keep_answering_ = false;
};

}  // namespace test
}  // namespace mb2co
