// Driver for the Microchip MCP2515 stand-alone CAN controller (SparkFun
// CAN-BUS shield on the Arduino Uno). Portable C++14: the chip is reached
// through a two-function SPI interface, so the same code runs on the AVR
// (Arduino SPI, firmware/avr/port) and on the host against a register-level
// model (tests/mcp2515).
//
// Contract:
// * Single-threaded: every call comes from the main loop. No call may run in
//   an ISR (the SPI bus is not locked). The INT pin is polled: call service()
//   when INT is low, and also every few milliseconds so bus-off recovery
//   (which raises no interrupt) is noticed.
// * No heap; the caller owns the driver and the SPI context.
// * Frames to send: 3 hardware buffers. The chip sends pending frames in the
//   order bus arbitration would (lowest identifier first, standard before
//   extended with the same base id, frames with equal ids first-in first-out):
//   the driver re-ranks the transmit priorities on every send.
// * Frames received: RXB0 (rolls over into RXB1 when full) and RXB1; the
//   driver drains both back to back into a 2-frame stage so frames come out in
//   arrival order.
// * Failures are counted (Counters, never decremented, wrap at 2^16) and
//   reported as events; nothing blocks and nothing allocates.
#pragma once
#include <stdint.h>

#include "bit_timing.h"
#include "canopen/can_frame.h"
#include "filter_plan.h"

namespace mb2co {
namespace mcp2515 {

/// The SPI link to the chip. Mode 0, MSB first, at most 10 MHz.
struct Spi {
  uint8_t (*transfer)(void* ctx, uint8_t out);  ///< full duplex: returns the byte clocked in
  void (*select)(void* ctx, bool active);       ///< active: CS low (start of an instruction)
  void* ctx;
};

enum class Mode : uint8_t { kNormal, kLoopback, kListenOnly };

/// CAN fault confinement state of the controller (CiA 301 EMCY 8120h/8140h).
enum class ErrorState : uint8_t {
  kActive,   ///< both counters below 96
  kWarning,  ///< TEC or REC >= 96 (EFLG.EWARN)
  kPassive,  ///< TEC or REC >= 128: the node may no longer send active error flags
  kBusOff,   ///< TEC > 255: off the bus until 128 x 11 recessive bits were seen
};

/// Bits returned by service().
enum : uint8_t {
  kEventRxOverflow = 0x01,       ///< frames were lost: both buffers were full (EMCY 8110h)
  kEventStateChanged = 0x02,     ///< error_state() differs from the previous service()
  kEventBusOff = 0x04,           ///< entered bus-off
  kEventBusOffRecovered = 0x08,  ///< back on the bus after bus-off (EMCY 8140h)
};

struct Counters {
  uint16_t rx_frames;     ///< frames handed out by receive()
  uint16_t tx_frames;     ///< frames accepted by send() (queued in a hardware buffer)
  uint16_t tx_full;       ///< send() refused: all 3 buffers busy
  uint16_t tx_invalid;    ///< send() refused: dlc > 8 or id out of range
  uint16_t rx_overflows;  ///< overflow flags seen (each: at least one frame lost)
  uint16_t bus_offs;      ///< times bus-off was entered
};

class Driver {
 public:
  /// `spi` is copied; its ctx must outlive the driver. constexpr: a global
  /// driver built from a constant Spi is initialised data, not code.
  constexpr explicit Driver(const Spi& spi)
      : spi_(spi),
        mode_(0),  // normal mode (REQOP 000)
        state_(ErrorState::kActive),
        seq_(0),
        tx_key_{0, 0, 0},
        tx_seq_{0, 0, 0},
        tx_prio_{kNoPriority, kNoPriority, kNoPriority},
        stage_{},
        stage_next_(0),
        stage_count_(0),
        counters_{} {}
  static constexpr uint8_t kNoPriority = 0xFF;  ///< tx_prio_: TXP not known

