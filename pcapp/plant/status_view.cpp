#include "status_view.h"

namespace mb2co {
namespace pcapp {

namespace {
const char kClearLine[] = "\r\033[K";
}

void StatusView::event(double t_s, const std::string& text) {
  if (line_shown_) std::fputs(kClearLine, out_);
  line_shown_ = false;
  std::fprintf(out_, "%.3f %s\n", t_s, text.c_str());
  std::fflush(out_);
}

void StatusView::status(const std::string& line) {
  if (!terminal_) return;
  std::fputs(kClearLine, out_);
  std::fputs(line.c_str(), out_);
  std::fflush(out_);
  line_shown_ = true;
}

void StatusView::finish() {
  if (line_shown_) std::fputc('\n', out_);
  line_shown_ = false;
  std::fflush(out_);
}

}  // namespace pcapp
}  // namespace mb2co

namespace mb2co {
namespace pcapp {

const char* nmt_state_name(uint8_t state) {
  struct Name {
    uint8_t state;
    const char* text;
  };
  static const Name kNames[] = {{0x00, "boot-up"},
                                {0x04, "stopped"},
                                {0x05, "operational"},
                                {0x7F, "pre-operational"},
                                {modbus::net::kStateUnknown, "unknown"}};
  for (const Name& n : kNames)
    if (n.state == state) return n.text;
  return "invalid state";
}

bool append_view_entries(const modbus::NetMessage& m, std::vector<modbus::NetViewEntry>* out) {
  if (m.service != modbus::NetService::kNetworkView || m.data_length % modbus::net::kViewEntryBytes != 0)
    return false;
  for (uint16_t i = 0; i < m.data_length / modbus::net::kViewEntryBytes; ++i)
    out->push_back(modbus::net_view_entry(m, i));
  return true;
}

std::vector<std::string> NeighboursView::update(const std::vector<modbus::NetViewEntry>& view) {
  std::vector<std::string> events;
  std::vector<Known> next;
  for (const modbus::NetViewEntry& e : view) {
    const bool silent = e.age_ms >= kSilentMs;
    const std::string who = "node " + std::to_string(e.node_id);
    const Known* before = nullptr;
    for (const Known& k : known_)
      if (k.node_id == e.node_id) before = &k;
    if (!before) {
      events.push_back(who + " heard: " + nmt_state_name(e.nmt_state));
    } else {
      if (before->state != e.nmt_state)
        events.push_back(who + " " + nmt_state_name(before->state) + " -> " + nmt_state_name(e.nmt_state));
      if (silent && !before->silent) {
        char b[64];
        if (e.age_ms == modbus::net::kAgeSaturated)
          std::snprintf(b, sizeof b, "%s silent for 65.5 s or more", who.c_str());
        else
          std::snprintf(b, sizeof b, "%s silent for %.1f s", who.c_str(), e.age_ms / 1000.0);
        events.push_back(b);
      } else if (!silent && before->silent) {
        events.push_back(who + " heard again: " + nmt_state_name(e.nmt_state));
      }
    }
    next.push_back(Known{e.node_id, e.nmt_state, silent});
  }
  known_ = next;
  polled_ = true;
  return events;
}

std::string NeighboursView::summary() const {
  if (!polled_) return std::string();
  if (known_.empty()) return "neighbours none heard";
  std::string s = "neighbours";
  for (size_t i = 0; i < known_.size(); ++i) {
    s += (i ? ", " : " ") + std::to_string(known_[i].node_id) + " " + nmt_state_name(known_[i].state);
    if (known_[i].silent) s += " (silent)";
  }
  return s;
}

}  // namespace pcapp
}  // namespace mb2co
