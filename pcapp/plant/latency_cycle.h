// The latency mode (seed 000 §11): each cycle reads a button and writes its
// level to the lab LED (plant::ButtonToLed). Per press it takes the delay
// from the firmware's timestamp of the button edge (2300h/1) to its
// timestamp of the LED change (2300h/2): both on the gateway's own clock,
// so the PC's clock and the USB latency of the read do not enter.
// Remote mode: the button sits on another node and reaches this gateway by
// PDO (2130h/1). The start is the remote node's own edge stamp (its
// 2300h/1, read by the app through the gateway: set_remote_edge()), on the
// clock TIME made common (remote_clock.h): the whole path, debounce and CAN
// hop included, with the clock offset's uncertainty per press.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "cycle_mode.h"
#include "latency_stats.h"
#include "plant/latency_lab.h"
#include "remote_clock.h"

namespace mb2co {
namespace pcapp {

struct PressRecord {
  uint32_t press = 0;     ///< 1, 2, ...
  uint64_t cycle = 0;     ///< cycle in which the LED change was seen
  uint32_t edge_us = 0;   ///< button edge (remote: the remote station's stamp), firmware clock
  uint32_t led_us = 0;    ///< LED change, firmware clock
  uint32_t delay_us = 0;  ///< led_us - edge_us, wrap-safe
  /// Remote only (common clock): the PDO's arrival here minus the edge
  /// (debounce, TPDO, CAN hop), and the clock offset's uncertainty (±).
  uint32_t hop_us = 0;
  uint32_t uncertainty_us = 0;
};

class LatencyCycle : public CycleMode {
 public:
  /// `button`: a gateway::Button bit. `max_presses` 0 = no limit.
  LatencyCycle(const RegisterLayout& layout, bool remote, uint8_t button, uint32_t max_presses,
               ClockBound bound = ClockBound());

  /// Remote mode: a press was seen whose edge stamp is still to be read
  /// from the remote station (before its LED change is taken).
  bool wants_remote_edge() const { return remote_ && pending_ && !edge_known_; }
  /// The remote edge of the pending press and both clocks' last set.
  void set_remote_edge(const RemoteEdge& e);
  /// The remote edge could not be read: the pending press is missed.
  void remote_edge_lost();

  std::vector<Field> required_reads() const override;
  std::vector<Field> optional_reads() const override { return {}; }
  std::vector<Field> writes() const override { return {Field::kLabLed}; }

  void step(const RegisterImage& in, RegisterImage& out) override;
  void step_offline() override {}
  void link_lost() override;
  void safe_outputs(RegisterImage& out) const override;
  bool done() const override { return max_presses_ != 0 && records_.size() >= max_presses_; }

  std::string take_event() override;
  std::string status() const override;
  std::vector<const char*> column_names() const override;
  void columns(std::vector<LogValue>& out) const override;
  std::string summary() const override;

  const std::vector<PressRecord>& records() const { return records_; }
  const LatencyStats& stats() const { return stats_; }
  /// Presses whose LED-on time could not be taken (released before the
  /// LED change was read, or the link went down in between).
  uint32_t missed() const { return missed_; }
  /// The CSV of every press (header + one row each).
  std::string csv() const;

 private:
  const RegisterLayout& layout_;
  bool remote_;
  uint8_t button_;
  uint32_t max_presses_;
  plant::ButtonToLed lab_;
  bool pending_ = false;  ///< a press whose LED change we wait for
  uint32_t pending_edge_us_ = 0;
  ClockBound bound_;
  bool edge_known_ = false;  ///< remote: pending_edge_us_ and edge_ read
  RemoteEdge edge_;          ///< remote: of the pending press
  uint32_t arrival_us_ = 0;  ///< remote: 2300h/3 when the press was seen
  uint32_t max_uncertainty_us_ = 0;
  uint32_t led_us_before_ = 0;  ///< LED timestamp when the press was seen
  uint64_t cycle_ = 0;
  bool level_ = false;
  uint32_t missed_ = 0;
  std::vector<PressRecord> records_;
  LatencyStats stats_;
  std::string event_;
};

}  // namespace pcapp
}  // namespace mb2co
