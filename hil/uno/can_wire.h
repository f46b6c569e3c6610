// The CAN side of the simulated Uno: the MCP2515 model on the SPI bus and a
// wire that carries one frame at a time, each for its exact length in bits
// (timing/can_bits.h, stuff bits included) at the bit rate the image wrote
// into CNF1..CNF3 (16 MHz crystal of the SparkFun shield).
//
// A frame the chip sends leaves its TX buffer (TXREQ clears, TXnIF sets) and
// is handed out at the end of its last bit; a frame from the outside is
// received into RXB0/RXB1 at the end of its last bit. When both wait for the
// idle wire, the lower identifier wins (arbitration), and so among frames
// from outside that wait for it. Not modelled: ACK and
// error frames (every frame is acknowledged), bit errors, overload frames.
//
// Time is the simulated CPU cycle count (16 MHz). The owner calls advance()
// at next_event() and after anything that may start a frame (end of an SPI
// instruction, a frame from outside).
//
// A frame from outside may carry the cycle it reached the bus: it waits for
// that moment, so frames that came some time apart stay apart even when the
// owner hands them over together (mb2co-uno reads a socket's backlog after
// the host held the simulation up: squeezed back to back, those frames would
// overrun the chip's two receive buffers, which no real bus would do).
#pragma once
#include <stdint.h>

#include <deque>
#include <vector>

#include "canopen/can_frame.h"
#include "mcp2515_model.h"

namespace mb2co {
namespace uno {

class CanWire {
 public:
  static constexpr uint64_t kIdle = UINT64_MAX;

  /// `cpu_hz`: cycles per second of the clock the times below count.
  explicit CanWire(uint32_t cpu_hz);

  mcp2515::model::Mcp2515Model& chip() { return chip_; }
  /// INT pin of the chip (active low).
  bool int_low() const { return chip_.int_low(); }

  /// A frame from another node that reached the bus at cycle `arrival` (at
  /// the earliest `now`; never before the frame handed over before it): it
  /// waits for that cycle and then for the idle wire.
  void frame_from_bus(const CanFrame& frame, uint64_t now, uint64_t arrival = 0);
  /// Completes the frame on the wire if it ends by `now` and starts the next
  /// waiting one.
  void advance(uint64_t now);
  /// Cycle at which the frame on the wire ends or, with the wire idle, the
  /// next frame from outside arrives; kIdle when nothing is to happen.
  uint64_t next_event() const;

  /// A frame the chip put on the bus and when its last bit went.
  struct Sent {
    uint64_t end_cycle;
    CanFrame frame;
  };
  /// Frames sent since the last call, oldest first.
  std::vector<Sent> take_sent();
  /// Frames from outside that the chip's filters or full buffers dropped.
  uint64_t rx_dropped() const { return rx_dropped_; }
  /// Of those, the frames lost because the buffers they could go to were
  /// full (the chip set RX0OVR/RX1OVR): what the image reports as EMCY 8110h.
  uint64_t rx_overflowed() const { return rx_overflowed_; }
  /// Frames from outside the wire has carried (put on it; the chip receives
  /// or drops each at its last bit), and the cycles the wire has been or is
  /// busy with any frame: the bus load the image sees is their growth over
  /// its time.
  uint64_t carried_in() const { return carried_in_; }
  uint64_t busy_cycles() const { return busy_cycles_; }

 private:
  uint64_t frame_cycles(const CanFrame& frame) const;

  mcp2515::model::Mcp2515Model chip_;
  uint32_t cpu_hz_;
  struct Inbound {
    CanFrame frame;
    uint64_t arrival;  ///< cycle it reached the bus; not decreasing along inbound_
  };
  std::deque<Inbound> inbound_;  ///< from outside, waiting for their arrival and the wire
  std::vector<Sent> sent_;
  uint64_t busy_until_ = kIdle;    ///< end of the frame on the wire
  bool on_wire_outbound_ = false;  ///< the frame on the wire is the chip's
  CanFrame on_wire_{};
  uint64_t rx_dropped_ = 0;
  uint64_t rx_overflowed_ = 0;
  uint64_t carried_in_ = 0;
  uint64_t busy_cycles_ = 0;
};

/// True when `a` wins arbitration against `b` (lower identifier; with equal
/// base identifiers a standard frame beats an extended one, data beats remote).
bool wins_arbitration(const CanFrame& a, const CanFrame& b);

}  // namespace uno
}  // namespace mb2co
