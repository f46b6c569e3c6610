#include "sim/worst_presses.h"

#include <algorithm>
#include <functional>
#include <vector>

#include "canopen/nmt_slave.h"
#include "gateway/line_app.h"

namespace mb2co {
namespace sim {
namespace {

constexpr SimNs kMs = kNsPerMs;
constexpr SimNs kS = kNsPerS;
constexpr SimNs kSlice = 2 * kMs;  ///< how often the operator looks at the LED

// The grid: kCoarse phases over one PC cycle pressed kCoarseRepeats times
// each, then kFine + 1 phases spanning two coarse steps either side of the
// worst coarse phase, pressed kFineRepeats times each.
constexpr uint32_t kCoarse = 64;
constexpr uint32_t kCoarseRepeats = 2;
constexpr uint32_t kFine = 32;
constexpr uint32_t kFineRepeats = 12;
// Then the neighbours' power-on phase: kPhasings offsets, spread over the
// worst latency found, at which their periodic frames (heartbeat, TPDO1
// event timer: both run from their power-on) reach the lab's Arduinos,
// each pressed kPhasingRepeats times at the worst phase.
constexpr uint32_t kPhasings = 96;
constexpr uint32_t kPhasingRepeats = 6;
// The neighbours' power-on phase against the end of the path (Modbus only):
// kEndPhasings offsets over kEndSpan pressed kEndRepeats times each, then
// kEndFine + 1 offsets over kEndFineSpan around the worst and around the
// worst at least kEndApart from it, kEndFineRepeats times each.
constexpr uint32_t kEndPhasings = 70;
constexpr uint32_t kEndRepeats = 3;
constexpr SimNs kEndSpan = 7 * kMs;
constexpr uint32_t kEndFine = 16;
constexpr uint32_t kEndFineRepeats = 24;
constexpr SimNs kEndApart = 2 * kMs;
constexpr SimNs kEndFineSpan = 400 * kNsPerUs;
constexpr SimNs kPowerOff = 50 * kMs;  ///< off that long (capacitors drained)
// Then every station's frames at once (with the interference): the PC's
// Arduino's communication reset (NMT) so that its heartbeat and TPDO1
// timer come kPressOffsets offsets up to kPressSpan before the press, the
// neighbours' power-on so that theirs come kLedOffsets offsets up to
// kLedSpan before the LED's PDO, the other stations' STOP2 kStop2Leads
// leads up to kStop2Span before the press; each point pressed once.
constexpr uint32_t kPressOffsets = 6;
constexpr SimNs kPressSpan = 3 * kMs;
constexpr uint32_t kLedOffsets = 6;
constexpr SimNs kLedSpan = 3 * kMs;
constexpr uint32_t kStop2Leads = 3;
constexpr SimNs kStop2Span = 600 * kNsPerUs;
constexpr uint32_t kPollOffsets = 28;
constexpr uint32_t kPollPressOffsets = 3;

class Operator {
 public:
  Operator(Line& line, int button_station, int led_station, uint32_t button_pdo_id, uint32_t led_pdo_id,
           bool interference)
      : line_(line),
        button_(button_station),
        led_station_(led_station),
        led_pdo_id_(led_pdo_id),
        interference_(interference) {
    line_.on_can = [this](const CanAttempt& a) {
      if (!a.error && a.frame.id == led_pdo_id_ && a.frame.dlc > 0 && (a.frame.data[0] & 1u) &&
          led_pdo_sof_ == 0)
        led_pdo_sof_ = a.sof_ns;
      if (!a.error && a.frame.id == watched_id_ && a.frame.dlc > 0 && a.frame.data[0] != 0 &&
          watched_sof_ == 0)
        watched_sof_ = a.sof_ns;
    };
    // A press whose button or LED PDO a full receive buffer dropped is
    // outside the bound's assumption (no frame lost): counted lost, not
    // measured, even when a later PDO still carries it.
    for (int s = 0; s < line_.size(); ++s) {
      std::function<void(const CanFrame&)>& hook = line_.node(s).can().on_overflow;
      saved_.push_back(hook);
      hook = [this, button_pdo_id, led_pdo_id, chained = hook](const CanFrame& f) {
        if (chained) chained(f);
        if (f.id == button_pdo_id || f.id == led_pdo_id) lab_pdo_lost_ = true;
      };
    }
  }
  ~Operator() {
    line_.on_leds = nullptr;
    line_.on_can = nullptr;
    for (int s = 0; s < line_.size(); ++s) line_.node(s).can().on_overflow = saved_[static_cast<size_t>(s)];
  }

