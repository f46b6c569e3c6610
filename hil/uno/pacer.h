// Keeps simulated time in step with the wall clock (CLOCK_MONOTONIC µs).
//
// Invariant while paced: the simulation never runs more than kLeadUs ahead
// of the wall clock. When it falls behind by more than kBehindUs (simavr too
// slow, or the host paused us), the mapping is moved instead of catching up
// in a burst: a burst would squeeze the gaps the image sees between the
// bytes and frames that come in meanwhile (Modbus t3.5!).
#pragma once
#include <stdint.h>

#include <string>

namespace mb2co {
namespace uno {

class Pacer {
 public:
  /// How far the simulation may run ahead, which is also how long one pass
  /// of the loop lasts: a sleep and a wake-up per kLeadUs. 2 ms, not 1: a
  /// wake-up costs ~80 us of CPU under user-mode Linux (the vcan tests and
  /// hil/live run there, all boards on its one CPU), and three boards with
  /// 1000 of them a second plus simavr's own ~18 % each took that CPU over
  /// its limit (hold-ups, late Modbus answers). What it costs: a byte or
  /// frame from outside reaches the image up to kLeadUs late, one the image
  /// sends leaves up to kLeadUs early (on average the two cancel: the Modbus
  /// master's mean exchange time was the same with 1 and 2 ms).
  static constexpr uint64_t kLeadUs = 2000;
  /// Behind by up to this much, the simulation catches up (passes back to
  /// back, no sleep); further behind, it goes on from where it stands. Not
  /// more: a board the host starves would then lag that far for good, and
  /// every frame it sends reach its peers that late (100 ms was tried: SYNC
  /// round trips of 68-302 ms in docs/labs.md's session at load 13).
  static constexpr uint64_t kBehindUs = 20000;
  /// What came in during a hold-up reaches the simulation within this much
  /// of its time after the move (sim_of()).
  static constexpr uint64_t kReplayUs = 10000;
  /// Speed is judged over windows of this much wall time.
  static constexpr uint64_t kWindowUs = 1000000;

  /// `paced` false: allowed_sim_us() never holds the simulation back.
  Pacer(bool paced, uint64_t wall_us, uint64_t sim_us);

  /// Simulated time the simulation may run to at wall time `wall_us`,
  /// given it stands at `sim_us` (moves the mapping when far behind).
  uint64_t allowed_sim_us(uint64_t sim_us, uint64_t wall_us);
  /// Wall µs to wait before allowed_sim_us() lets the simulation past `sim_us`.
  uint64_t wait_us(uint64_t sim_us, uint64_t wall_us) const;
  /// The wall time (CLOCK_MONOTONIC µs) that simulated time `sim_us` stands for.
  uint64_t wall_of(uint64_t sim_us) const { return offset_us_ + sim_us; }
  /// The simulated time at which something that happened at wall time
  /// `wall_us` reaches the simulation (a CAN frame's kernel timestamp). A
  /// time before the last move of the mapping keeps the mapping it happened
  /// under, squeezed: what came in while the simulation was held up arrives
  /// after where the simulation stood, spread over at most kReplayUs in the
  /// order and proportion it came, not all at once (that would overrun the
  /// chip's two receive buffers) and not over the whole hold-up (what comes
  /// next would queue behind it and reach the chip back to back).
  uint64_t sim_of(uint64_t wall_us) const;

  /// Times the mapping moved (the simulation was held up more than
  /// kBehindUs) and the simulated time it did not catch up in all.
  uint64_t jumps() const { return jumps_; }
  uint64_t dropped_us() const { return dropped_us_; }

  /// Once, the first time a whole window ran slower than 95 % of real time
  /// while the simulation was behind: a one-line report; otherwise "".
  std::string slow_report(uint64_t sim_us, uint64_t wall_us);

 private:
  bool paced_;
  uint64_t offset_us_;             ///< wall_us - sim_us of the mapping
  uint64_t moved_at_wall_us_ = 0;  ///< when the mapping last moved (0: never)
  uint64_t offset_before_us_ = 0;  ///< the mapping before that move
  uint64_t held_at_sim_us_ = 0;    ///< where the simulation stood at that move
  uint64_t held_for_us_ = 0;       ///< and how far behind it was: the hold-up
  uint64_t window_wall_us_;        ///< start of the current speed window
  uint64_t window_sim_us_;
  bool behind_in_window_ = false;
  bool reported_ = false;
  uint64_t jumps_ = 0;
  uint64_t dropped_us_ = 0;
};

}  // namespace uno
}  // namespace mb2co
