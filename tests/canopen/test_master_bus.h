// Test helper for the master's services: a virtual CAN bus between the
// master (its services' sink and receive function) and real I/O nodes
// (ionode::IoNode on the node core), driven by a virtual clock. Every frame
// one side sends reaches every other station in the same step, in order; an
// unplugged node keeps running but neither sends nor receives.
#pragma once
#include <gtest/gtest.h>
#include <stdint.h>

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "frame_log.h"
#include "ionode/io_node.h"

namespace mb2co {
namespace test {

class MasterBus {
 public:
  struct Station {
    FrameLog log;
    ionode::IoNode io{log.sink()};
    bool plugged = true;
  };

  uint32_t now = 0;                                                   ///< virtual µs clock
  std::function<void(uint32_t now_us)> master_process;                ///< the master's services' process()
  std::function<void(const CanFrame& f, uint32_t now_us)> master_rx;  ///< frames reaching the master
  std::vector<std::pair<uint32_t, std::string>> trace;  ///< every frame on the bus, with its time

  CanSink master_sink() { return master_log_.sink(); }

  /// A node started at `now` with `node_id` (boot-up on the bus).
  Station& add_node(uint8_t node_id) {
    stations_.emplace_back(new Station());
    Station& s = *stations_.back();
    s.io.start(node_id, now);
    deliver();
    return s;
  }
  /// Frames sent since the last call, as "<703> 7F" strings (trace kept).
  std::vector<std::string> take() {
    std::vector<std::string> out;
    for (size_t i = taken_; i < trace.size(); ++i) out.push_back(trace[i].second);
    taken_ = trace.size();
    return out;
  }
  /// Time of the last frame on the bus whose text is `text`; false if none.
  bool last_time_of(const std::string& text, uint32_t* at) const {
    for (size_t i = trace.size(); i-- > 0;) {
      if (trace[i].second == text) {
        *at = trace[i].first;
        return true;
      }
    }
    return false;
  }

  /// Hands frames between the stations until the bus is quiet.
  void deliver() {
    for (int round = 0; round < 16; ++round) {
      bool any = false;
      for (const CanFrame& f : take_log(master_log_)) {
        any = true;
        put_on_bus(f, nullptr);
      }
      for (auto& s : stations_) {
        for (const CanFrame& f : take_log(s->log)) {
          if (!s->plugged) continue;
          any = true;
          put_on_bus(f, s.get());
        }
      }
      if (!any) return;
    }
    ADD_FAILURE() << "the bus never went quiet";
  }
  /// One step of `us`: the clock advances, everyone processes, frames flow.
  void step(uint32_t us) {
    now += us;
    if (master_process) master_process(now);
    for (auto& s : stations_) s->io.process(now);
    deliver();
  }
  /// Runs `us` in steps of `step_us`.
  void run(uint32_t us, uint32_t step_us = 100) {
    while (us >= step_us) {
      step(step_us);
      us -= step_us;
    }
    if (us != 0) step(us);
  }
  /// Hands a hand-written frame to the master as if a node sent it.
  void inject(const CanFrame& f) { put_on_bus(f, nullptr, true); }

 private:
  static std::vector<CanFrame> take_log(FrameLog& log) {
    std::vector<CanFrame> f = log.frames;
    log.frames.clear();
    return f;
  }
  void put_on_bus(const CanFrame& f, Station* from, bool from_outside = false) {
    trace.emplace_back(now, to_string(f));
    if ((from != nullptr || from_outside) && master_rx) master_rx(f, now);
    for (auto& s : stations_) {
      if (s.get() != from && s->plugged) s->io.receive(f, now);
    }
  }

  FrameLog master_log_;
  std::vector<std::unique_ptr<Station>> stations_;
  size_t taken_ = 0;
};

}  // namespace test
}  // namespace mb2co
