// One station's PC in virtual time: a Modbus/RTU master on the serial link
// (the shared codec, as libmodbus would behave: flush before a request,
// response end found by predicting its length, a response timeout) and a
// control program run once per cycle. Cycle k starts at phase + k·cycle plus
// a jitter drawn from [0, jitter_ns]; a cycle still busy at the next start
// delays it (back to back). A request may be split by a gap (a USB stack
// that breaks a frame), with probability split_ppm per request.
#pragma once
#include <stdint.h>

#include <functional>
#include <memory>
#include <vector>

#include "modbus/master_codec.h"
#include "sim/event_queue.h"
#include "sim/rng.h"
#include "sim/serial_link.h"

namespace mb2co {
namespace sim {

struct PcTiming {
  SimNs cycle_ns = 20 * kNsPerMs;
  SimNs jitter_ns = 1 * kNsPerMs;    ///< cycle start late by [0, jitter]
  SimNs compute_ns = 0;              ///< from a response to the next request
  SimNs timeout_ns = 50 * kNsPerMs;  ///< response timeout after the request
  uint32_t split_ppm = 0;            ///< requests split by a gap, per million
  SimNs split_gap_min_ns = 1 * kNsPerMs;
  SimNs split_gap_max_ns = 3 * kNsPerMs;
};

/// The control process on the PC. A cycle is a chain of transactions: the
/// program gives the first request, then after each answer the next one
/// (or none: the cycle ends).
class PcProgram {
 public:
  virtual ~PcProgram() = default;
  /// Returns the request's length (0: nothing to do this cycle).
  virtual uint16_t first_request(uint8_t* out, uint16_t capacity) = 0;
  /// `r` is null when the transaction failed (timeout, bad CRC, exception
  /// parse error). Returns the next request's length, 0 to end the cycle.
  virtual uint16_t on_response(const modbus::Response* r, uint8_t* out, uint16_t capacity) = 0;
};

struct PcCounters {
  uint64_t cycles = 0;
  uint64_t overruns = 0;  ///< a cycle started late because the last was busy
  uint64_t transactions = 0;
  uint64_t failures = 0;  ///< timeouts and bad responses
  uint64_t splits = 0;    ///< requests sent with a gap inside
};

class PcStation final : public Handler {
 public:
  PcStation(EventQueue& queue, int index, UartChannel& to_node, const PcTiming& timing, uint64_t seed);

  int index() const { return index_; }
  void set_program(std::unique_ptr<PcProgram> program) { program_ = std::move(program); }
  PcProgram* program() { return program_.get(); }
  /// Starts cycling at now() + a random phase within one cycle.
  void start();
  /// Stops cycling (the program stays; a transaction in flight is dropped).
  void stop();
  void set_timing(const PcTiming& timing) { timing_ = timing; }

  /// Where the node's characters come from (the link's node-to-PC channel).
  void attach_serial(UartChannel* rx);

  /// Every finished transaction: request, response (empty on failure).
  std::function<void(int station, const uint8_t* req, uint16_t req_len, bool ok, modbus::ParseStatus status)>
      on_transaction;

  const PcCounters& counters() const { return counters_; }

  void on_event(uint32_t code, uint64_t arg) override;

 private:
  enum Code : uint32_t { kCycle, kTimeout, kSend };
  void begin_cycle();
  void send_request();
  void complete(bool timed_out);
  void on_byte(uint8_t byte);
  /// Expected length of the response so far received (0: not yet known).
  uint16_t expected_length() const;

  EventQueue& q_;
  int index_;
  UartChannel& tx_;
  UartChannel* rx_ = nullptr;
  PcTiming timing_;
  Rng rng_;
  std::unique_ptr<PcProgram> program_;
  bool running_ = false;
  bool busy_ = false;
  bool start_when_free_ = false;
  SimNs nominal_ns_ = 0;  ///< nominal start of the next cycle
  uint32_t generation_ = 0;
  uint32_t txn_ = 0;  ///< transaction number (stale timeouts)
  bool awaiting_ = false;
  uint8_t req_[256];
  uint16_t req_len_ = 0;
  std::vector<uint8_t> rsp_;
  PcCounters counters_;
};

}  // namespace sim
}  // namespace mb2co
