// CAN bus model, bit-timed in virtual time (ISO 11898-1 as far as timing
// goes): one frame at a time, never pre-empted; when the bus becomes free
// (end of the 3-bit interframe space) every controller with a pending frame
// starts together and the lowest arbitration key wins; a frame queued while
// the bus is idle starts at once, and any frame queued during that first bit
// (SOF) still joins the arbitration. Each frame lasts its exact stuffed
// length (timing::frame_bits_exact: CRC computed, stuff bits counted); it is
// delivered to every other powered controller at the end of EOF, and the bus
// is free 3 bits later.
//
// Controllers model the MCP2515: 3 transmit buffers sent lowest identifier
// first (FIFO among equal identifiers, as the mcp2515 driver ranks them),
// 2 receive buffers (a frame arriving when both hold unread frames is lost
// and counted), transmit/receive error counters with error-active, passive
// and bus-off states, and automatic bus-off recovery after 128 x 11
// recessive bits (taken as 1408 bit times).
//
// Injected faults: random corruption of frames (an error frame of 23 bits:
// flag 6 + echo 6 + delimiter 8 + IFS 3; the frame is retransmitted), a
// controller whose transmissions all fail (it errs into bus-off, recovers,
// errs again while the fault lasts), power off/on (buffers and counters
// cleared).
#pragma once
#include <stdint.h>

#include <functional>
#include <vector>

#include "canopen/can_frame.h"
#include "filter_plan.h"
#include "sim/event_queue.h"
#include "sim/frame_bits_memo.h"
#include "sim/rng.h"

namespace mb2co {
namespace sim {

enum class CanErrorState : uint8_t { kActive, kPassive, kBusOff };

/// What happened to one transmission attempt, for observers.
struct CanAttempt {
  SimNs sof_ns;   ///< start of frame
  SimNs end_ns;   ///< end of EOF (delivery), or the bit where the error was seen
  SimNs free_ns;  ///< bus free again (after IFS or the error frame)
  int sender;     ///< controller index
  CanFrame frame;
  uint16_t bits;  ///< exact length SOF..IFS, stuff bits included
  uint16_t stuff_bits;
  bool error;     ///< destroyed: error frame, the frame stays queued
  int receivers;  ///< controllers that took the frame (0 on error)
};

struct CanControllerCounters {
  uint64_t tx_ok = 0;
  uint64_t tx_errors = 0;   ///< attempts destroyed by an error frame
  uint64_t tx_refused = 0;  ///< send() with all 3 buffers busy (or off)
  uint64_t rx_ok = 0;
  uint64_t rx_overflows = 0;  ///< frames lost: both receive buffers full
  uint64_t rx_filtered = 0;   ///< frames the acceptance filters rejected
  uint64_t bus_offs = 0;
};

class CanBus;

class CanController {
 public:
  static constexpr int kTxBuffers = 3;

  /// Registers itself with `bus`; both must outlive the run.
  CanController(CanBus& bus, size_t rx_buffers = 2);
  CanController(const CanController&) = delete;
  CanController& operator=(const CanController&) = delete;

  int index() const { return index_; }
  /// Transmit buffers not holding a pending frame (0 when off or bus-off
  /// does not matter: frames wait in their buffers through bus-off).
  int free_tx() const;
  /// Queues `f` in a free transmit buffer; false (counted) when none is free
  /// or the controller is unpowered.
  bool send(const CanFrame& f);
  /// Oldest received frame; false when none.
  bool receive(CanFrame& f);
  size_t rx_waiting() const { return rx_count_; }

  /// Power: off clears buffers and error counters and leaves the bus.
  void set_powered(bool on);
  bool powered() const { return powered_; }
  /// Acceptance masks and filters (standard ids only; extended frames are
  /// then rejected); null: every frame is received.
  void set_acceptance(const mcp2515::FilterPlan* plan);
  /// Whether the acceptance filters let a standard frame with `id` in.
  bool accepts(uint16_t id) const { return !filtered_ || mcp2515::plan_accepts(plan_, id); }
  /// Fault: while set, every frame this controller sends is destroyed.
  void set_tx_broken(bool broken) { tx_broken_ = broken; }