  /// Resets the chip, sets the bit rate, accepts every frame (see
  /// set_filters), enables RX/error interrupts on INT and enters `mode`.
  /// False when the chip does not answer (no shield, wrong CS pin).
  bool begin(Bitrate rate, Mode mode);

  /// Switches the operating mode directly. False when the chip did not
  /// confirm in time (it finishes a frame in progress first).
  bool set_mode(Mode mode);

  /// Programs acceptance masks and filters for the standard ids `ids` (see
  /// filter_plan.h). Briefly enters configuration mode (frames on the bus
  /// meanwhile are missed) and returns to the previous mode. False on a bad
  /// list or when the chip does not confirm the mode changes. `plan_out`, if
  /// given, tells whether the filters are exact.
  bool set_filters(const uint16_t* ids, uint8_t count, FilterPlan* plan_out = nullptr);

  /// Programs `plan` as set_filters does, for a plan computed beforehand
  /// (FilterPlanner: planning in steps keeps the main loop going).
  bool set_filters(const FilterPlan& plan) { return configure_filters(&plan); }

  /// Turns filters off: every valid frame, standard and extended, is received.
  bool accept_all();

  /// Queues `frame` in a free transmit buffer. False (and counted) when the
  /// frame is invalid or all three buffers are busy; never blocks.
  bool send(const CanFrame& frame);

  /// Takes the oldest received frame. False when none is waiting.
  bool receive(CanFrame& frame);

  /// Handles the chip's flags: fetches received frames into the stage,
  /// clears and counts RX overflows, follows the error state. Returns kEvent*
  /// bits for what happened since the previous call.
  uint8_t service();

  ErrorState error_state() const { return state_; }
  const Counters& counters() const { return counters_; }
  /// Transmit / receive error counters read from the chip.
  uint8_t tec();
  uint8_t rec();

  /// A CanSink (shared/canopen/can_frame.h) that sends through this driver.
  CanSink sink() { return CanSink{&Driver::sink_send, this}; }

 private:
  static bool sink_send(void* ctx, const CanFrame& frame);

  void xfer(uint8_t* bytes, uint8_t count);      ///< in place, CS already low
  void transact(uint8_t* bytes, uint8_t count);  ///< one instruction: CS low, xfer, CS high
  uint8_t read(uint8_t address);
  void write(uint8_t address, const uint8_t* values, uint8_t count);  ///< count <= 12
  void write1(uint8_t address, uint8_t value) { write(address, &value, 1); }
  void bit_modify(uint8_t address, uint8_t mask, uint8_t value);
  void command(uint8_t instruction);          ///< one-byte RESET / RTS
  uint8_t command_read(uint8_t instruction);  ///< READ STATUS / RX STATUS
  bool request_mode(uint8_t opmode);
  bool configure_filters(const FilterPlan* plan);
  void fetch_received();
  void read_rx_buffer(uint8_t start, CanFrame& frame);
  void rank_transmit_buffers(uint8_t queued);

  Spi spi_;
  uint8_t mode_;  ///< REQOP bits of the mode to return to after configuration
  ErrorState state_;
  uint8_t seq_;          ///< send sequence number: FIFO order among equal ids
  uint32_t tx_key_[3];   ///< arbitration key of the frame in each TX buffer (lower first)
  uint8_t tx_seq_[3];    ///< seq_ when that frame was queued
  uint8_t tx_prio_[3];   ///< TXP last written to a pending buffer, 0xFF: unknown
  CanFrame stage_[2];    ///< received frames already read from the chip, oldest first
  uint8_t stage_next_;   ///< next frame receive() hands out
  uint8_t stage_count_;  ///< valid frames in stage_ (0 when all were handed out)
  Counters counters_;
};

/// Position of `frame` in bus arbitration: lower keys win. Standard frames
/// compare as SID, RTR, IDE=0; extended as SID, SRR=1, IDE=1, EID. The
/// extended RTR bit is left out: an extended data and remote frame with the
/// same id have equal keys (the driver then sends them first-in first-out).
uint32_t arbitration_key(const CanFrame& frame);

}  // namespace mcp2515
}  // namespace mb2co