  /// Presses at `at` (≥ now), releases once the LED is on, waits for it to
  /// go off. False: the LED did not come within 1 s (a lost press). With
  /// interference, STOP2 is pressed on every station with the lab button
  /// (a STOP2 event: each station's TPDO1 and button TPDO2 leave with the
  /// button's PDO) and STOP on every station `down_at` after the press (0:
  /// not; their TPDO2s leave with the LED's PDO when down_at is the LED
  /// PDO's time less a debounce).
  bool press(SimNs at, SimNs down_at, SimNs* latency, SimNs* led_pdo_after) {
    if (interference_ && stop2_lead_ != 0) {
      line_.run_until(at - stop2_lead_);
      for (int s = 0; s < line_.size(); ++s) {
        if (s != button_) line_.set_button(s, gateway::kStop2, true);
      }
    }
    line_.run_until(at);
    // Still on from the last press (its LED-off PDO lost in a receive
    // overflow): this press measures nothing.
    const bool stale = lab_;
    led_pdo_sof_ = 0;
    lab_pdo_lost_ = false;
    line_.set_button(button_, gateway::kStart, true);
    if (interference_) {
      for (int s = 0; s < line_.size(); ++s) {
        if (s == button_ ? lab_stop2_ : stop2_lead_ == 0) line_.set_button(s, gateway::kStop2, true);
      }
      if (down_at != 0) {
        line_.at(at + down_at, [this] {
          for (int s = 0; s < line_.size(); ++s) line_.set_button(s, gateway::kStop, true);
        });
      }
    }
    const SimNs on = wait_for(true, at + kS);
    const bool dropped = lab_pdo_lost_;  // before the LED came on
    // Held long enough to count (the debounce), released together.
    line_.run_until(std::max(line_.now(), at + down_at + 25 * kMs));
    for (int s = 0; s < line_.size(); ++s) {
      if (s == button_) line_.set_button(s, gateway::kStart, false);
      if (interference_) line_.set_button(s, gateway::kStop2, false);
      if (interference_) line_.set_button(s, gateway::kStop, false);
    }
    wait_for(false, line_.now() + kS);
    if (on == 0 || dropped || stale) return false;
    *latency = on - at;
    *led_pdo_after = led_pdo_sof_ > at ? led_pdo_sof_ - at : 0;
    return true;
  }

  /// Switches `stations` off and on again at `on_at` (> now + kPowerOff):
  /// their heartbeat and event timers then run from that power-on.
  void repower(const std::vector<int>& stations, SimNs on_at) {
    line_.run_until(on_at - kPowerOff);
    for (int s : stations) line_.power(s, false);
    line_.run_until(on_at);
    for (int s : stations) line_.power(s, true);
  }

  /// With the interference, the other stations' STOP2 is pressed `lead`
  /// before the lab button (0: with it), so that their frames reach the
  /// lab's Arduino before the pass that counts its press.
  void set_stop2_lead(SimNs lead) { stop2_lead_ = lead; }
  /// With the interference, whether the lab button's station presses STOP2
  /// too (its TPDO1 then leaves with the button's PDO).
  void set_lab_stop2(bool pressed) { lab_stop2_ = pressed; }

  /// Start of the first frame with `id` (not a boot-up: first byte ≠ 0)
  /// from now until `deadline` (0: none).
  SimNs first_frame(uint32_t id, SimNs deadline) {
    watched_id_ = id;
    watched_sof_ = 0;
    while (watched_sof_ == 0 && line_.now() < deadline) line_.run_for(kSlice);
    watched_id_ = 0;
    return watched_sof_;
  }

 private:
  /// Runs until the lab LED is `level` (its time) or `deadline` (0).
  SimNs wait_for(bool level, SimNs deadline) {
    changed_at_ = 0;
    want_ = level;
    line_.on_leds = [this](int s, uint8_t leds) {
      if (s != led_station_) return;
      lab_ = (leds & gateway::kLedLab) != 0;
      if (lab_ == want_ && changed_at_ == 0) changed_at_ = line_.now();
    };
    while (lab_ != level && line_.now() < deadline) line_.run_for(kSlice);
    return lab_ == level ? (changed_at_ != 0 ? changed_at_ : line_.now()) : 0;
  }