  CanErrorState state() const { return state_; }
  uint16_t tec() const { return tec_; }
  uint16_t rec() const { return rec_; }
  const CanControllerCounters& counters() const { return counters_; }

  /// Called when a frame was taken into a receive buffer (may be empty).
  std::function<void()> on_rx;
  /// Called when an accepted frame was lost: both receive buffers full.
  std::function<void(const CanFrame&)> on_overflow;

 private:
  friend class CanBus;
  struct TxBuf {
    CanFrame frame;
    uint32_t key;
    uint64_t seq;
    bool used;
  };
  /// Index of the buffer that goes next, or -1.
  int next_tx() const;
  bool on_bus() const { return powered_ && state_ != CanErrorState::kBusOff; }
  void count_tx_error();
  void count_rx_error();
  void deliver(const CanFrame& f);
  void update_state();

  CanBus& bus_;
  int index_;
  TxBuf tx_[kTxBuffers] = {};
  uint64_t tx_seq_ = 0;
  std::vector<CanFrame> rx_;
  size_t rx_head_ = 0;
  size_t rx_count_ = 0;
  uint16_t tec_ = 0;
  uint16_t rec_ = 0;
  CanErrorState state_ = CanErrorState::kActive;
  bool powered_ = true;
  bool tx_broken_ = false;
  bool filtered_ = false;
  mcp2515::FilterPlan plan_ = {};
  uint32_t generation_ = 0;  ///< invalidates a scheduled recovery after power-off
  CanControllerCounters counters_;
};

class CanBus final : public Handler {
 public:
  /// `bitrate_bps` must divide 10^9 (every CiA 301 rate does).
  CanBus(EventQueue& queue, uint32_t bitrate_bps, uint64_t seed);

  uint32_t bitrate_bps() const { return bitrate_bps_; }
  SimNs bit_ns() const { return bit_ns_; }
  /// Random corruption of any frame with probability ppm / 10^6.
  void set_corruption_ppm(uint32_t ppm) { corruption_ppm_ = ppm; }
  /// Every attempt (delivered or destroyed), at its end.
  std::function<void(const CanAttempt&)> observer;
  /// Bus-off entered (true) or left (false) by a controller.
  std::function<void(int controller, bool bus_off)> on_bus_off;

  uint64_t frames_ok() const { return frames_ok_; }
  uint64_t error_frames() const { return error_frames_; }
  /// Of error_frames(): frames nobody acknowledged because no other
  /// controller was powered and on the bus (a line powering up, one Arduino
  /// before the next): the sender's retries, not a fault of the wire.
  uint64_t ack_error_frames() const { return ack_error_frames_; }
  SimNs busy_ns() const { return busy_ns_; }
  const std::vector<CanController*>& controllers() const { return controllers_; }

  void on_event(uint32_t code, uint64_t arg) override;

 private:
  friend class CanController;
  enum Code : uint32_t { kArbitrate, kEnd, kFree, kRecover };
  enum class State : uint8_t { kIdle, kArbitrating, kBusy };

  int attach(CanController* c);
  /// A controller has a frame pending (again).
  void request();
  void arbitrate();
  void finish();
  void schedule_recovery(CanController& c);

  EventQueue& q_;
  uint32_t bitrate_bps_;
  SimNs bit_ns_;
  Rng rng_;
  FrameBitsMemo frame_bits_;  ///< each frame's exact length (arbitrate)
  uint32_t corruption_ppm_ = 0;
  std::vector<CanController*> controllers_;
  State state_ = State::kIdle;
  CanAttempt current_ = {};
  int current_buf_ = -1;
  uint32_t current_gen_ = 0;
  bool ack_error_ = false;
  uint64_t frames_ok_ = 0;
  uint64_t error_frames_ = 0;
  uint64_t ack_error_frames_ = 0;
  SimNs busy_ns_ = 0;
};

}  // namespace sim
}  // namespace mb2co
