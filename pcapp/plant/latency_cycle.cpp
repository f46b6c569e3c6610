#include "latency_cycle.h"

#include "gateway/line_app.h"

namespace mb2co {
namespace pcapp {

LatencyCycle::LatencyCycle(const RegisterLayout& layout, bool remote, uint8_t button, uint32_t max_presses,
                           ClockBound bound)
    : layout_(layout), remote_(remote), button_(button), max_presses_(max_presses), bound_(bound) {}

void LatencyCycle::set_remote_edge(const RemoteEdge& e) {
  edge_ = e;
  pending_edge_us_ = e.edge_us;
  edge_known_ = true;
}

void LatencyCycle::remote_edge_lost() {
  if (pending_) ++missed_;
  pending_ = false;
}

std::vector<Field> LatencyCycle::required_reads() const {
  if (remote_) return {Field::kRemoteButtons, Field::kRemoteUs, Field::kLedUs, Field::kLeds};
  return {Field::kInputs, Field::kEdgeUs, Field::kLedUs, Field::kLeds};
}

void LatencyCycle::step(const RegisterImage& in, RegisterImage& out) {
  ++cycle_;
  const uint8_t buttons =
      static_cast<uint8_t>(in.get(layout_, remote_ ? Field::kRemoteButtons : Field::kInputs));
  const uint32_t edge_us = in.get(layout_, remote_ ? Field::kRemoteUs : Field::kEdgeUs);
  const uint32_t led_us = in.get(layout_, Field::kLedUs);
  const bool lab_on = (in.get(layout_, Field::kLeds) & gateway::kLedLab) != 0;

  // First the LED change of a pending press, seen in this read.
  if (pending_ && led_us != led_us_before_) {
    pending_ = false;
    // Missed: the LED went on and off again before we read it (its on-time
    // is gone), or, remote, it changed before the remote edge was read.
    if (lab_on && (!remote_ || edge_known_)) {
      PressRecord r;
      r.press = static_cast<uint32_t>(records_.size() + 1);
      r.cycle = cycle_;
      r.edge_us = pending_edge_us_;
      r.led_us = led_us;
      r.delay_us = led_us - pending_edge_us_;  // wraps like the firmware's micros()
      event_ = "press " + std::to_string(r.press) + " delay_us=" + std::to_string(r.delay_us);
      if (remote_) {
        // Each clock's age since its last TIME frame when it took its stamp
        // (the edge there, the LED here): the drift term grows with them.
        r.hop_us = arrival_us_ - r.edge_us;
        const uint32_t age_here = clock_age_us(led_us, edge_.set_here_us, edge_.prev_set_here_us);
        const uint32_t age_remote = clock_age_us(r.edge_us, edge_.set_remote_us, edge_.prev_set_remote_us);
        r.uncertainty_us = clock_uncertainty_us(bound_, age_here, age_remote);
        if (r.uncertainty_us > max_uncertainty_us_) max_uncertainty_us_ = r.uncertainty_us;
        event_ += " +-" + std::to_string(r.uncertainty_us) + " hop_us=" + std::to_string(r.hop_us);
      }
      records_.push_back(r);
      stats_.add(r.delay_us);
    } else {
      ++missed_;
    }
  }
  const uint32_t presses_before = lab_.presses();
  level_ = (buttons & button_) != 0;
  const bool led = lab_.step(level_);
  if (lab_.presses() != presses_before) {
    if (pending_) ++missed_;
    pending_ = true;
    pending_edge_us_ = edge_us;  // remote: the PDO's arrival until set_remote_edge()
    arrival_us_ = edge_us;
    edge_known_ = false;
    led_us_before_ = led_us;
  }
  out.put(layout_, Field::kLabLed, led ? 1u : 0u);
}

void LatencyCycle::link_lost() {
  if (pending_) ++missed_;
  pending_ = false;
  lab_ = plant::ButtonToLed();
}

void LatencyCycle::safe_outputs(RegisterImage& out) const {
  out.put(layout_, Field::kLabLed, 0);
}

std::string LatencyCycle::take_event() {
  std::string e;
  e.swap(event_);
  return e;
}

std::string LatencyCycle::status() const {
  std::string s = std::string("latency ") + (remote_ ? "remote" : "local") + " button " +
                  (level_ ? "down" : "up") + " | presses " + std::to_string(records_.size());
  if (!records_.empty()) {
    s += " last " + std::to_string(records_.back().delay_us) + " us min " + std::to_string(stats_.min_us()) +
         " max " + std::to_string(stats_.max_us());
  }
  return s;
}

std::vector<const char*> LatencyCycle::column_names() const {
  return {"button", "led", "pending", "presses"};
}

void LatencyCycle::columns(std::vector<LogValue>& out) const {
  out.push_back(LogValue{level_ ? 1 : 0, nullptr});
  out.push_back(LogValue{lab_.led() ? 1 : 0, nullptr});
  out.push_back(LogValue{pending_ ? 1 : 0, nullptr});
  out.push_back(LogValue{static_cast<int64_t>(records_.size()), nullptr});
}

std::string LatencyCycle::summary() const {
  std::string s = "presses=" + std::to_string(records_.size()) + " missed=" + std::to_string(missed_);
  if (remote_) {
    s += " clock=common(TIME) uncertainty_us<=" + std::to_string(max_uncertainty_us_) + " (spread " +
         std::to_string(bound_.spread_us) + " + " + std::to_string(bound_.drift_ppm) + " ppm x clock ages)";
  }
  return s + "\n" + stats_.report();
}

std::string LatencyCycle::csv() const {
  std::string s = remote_ ? "press,cycle,edge_us,led_us,delay_us,hop_us,uncertainty_us\n"
                          : "press,cycle,edge_us,led_us,delay_us\n";
  for (const PressRecord& r : records_) {
    s += std::to_string(r.press) + "," + std::to_string(r.cycle) + "," + std::to_string(r.edge_us) + "," +
         std::to_string(r.led_us) + "," + std::to_string(r.delay_us);
    if (remote_) s += "," + std::to_string(r.hop_us) + "," + std::to_string(r.uncertainty_us);
    s += "\n";
  }
  return s;
}

}  // namespace pcapp
}  // namespace mb2co
