// RTU frame reception from timestamped characters (serial line spec §2.5.1.1,
// Figure 14): a frame ends after t3.5 of silence; a silence longer than t1.5
// inside a frame makes it invalid (it is still collected to its end so that
// its tail is not taken for a new frame).
//
// Timestamps: `byte_us` is when the character had been received completely
// (its stop bit, or the moment a port read it: never earlier). The silence
// before a character is therefore byte_us - previous byte_us - char_us.
// All comparisons are wrap-safe on the 32-bit µs clock; stamps that go
// backwards count as no silence.
#pragma once
#include <stdint.h>

#include "modbus/protocol.h"
#include "modbus/rtu_timing.h"

namespace mb2co {
namespace modbus {

enum class FrameStatus : uint8_t {
  kOk,            ///< CRC right, at least 4 bytes
  kBadCrc,        ///< complete but CRC wrong
  kTooShort,      ///< fewer than 4 bytes
  kT15Violation,  ///< a silence > t1.5 (but < t3.5) between two characters
  kCharError,     ///< the port reported a parity/framing error in a character
  kOverrun,       ///< longer than the buffer (its capacity): bytes were lost
};

/// The state of an RtuFramer that starts at zero: one block, value-initialised
/// by its constructor (one zero-fill instead of a store per member).
struct RtuFramerState {
  enum class State : uint8_t { kIdle, kInitial, kReceiving };
  uint32_t last_us_;  ///< stamp of the last character (or begin())
  uint16_t length_;   ///< ≤ capacity_
  State state_;
  uint8_t flags_;
  bool ignore_t15_;  ///< !set_check_t15(): stored inverted so that it starts at zero
};

/// Collects a frame into a caller-owned buffer (reused for the response).
/// Not re-entrant: call from one context only (the main loop).
class RtuFramer : private RtuFramerState {
 public:
  /// `buffer` holds `capacity` bytes (kMinAduBytes..kMaxAduBytes; a larger
  /// value counts as kMaxAduBytes) and must outlive the framer.
  RtuFramer(const RtuTiming& timing, uint8_t* buffer, uint16_t capacity)
      : RtuFramerState(),
        timing_(timing),
        buf_(buffer),
        capacity_(capacity < kMaxAduBytes ? capacity : kMaxAduBytes) {}

  void set_timing(const RtuTiming& timing) { timing_ = timing; }
  const RtuTiming& timing() const { return timing_; }
  /// When false, a silence > t1.5 inside a frame is ignored (for ports whose
  /// timestamps jitter by more than t1.5, e.g. a busy main loop reading an
  /// interrupt-filled ring buffer).
  void set_check_t15(bool check) { ignore_t15_ = !check; }

  /// Power-up ("initial state"): no frame is accepted until t3.5 of silence
  /// has passed since `now_us`. Without begin() the framer starts idle.
  void begin(uint32_t now_us);

  /// True when a frame in progress ended at `now_us` (t3.5 since its last byte).
  bool frame_due(uint32_t now_us) const;
  /// True when a character stamped `byte_us` starts after the frame in
  /// progress ended: finish() that frame before push()ing the character.
  bool frame_due_before(uint32_t byte_us) const;

  /// Adds a received character (never call while frame_due_before(byte_us)).
  void push(uint8_t byte, uint32_t byte_us) { push_char(byte, byte_us, false); }
  /// A character that arrived with a parity/framing error: it belongs to the
  /// frame (or starts one) and makes it invalid.
  void push_error(uint32_t byte_us) { push_char(0, byte_us, true); }
  /// push(byte) or, when `error`, push_error(): the one definition (a single
  /// caller on the Uno, where it is inlined into the slave's).
  void push_char(uint8_t byte, uint32_t byte_us, bool error);

  /// Leaves the initial state after t3.5 of silence; call regularly.
  void tick(uint32_t now_us);

  /// Closes the frame in progress (call when frame_due*): returns its status
  /// and leaves the bytes in buffer()[0, length()) until the next push.
  FrameStatus finish();

  /// Deadline of the next state change (end of frame or of the initial
  /// wait); false when idle (nothing to wait for).
  bool deadline(uint32_t& at_us) const;

  uint8_t* buffer() { return buf_; }
  const uint8_t* buffer() const { return buf_; }
  uint16_t capacity() const { return capacity_; }
  uint16_t length() const { return length_; }
  bool receiving() const { return state_ == State::kReceiving; }

 private:
  enum : uint8_t { kFlagT15 = 0x01, kFlagCharError = 0x02, kFlagOverrun = 0x04 };

  uint32_t silence_before(uint32_t byte_us) const;
  /// True when t3.5 has passed from the last character (or begin()) to
  /// `now_us`. Out of line: frame_due() and tick() share it.
  __attribute__((noinline)) bool t35_passed(uint32_t now_us) const;

  RtuTiming timing_;
  uint8_t* buf_;
  uint16_t capacity_;  ///< ≤ kMaxAduBytes
};

}  // namespace modbus
}  // namespace mb2co