  Line& line_;
  int button_;
  int led_station_;
  uint32_t led_pdo_id_;
  bool interference_;
  bool lab_ = false;
  bool want_ = false;
  SimNs changed_at_ = 0;
  SimNs led_pdo_sof_ = 0;
  bool lab_pdo_lost_ = false;
  uint32_t watched_id_ = 0;
  SimNs watched_sof_ = 0;
  SimNs stop2_lead_ = 0;
  bool lab_stop2_ = true;
  std::vector<std::function<void(const CanFrame&)>> saved_;
};

}  // namespace

PressRun search_worst_presses(Line& line, int button_station, int led_station, bool interference,
                              const Progress& progress) {
  PressRun r;
  const LineConfig& c = line.config();
  Operator op(line, button_station, led_station, 0x280u + static_cast<uint32_t>(c.lab_remote + 1),
              0x380u + static_cast<uint32_t>(c.lab_pc + 1), interference);
  const SimNs cycle = c.pc.cycle_ns;
  const SimNs debounce = SimNs{c.debounce_ms} * kMs;
  const SimNs origin = 2 * kS;
  std::vector<int> neighbours;  // the stations the search switches off and on
  for (int s = 0; s < line.size(); ++s) {
    if (s != button_station && s != led_station && s != c.lab_pc) neighbours.push_back(s);
  }
  const uint32_t total = kCoarse * kCoarseRepeats + (kFine + 1) * kFineRepeats +
                         (neighbours.empty() ? 0 : kPhasings * kPhasingRepeats) +
                         (neighbours.empty() || interference
                              ? 0
                              : kEndPhasings * kEndRepeats + 2 * (kEndFine + 1) * kEndFineRepeats) +
                         (neighbours.empty() || !interference
                              ? 0
                              : kStop2Leads * kPressOffsets * kLedOffsets + kPollOffsets * kPollPressOffsets);
  uint32_t presses = 0;
  // The next time ≥ 150 ms from now whose offset in the PC's cycle (counted
  // from `origin`) is `phase`: the line has settled after the last press.
  auto next_at = [&](SimNs phase, SimNs lead = 150 * kMs) {
    const SimNs earliest = line.now() + lead;
    const SimNs base = earliest - (earliest - origin) % cycle;
    const SimNs t = base + phase;
    return t >= earliest ? t : t + cycle;
  };
  // One press at `phase`; `led_pdo` is when the LED's PDO left after the
  // last press at this phase (0: unknown), the STOPs of the interference
  // are timed from it, `lead` earlier than a debounce before it.
  auto measure = [&](SimNs phase, SimNs* led_pdo, SimNs lead, SimNs at = 0) {
    SimNs latency = 0;
    SimNs pdo = 0;
    const SimNs down_at = *led_pdo > debounce + lead ? *led_pdo - debounce - lead : 0;
    if (op.press(at != 0 ? at : next_at(phase), down_at, &latency, &pdo)) {
      r.samples_ns.push_back(latency);
      if (pdo != 0) *led_pdo = pdo;
    } else {
      ++r.lost;
      latency = 0;
    }
    ++presses;
    if (progress) progress(static_cast<double>(presses) / total);
    return latency;
  };
  auto lead_of = [](uint32_t n) { return SimNs{n % 6} * 250 * kNsPerUs; };
  line.run_until(origin);
  const SimNs coarse_step = cycle / kCoarse;
  SimNs worst_phase = 0;
  SimNs worst = 0;
  for (uint32_t k = 0; k < kCoarse; ++k) {
    SimNs led_pdo = 0;
    for (uint32_t n = 0; n < kCoarseRepeats; ++n) {
      const SimNs v = measure(k * coarse_step, &led_pdo, lead_of(n + 2));
      if (v > worst) {
        worst = v;
        worst_phase = k * coarse_step;
      }
    }
  }
  const SimNs span = 4 * coarse_step;
  SimNs fine_worst = 0;
  SimNs steady_sum = 0;  // the phase whose presses are longest on average
  SimNs steady_phase = worst_phase;
  SimNs fine_phase = worst_phase;
  for (uint32_t k = 0; k <= kFine; ++k) {
    const SimNs phase = (worst_phase + cycle - span / 2 + k * span / kFine) % cycle;
    SimNs led_pdo = 0;
    SimNs sum = 0;
    for (uint32_t n = 0; n < kFineRepeats; ++n) {
      const SimNs v = measure(phase, &led_pdo, lead_of(n));
      sum += v;
      if (v > fine_worst) {
        fine_worst = v;
        fine_phase = phase;
      }
    }
    if (sum > steady_sum) {
      steady_sum = sum;
      steady_phase = phase;
    }
  }
  if (neighbours.empty() || fine_worst == 0) return r;
  // The neighbours' power-on phase: switched off and on so that the first
  // heartbeat of the first of them (and what runs with it, its TPDO1's
  // event timer) comes `offset` after a press at the worst phase, offsets
  // spread over the worst latency. Calibrated once: the time from the
  // power-on to that first heartbeat.
  const uint32_t hb_id = 0x700u + static_cast<uint32_t>(neighbours.front() + 1);
  const SimNs calibrate_on = line.now() + kPowerOff + 10 * kMs;
  op.repower(neighbours, calibrate_on);
  const SimNs first_hb = op.first_frame(hb_id, calibrate_on + kS);
  if (first_hb == 0) return r;
  const SimNs boot_to_hb = first_hb - calibrate_on;
  // The end of the path: the neighbours' first heartbeat (and their TPDO1
  // timer, within 1.7 ms of it) `offset` after a press at the steady phase (the
  // fine phase whose presses are longest on average: the press is counted
  // after the read it just misses at nearly every repetition), offsets
  // spread over the last kEndSpan of its mean latency: there the frames
  // reach the passes of the PC's poll (the pass in progress when the
  // read's t3.5 ends, the read pass, write_seen's, the write pass). Then
  // the refinement, every other press at the fine stage's worst phase
  // (missed less often, longer when missed): the PC's start jitter, which
  // the bound charges whole, differs at every press. Modbus only: with
  // the interference the STOP2 and STOP frames fill those passes already
  // and the CANopen cases keep their samples.
  const bool end_stage = !interference;
  // Needs a PC's Arduino other than the lab button's (Modbus + CANopen).
  const bool all_at_once = interference && c.lab_pc != button_station;
  const SimNs steady_end = steady_sum / kFineRepeats;
  // `phase` pressed with the neighbours' first heartbeat `offset` after the
  // steady phase's press time (the end of the path stays where it was).
  auto end_press = [&](SimNs phase, SimNs offset, SimNs* led_pdo, uint32_t n) {
    const SimNs at = next_at(phase, kPowerOff + 10 * kMs + boot_to_hb + 300 * kMs + kMs);
    const SimNs later = (phase + cycle - steady_phase) % cycle;  // wrapped: up to a cycle
    const SimNs steady_at = later < cycle / 2 ? at - later : at + (cycle - later);
    op.repower(neighbours, steady_at + offset - boot_to_hb);
    return measure(phase, led_pdo, lead_of(n), at);
  };
  auto coarse_offset = [&](uint32_t k) {
    return steady_end - kEndSpan - kMs / 2 + k * kEndSpan / kEndPhasings;
  };
  std::vector<SimNs> end_latency;  // per coarse offset, the worst of its presses
  for (uint32_t k = 0; end_stage && k < kEndPhasings; ++k) {
    const SimNs offset = coarse_offset(k);
    SimNs led_pdo = 0;
    SimNs worst_here = 0;
    for (uint32_t n = 0; n < kEndRepeats; ++n)
      worst_here = std::max(worst_here, end_press(steady_phase, offset, &led_pdo, n));
    end_latency.push_back(worst_here);
  }
  // Refined around the worst offset and around the worst one at least
  // kEndApart from it: the frames reach the read's passes and the write's
  // passes at offsets that far apart, and which of them wins the coarse
  // grid is chance (the PC's jitter).
  std::vector<SimNs> end_offsets;
  for (uint32_t pick = 0; pick < 2 && !end_latency.empty(); ++pick) {
    SimNs best = 0;
    SimNs best_offset = 0;
    for (uint32_t k = 0; k < end_latency.size(); ++k) {
      const SimNs offset = coarse_offset(k);
      const bool apart = end_offsets.empty() || offset + kEndApart <= end_offsets.front() ||
                         offset >= end_offsets.front() + kEndApart;
      if (apart && end_latency[k] > best) {
        best = end_latency[k];
        best_offset = offset;
      }
    }
    if (best != 0) end_offsets.push_back(best_offset);
  }
  for (SimNs around : end_offsets) {
    for (uint32_t k = 0; k <= kEndFine; ++k) {
      const SimNs offset = around - kEndFineSpan / 2 + k * kEndFineSpan / kEndFine;
      SimNs led_pdo = 0;
      for (uint32_t n = 0; n < kEndFineRepeats; ++n)
        end_press(n % 2 == 0 ? steady_phase : fine_phase, offset, &led_pdo, n);
    }
  }
  for (uint32_t k = 0; k < kPhasings; ++k) {
    // Half of the offsets just before the press, half just before the
    // debounce runs out: there a frame lengthens the pass in progress and
    // the press is counted later.
    const SimNs around = (k % 2 == 0 ? 0 : debounce) + 2 * kMs;
    const SimNs offset = around - (k / 2) * 3 * kMs / kPhasings;
    SimNs led_pdo = 0;
    for (uint32_t n = 0; n < kPhasingRepeats; ++n) {
      // The press up to 1.5 ms before the worst phase: frames that count
      // it later make up for it.
      const SimNs phase = (fine_phase + cycle - n * 1500 * kNsPerUs / kPhasingRepeats) % cycle;
      // Room for the switching off, the boot and the line settling.
      const SimNs at = next_at(phase, kPowerOff + 10 * kMs + boot_to_hb + 300 * kMs);
      op.repower(neighbours, at + offset - boot_to_hb);
      measure(phase, &led_pdo, lead_of(n), at);
    }
  }
  if (!all_at_once) return r;
  // Every station's frames at once. The PC's Arduino cannot be switched off
  // (its Modbus slave would stop): the lab's NMT master (a PC on the bus)
  // resets its communication instead, which restarts its heartbeat and its
  // TPDO1 event timer (CiA 301: the TPDO1 leaves on entering operational,
  // the timer runs from there) while the application and the Modbus slave
  // run on; the RUN state is the application's and stays. Calibrated once:
  // the time from the NMT frame to its first heartbeat.
  CanController master(line.bus());
  auto reset_comm = [&](int station, SimNs at) {
    line.at(at, [&master, station] {
      CanFrame f{};
      f.dlc = 2;
      f.data[0] = canopen::kNmtResetCommunication;
      f.data[1] = static_cast<uint8_t>(station + 1);
      master.send(f);
    });
  };
  auto reset_to_hb_of = [&](int station) {
    const SimNs reset_at = line.now() + 10 * kMs;
    reset_comm(station, reset_at);
    line.run_until(reset_at + 10 * kMs);  // its boot-up has left
    const SimNs hb = op.first_frame(0x700u + static_cast<uint32_t>(station + 1), reset_at + kS);
    return hb != 0 ? hb - reset_at : 0;
  };
  const SimNs reset_to_hb = reset_to_hb_of(c.lab_pc);
  const SimNs lab_reset_to_hb = reset_to_hb_of(button_station);
  if (reset_to_hb == 0 || lab_reset_to_hb == 0) return r;
  SimNs led_pdo = 0;
  SimNs led_pdo_after = steady_end;  // refined by every press
  uint32_t n = 0;
  // One press with station 1's heartbeat `pc_before` before it, the
  // neighbours' `before_led` before the LED's PDO and, unless 0, the lab
  // Arduino's `lab_after` after it.
  auto press_placed = [&](SimNs pc_before, SimNs before_led, SimNs lab_after) {
    const SimNs phase = n % 2 == 0 ? fine_phase : steady_phase;
    const SimNs at = next_at(phase, kPowerOff + 10 * kMs + std::max(boot_to_hb, reset_to_hb) + 300 * kMs);
    reset_comm(c.lab_pc, at - pc_before - reset_to_hb);
    if (lab_after != 0) reset_comm(button_station, at + lab_after - lab_reset_to_hb);
    if (led_pdo_after > before_led) op.repower(neighbours, at + led_pdo_after - before_led - boot_to_hb);
    measure(phase, &led_pdo, lead_of(n), at);
    if (led_pdo != 0) led_pdo_after = led_pdo;
    ++n;
  };
  for (uint32_t k = 0; k < kStop2Leads; ++k) {
    op.set_stop2_lead(k * kStop2Span / (kStop2Leads - 1));
    for (uint32_t a = 0; a < kPressOffsets; ++a) {
      for (uint32_t b = 0; b < kLedOffsets; ++b)
        press_placed((a + 1) * kPressSpan / kPressOffsets, (b + 1) * kLedSpan / kLedOffsets, 0);
    }
  }
  op.set_stop2_lead(0);
  // The same without STOP2 on the lab's Arduino: its TPDO1 no longer
  // blocks the button's PDO, but its event timer is not restarted by a
  // STOP2 send, so its heartbeat and timer TPDO1 (its communication reset
  // like the PC's Arduino's) can reach the passes of the PC's poll, as in
  // stage 3: kPollOffsets offsets over the last kEndSpan before the LED's
  // PDO.
  op.set_lab_stop2(false);
  for (uint32_t p = 0; p < kPollOffsets; ++p) {
    for (uint32_t a = 0; a < kPollPressOffsets; ++a) {
      const SimNs spread = (a + 1) * kMs / (kPollPressOffsets + 1);
      press_placed(spread * kPressSpan / kMs, spread * kLedSpan / kMs,
                   led_pdo_after - kEndSpan + p * kEndSpan / kPollOffsets);
    }
  }
  op.set_lab_stop2(true);
  return r;
}

}  // namespace sim
}  // namespace mb2co
